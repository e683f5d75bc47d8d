// The real light probe: equirectangular lookup of the data contract
// (u = atan2(x, −z)/2π, v = acos(y)/π, row 0 = +Y), image-based lighting terms.
// Bindings are declared by the including pass: env_radiance, env_irradiance, env_dfg, env_sampler.

fn equirect_uv(d: vec3f) -> vec2f {
    let u = atan2(d.x, -d.z) / (2.0 * PI);
    return vec2f(fract(u + 1.0), acos(clamp(d.y, -1.0, 1.0)) / PI);
}

fn probe_dir(frame: Frame, world_dir: vec3f) -> vec3f {
    return (frame.probe_from_world * vec4f(world_dir, 0.0)).xyz;
}

// Radiance arriving from `world_dir`, prefiltered for GGX `roughness`.
fn env_radiance_at(frame: Frame, world_dir: vec3f, roughness: f32) -> vec3f {
    if (frame.counts.y == 0u) { return vec3f(0.0); }
    let lod = roughness * f32(frame.counts.w - 1u);
    let uv = equirect_uv(probe_dir(frame, world_dir));
    return textureSampleLevel(env_radiance, env_sampler, uv, lod).rgb * frame.exposure_env.y;
}

// Irradiance E(n) = ∫ L(ω) max(0, n·ω) dω on a surface facing `world_normal`.
fn env_irradiance_at(frame: Frame, world_normal: vec3f) -> vec3f {
    if (frame.counts.y == 0u) { return vec3f(0.0); }
    let uv = equirect_uv(probe_dir(frame, world_normal));
    return textureSampleLevel(env_irradiance, env_sampler, uv, 0.0).rgb * frame.exposure_env.y;
}

// Split-sum albedo of the specular lobe: the part of the light the surface reflects
// specularly (Karis 2013), F0·A + F90·B.
fn env_specular_albedo(s: Surface) -> vec3f {
    let ab = env_dfg(max(dot(s.normal, s.view), 1e-4), s.roughness);
    return surface_f0(s) * ab.x + surface_f90(s) * ab.y;
}

// What the specular lobe (of albedo `specular_albedo`) leaves to the diffuse one (glTF
// fresnel_mix, averaged over the lobe).
fn env_diffuse_weight(s: Surface, specular_albedo: vec3f) -> vec3f {
    return (vec3f(1.0) - specular_albedo) * (1.0 - s.metallic) * (1.0 - s.transmission);
}

// The probe's diffuse light.
fn env_diffuse(frame: Frame, s: Surface, specular_albedo: vec3f) -> vec3f {
    return env_diffuse_weight(s, specular_albedo) * s.base_color / PI * env_irradiance_at(frame, s.normal);
}

// Unshadowed image-based light reflected (and refracted) toward the eye.
fn env_shading(frame: Frame, s: Surface, refraction: vec3f) -> vec3f {
    let specular_albedo = env_specular_albedo(s);
    let specular = specular_albedo * env_radiance_at(frame, reflect(-s.view, s.normal), s.roughness);
    return (env_diffuse(frame, s, specular_albedo) + specular) * s.occlusion + refraction;
}
