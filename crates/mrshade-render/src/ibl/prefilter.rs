//! GGX-prefiltered radiance for the split-sum approximation (Karis 2013, with n = v = r),
//! by filtered importance sampling.

use super::pyramid::EquirectPyramid;
use glam::{Vec2, Vec3};
use mrshade_core::HdrImage;
use mrshade_core::brdf::{ggx_d, hammersley, sample_ggx_half_vector};
use mrshade_core::math::dir_from_equirect_uv;
use std::f32::consts::PI;

/// Samples per texel of each rough level.
const SAMPLES: u32 = 256;

/// `levels` images; level k has roughness `k / (levels − 1)` and is `2^k` times smaller
/// than level 0 of `pyramid` (level 0 is the unfiltered mirror image).
pub fn prefiltered_radiance(pyramid: &EquirectPyramid, levels: u32) -> Vec<HdrImage> {
    let base = &pyramid.levels[0];
    let texel_solid_angle = 4.0 * PI / (base.width * base.height) as f32;
    let mut out = vec![base.clone()];
    for level in 1..levels {
        let roughness = level as f32 / (levels - 1) as f32;
        let (w, h) = ((base.width >> level).max(2), (base.height >> level).max(1));
        out.push(filter_level(pyramid, w, h, roughness, texel_solid_angle));
    }
    out
}

fn filter_level(pyramid: &EquirectPyramid, w: u32, h: u32, roughness: f32, texel_solid_angle: f32) -> HdrImage {
    let alpha = roughness * roughness;
    let samples: Vec<Vec2> = (0..SAMPLES).map(|i| hammersley(i, SAMPLES)).collect();
    let mut pixels = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let n = dir_from_equirect_uv(Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32));
            let (t, b) = n.any_orthonormal_pair();
            let mut sum = Vec3::ZERO;
            let mut weight = 0.0;
            for &xi in &samples {
                let hl = sample_ggx_half_vector(xi, alpha);
                let hv = t * hl.x + b * hl.y + n * hl.z;
                let l = 2.0 * n.dot(hv) * hv - n;
                let n_dot_l = n.dot(l);
                if n_dot_l <= 0.0 {
                    continue;
                }
                // pdf of l with n = v: D(h)/4. Read the pyramid where one texel covers the
                // sample's share of the lobe.
                let pdf = ggx_d(hl.z, alpha) / 4.0;
                let sample_solid_angle = 1.0 / (SAMPLES as f32 * pdf.max(1e-8));
                let lod = (0.5 * (sample_solid_angle / texel_solid_angle).log2() + 1.0).max(0.0);
                sum += pyramid.sample(l, lod) * n_dot_l;
                weight += n_dot_l;
            }
            pixels.push((sum / weight.max(1e-8)).to_array());
        }
    }
    HdrImage { width: w, height: h, pixels }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_constant_probe_stays_constant_at_every_roughness() {
        let img = HdrImage::filled(64, 32, [2.0, 1.0, 0.5]);
        let p = EquirectPyramid::new(&img);
        for level in prefiltered_radiance(&p, 4) {
            for px in &level.pixels {
                assert!((Vec3::from(*px) - Vec3::new(2.0, 1.0, 0.5)).abs().max_element() < 1e-3);
            }
        }
    }

    #[test]
    fn a_sun_spreads_without_losing_its_peak_direction() {
        let mut img = HdrImage::filled(128, 64, [0.0; 3]);
        // A bright texel on the horizon at u = 0.5 (direction +Z).
        img.pixels[32 * 128 + 64] = [1000.0; 3];
        let p = EquirectPyramid::new(&img);
        let levels = prefiltered_radiance(&p, 4);
        let rough = &levels[2];
        let at = |d: Vec3| {
            let uv = mrshade_core::math::equirect_uv_from_dir(d);
            rough.get((uv.x * rough.width as f32) as u32, (uv.y * rough.height as f32) as u32)[0]
        };
        assert!(at(Vec3::Z) > at(Vec3::new(0.5, 0.0, 0.87).normalize()));
        assert!(at(Vec3::NEG_Z) < 1e-3);
    }
}
