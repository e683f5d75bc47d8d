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

const NO_TEXTURE: u32 = 0xffffffffu;
