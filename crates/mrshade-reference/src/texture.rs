//! Bilinear texture lookups on the CPU, with the glTF sampler's wrap modes and sRGB decoding.

use glam::{Vec2, Vec4};
use mrshade_core::color::srgb_to_linear;
use mrshade_scene::{Material, Scene, Texture, TextureRef};

/// The texel value at `uv` (bilinear), linear RGBA: sRGB textures are decoded per texel.
pub fn sample(scene: &Scene, texture: TextureRef, uv: Vec2) -> Vec4 {
    let tex = &scene.textures[texture.texture];
    let x = uv.x * tex.width as f32 - 0.5;
    let y = uv.y * tex.height as f32 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let texel = |dx: i64, dy: i64| {
        let i = wrap(x0 as i64 + dx, tex.width, tex.repeat_u);
        let j = wrap(y0 as i64 + dy, tex.height, tex.repeat_v);
        texel(tex, i, j)
    };
    let top = texel(0, 0) * (1.0 - fx) + texel(1, 0) * fx;
    let bottom = texel(0, 1) * (1.0 - fx) + texel(1, 1) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// The material's base-color alpha at `uv` (for alpha masks).
pub fn sample_alpha(scene: &Scene, material: &Material, uv: Vec2) -> f32 {
    let texel = material.base_color_texture.map_or(1.0, |t| sample(scene, t, uv).w);
    material.base_color.w * texel
}

fn wrap(i: i64, size: u32, repeat: bool) -> u32 {
    let size = size as i64;
    if repeat { i.rem_euclid(size) as u32 } else { i.clamp(0, size - 1) as u32 }
}

fn texel(tex: &Texture, x: u32, y: u32) -> Vec4 {
    let i = ((y * tex.width + x) * 4) as usize;
    let c = &tex.rgba8[i..i + 4];
    let v = |b: u8| b as f32 / 255.0;
    if tex.srgb {
        Vec4::new(srgb_to_linear(v(c[0])), srgb_to_linear(v(c[1])), srgb_to_linear(v(c[2])), v(c[3]))
    } else {
        Vec4::new(v(c[0]), v(c[1]), v(c[2]), v(c[3]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker() -> Scene {
        let mut scene = Scene::default();
        scene.textures.push(Texture {
            name: "t".into(),
            width: 2,
            height: 1,
            rgba8: vec![0, 0, 0, 255, 255, 255, 255, 0],
            srgb: false,
            repeat_u: true,
            repeat_v: false,
        });
        scene
    }

    #[test]
    fn texel_centres_return_texels_and_midpoints_blend() {
        let scene = checker();
        let t = TextureRef { texture: 0 };
        assert!(sample(&scene, t, Vec2::new(0.25, 0.5)).abs_diff_eq(Vec4::new(0.0, 0.0, 0.0, 1.0), 1e-6));
        assert!(sample(&scene, t, Vec2::new(0.75, 0.5)).abs_diff_eq(Vec4::new(1.0, 1.0, 1.0, 0.0), 1e-6));
        assert!(sample(&scene, t, Vec2::new(0.5, 0.5)).abs_diff_eq(Vec4::splat(0.5), 1e-6));
        // Repeat along u: u = 0 blends the last and first texels.
        assert!(sample(&scene, t, Vec2::new(0.0, 0.5)).abs_diff_eq(Vec4::splat(0.5), 1e-6));
    }
}
