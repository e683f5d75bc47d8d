// Interleaved indirect shading (Knecht §2.7 Eq. 5.6–5.8, §2.10): pixel (x, y) is shaded by
// the VPLs i ≡ (x mod I) + I·(y mod I) (mod I²), a different subset for each pixel of an I×I
// block, scaled by I² so that each pixel estimates the full sum; the filter pass then merges
// the block. Both buffers are written from the same evaluation:
//   L_rv += L_o · (1 − ir) · min(V_r, V_v)          (5.6, 5.8)
//   L_r  += L_o · x̄ · r(p) · V_r                     (5.7, with the path flag of §2.8)
// (plus the light of each VPL's co-located VPL3, see vpl.wgsl).
// Directional (environment) VPLs carry the probe's direct light: for them the pass sums, per
// color channel c, the visibilities weighted by w_c = power_c · cos θ: Σw_c·V_rv, Σw_c·V_r and
// Σw_c, from which the final pass scales the probe's exact image-based light (a ratio
// estimator of shadowed light, Heitz et al. 2018): the probe's shadows come from the
// environment VPLs and their ISMs, its light from the prefiltered probe, so sun and lamp
// pixels neither vanish nor sparkle. Per channel, because what an occluder removes has the
// color of the directions it hides: one luminance-weighted ratio gave a virtual object's
// shadow the color of the whole sky and sun, and a bunny half-lit by a blue sky and a warm
// sun 4 % too much red and 3 % too little blue (desk-bunny region FLIP 0.069 → 0.046).

struct IndirectParams {
    // interleave I, VPL count, near-field samples, 1 if the probe's caustics are photons
    info: vec4u,
    // clamp distance d_min (m), unused…
    values: vec4f,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: IndirectParams;
@group(0) @binding(2) var gbuffer_depth_motion: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_albedo_metallic: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal_roughness: texture_2d<f32>;
@group(0) @binding(5) var gbuffer_specular: texture_2d<f32>;
@group(0) @binding(6) var gbuffer_flags: texture_2d<u32>;
@group(0) @binding(7) var<storage, read> materials: array<Material>;

@group(1) @binding(0) var<storage, read> vpls: array<Vpl>;
@group(1) @binding(1) var<uniform> ism: IsmParams;
@group(1) @binding(2) var<storage, read> ism_real: array<u32>;
@group(1) @binding(3) var<storage, read> ism_virtual: array<u32>;

@group(2) @binding(0) var out_rv: texture_storage_2d<rgba16float, write>;
@group(2) @binding(1) var out_r: texture_storage_2d<rgba16float, write>;
@group(2) @binding(2) var out_env_rv: texture_storage_2d<rgba16float, write>;
@group(2) @binding(3) var out_env_r: texture_storage_2d<rgba16float, write>;
@group(2) @binding(4) var out_env_weight: texture_storage_2d<rgba16float, write>;

// The previous frame's radiance (source of the near-field bounce, nearfield.wgsl).
@group(3) @binding(0) var previous_l_rv: texture_2d<f32>;
@group(3) @binding(1) var previous_l_r: texture_2d<f32>;

// Visibility of VPL `index` at receiver `p` (normal `n`) past the casters of one atlas: 0 or
// 1, or the transmittance of a transmissive nearest caster.
// Offsets and biases keep a surface from shadowing itself; they are needed only where the
// receiver's own surface is in the atlas (a real receiver in the real atlas, a virtual one
// in the virtual atlas). Elsewhere they would only grow the other atlas's shadows, most
// visibly where a virtual object touches the real surface it stands on.
fn ism_visible(index: u32, v: Vpl, p: vec3f, n: vec3f, virtual_atlas: bool, own_atlas: bool) -> f32 {
    let first = ism_project(v, p, ism, virtual_atlas);
    let extent = ism_texel_extent(v, first.depth, ism, virtual_atlas);
    // Depth bias against the quantisation of the other atlas's depths: half a texel for
    // splatted maps; a tenth for the triangle-rasterised directional maps, whose texels hold
    // exact depths at their centres. (Half a texel there is 1–2 cm under a room-sized proxy:
    // the bottom of a virtual object standing on a real desk then saw the probe through the
    // desk and glowed; desk-bunny region FLIP 0.071 → 0.069.)
    var offset = 0.0;
    var limit_bias = select(0.5, 0.1, vpl_kind(v) == VPL_DIRECTIONAL) * extent;
    if (own_atlas) {
        if (vpl_kind(v) == VPL_DIRECTIONAL) {
            // Exact triangle maps: a texel-and-a-half of normal offset and half a texel of
            // depth bias suffice; a bias relative to the map's sphere would erase the
            // shadows of thin casters (a book on a desk) under a room-sized real proxy.
            offset = 1.5 * extent;
            limit_bias = 0.5 * extent;
        } else {
            // Lift the receiver off its own surface's splats: by a texel and by the splat size.
            let splat = select(ism.splat.x, ism.splat.y, virtual_atlas) * ism.splat.w;
            offset = max(extent, splat);
            limit_bias = first.depth * ism.splat.z + extent;
        }
    }
    let c = ism_project(v, p + n * offset, ism, virtual_atlas);
    if (!c.valid) { return 1.0; }
    let i = ism_texel_index(index, c.uv, ism);
    let stored = select(ism_real[i], ism_virtual[i], virtual_atlas);
    if (ism_decode(stored) >= c.depth - limit_bias) { return 1.0; }
    // The probe's light through a transmissive caster: its photons carry it when they fly
    // (RenderSettings::probe_caustics), else the shadow lets it through.
    let photons = vpl_kind(v) == VPL_DIRECTIONAL && params.info.w == 1u;
    if (!ism_caster_known(stored) || photons) { return 0.0; }
    return caster_transmittance(materials[ism_caster_material(stored)]);
}

// f_r · cos θ_l of the receiver toward a VPL. On a surface the specular stage traces (a mirror,
// a glass, a smooth metal) the specular lobe is the stage's: its reflection of the surfaces
// these VPLs light. Here, a near-delta GGX lobe turned each VPL into a firefly that the
// interleaving spread into a block (desk-mirror's sphere), and counted that light twice.
fn receiver_brdf_cos(s: Surface, l: vec3f, traced: bool) -> vec3f {
    let lobes = brdf_lobes(s, l);
    return select(lobes.diffuse + lobes.specular, lobes.diffuse, traced);
}

// (V_r, V_v) of VPL `index` at receiver `p` with normal `n`, on a real or virtual surface.
fn ism_visibility(index: u32, v: Vpl, p: vec3f, n: vec3f, real: bool) -> vec2f {
    return vec2f(ism_visible(index, v, p, n, false, real), ism_visible(index, v, p, n, true, !real));
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id.xy >= frame.size.xy)) { return; }
    let pixel = vec2i(id.xy);
    let flags = textureLoad(gbuffer_flags, pixel, 0).r;
    if (!is_covered(flags)) {
        textureStore(out_rv, pixel, vec4f(0.0));
        textureStore(out_r, pixel, vec4f(0.0));
        textureStore(out_env_rv, pixel, vec4f(0.0));
        textureStore(out_env_r, pixel, vec4f(0.0));
        textureStore(out_env_weight, pixel, vec4f(0.0));
        return;
    }
    let p = world_from_pixel(frame, vec2f(id.xy) + 0.5, textureLoad(gbuffer_depth_motion, pixel, 0).x);
    var s = gbuffer_surface(
        p,
        frame.camera_position.xyz,
        textureLoad(gbuffer_albedo_metallic, pixel, 0),
        textureLoad(gbuffer_normal_roughness, pixel, 0),
        textureLoad(gbuffer_specular, pixel, 0),
    );
    let m = materials[material_of(flags)];
    s.transmission = m.transmission.x;
    let traced = is_traced(m);
    let r_p = r_of(flags);
    let receiver_real = is_real(flags);

    let interleave = params.info.x;
    let step = interleave * interleave;
    // The subset of a pixel rotates from frame to frame (7 is coprime with every I² ≤ 64 that
    // is not a multiple of 7), so temporal smoothing sees every subset at every pixel.
    let frame_index = u32(frame.exposure_env.w);
    let subset = ((id.x % interleave) + interleave * (id.y % interleave) + 7u * frame_index) % step;
    let d_min2 = params.values.x * params.values.x;
    var l_rv = vec3f(0.0);
    var l_r = vec3f(0.0);
    var env_rv = vec3f(0.0);
    var env_r = vec3f(0.0);
    var env_weight = vec3f(0.0);
    for (var i = subset; i < params.info.y; i += step) {
        let v = vpls[i];
        let kind = vpl_kind(v);
        if (kind == VPL_SURFACE) {
            let to = v.position.xyz - p;
            let d2 = max(dot(to, to), 1e-12);
            let l = to * inverseSqrt(d2);
            if (dot(s.normal, l) <= 0.0) { continue; }
            let emission = vpl_emission(v, -l);
            if (all(emission == vec3f(0.0))) { continue; }
            let transfer = receiver_brdf_cos(s, l, traced) * emission / max(d2, d_min2);
            let l_o = transfer * v.power.rgb;
            let vis = ism_visibility(i, v, p, s.normal, receiver_real);
            let route = vpl_routing(v.info.x, r_p, vis);
            l_rv += l_o * route.x;
            l_r += l_o * route.y + transfer * v.power_ir.rgb * route.z;
        } else if (kind == VPL_DIRECTIONAL) {
            let cos_theta = dot(s.normal, -v.position.xyz);
            if (cos_theta <= 0.0) { continue; }
            let w = v.power.rgb * cos_theta;
            let vis = ism_visibility(i, v, p, s.normal, receiver_real);
            env_rv += w * min(vis.x, vis.y);
            env_r += w * vis.x;
            env_weight += w;
        }
    }
    let scale = f32(step);
    let near = near_field(pixel, s, traced, r_p, params.values.x, params.info.z, frame_index);
    textureStore(out_rv, pixel, vec4f(l_rv * scale + near.rv, 1.0));
    textureStore(out_r, pixel, vec4f(l_r * scale + near.r, 1.0));
    textureStore(out_env_rv, pixel, vec4f(env_rv, 1.0));
    textureStore(out_env_r, pixel, vec4f(env_r, 1.0));
    textureStore(out_env_weight, pixel, vec4f(env_weight, 1.0));
}
