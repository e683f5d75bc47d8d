// G-buffer flag word (mirrors mrshade_core::flags; checked by a test).
const SURFACE_COVERED: u32 = 1u;
const SURFACE_REAL: u32 = 2u;
const SURFACE_MATERIAL_SHIFT: u32 = 8u;

fn is_covered(flags: u32) -> bool { return (flags & SURFACE_COVERED) != 0u; }
fn is_real(flags: u32) -> bool { return (flags & SURFACE_REAL) != 0u; }
// r(p) of Knecht's equations: 1 on real surfaces, 0 on virtual ones.
fn r_of(flags: u32) -> f32 { return select(0.0, 1.0, is_real(flags)); }
fn material_of(flags: u32) -> u32 { return flags >> SURFACE_MATERIAL_SHIFT; }

// Material factors that are not stored per pixel (mirrors `GpuMaterial` in src/scene_gpu/materials.rs).
struct Material {
    base_color: vec4f,
    // metallic, roughness, normal scale, occlusion strength
    params: vec4f,
    // dielectric F0 (rgb, KHR_materials_specular × _ior), dielectric F90 (= specular factor)
    dielectric: vec4f,
    // transmission, ior, thickness, attenuation distance
    transmission: vec4f,
    // attenuation color, alpha cutoff (< 0: opaque)
    attenuation_cutoff: vec4f,
    emissive: vec4f,
    // array layers of base color (sRGB), metallic-roughness, normal, occlusion (linear); NO_TEXTURE if absent
    texture_layers: vec4u,
    // emissive layer (sRGB), repeat bits (u, v per slot in the order above + emissive),
    // 1 if double-sided, 1 if the specular stage traces it
    texture_info: vec4u,
}

fn is_traced(m: Material) -> bool { return m.texture_info.w != 0u; }
fn is_double_sided(m: Material) -> bool { return m.texture_info.z == 1u; }

// The base color of a VPL on material `m` (base color `base`, metalness `metallic`): glTF's
// transmission takes its share from the dielectric's diffuse lobe (KHR_materials_transmission),
// so a glass VPL bounces only its Fresnel reflection. (As a white diffuse surface, a glass
// bunny lit the desk around it like a lamp once its shadow let that light through.)
fn vpl_base_color(m: Material, base: vec3f, metallic: f32) -> vec3f {
    return base * (1.0 - m.transmission.x * (1.0 - metallic));
}

// The share of the light that a caster of material `m` lets through its shadow: 0 if opaque;
// for a transmissive one, both interfaces' Fresnel transmittance averaged over the hemisphere
// (Schlick's average F0 + (1 − F0)/21), its base color and Beer–Lambert over its thickness
// (KHR_materials_volume). Light that glass refracts is not moved (punctual lights' caustics
// do that), only not lost: under a probe, whose light comes from every direction, a glass
// object's shadow is faint (the desk-glass answer), where an opaque caster's was dark.
// Normal-incidence reflectance of material `m` (its metallic blend of the dielectric's F0 and
// the base color), for code that has the material and no Surface (surface_f0).
fn material_f0(m: Material) -> vec3f { return mix(m.dielectric.rgb, m.base_color.rgb, m.params.x); }

fn caster_transmittance(m: Material) -> f32 {
    let t = m.transmission.x;
    if (t <= 0.0) { return 0.0; }
    let f0 = dot(m.dielectric.rgb, vec3f(1.0 / 3.0));
    let through = 1.0 - (f0 + (1.0 - f0) / 21.0);
    let beer = pow(max(m.attenuation_cutoff.rgb, vec3f(1e-6)), vec3f(m.transmission.z / m.transmission.w));
    return clamp(t * through * through * dot(m.base_color.rgb * beer, vec3f(1.0 / 3.0)), 0.0, 1.0);
}

const NO_TEXTURE: u32 = 0xffffffffu;
