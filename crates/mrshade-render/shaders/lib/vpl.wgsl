// Virtual point lights and their flags (Knecht §2.7, §2.8). Mirrors `GpuVpl` in
// src/passes/vpl/mod.rs (checked by a test).

const VPL_EMPTY: u32 = 0u;
// A point on a surface that reflects the light it received (RSM or bounce VPL).
const VPL_SURFACE: u32 = 1u;
// Light from a probe direction: parallel light of irradiance `power` (environment VPL).
const VPL_DIRECTIONAL: u32 = 2u;

// Flag bits (info.x).
// r(VPL): the VPL lies on a real surface.
const VPL_REAL: u32 = 1u;
// ir(VPL): "illuminate real only" (VPL3): real light that a virtual object now blocks.
const VPL_IR: u32 = 2u;
// x̄: every element of the light path so far is real.
const VPL_PATH_REAL: u32 = 4u;
// The VPL's light has been reflected diffusely more than once (the multiple-bounce source):
// its near field is the screen's (nearfield.wgsl), so it is clamped at the wider distance of
// VplShading.d_bounce.
const VPL_BOUNCED: u32 = 8u;

struct Vpl {
    // xyz: world position (surface) or unit direction of propagation (directional);
    // w: the surface area (m²) a surface VPL stands for (its share of the sampled surfaces)
    position: vec4f,
    // xyz: surface normal (on the lit side); w: roughness. Directional: x the solid angle
    // (sr) the VPL stands for.
    normal: vec4f,
    // rgb: incident power Φ_in, W (surface) or irradiance E, W/m² (directional); w: metallic
    power: vec4f,
    // rgb: power of a co-located VPL3 (ir = 1): real light that reaches this real surface in
    // L_r but that virtual content blocks in L_rv; it adds to L_r only. w unused.
    power_ir: vec4f,
    // rgb: base color; w: dielectric F90
    albedo: vec4f,
    // xyz: unit direction toward where the light came from; w: dielectric F0 (mean)
    incoming: vec4f,
    // flags, source index, kind, reflections of the light so far (1 for RSM VPLs, 0 for
    // directional ones)
    info: vec4u,
}

fn vpl_kind(v: Vpl) -> u32 { return v.info.z; }

// The flag rules (Knecht §2.7 Eq. 5.6–5.8, §2.8 Eq. 5.9–5.10): the weights with which a
// surface VPL with `flags` adds its light to (x) L_rv and (y) L_r at a receiver with
// r(p) = `r_p` and visibilities `vis` = (V_r, V_v), and (z) the weight of its co-located
// VPL3's light, which adds to L_r only:
//   L_rv: (1 − ir) · min(V_r, V_v)      L_r: x̄ · r(p) · V_r      VPL3: r(p) · V_r
fn vpl_routing(flags: u32, r_p: f32, vis: vec2f) -> vec3f {
    let ir = select(0.0, 1.0, (flags & VPL_IR) != 0u);
    let path_real = select(0.0, 1.0, (flags & VPL_PATH_REAL) != 0u);
    return vec3f((1.0 - ir) * min(vis.x, vis.y), path_real * r_p * vis.x, r_p * vis.x);
}

// VPLs reflect with at least this roughness. A VPL on a mirror (roughness 0) would otherwise
// emit through a GGX lobe of width ~0: a singularity that a few hundred VPLs turn into
// fireflies on every receiver. Clamping the lobe (the usual remedy for glossy VPLs, Křivánek
// et al. 2010) keeps the VPL's energy and spreads it over a lobe the VPL count can sample.
// At 0.3 the desk under desk-mirror's sphere still showed 4×4 blocks of one VPL's light
// (region FLIP 0.127 → 0.122 at 0.6).
const VPL_MIN_ROUGHNESS: f32 = 0.6;

// The BRDF of the surface under a surface VPL, "seen" from its incoming light direction.
fn vpl_surface(v: Vpl) -> Surface {
    var s: Surface;
    s.position = v.position.xyz;
    s.normal = v.normal.xyz;
    s.view = v.incoming.xyz;
    s.base_color = v.albedo.rgb;
    s.metallic = v.power.w;
    s.roughness = max(v.normal.w, VPL_MIN_ROUGHNESS);
    s.dielectric_f0 = vec3f(v.incoming.w);
    s.dielectric_f90 = v.albedo.w;
    s.transmission = 0.0;
    s.emission = vec3f(0.0);
    s.occlusion = 1.0;
    return s;
}

// f_r(in, out) · cos of a surface VPL toward unit direction `out` (times a power: intensity).
fn vpl_emission(v: Vpl, out: vec3f) -> vec3f {
    return brdf_cos(vpl_surface(v), out);
}

// Radiant intensity of a surface VPL toward unit direction `out`: Φ_in · f_r(in, out) · cos.
fn vpl_intensity(v: Vpl, out: vec3f) -> vec3f {
    return v.power.rgb * vpl_emission(v, out);
}
