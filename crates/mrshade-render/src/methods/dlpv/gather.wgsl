// The merge with the real scene (Franke §2.12.6, Eq. 5.14–5.16), per pixel: the accumulated
// volumes are read trilinearly half a cell along the surface normal (where injection put
// its light) and evaluated for the inverted normal, E = ⟨c, clamped cosine(−n)⟩ / h², the
// irradiance of a cell's intensity over its cross-section (V_ρ gathered from VPLs with its
// band 2). Virtual pixels take V_ρ's light
// (Eq. 5.15); real ones the real scene's bounce light of V_μ in both L_rv and L_r (the
// model of the photo the α-scaled composite divides by) and the signed change of V_Δ in
// L_rv (Eq. 5.16), so that L_rv − L_r is the change. On real pixels the virtual content's
// shadow of the probe's broad lights is in the direct change, that of the others (up to
// `dlpv.sharp_probe_shadows_deg`) read from their maps here, soft by each light's radius
// with `dlpv.soft_probe_shadows`; virtual ones see the probe
// through the maps of its directional lights, soft by each light's radius with
// `dlpv.soft_virtual_probe_shadows` (spec §2.3's suggested upgrade of ambient
// occlusion to directional occlusion): the visibility sums Σw·V over the lights,
// w = E_k·⟨n, l_k⟩₊ per channel, V = 0 where a real or virtual surface lies toward the light
// (the desk below, the object itself).

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: DlpvParams;
@group(0) @binding(2) var gbuffer_depth_motion: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_albedo_metallic: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal_roughness: texture_2d<f32>;
@group(0) @binding(5) var gbuffer_specular: texture_2d<f32>;
@group(0) @binding(6) var gbuffer_flags: texture_2d<u32>;
@group(0) @binding(7) var<storage, read> materials: array<Material>;

// The accumulated V_ρ, V_Δ, V_μ one after the other, each channel-major.
@group(1) @binding(0) var<storage, read> volumes: array<vec4f>;
// The probe's directional lights and their maps (shaders/lib/probe_maps.wgsl).
@group(1) @binding(1) var<uniform> probe_lookups: array<ProbeLookup, PROBE_LIGHTS_MAX>;
@group(1) @binding(2) var<storage, read> probe_heights: array<f32>;
@group(1) @binding(3) var<uniform> probe_info: vec4u;
@group(1) @binding(4) var<storage, read> probe_heights_near: array<f32>;
// V_ρ's band 2 where it is gathered (volume.wgsl).
@group(1) @binding(5) var<storage, read> rho_band2: array<vec4f>;

// Group 2: the IndirectLight targets (shaders/lib/indirect_out.wgsl).

@group(3) @binding(0) var env_radiance: texture_2d<f32>;
@group(3) @binding(1) var env_irradiance: texture_2d<f32>;
@group(3) @binding(2) var env_dfg_table: texture_2d<f32>;
@group(3) @binding(3) var env_sampler: sampler;

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
    let specular_albedo = env_specular_albedo(s);
    let diffuse = env_diffuse_weight(s, specular_albedo) * s.base_color / PI;
    if (is_real(flags)) {
        let model = diffuse * max(volume_irradiance(VOLUME_MU, s.position, s.normal), vec3f(0.0));
        let change = diffuse * volume_irradiance(VOLUME_DELTA, s.position, s.normal);
        // The probe's light shadowed by the real scene in both solutions (walls hold some of it
        // back: unshadowed in L_r, the model of the photo in cornell had 1.58 / 1.64 / 1.46 times
        // the photo's light instead of 1.43 / 1.46 / 1.17, and the α-scaled composite weakened
        // every change by as much; most of the rest is V_μ's self-illumination, spec §2.12.9),
        // and in L_rv also by the virtual content's shadow of its sharp lights (up to
        // `dlpv.sharp_probe_shadows_deg`; the volume's direct change holds the rest,
        // inject.wgsl). As shares of the probe's light: raw sums of a bright probe would
        // overflow the f16 targets.
        let probe = probe_map_real_light(s.position, s.normal, params.scale.y, (params.gathered.z & SOFT_REAL) != 0u);
        let total = probe.all_weight;
        let env_r = select(vec3f(1.0), probe.visible_r / total, total > vec3f(0.0));
        let taken = select(vec3f(0.0), probe.blocked / total, total > vec3f(0.0));
        store_indirect(pixel, model + change, model, env_r - taken, env_r, vec3f(1.0));
        return;
    }
    let light = diffuse * max(volume_irradiance(VOLUME_RHO, s.position, s.normal), vec3f(0.0));
    var v: ProbeMapVisibility;
    if ((params.gathered.z & SOFT_VIRTUAL) != 0u) {
        v = probe_map_soft_visibility(s.position, s.normal);
    } else {
        v = probe_map_visibility(s.position, s.normal, 0.0);
    }
    if (all(v.weight == vec3f(0.0))) {
        store_indirect(pixel, light, vec3f(0.0), vec3f(1.0), vec3f(1.0), vec3f(1.0));
        return;
    }
    store_indirect(pixel, light, vec3f(0.0), v.visible_rv, v.visible_rv, v.weight);
}
