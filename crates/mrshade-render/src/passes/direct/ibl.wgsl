// The probe's light on a surface by `[ibl] virtual` (Franke §2.1–§2.2), for virtual surfaces;
// real ones always take the prefiltered maps (their light is the photo's; only L_r's model).
// - prefiltered: irradiance map and GGX-prefiltered chain (env.wgsl);
// - sh: irradiance from the nine SH coefficients the probe_sh pass projects every frame
//   (E(n) = Σ Â_l c_lm y_lm(n)), specular as prefiltered;
// - prt: the prt pass's irradiance with self-shadowing where it applies (rigid objects),
//   else SH; specular by the Sum of Gaussians (spec §2.5: the GGX lobe's three Gaussians
//   read from the probe's pyramid, shadowed by the PRT visibility) or as fis;
// - fis: SH irradiance and, per pixel, GGX filtered importance sampling of the probe's
//   box-filtered pyramid (Křivánek & Colbert 2008): `samples` half vectors from the GGX
//   distribution (Hammersley), each read at the mip whose texel spans its sample's solid
//   angle, lod = ½·log2(Ω_s/Ω_p) + 1, Ω_s = 1/(N·pdf), Ω_p = 4π/(w·h); weighted by n·l.

@group(2) @binding(4) var<storage, read> probe_sh: array<vec4f, 9>;
@group(2) @binding(5) var env_pyramid: texture_2d<f32>;
// shading (IBL_*), samples, 1: Sum-of-Gaussians specular for prt, the SoG table's side
@group(2) @binding(6) var<uniform> ibl: vec4u;
// PRT irradiance (a = 1 where it applies).
@group(2) @binding(7) var prt_irradiance: texture_2d<f32>;
// The GGX lobe's Sum-of-Gaussians fit (mrshade_core::sog): per cell (roughness row, n·v
// column, texel centres), SOG_LOBES × (μ: offset toward the normal, σ, weight, 0).
@group(2) @binding(8) var<storage, read> sog_table: array<vec4f>;
const SOG_LOBES: u32 = 3u;

const IBL_PREFILTERED: u32 = 0u;
const IBL_SH: u32 = 1u;
const IBL_FIS: u32 = 2u;
const IBL_PRT: u32 = 3u;

// The probe's unshadowed irradiance from its nine SH coefficients.
fn sh_irradiance(n: vec3f) -> vec3f {
    if (frame.counts.y == 0u) { return vec3f(0.0); }
    let b = sh9(probe_dir(frame, n));
    var e = vec3f(0.0);
    for (var k = 0u; k < 9u; k++) {
        e += probe_sh[k].rgb * (sh9_clamped_cosine_band(k) * b[k]);
    }
    return max(e, vec3f(0.0)) * frame.exposure_env.y;
}

fn probe_irradiance(n: vec3f, mode: u32, pixel: vec2i) -> vec3f {
    if (mode == IBL_PREFILTERED) { return env_irradiance_at(frame, n); }
    if (mode == IBL_PRT) {
        let prt = textureLoad(prt_irradiance, pixel, 0);
        if (prt.a > 0.5) { return prt.rgb; }
    }
    return sh_irradiance(n);
}

// How much of the probe a pixel's object lets through, from PRT: its self-shadowed irradiance
// over the unshadowed one (spec §2.5: "multiply by the PRT SH visibility"); 1 without PRT.
fn prt_visibility(n: vec3f, pixel: vec2i) -> f32 {
    let prt = textureLoad(prt_irradiance, pixel, 0);
    let open = dot(sh_irradiance(n), vec3f(1.0));
    if (prt.a < 0.5 || open <= 0.0) { return 1.0; }
    return clamp(dot(prt.rgb, vec3f(1.0)) / open, 0.0, 1.0);
}

// The glossy reflection of the probe by the Sum of Gaussians (spec §2.5, Eq. 4.25–4.26): the
// lobe's Gaussians, interpolated bilinearly in (n·v, roughness) from the table, each read
// from the pyramid at its direction (ω_r turned toward the normal by μ) and at the level
// whose blur is its σ.
fn sog_radiance(s: Surface) -> vec3f {
    let n = s.normal;
    let r = reflect(-s.view, n);
    let side = ibl.w;
    let cell = clamp(vec2f(max(dot(n, s.view), 0.0), s.roughness) * f32(side) - 0.5, vec2f(0.0), vec2f(f32(side - 1u)));
    let c0 = vec2u(floor(cell));
    let c1 = min(c0 + 1u, vec2u(side - 1u));
    let f = cell - vec2f(c0);
    let toward_n = n - dot(n, r) * r;
    let t = select(tangent_frame(r)[0], normalize(toward_n), dot(toward_n, toward_n) > 1e-8);
    // A level's texels span θ_L = 2^L·2π/width at the equator; its box filter and the
    // bilinear lookup blur by σ ≈ θ_L/2 together (w²/12 + w²/6 = w²/4).
    let texel_angle = 2.0 * PI / f32(textureDimensions(env_pyramid, 0).x);
    var sum = vec3f(0.0);
    for (var k = 0u; k < SOG_LOBES; k++) {
        let g = mix(
            mix(sog_table[(c0.y * side + c0.x) * SOG_LOBES + k], sog_table[(c0.y * side + c1.x) * SOG_LOBES + k], f.x),
            mix(sog_table[(c1.y * side + c0.x) * SOG_LOBES + k], sog_table[(c1.y * side + c1.x) * SOG_LOBES + k], f.x),
            f.y,
        );
        let d = normalize(r * cos(g.x) + t * sin(g.x));
        let lod = max(log2(2.0 * g.y / texel_angle), 0.0);
        sum += g.z * textureSampleLevel(env_pyramid, env_sampler, equirect_uv(probe_dir(frame, d)), lod).rgb;
    }
    return sum * frame.exposure_env.y;
}

fn fis_radiance(s: Surface) -> vec3f {
    let n = s.normal;
    let v = s.view;
    let alpha = max(s.roughness * s.roughness, 1e-4);
    let size = vec2f(textureDimensions(env_pyramid, 0));
    let texel_solid_angle = 4.0 * PI / (size.x * size.y);
    let count = max(ibl.y, 1u);
    let t = tangent_frame(n);
    var sum = vec3f(0.0);
    var weight = 0.0;
    for (var i = 0u; i < count; i++) {
        let u = vec2f((f32(i) + 0.5) / f32(count), halton2(i));
        let phi = 2.0 * PI * u.y;
        let cos_h = sqrt((1.0 - u.x) / (1.0 + (alpha * alpha - 1.0) * u.x));
        let sin_h = sqrt(max(1.0 - cos_h * cos_h, 0.0));
        let h = normalize(t[0] * (cos(phi) * sin_h) + t[1] * (sin(phi) * sin_h) + n * cos_h);
        let l = reflect(-v, h);
        let n_dot_l = dot(n, l);
        if (n_dot_l <= 0.0) { continue; }
        let pdf = d_ggx(cos_h, alpha) * cos_h / (4.0 * max(dot(v, h), 1e-4));
        let lod = max(0.5 * log2(1.0 / (f32(count) * pdf) / texel_solid_angle) + 1.0, 0.0);
        let uv = equirect_uv(probe_dir(frame, l));
        sum += textureSampleLevel(env_pyramid, env_sampler, uv, lod).rgb * n_dot_l;
        weight += n_dot_l;
    }
    if (weight <= 0.0) { return env_radiance_at(frame, reflect(-v, n), s.roughness); }
    return sum / weight * frame.exposure_env.y;
}

fn probe_diffuse(s: Surface, specular_albedo: vec3f, mode: u32, pixel: vec2i) -> vec3f {
    return env_diffuse_weight(s, specular_albedo) * s.base_color / PI * probe_irradiance(s.normal, mode, pixel);
}

// Image-based light reflected (and refracted) toward the eye: env_shading by `mode`.
fn probe_shading(s: Surface, refraction: vec3f, mode: u32, pixel: vec2i) -> vec3f {
    let specular_albedo = env_specular_albedo(s);
    var specular: vec3f;
    if (mode == IBL_PRT && ibl.z == 1u && frame.counts.y != 0u) {
        specular = sog_radiance(s) * prt_visibility(s.normal, pixel);
    } else if ((mode == IBL_FIS || mode == IBL_PRT) && frame.counts.y != 0u) {
        specular = fis_radiance(s);
    } else {
        specular = env_radiance_at(frame, reflect(-s.view, s.normal), s.roughness);
    }
    return (probe_diffuse(s, specular_albedo, mode, pixel) + specular_albedo * specular) * s.occlusion + refraction;
}
