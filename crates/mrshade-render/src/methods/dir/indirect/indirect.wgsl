// Interleaved indirect shading (Knecht §2.7 Eq. 5.6–5.8, §2.10): pixel (x, y) is shaded by
// the VPLs i ≡ (x mod I) + I·(y mod I) (mod I²), a different subset for each pixel of an I×I
// block, scaled by I² so that each pixel estimates the full sum; the filter pass then merges
// the block. Both buffers are written from the same evaluation (vpl_light.wgsl).
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
    // clamp distance d_min (m), near-field radius of the multiple-bounce light (m; ≤ d_min:
    // none), unused…
    values: vec4f,
    // samples of the multiple-bounce near field, unused…
    near: vec4u,
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

// Group 2: the IndirectLight targets (shaders/lib/indirect_out.wgsl).

// The previous frame's radiance and the indirect part of it (sources of the near-field
// bounce, nearfield.wgsl).
@group(3) @binding(0) var previous_l_rv: texture_2d<f32>;
@group(3) @binding(1) var previous_l_r: texture_2d<f32>;
@group(3) @binding(2) var previous_indirect_rv: texture_2d<f32>;
@group(3) @binding(3) var previous_indirect_r: texture_2d<f32>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id.xy >= frame.size.xy)) { return; }
    let pixel = vec2i(id.xy);
    let flags = textureLoad(gbuffer_flags, pixel, 0).r;
    if (!is_covered(flags)) {
        store_no_indirect(pixel);
        return;
    }
    var s = pixel_surface(pixel);
    let m = materials[material_of(flags)];
    s.transmission = m.transmission.x;
    let traced = is_traced(m);
    let r_p = r_of(flags);

    let interleave = params.info.x;
    let step = interleave * interleave;
    // The subset of a pixel rotates from frame to frame (7 is coprime with every I² ≤ 64 that
    // is not a multiple of 7), so temporal smoothing sees every subset at every pixel.
    let frame_index = u32(frame.exposure_env.w);
    let subset = ((id.x % interleave) + interleave * (id.y % interleave) + 7u * frame_index) % step;
    let d_min = params.values.x;
    let screen_scale = pixels_per_metre(s.position, vec2f(pixel) + 0.5);
    // The near fields gather what receiver_brdf_cos reflects: nothing on a traced metal or glass.
    let gathers = reflects_vpls(s, traced);
    let bounced = near_field_bounced(pixel, s, traced, r_p, d_min, screen_scale, params.values.y, select(0u, params.near.x, gathers), frame_index);
    let how = VplShading(d_min, bounced.d_bounce, vec2f(pixel) + 0.5, bounced.radius_px, screen_scale, params.info.w == 1u, true);
    let light = vpl_light(s, traced, r_p, subset, step, params.info.y, how);
    let scale = f32(step);
    let near = near_field(pixel, s, traced, r_p, d_min, screen_scale, select(0u, params.info.z, gathers), frame_index);
    // Surroundings mirrored by virtual metals (vpl_light.wgsl): p's own radiance of the previous
    // frame stands for theirs.
    let mirrored = light.mirrored * scale * textureLoad(previous_l_rv, pixel, 0).rgb;
    store_indirect(pixel, light.rv * scale + near.rv + bounced.light.rv + mirrored, light.r * scale + near.r + bounced.light.r, light.env_rv, light.env_r, light.env_weight);
}
