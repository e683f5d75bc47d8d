//! The real light probe as an infinitely distant light: radiance lookup with the data
//! contract's mapping (`u = atan2(x, −z)/2π`, `v = acos(y)/π`, rotation about +Y, intensity)
//! and importance sampling proportional to its luminance (piecewise constant over texels,
//! pbrt-v4 §12.5.2), so that sun and lamp pixels of real probes are found by few samples.

use glam::{Mat3, Vec2, Vec3};
use mrshade_core::HdrImage;
use mrshade_core::color::luminance;
use mrshade_core::math::{dir_from_equirect_uv, equirect_uv_from_dir, probe_from_world};
use mrshade_scene::Environment;
use std::f32::consts::PI;

/// A sampled direction toward the probe.
#[derive(Clone, Copy, Debug)]
pub struct EnvSample {
    /// World-space unit direction.
    pub dir: Vec3,
    /// Radiance arriving from it.
    pub radiance: Vec3,
    /// Solid-angle density of having chosen it.
    pub pdf: f32,
}

/// The probe, ready for lookups and sampling.
pub struct EnvironmentLight {
    width: u32,
    height: u32,
    /// Radiance × intensity, row 0 = +Y.
    image: HdrImage,
    probe_from_world: Mat3,
    world_from_probe: Mat3,
    /// Per row: cumulative sums of the sampling weights (length width + 1).
    conditional: Vec<Vec<f32>>,
    /// Cumulative sums of the row totals (length height + 1).
    marginal: Vec<f32>,
}

impl EnvironmentLight {
    /// Prepares `env` for lookups and sampling.
    pub fn new(env: &Environment) -> Self {
        let (width, height) = (env.image.width, env.image.height);
        let image =
            HdrImage { width, height, pixels: env.image.pixels.iter().map(|p| p.map(|c| c * env.intensity)).collect() };
        let lum = |x: i64, y: i64| {
            let x = x.rem_euclid(width as i64) as u32;
            let y = y.clamp(0, height as i64 - 1) as u32;
            luminance(image.get(x, y)).max(0.0)
        };
        let mut conditional = Vec::with_capacity(height as usize);
        let mut marginal = vec![0.0f32];
        for y in 0..height {
            let sin_theta = (PI * (y as f32 + 0.5) / height as f32).sin();
            let mut cdf = vec![0.0f32];
            for x in 0..width {
                // The largest neighbour: bilinear lookups reach one texel around, so every
                // direction with light keeps a non-zero density.
                let mut w = 0.0f32;
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        w = w.max(lum(x as i64 + dx, y as i64 + dy));
                    }
                }
                cdf.push(cdf[x as usize] + w * sin_theta);
            }
            marginal.push(marginal[y as usize] + cdf[width as usize]);
            conditional.push(cdf);
        }
        let probe_from_world = probe_from_world(env.rotation_deg);
        EnvironmentLight {
            width,
            height,
            image,
            probe_from_world,
            world_from_probe: probe_from_world.transpose(),
            conditional,
            marginal,
        }
    }

    /// Radiance arriving from world direction `dir` (bilinear between texel centres).
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        let uv = equirect_uv_from_dir(self.probe_from_world * dir);
        Vec3::from(self.image.equirect_bilinear(uv.x, uv.y))
    }

    /// Whether the probe has any light to sample.
    pub fn is_black(&self) -> bool {
        self.total() <= 0.0
    }

    fn total(&self) -> f32 {
        *self.marginal.last().unwrap_or(&0.0)
    }

    /// A direction drawn with density ∝ luminance, from two uniform numbers.
    pub fn sample(&self, xi: Vec2) -> Option<EnvSample> {
        let total = self.total();
        if total <= 0.0 {
            return None;
        }
        let (y, fy) = pick(&self.marginal, xi.y * total);
        let row = &self.conditional[y];
        let (x, fx) = pick(row, xi.x * row[self.width as usize]);
        let uv = Vec2::new((x as f32 + fx) / self.width as f32, (y as f32 + fy) / self.height as f32);
        let dir = self.world_from_probe * dir_from_equirect_uv(uv);
        let pdf = self.pdf_of_texel(x, y, uv.y);
        (pdf > 0.0).then(|| EnvSample { dir, radiance: self.radiance(dir), pdf })
    }

    /// The solid-angle density with which [`Self::sample`] picks world direction `dir`.
    pub fn pdf(&self, dir: Vec3) -> f32 {
        if self.total() <= 0.0 {
            return 0.0;
        }
        let uv = equirect_uv_from_dir(self.probe_from_world * dir);
        let x = ((uv.x * self.width as f32) as usize).min(self.width as usize - 1);
        let y = ((uv.y * self.height as f32) as usize).min(self.height as usize - 1);
        self.pdf_of_texel(x, y, uv.y)
    }

    /// Density of texel (x, y) per unit solid angle at latitude `v`.
    fn pdf_of_texel(&self, x: usize, y: usize, v: f32) -> f32 {
        let weight = self.conditional[y][x + 1] - self.conditional[y][x];
        // Density over the unit uv square, then the equirectangular Jacobian 2π² sin θ.
        let pdf_uv = weight * (self.width * self.height) as f32 / self.total();
        let sin_theta = (v * PI).sin();
        if sin_theta <= 1e-6 { 0.0 } else { pdf_uv / (2.0 * PI * PI * sin_theta) }
    }
}

/// The bin of `cdf` (cumulative, starting at 0) that contains `value`, and where in it.
fn pick(cdf: &[f32], value: f32) -> (usize, f32) {
    let n = cdf.len() - 1;
    // The last bin whose start is ≤ value, skipping empty bins.
    let mut i = cdf.partition_point(|&c| c <= value).saturating_sub(1).min(n - 1);
    while i > 0 && cdf[i + 1] <= cdf[i] {
        i -= 1;
    }
    while cdf[i + 1] <= cdf[i] && i + 1 < n {
        i += 1;
    }
    let width = cdf[i + 1] - cdf[i];
    let f = if width > 0.0 { ((value - cdf[i]) / width).clamp(0.0, 0.999_999) } else { 0.5 };
    (i, f)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn probe(f: impl Fn(u32, u32) -> [f32; 3], rotation_deg: f32) -> EnvironmentLight {
        let mut image = HdrImage::filled(32, 16, [0.0; 3]);
        for y in 0..16 {
            for x in 0..32 {
                image.pixels[(y * 32 + x) as usize] = f(x, y);
            }
        }
        EnvironmentLight::new(&Environment { image, rotation_deg, intensity: 2.0 })
    }

    #[test]
    fn sampling_density_integrates_to_one_and_matches_pdf() {
        let env = probe(|x, y| [(x + 1) as f32 * (y % 3) as f32, 1.0, 0.5], 30.0);
        // ∫ pdf dω over the sphere by the texel-solid-angle quadrature of a fine grid.
        let (w, h) = (256u32, 128u32);
        let mut integral = 0.0f64;
        for y in 0..h {
            for x in 0..w {
                let uv = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                let d = dir_from_equirect_uv(uv);
                integral += (env.pdf(d) * mrshade_core::math::equirect_texel_solid_angle(y, w, h)) as f64;
            }
        }
        assert!((integral - 1.0).abs() < 0.01, "{integral}");
        for i in 0..64 {
            let xi = Vec2::new((i as f32 + 0.5) / 64.0, ((i * 37 % 64) as f32 + 0.5) / 64.0);
            let s = env.sample(xi).unwrap();
            assert!((s.pdf - env.pdf(s.dir)).abs() <= 1e-3 * s.pdf, "{} {}", s.pdf, env.pdf(s.dir));
        }
    }

    #[test]
    fn lookups_follow_the_contract_with_rotation_and_intensity() {
        // A probe bright only in the columns around u = 0.25 (+X unrotated).
        let env = probe(|x, _| if x == 7 || x == 8 { [1.0; 3] } else { [0.0; 3] }, 90.0);
        // Rotated by +90° about +Y, +X content appears at −Z... (+X rotated right-handed → −Z).
        let at = env.radiance(Vec3::NEG_Z);
        assert!((at.x - 2.0).abs() < 1e-5, "{at}");
        assert!(env.radiance(Vec3::X).x < 1e-6);
    }

    #[test]
    fn a_black_probe_is_not_sampled() {
        let env = probe(|_, _| [0.0; 3], 0.0);
        assert!(env.is_black() && env.sample(Vec2::splat(0.5)).is_none() && env.pdf(Vec3::Y) == 0.0);
    }
}
