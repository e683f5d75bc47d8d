//! A box-filtered mip pyramid of an equirectangular map, averaged with solid-angle weights
//! so every level keeps the probe's power, and sampled bilinearly/trilinearly with the
//! contract's wrap in u and clamp in v.

use glam::Vec3;
use mrshade_core::HdrImage;
use mrshade_core::math::{equirect_texel_solid_angle, equirect_uv_from_dir};

/// Level 0 is the input; level k is `2^k` times smaller, down to 2×1.
pub struct EquirectPyramid {
    /// The levels.
    pub levels: Vec<HdrImage>,
}

impl EquirectPyramid {
    /// Builds the pyramid of `base` (width must be twice the height).
    pub fn new(base: &HdrImage) -> Self {
        let mut levels = vec![base.clone()];
        while levels.last().is_some_and(|l| l.height >= 2 && l.width >= 4) {
            levels.push(downsample(levels.last().expect("non-empty")));
        }
        Self { levels }
    }

    /// Bilinear lookup in level `level` at `(u, v)` ∈ [0, 1)², u wrapping.
    pub fn bilinear(&self, level: usize, u: f32, v: f32) -> Vec3 {
        Vec3::from(self.levels[level.min(self.levels.len() - 1)].equirect_bilinear(u, v))
    }

    /// Trilinear lookup of direction `d` at fractional level `lod`.
    pub fn sample(&self, d: Vec3, lod: f32) -> Vec3 {
        let uv = equirect_uv_from_dir(d);
        let lod = lod.clamp(0.0, (self.levels.len() - 1) as f32);
        let l0 = lod.floor() as usize;
        let t = lod - l0 as f32;
        let a = self.bilinear(l0, uv.x, uv.y);
        if t == 0.0 { a } else { a.lerp(self.bilinear(l0 + 1, uv.x, uv.y), t) }
    }
}

/// Halves an equirectangular image, weighting each source texel by its solid angle.
fn downsample(src: &HdrImage) -> HdrImage {
    let (w, h) = (src.width / 2, src.height / 2);
    let mut pixels = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        let wa = equirect_texel_solid_angle(2 * y, src.width, src.height);
        let wb = equirect_texel_solid_angle(2 * y + 1, src.width, src.height);
        for x in 0..w {
            let mut sum = Vec3::ZERO;
            for (dy, wy) in [(0, wa), (1, wb)] {
                for dx in 0..2 {
                    sum += Vec3::from(src.get(2 * x + dx, 2 * y + dy)) * wy;
                }
            }
            pixels.push((sum / (2.0 * (wa + wb))).to_array());
        }
    }
    HdrImage { width: w, height: h, pixels }
}

/// Power of an equirectangular map: Σ L · dΩ (per channel).
#[cfg(test)]
pub fn power(img: &HdrImage) -> Vec3 {
    let mut sum = Vec3::ZERO;
    for y in 0..img.height {
        let dw = equirect_texel_solid_angle(y, img.width, img.height);
        for x in 0..img.width {
            sum += Vec3::from(img.get(x, y)) * dw;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_level_keeps_the_power() {
        let mut img = HdrImage::filled(64, 32, [0.1, 0.2, 0.3]);
        img.pixels[5 * 64 + 7] = [3700.0, 100.0, 1.0];
        let p = EquirectPyramid::new(&img);
        let p0 = power(&p.levels[0]);
        for level in &p.levels {
            assert!((power(level) - p0).abs().max_element() < 1e-3 * p0.max_element(), "{:?}", power(level));
        }
        assert_eq!(p.levels.last().map(|l| (l.width, l.height)), Some((2, 1)));
    }

    #[test]
    fn bilinear_wraps_in_u() {
        let mut img = HdrImage::filled(4, 2, [0.0; 3]);
        img.pixels[0] = [1.0, 1.0, 1.0];
        img.pixels[4] = [1.0, 1.0, 1.0];
        let p = EquirectPyramid::new(&img);
        // Exactly between the last and the first column.
        assert!((p.bilinear(0, 0.0, 0.5).x - 0.5).abs() < 1e-6);
    }
}
