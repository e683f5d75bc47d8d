//! Importance sampling of the real probe (Knecht §2.2, §5.2.7): a luminance pyramid of the
//! equirectangular probe, descended by hierarchical sample warping (Clarberg et al. 2005)
//! on the GPU to place the environment VPLs. Importance is luminance × solid angle, so every
//! environment VPL carries about the same power: a sun or lamp of ~3700 gets many VPLs of
//! ordinary flux instead of one firefly.

use glam::{Vec2, Vec3};
use mrshade_core::HdrImage;
use mrshade_core::color::luminance;
use mrshade_core::math::{dir_from_equirect_uv, equirect_texel_solid_angle};

/// Width of the finest level (the probe is box-filtered to `WIDTH × WIDTH/2`).
pub const WIDTH: u32 = 256;

/// The pyramid and the radiance of its finest level.
pub struct ProbePyramid {
    /// Finest level size.
    pub width: u32,
    /// Finest level height.
    pub height: u32,
    /// Importance of every level, finest first, each row-major; the last level is 2×1.
    pub importance: Vec<f32>,
    /// Start of each level in `importance`.
    pub offsets: Vec<u32>,
    /// Linear radiance of the finest level (rgb, w unused).
    pub radiance: Vec<[f32; 4]>,
}

impl ProbePyramid {
    /// Builds the pyramid of `probe`.
    pub fn new(probe: &HdrImage) -> Self {
        let (width, height) = (WIDTH, WIDTH / 2);
        let base = probe.resized(width, height);
        let mut levels: Vec<Vec<f32>> = vec![
            (0..height)
                .flat_map(|y| {
                    let dw = equirect_texel_solid_angle(y, width, height);
                    let base = &base;
                    (0..width).map(move |x| luminance(base.get(x, y)).max(0.0) * dw)
                })
                .collect(),
        ];
        let (mut w, mut h) = (width, height);
        while h > 1 {
            let prev = levels.last().expect("level");
            let (nw, nh) = (w / 2, h / 2);
            let next = (0..nh)
                .flat_map(|y| {
                    (0..nw).map(move |x| {
                        let at = |dx: u32, dy: u32| prev[((2 * y + dy) * w + 2 * x + dx) as usize];
                        at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1)
                    })
                })
                .collect();
            levels.push(next);
            (w, h) = (nw, nh);
        }
        let mut offsets = Vec::new();
        let mut importance = Vec::new();
        for l in &levels {
            offsets.push(importance.len() as u32);
            importance.extend_from_slice(l);
        }
        let radiance = base.pixels.iter().map(|p| [p[0], p[1], p[2], 0.0]).collect();
        Self { width, height, importance, offsets, radiance }
    }

    /// Total importance (the 2×1 top level summed).
    pub fn total(&self) -> f32 {
        let top = *self.offsets.last().expect("levels") as usize;
        self.importance[top] + self.importance[top + 1]
    }

    /// The CPU twin of the GPU warp: maps `u ∈ [0,1)²` to a finest-level texel and the
    /// remaining `u` inside it, with the texel's probability.
    pub fn warp(&self, mut u: Vec2) -> (u32, u32, Vec2, f32) {
        let levels = self.offsets.len();
        let imp = |level: usize, x: u32, y: u32| {
            let w = self.width >> level;
            self.importance[self.offsets[level] as usize + (y * w + x) as usize]
        };
        // Top level: two cells side by side.
        let (l, r) = (imp(levels - 1, 0, 0), imp(levels - 1, 1, 0));
        let (mut x, mut y) = if u.x * (l + r) < l {
            u.x = (u.x * (l + r) / l.max(1e-30)).min(0.999_999);
            (0u32, 0u32)
        } else {
            u.x = ((u.x * (l + r) - l) / r.max(1e-30)).min(0.999_999);
            (1, 0)
        };
        for level in (0..levels - 1).rev() {
            let (x0, y0) = (2 * x, 2 * y);
            let (a, b, c, d) =
                (imp(level, x0, y0), imp(level, x0 + 1, y0), imp(level, x0, y0 + 1), imp(level, x0 + 1, y0 + 1));
            let left = a + c;
            let total = left + b + d;
            let column = if u.x * total < left {
                u.x = (u.x * total / left.max(1e-30)).min(0.999_999);
                0
            } else {
                u.x = ((u.x * total - left) / (b + d).max(1e-30)).min(0.999_999);
                1
            };
            let (top, bottom) = if column == 0 { (a, c) } else { (b, d) };
            let row = if u.y * (top + bottom) < top {
                u.y = (u.y * (top + bottom) / top.max(1e-30)).min(0.999_999);
                0
            } else {
                u.y = ((u.y * (top + bottom) - top) / bottom.max(1e-30)).min(0.999_999);
                1
            };
            (x, y) = (x0 + column, y0 + row);
        }
        (x, y, u, imp(0, x, y) / self.total())
    }

    /// Direction (probe space) of texel (x, y) at offset `u` inside it.
    pub fn direction(&self, x: u32, y: u32, u: Vec2) -> Vec3 {
        dir_from_equirect_uv(Vec2::new((x as f32 + u.x) / self.width as f32, (y as f32 + u.y) / self.height as f32))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrshade_core::brdf::hammersley;

    #[test]
    fn a_sun_gets_samples_in_proportion_to_its_power() {
        // A uniform sky of radiance 1 and a sun texel holding as much power as the whole sky.
        let mut img = HdrImage::filled(256, 128, [1.0; 3]);
        let sun_solid_angle = equirect_texel_solid_angle(40, 256, 128);
        let sky = 4.0 * std::f32::consts::PI;
        img.pixels[(40 * 256 + 100) as usize] = [sky / sun_solid_angle; 3];
        let p = ProbePyramid::new(&img);
        let n = 4096;
        let hits = (0..n)
            .filter(|&i| {
                let (x, y, _, _) = p.warp(hammersley(i, n));
                (x, y) == (100, 40)
            })
            .count();
        assert!((hits as f32 / n as f32 - 0.5).abs() < 0.02, "{hits}");
    }

    #[test]
    fn the_estimator_of_irradiance_is_unbiased_for_a_uniform_sky() {
        // E on an upward surface from a sky of radiance 1 over the upper hemisphere = π.
        let mut img = HdrImage::filled(256, 128, [0.0; 3]);
        for y in 0..64 {
            for x in 0..256 {
                img.pixels[(y * 256 + x) as usize] = [1.0; 3];
            }
        }
        let p = ProbePyramid::new(&img);
        let n = 8192;
        let mut e = 0.0f64;
        for i in 0..n {
            let (x, y, u, pdf_texel) = p.warp(hammersley(i, n));
            let dir = p.direction(x, y, u);
            let solid_angle = equirect_texel_solid_angle(y, p.width, p.height);
            let l = p.radiance[(y * p.width + x) as usize][0];
            e += (l * solid_angle / pdf_texel * dir.y.max(0.0)) as f64 / n as f64;
        }
        assert!((e - std::f64::consts::PI).abs() < 0.05, "{e}");
    }
}
