// Per-pixel cone tracing (Franke §2.13.3–§2.13.5, Eq. 5.21–5.25), once per trace texel
// (texel.wgsl): the nine diffuse cones gather the injected bounce light of both solutions
// (T_Δ² on real pixels as L_rv − L_r, T_ρ² on virtual ones) and their opacity shadows the
// probe's light per channel (Σw·V_rv, Σw·V_r, Σw with w the probe's light in a cone's
// direction times its weight); one cone along the reflected view ray, as wide as the GGX lobe
// of the surface's roughness, gathers the glossy reflection of what the volumes hold (virtual
// objects mirrored in a real desk). Mirror-like and transmissive materials leave that to the
// specular stage. Written as irradiance and radiance, before any material: resolve.wgsl
// applies each pixel's own. Pixels whose cones miss the volume get no indirect light and an
// unshadowed probe, as with `direct`. Where the maps of the probe's directional lights cover
// the pixel (`dvct.probe_lights`), they shadow the light of those narrower than a diffuse cone
// instead of the cones: a small bright source of the probe (a window, a lamp) casts the sharp
// shadow the answer has, which nine wide cones blur into a faint one (and a wall one voxel
// thick lets partly through); a broad sky's lights, whose 32 hard shadows would band where the
// answer's is soft, stay with the cones. The virtual content's shadow on real surfaces takes
// the maps' only for the narrowest lights (half that width). A still view's lights are drawn
// anew each frame (`dvct.sample_probe_lights`) as points (angular radius 0): their maps then
// shadow all of the probe's light, and the frames' mean is its exact soft shadow.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: VolumeParams;
@group(0) @binding(2) var gbuffer_depth_motion: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_albedo_metallic: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal_roughness: texture_2d<f32>;
@group(0) @binding(5) var gbuffer_specular: texture_2d<f32>;
@group(0) @binding(6) var gbuffer_flags: texture_2d<u32>;
@group(0) @binding(7) var<storage, read> materials: array<Material>;

// Group 1: the volumes (cones.wgsl).

// Group 2: the trace texels' IndirectLight targets (shaders/lib/indirect_out.wgsl: the
// diffuse cones' irradiance of both solutions and the probe's visibility sums), the glossy
// cone's radiance of both solutions, and a still view's thin rays (still_rays.wgsl, 8 and 9).
@group(2) @binding(5) var out_glossy_rv: texture_storage_2d<rgba16float, write>;
@group(2) @binding(6) var out_glossy_r: texture_storage_2d<rgba16float, write>;

@group(3) @binding(0) var env_radiance: texture_2d<f32>;
@group(3) @binding(1) var env_irradiance: texture_2d<f32>;
@group(3) @binding(2) var env_dfg_table: texture_2d<f32>;
@group(3) @binding(3) var env_sampler: sampler;
// The probe's directional lights and their maps (shaders/lib/probe_maps.wgsl).
@group(3) @binding(4) var<uniform> probe_lookups: array<ProbeLookup, PROBE_LIGHTS_MAX>;
@group(3) @binding(5) var<storage, read> probe_heights: array<f32>;
@group(3) @binding(6) var<uniform> probe_info: vec4u;

// Diameter-to-length ratio of the cone that holds a GGX lobe of `roughness` (α = r²; the
// lobe's half width is about atan α), at least a voxel's worth over the volume.
fn specular_aperture(roughness: f32) -> f32 {
    let alpha = roughness * roughness;
    return clamp(2.0 * alpha, 1.0 / f32(params.info.x), 1.5);
}

// The cones of the surface seen in `pixel` (covered, of G-buffer `flags`), their cone frame
// turned by `turn`.
fn trace_pixel(pixel: vec2i, flags: u32, turn: f32) -> Traced {
    let s = pixel_surface(pixel);
    return trace_surface(s, flags, gather_surface(s, flags, turn));
}

// What the diffuse cones of surface `s` (of G-buffer `flags`) gather, turned by `turn`.
// Virtual surfaces gather with thin rays where `dvct.virtual_rays` asks for them (cones.wgsl
// gather_rays), real ones with the cones: they make up most of the frame.
fn gather_surface(s: Surface, flags: u32, turn: f32) -> Gathered {
    if (VIRTUAL_RAYS > 0u && !is_real(flags)) {
        return gather_rays(s.position, s.normal, turn);
    }
    return gather_diffuse(s.position, s.normal, pixel_spacing(), turn);
}

// The light of surface `s` (of G-buffer `flags`) from what its diffuse cones gathered, `e`:
// its glossy cone, and the probe's visibility of the cones blended with the maps'.
fn trace_surface(s: Surface, flags: u32, e: Gathered) -> Traced {
    let m = materials[material_of(flags)];
    // Zero-initialised: no glossy light on traced surfaces.
    var glossy: Cone;
    if (!is_traced(m)) {
        let d = reflect(-s.view, s.normal);
        let aperture = specular_aperture(s.roughness);
        glossy = trace_cone(cone_origin(s.position, s.normal), d, aperture, pixel_spacing(), voxel_side(), s.normal);
    }
    var env = e;
    // The probe's light from lights narrower than a cone shadowed by their maps, the rest by
    // the cones: the visibility ratios blended by the share of the light the sharp ones bring.
    let maps = probe_map_visibility(s.position, s.normal, atan(0.5 * params.cone.x));
    if (maps.covered && all(maps.weight > vec3f(0.0))) {
        let sharp = maps.weight / maps.all_weight;
        // In the cones' units (Σw of the probe's light), so that the resolve weighs texels of
        // either kind alike.
        let units = select(vec3f(1.0), e.env, all(e.env > vec3f(0.0)));
        let cones_rv = select(vec3f(1.0), e.env_rv / e.env, e.env > vec3f(0.0));
        let cones_r = select(vec3f(1.0), e.env_r / e.env, e.env > vec3f(0.0));
        env.env_r = units * mix(cones_r, maps.visible_r / maps.weight, sharp);
        if (is_real(flags)) {
            // The virtual content's shadow in it (the share of the real-only light it leaves):
            // the maps' for lights narrower than half that of the sharp ones above (a studio's
            // softbox, a sun: the tall block's sharp shadow on cornell's red wall, the bunny's
            // on its desk), the cones' for the rest. Lights up to a cone's width cast 32 hard
            // shadows where the answer's is soft: desk-spot-real's region FLIP 0.116 → 0.135.
            let narrow = probe_map_visibility(s.position, s.normal, 0.5 * atan(0.5 * params.cone.x));
            let cones_v = select(vec3f(1.0), cones_rv / cones_r, cones_r > vec3f(0.0));
            var v = cones_v;
            if (all(narrow.visible_r > vec3f(0.0))) {
                v = mix(cones_v, narrow.visible_rv / narrow.visible_r, narrow.weight / narrow.all_weight);
            }
            env.env_rv = env.env_r * v;
        } else {
            env.env_rv = units * mix(cones_rv, maps.visible_rv / maps.weight, sharp);
        }
        env.env = units;
    }
    return Traced(e.rv, e.r, env.env_rv, env.env_r, env.env, glossy.rv.rgb, glossy.r.rgb);
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    let texel = vec2i(id.xy);
    if (any(texel >= trace_size())) { return; }
    let pixel = representative(texel);
    if (pixel.x < 0) {
        store_no_indirect(texel);
        textureStore(out_glossy_rv, texel, vec4f(0.0));
        textureStore(out_glossy_r, texel, vec4f(0.0));
        return;
    }
    let flags = textureLoad(gbuffer_flags, pixel, 0).r;
    let s = pixel_surface(pixel);
    // A still view's virtual texels: the running mean of each frame's few thin rays
    // (still_rays.wgsl).
    var e: Gathered;
    if (still_rays_active() && !is_real(flags)) {
        e = still_gather(texel, flags, s, cone_turn(texel));
    } else {
        e = gather_surface(s, flags, cone_turn(texel));
    }
    let t = trace_surface(s, flags, e);
    store_indirect(texel, t.e_rv, t.e_r, t.env_rv, t.env_r, t.env);
    textureStore(out_glossy_rv, texel, vec4f(t.glossy_rv, 1.0));
    textureStore(out_glossy_r, texel, vec4f(t.glossy_r, 1.0));
}

// The pixels the resolve listed (resolve.wgsl list_for_retrace), each traced on its own and
// its light stored with its material, over the blend the resolve wrote (group 2 is then the
// method's IndirectLight, at the internal size, and the list).
struct RetraceList {
    groups: u32,
    groups_y: u32,
    groups_z: u32,
    count: u32,
    pixels: array<u32>,
}

@group(2) @binding(7) var<storage, read> retrace_list: RetraceList;

@compute @workgroup_size(64)
fn cs_retrace(@builtin(global_invocation_id) id: vec3u) {
    if (id.x >= min(retrace_list.count, arrayLength(&retrace_list.pixels))) { return; }
    let packed = retrace_list.pixels[id.x];
    let pixel = vec2i(i32(packed & 0xffffu), i32(packed >> 16u));
    let flags = textureLoad(gbuffer_flags, pixel, 0).r;
    // Turned as a trace texel of its own (as with `dvct.trace_block` = 1): nothing blends it.
    store_pixel_light(pixel, flags, trace_pixel(pixel, flags, cone_turn(pixel)));
}
