// glTF 2.0 metallic-roughness BRDF (Appendix B) with KHR_materials_specular's F0/F90.
// CPU twins of these terms live in mrshade_core::brdf.

fn d_ggx(n_dot_h: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let f = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return a2 / max(PI * f * f, 1e-12);
}

fn v_smith_ggx(n_dot_v: f32, n_dot_l: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let gv = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
    let gl = n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
    return 0.5 / max(gv + gl, 1e-12);
}

fn schlick(f0: vec3f, f90: f32, cos_theta: f32) -> vec3f {
    return f0 + (vec3f(f90) - f0) * pow(clamp(1.0 - cos_theta, 0.0, 1.0), 5.0);
}

// Everything the BRDF needs at one shading point.
struct Surface {
    position: vec3f,
    normal: vec3f,
    view: vec3f,
    base_color: vec3f,
    metallic: f32,
    roughness: f32,
    dielectric_f0: vec3f,
    dielectric_f90: f32,
    transmission: f32,
    emission: vec3f,
    occlusion: f32,
}

// The surface a G-buffer pixel stores at world position `p`, seen from `eye`: the texels of
// its albedo/metallic, normal/roughness and specular (F0, F90) targets. No emission or
// transmission, full occlusion: passes that use them set them.
fn gbuffer_surface(p: vec3f, eye: vec3f, albedo_metallic: vec4f, normal_roughness: vec4f, specular: vec4f) -> Surface {
    var s: Surface;
    s.position = p;
    s.normal = normalize(normal_roughness.xyz);
    s.view = normalize(eye - p);
    s.base_color = albedo_metallic.rgb;
    s.metallic = albedo_metallic.a;
    s.roughness = normal_roughness.a;
    s.dielectric_f0 = specular.rgb;
    s.dielectric_f90 = specular.a;
    s.transmission = 0.0;
    s.emission = vec3f(0.0);
    s.occlusion = 1.0;
    return s;
}

fn surface_f0(s: Surface) -> vec3f { return mix(s.dielectric_f0, s.base_color, s.metallic); }
fn surface_f90(s: Surface) -> f32 { return mix(s.dielectric_f90, 1.0, s.metallic); }

// f_r(l, v) · (n·l) for light arriving from direction `l`.
// f_r · cos θ_l split into its lobes.
struct Lobes {
    diffuse: vec3f,
    specular: vec3f,
}

fn brdf_lobes(s: Surface, l: vec3f) -> Lobes {
    var out: Lobes;
    let n_dot_l = dot(s.normal, l);
    let n_dot_v = max(dot(s.normal, s.view), 1e-4);
    if (n_dot_l <= 0.0) { return out; }
    let h = normalize(l + s.view);
    let alpha = max(s.roughness * s.roughness, 1e-3);
    let f = schlick(surface_f0(s), surface_f90(s), max(dot(s.view, h), 0.0));
    out.specular = f * d_ggx(max(dot(s.normal, h), 0.0), alpha) * v_smith_ggx(n_dot_v, n_dot_l, alpha) * n_dot_l;
    out.diffuse = (vec3f(1.0) - f) * (1.0 - s.metallic) * (1.0 - s.transmission) * s.base_color / PI * n_dot_l;
    return out;
}

// Whether the diffuse lobe of `s` can be non-zero (brdf_lobes: not a pure metal, not fully
// transmissive, not black).
fn has_diffuse(s: Surface) -> bool {
    return s.metallic < 1.0 && s.transmission < 1.0 && any(s.base_color > vec3f(0.0));
}

fn brdf_cos(s: Surface, l: vec3f) -> vec3f {
    let lobes = brdf_lobes(s, l);
    return lobes.diffuse + lobes.specular;
}
