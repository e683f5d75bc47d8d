// Real spherical harmonics of bands 0 and 1, four coefficients (Franke §2.0.3; the constants
// of mrshade_core::sh, tested equal), in the order i = l(l+1) + m: Y0, Y1·y, Y1·z, Y1·x.

const SH_Y0: f32 = 0.2820948;
const SH_Y1: f32 = 0.4886025;

// The basis at unit direction `d`.
fn sh4(d: vec3f) -> vec4f {
    return vec4f(SH_Y0, SH_Y1 * d.y, SH_Y1 * d.z, SH_Y1 * d.x);
}

// Coefficients of the clamped cosine max(0, d·ω) (zonal Â_0 = π, Â_1 = 2π/3).
fn sh4_clamped_cosine(d: vec3f) -> vec4f {
    return vec4f(PI * SH_Y0, 2.0 * PI / 3.0 * SH_Y1 * vec3f(d.y, d.z, d.x));
}
