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

// Band 2's first four functions (coefficients 4–7) at unit direction `d`.
fn sh9_band2(d: vec3f) -> vec4f {
    return vec4f(
        1.0925484 * d.x * d.y,
        1.0925484 * d.y * d.z,
        0.31539157 * (3.0 * d.z * d.z - 1.0),
        1.0925484 * d.x * d.z,
    );
}

// Band 2's last function (coefficient 8).
fn sh9_y8(d: vec3f) -> f32 {
    return 0.5462742 * (d.x * d.x - d.y * d.y);
}

// Bands 0–2, nine functions (mrshade_core::sh::basis9).
fn sh9(d: vec3f) -> array<f32, 9> {
    let b = sh9_band2(d);
    return array<f32, 9>(SH_Y0, SH_Y1 * d.y, SH_Y1 * d.z, SH_Y1 * d.x, b.x, b.y, b.z, b.w, sh9_y8(d));
}

// Bands 0–3, sixteen functions (mrshade_core::sh::basis16): 16-coefficient PRT.
fn sh16(d: vec3f) -> array<f32, 16> {
    let b = sh9(d);
    let z2 = d.z * d.z;
    return array<f32, 16>(
        b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7], b[8],
        0.5900436 * d.y * (3.0 * d.x * d.x - d.y * d.y),
        2.8906114 * d.x * d.y * d.z,
        0.4570458 * d.y * (5.0 * z2 - 1.0),
        0.3731763 * d.z * (5.0 * z2 - 3.0),
        0.4570458 * d.x * (5.0 * z2 - 1.0),
        1.4453057 * d.z * (d.x * d.x - d.y * d.y),
        0.5900436 * d.x * (d.x * d.x - 3.0 * d.y * d.y),
    );
}

// Zonal coefficient Â_l of the clamped cosine for coefficient `i` (π, 2π/3, π/4 by band).
fn sh9_clamped_cosine_band(i: u32) -> f32 {
    if (i == 0u) { return PI; }
    if (i < 4u) { return 2.0 * PI / 3.0; }
    return PI / 4.0;
}
