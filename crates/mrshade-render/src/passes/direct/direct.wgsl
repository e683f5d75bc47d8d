// Differential shading of direct light (Knecht §2.7, Eq. 5.1–5.5), plus, with the `dir`
// method, the merged indirect light. For every pixel and every primary light, the
// unoccluded radiance L_o is written to both buffers at once:
//   L_rv += L_o · min(V_r, V_v)          (5.1, 5.3)
//   L_r  += L_o · r(pl) · r(p) · V_r     (5.2)
// The probe is real light: it adds to L_rv everywhere and to L_r on real surfaces, unshadowed
// with `direct`, shadowed through the environment VPLs with `dir`. Where no surface covers a
// pixel both buffers hold the probe itself.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> shadow_params: ShadowParams;
@group(0) @binding(2) var gbuffer_depth_motion: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_albedo_metallic: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal_roughness: texture_2d<f32>;
@group(0) @binding(5) var gbuffer_specular: texture_2d<f32>;
@group(0) @binding(6) var gbuffer_emission_occlusion: texture_2d<f32>;
@group(0) @binding(7) var gbuffer_flags: texture_2d<u32>;
// With the `dir` method (shadow_params.size.z == 1): indirect light of both solutions and the
// environment visibility sums per channel (Σw_c·V_rv, Σw_c·V_r, Σw_c), merged and smoothed.
@group(0) @binding(8) var indirect_rv: texture_2d<f32>;
@group(0) @binding(9) var indirect_r: texture_2d<f32>;
@group(0) @binding(10) var indirect_env_rv: texture_2d<f32>;
@group(0) @binding(11) var indirect_env_r: texture_2d<f32>;
@group(0) @binding(12) var indirect_env_weight: texture_2d<f32>;

@group(1) @binding(0) var<storage, read> materials: array<Material>;
@group(1) @binding(1) var<storage, read> lights: array<Light>;
@group(1) @binding(2) var<storage, read> shadow_clip_from_world: array<mat4x4f>;
@group(1) @binding(3) var<storage, read> shadow_texels: array<vec2u>;

@group(2) @binding(0) var env_radiance: texture_2d<f32>;
@group(2) @binding(1) var env_irradiance: texture_2d<f32>;
@group(2) @binding(2) var env_dfg_table: texture_2d<f32>;
@group(2) @binding(3) var env_sampler: sampler;

@group(3) @binding(0) var out_l_rv: texture_storage_2d<rgba16float, write>;
@group(3) @binding(1) var out_l_r: texture_storage_2d<rgba16float, write>;

fn load_surface(pixel: vec2i) -> Surface {
    let eo = textureLoad(gbuffer_emission_occlusion, pixel, 0);
    var s = pixel_surface(pixel);
    s.emission = eo.rgb;
    s.occlusion = eo.a;
    return s;
}

// Light through a transmissive surface (KHR_materials_transmission + _volume), seen along
// the refracted view ray in the probe and attenuated by Beer–Lambert over the thickness.
// Used where the specular stage does not trace the material (it is off, or the glass rough).
fn refracted_probe(s: Surface, m: Material) -> vec3f {
    let t = m.transmission.x * (1.0 - s.metallic);
    if (t <= 0.0) { return vec3f(0.0); }
    let ior = max(m.transmission.y, 1.0);
    let dir = refract(-s.view, s.normal, 1.0 / ior);
    let absorption = select(vec3f(0.0), -log(max(m.attenuation_cutoff.rgb, vec3f(1e-4))) / m.transmission.w, m.transmission.w < 1e29);
    let transmittance = exp(-absorption * m.transmission.z);
    let f = schlick(surface_f0(s), surface_f90(s), max(dot(s.normal, s.view), 0.0));
    return t * (vec3f(1.0) - f) * s.base_color * transmittance * env_radiance_at(frame, dir, s.roughness);
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id.xy >= frame.size.xy)) { return; }
    let pixel = vec2i(id.xy);
    let centre = vec2f(id.xy) + 0.5;
    let flags = textureLoad(gbuffer_flags, pixel, 0).r;
    if (!is_covered(flags)) {
        let dir = normalize(world_from_pixel(frame, centre, 0.5) - frame.camera_position.xyz);
        let probe = env_radiance_at(frame, dir, 0.0);
        textureStore(out_l_rv, pixel, vec4f(probe, 1.0));
        textureStore(out_l_r, pixel, vec4f(probe, 1.0));
        return;
    }
    let m = materials[material_of(flags)];
    var s = load_surface(pixel);
    s.transmission = m.transmission.x;
    let r_p = r_of(flags);

    let punctual = punctual_radiance(s, r_p);
    var l_rv = punctual.rv;
    var l_r = punctual.r;
    // Mirror-like and transmissive materials leave their specular reflection and refraction
    // of the probe to the specular stage, which traces them (reflections spec §2.4).
    var probe: vec3f;
    let shading = select(IBL_PREFILTERED, ibl.x, r_p == 0.0);
    if (is_traced(m)) {
        probe = probe_diffuse(s, env_specular_albedo(s), shading, pixel) * s.occlusion;
    } else {
        probe = probe_shading(s, refracted_probe(s, m), shading, pixel);
    }
    if (shadow_params.size.z == 1u) {
        // DIR: the probe's light shadowed by the environment VPLs' visibility ratios, plus the
        // VPLs' indirect light (whose L_r already carries r(p)). The ratios are per channel: a
        // shadow has the color of the light it blocks (a virtual object that hides the blue
        // sky but not the warm sun casts a bluish shadow), not that of the probe's whole light.
        let weight = textureLoad(indirect_env_weight, pixel, 0).rgb;
        let ratio_rv = visibility_ratio(textureLoad(indirect_env_rv, pixel, 0).rgb, weight);
        let ratio_r = visibility_ratio(textureLoad(indirect_env_r, pixel, 0).rgb, weight);
        l_rv += probe * ratio_rv + s.emission + textureLoad(indirect_rv, pixel, 0).rgb;
        l_r += (probe * ratio_r + s.emission) * r_p + textureLoad(indirect_r, pixel, 0).rgb;
    } else {
        l_rv += probe + s.emission;
        l_r += (probe + s.emission) * r_p;
    }
    textureStore(out_l_rv, pixel, vec4f(l_rv, 1.0));
    textureStore(out_l_r, pixel, vec4f(l_r, 1.0));
}
