//! Irradiance `E(n) = ∫ L(ω) max(0, n·ω) dω` by direct summation over a coarse level of the
//! probe (exact for the Lambertian convolution up to that level's resolution; no spherical-
//! harmonics ringing around bright suns).

use super::pyramid::EquirectPyramid;
use glam::{Vec2, Vec3};
use mrshade_core::HdrImage;
use mrshade_core::math::{dir_from_equirect_uv, equirect_texel_solid_angle};

/// Source texels summed per output texel: the pyramid level at most this wide.
const SOURCE_WIDTH: u32 = 128;

/// The irradiance map, `width × width/2`.
pub fn irradiance_map(pyramid: &EquirectPyramid, width: u32) -> HdrImage {
    let src = pyramid.levels.iter().find(|l| l.width <= SOURCE_WIDTH).unwrap_or(&pyramid.levels[0]);
    let mut texels = Vec::with_capacity((src.width * src.height) as usize);
    for y in 0..src.height {
        let dw = equirect_texel_solid_angle(y, src.width, src.height);
        for x in 0..src.width {
            let uv = Vec2::new((x as f32 + 0.5) / src.width as f32, (y as f32 + 0.5) / src.height as f32);
            texels.push((dir_from_equirect_uv(uv), Vec3::from(src.get(x, y)) * dw));
        }
    }
    let height = width / 2;
    let mut pixels = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let n = dir_from_equirect_uv(Vec2::new((x as f32 + 0.5) / width as f32, (y as f32 + 0.5) / height as f32));
            let e: Vec3 = texels.iter().map(|(d, l)| *l * n.dot(*d).max(0.0)).sum();
            pixels.push(e.to_array());
        }
    }
    HdrImage { width, height, pixels }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    #[test]
    fn a_uniform_probe_gives_pi_times_its_radiance() {
        let p = EquirectPyramid::new(&HdrImage::filled(64, 32, [1.0, 2.0, 3.0]));
        let e = irradiance_map(&p, 16);
        for px in &e.pixels {
            assert!((Vec3::from(*px) - Vec3::new(PI, 2.0 * PI, 3.0 * PI)).abs().max_element() < 0.02, "{px:?}");
        }
    }

    #[test]
    fn upper_hemisphere_sky_lights_the_floor_not_the_ceiling() {
        let mut img = HdrImage::filled(64, 32, [0.0; 3]);
        for y in 0..16 {
            for x in 0..64 {
                img.pixels[y * 64 + x] = [1.0; 3];
            }
        }
        let e = irradiance_map(&EquirectPyramid::new(&img), 16);
        let up = e.get(0, 0)[0];
        let down = e.get(0, 7)[0];
        assert!((up - PI).abs() < 0.05, "{up}");
        assert!(down < 0.05, "{down}");
    }
}
