//! Mipmaps of RGBA8 textures, filtered in linear light for sRGB colour textures.

use mrshade_core::color::{linear_to_srgb_u8, srgb_u8_decode_table};

/// Mip levels `1..` of an RGBA8 image (level 0 not included), each a 2×2 box filter of the
/// previous (odd sides clamp), down to 1×1.
pub fn rgba8_mips(width: u32, height: u32, level0: &[u8], srgb: bool) -> Vec<(u32, u32, Vec<u8>)> {
    let table = srgb_u8_decode_table();
    let decode = |v: u8, channel: usize| if srgb && channel < 3 { table[v as usize] } else { v as f32 / 255.0 };
    let encode = |v: f32, channel: usize| {
        if srgb && channel < 3 { linear_to_srgb_u8(v) } else { (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8 }
    };
    let mut out: Vec<(u32, u32, Vec<u8>)> = Vec::new();
    let (mut w, mut h) = (width, height);
    let mut prev = level0.to_vec();
    while w > 1 || h > 1 {
        let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
        let mut next = vec![0u8; (nw * nh * 4) as usize];
        for y in 0..nh {
            for x in 0..nw {
                for c in 0..4 {
                    let mut sum = 0.0;
                    for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                        let sx = (2 * x + dx).min(w - 1);
                        let sy = (2 * y + dy).min(h - 1);
                        sum += decode(prev[((sy * w + sx) * 4) as usize + c], c);
                    }
                    next[((y * nw + x) * 4) as usize + c] = encode(sum / 4.0, c);
                }
            }
        }
        out.push((nw, nh, next.clone()));
        prev = next;
        (w, h) = (nw, nh);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_mips_average_in_linear_light() {
        // Black and white texels average to linear 0.5, which is sRGB code 188, not 128.
        let level0 = [0, 0, 0, 255, 255, 255, 255, 255];
        let mips = rgba8_mips(2, 1, &level0, true);
        assert_eq!(mips.len(), 1);
        assert_eq!(&mips[0].2[..4], &[188, 188, 188, 255]);
        let linear = rgba8_mips(2, 1, &level0, false);
        assert_eq!(&linear[0].2[..3], &[128, 128, 128]);
    }
}
