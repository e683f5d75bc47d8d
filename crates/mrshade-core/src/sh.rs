//! Real spherical harmonics of bands 0–2 (Franke §2.0.3, Eq. 4.5–4.7; Ramamoorthi & Hanrahan
//! 2001), and band 3 for 16-coefficient PRT (spec §2.4): the basis in Cartesian form, the
//! zonal coefficients of the clamped cosine, the projection of an equirectangular probe and
//! the irradiance it reconstructs (spec §2.1).
//! The same constants are in shaders/lib/sh.wgsl (tested equal).

use crate::HdrImage;
use crate::math::{dir_from_equirect_uv, equirect_texel_solid_angle};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// `Y_0^0`.
pub const Y0: f32 = 0.282_094_8;
/// Factor of the band-1 functions (`Y_1^{-1,0,1} = Y1·(y, z, x)`).
pub const Y1: f32 = 0.488_602_5;
/// Factor of `Y_2^{-2}`, `Y_2^{-1}`, `Y_2^1`.
pub const Y2: f32 = 1.092_548_4;
/// Factor of `Y_2^0 = Y20·(3z² − 1)`.
pub const Y20: f32 = 0.315_391_57;
/// Factor of `Y_2^2 = Y22·(x² − y²)`.
pub const Y22: f32 = 0.546_274_2;

/// Zonal coefficients `Â_l` of the clamped cosine `max(0, cos θ)` per band (RH01: π, 2π/3,
/// π/4): irradiance is `Σ Â_l c_lm Y_lm(n)` for radiance coefficients `c_lm`.
pub const CLAMPED_COSINE: [f32; 3] = [PI, 2.0 * PI / 3.0, PI / 4.0];

/// Band of coefficient `i` (`i = l(l+1) + m`, Eq. 4.7).
pub fn band(i: usize) -> usize {
    (i as f32).sqrt() as usize
}

/// The nine basis functions at unit direction `d`, in the order `i = l(l+1) + m`.
pub fn basis9(d: Vec3) -> [f32; 9] {
    let (x, y, z) = (d.x, d.y, d.z);
    [Y0, Y1 * y, Y1 * z, Y1 * x, Y2 * x * y, Y2 * y * z, Y20 * (3.0 * z * z - 1.0), Y2 * x * z, Y22 * (x * x - y * y)]
}

/// Factors of band 3 (Sloan 2008): `Y_3^{±3}`, `Y_3^{-2}`, `Y_3^{±1}`, `Y_3^0`; `Y_3^2` is
/// [`Y32`].
pub const Y3: [f32; 4] = [0.590_043_6, 2.890_611_4, 0.457_045_8, 0.373_176_3];
/// Factor of `Y_3^2 = Y32·z(x² − y²)`.
pub const Y32: f32 = 1.445_305_7;

/// The sixteen basis functions of bands 0–3 at unit direction `d`, in the order
/// `i = l(l+1) + m` (the first nine are [`basis9`]'s).
pub fn basis16(d: Vec3) -> [f32; 16] {
    let (x, y, z) = (d.x, d.y, d.z);
    let z2 = z * z;
    let band3 = [
        Y3[0] * y * (3.0 * x * x - y * y),
        Y3[1] * x * y * z,
        Y3[2] * y * (5.0 * z2 - 1.0),
        Y3[3] * z * (5.0 * z2 - 3.0),
        Y3[2] * x * (5.0 * z2 - 1.0),
        Y32 * z * (x * x - y * y),
        Y3[0] * x * (x * x - 3.0 * y * y),
    ];
    let b = basis9(d);
    std::array::from_fn(|i| if i < 9 { b[i] } else { band3[i - 9] })
}

/// `c_i = Σ L(t) y_i(ω_t) dω_t` of the equirectangular radiance `image` over every texel, for
/// the `N` functions of `basis`.
pub fn project_equirect<const N: usize>(image: &HdrImage, basis: fn(Vec3) -> [f32; N]) -> [Vec3; N] {
    let mut c = [Vec3::ZERO; N];
    for y in 0..image.height {
        let dw = equirect_texel_solid_angle(y, image.width, image.height);
        for x in 0..image.width {
            let uv = Vec2::new((x as f32 + 0.5) / image.width as f32, (y as f32 + 0.5) / image.height as f32);
            let l = Vec3::from(image.get(x, y)) * dw;
            for (ci, yi) in c.iter_mut().zip(basis(dir_from_equirect_uv(uv))) {
                *ci += l * yi;
            }
        }
    }
    c
}

/// Coefficients of a radiance function in bands 0–2, per color channel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sh9(pub [Vec3; 9]);

impl Sh9 {
    /// Projects the equirectangular radiance `image` (the data contract's mapping, as stored:
    /// rotation and intensity apply at lookup): `c_i = Σ L(t) y_i(ω_t) dω_t` over every texel
    /// (Eq. 4.8 by summation instead of Monte Carlo).
    pub fn project_equirect(image: &HdrImage) -> Self {
        Self(project_equirect(image, basis9))
    }

    /// Radiance reconstructed in direction `d` (Eq. 4.9).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        self.0.iter().zip(basis9(d)).map(|(c, y)| *c * y).sum()
    }

    /// Irradiance `∫ L(ω) max(0, n·ω) dω` on a surface of unit normal `n`.
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        self.0.iter().zip(basis9(n)).enumerate().map(|(i, (c, y))| *c * (CLAMPED_COSINE[band(i)] * y)).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image_of(f: impl Fn(Vec3) -> Vec3, width: u32) -> HdrImage {
        let height = width / 2;
        let mut pixels = Vec::new();
        for y in 0..height {
            for x in 0..width {
                let uv = Vec2::new((x as f32 + 0.5) / width as f32, (y as f32 + 0.5) / height as f32);
                pixels.push(f(dir_from_equirect_uv(uv)).to_array());
            }
        }
        HdrImage { width, height, pixels }
    }

    #[test]
    fn the_basis_is_orthonormal() {
        let n = 256;
        let mut gram = [[0.0f64; 16]; 16];
        for y in 0..n / 2 {
            let dw = equirect_texel_solid_angle(y, n, n / 2) as f64;
            for x in 0..n {
                let d = dir_from_equirect_uv(Vec2::new((x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / (n / 2) as f32));
                let b = basis16(d);
                assert_eq!(b[..9], basis9(d));
                for i in 0..16 {
                    for j in 0..16 {
                        gram[i][j] += (b[i] * b[j]) as f64 * dw;
                    }
                }
            }
        }
        for (i, row) in gram.iter().enumerate() {
            for (j, g) in row.iter().enumerate() {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((g - want).abs() < 2e-3, "<y{i}, y{j}> = {g}");
            }
        }
    }

    #[test]
    fn a_constant_projects_onto_band_zero_only() {
        // ∫ c·Y0 dω = c·Y0·4π = c·2√π.
        let sh = Sh9::project_equirect(&HdrImage::filled(512, 256, [1.0, 2.0, 3.0]));
        let want = 2.0 * PI.sqrt();
        assert!((sh.0[0] - Vec3::new(1.0, 2.0, 3.0) * want).abs().max_element() < 1e-3, "{:?}", sh.0[0]);
        for c in &sh.0[1..] {
            assert!(c.abs().max_element() < 1e-3, "{c:?}");
        }
        // and its irradiance is π·c on every normal.
        for n in [Vec3::X, Vec3::NEG_Y, Vec3::new(0.6, 0.0, 0.8)] {
            assert!((sh.irradiance(n) - Vec3::new(PI, 2.0 * PI, 3.0 * PI)).abs().max_element() < 2e-3);
        }
    }

    #[test]
    fn a_cosine_lobe_has_the_closed_form_zonal_coefficients() {
        // max(0, cos θ) about +z: c_l0 = Â_l·Y_l0(z) (RH01): π·Y0, 2π/3·Y1, π/4·2·Y20; the
        // others vanish.
        let sh = Sh9::project_equirect(&image_of(|d| Vec3::splat(d.z.max(0.0)), 512));
        let want = [PI * Y0, 0.0, 2.0 * PI / 3.0 * Y1, 0.0, 0.0, 0.0, PI / 4.0 * 2.0 * Y20, 0.0, 0.0];
        for (i, (c, w)) in sh.0.iter().zip(want).enumerate() {
            assert!((c.x - w).abs() < 2e-3, "c{i} = {} want {w}", c.x);
        }
    }

    #[test]
    fn irradiance_of_a_band_limited_probe_matches_direct_summation() {
        // A probe of bands 0–2 only: SH irradiance is exact, so it must equal ∫ L max(0, n·ω)
        // summed texel by texel.
        let f = |d: Vec3| Vec3::new(1.0 + 0.5 * d.y, 0.8 + 0.3 * d.x * d.z, 0.5 + 0.4 * d.y * d.y);
        let image = image_of(f, 256);
        let sh = Sh9::project_equirect(&image);
        for n in [Vec3::Y, Vec3::NEG_Y, Vec3::X, Vec3::new(0.0, 0.6, -0.8), Vec3::new(0.48, 0.6, 0.64)] {
            let mut direct = Vec3::ZERO;
            for y in 0..image.height {
                let dw = equirect_texel_solid_angle(y, image.width, image.height);
                for x in 0..image.width {
                    let uv = Vec2::new((x as f32 + 0.5) / 256.0, (y as f32 + 0.5) / 128.0);
                    let d = dir_from_equirect_uv(uv);
                    direct += Vec3::from(image.get(x, y)) * n.dot(d).max(0.0) * dw;
                }
            }
            let e = sh.irradiance(n);
            assert!((e - direct).abs().max_element() < 5e-3 * direct.max_element(), "{n}: {e} vs {direct}");
        }
    }
}
