//! A linear HDR RGB image: photos after decoding, probes, render outputs read back.

/// Linear RGB, row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct HdrImage {
    /// Width in pixels (> 0).
    pub width: u32,
    /// Height in pixels (> 0).
    pub height: u32,
    /// `width * height` pixels.
    pub pixels: Vec<[f32; 3]>,
}

impl HdrImage {
    /// An image filled with one value.
    pub fn filled(width: u32, height: u32, value: [f32; 3]) -> Self {
        Self { width, height, pixels: vec![value; (width * height) as usize] }
    }

    /// The pixel at column `x`, row `y`.
    pub fn get(&self, x: u32, y: u32) -> [f32; 3] {
        self.pixels[(y * self.width + x) as usize]
    }

    /// How many pixels hold NaN or an infinity, and where the first is (`None` if none).
    pub fn non_finite(&self) -> Option<(usize, (u32, u32))> {
        let bad = |p: &[f32; 3]| p.iter().any(|v| !v.is_finite());
        let first = self.pixels.iter().position(bad)?;
        let count = self.pixels.iter().filter(|p| bad(p)).count();
        Some((count, (first as u32 % self.width, first as u32 / self.width)))
    }

    /// Width / height.
    pub fn aspect(&self) -> f32 {
        self.width as f32 / self.height as f32
    }

    /// Resamples to `width × height` with an area (box) filter in linear light, the filter
    /// that keeps a photo's mean radiance when it is shrunk; enlarging falls back to the
    /// nearest source pixel under each target pixel's footprint.
    pub fn resized(&self, width: u32, height: u32) -> HdrImage {
        if width == self.width && height == self.height {
            return self.clone();
        }
        let sx = self.width as f64 / width as f64;
        let sy = self.height as f64 / height as f64;
        let mut pixels = Vec::with_capacity((width * height) as usize);
        for y in 0..height {
            let (y0, y1) = (y as f64 * sy, (y + 1) as f64 * sy);
            for x in 0..width {
                let (x0, x1) = (x as f64 * sx, (x + 1) as f64 * sx);
                pixels.push(self.box_average(x0, x1, y0, y1));
            }
        }
        HdrImage { width, height, pixels }
    }

    /// Mean over the source rectangle `[x0, x1) × [y0, y1)` in pixel units, weighting each
    /// source pixel by its overlap.
    fn box_average(&self, x0: f64, x1: f64, y0: f64, y1: f64) -> [f32; 3] {
        let mut sum = [0.0f64; 3];
        let mut weight = 0.0f64;
        let last_x = (x1.ceil() as u32).min(self.width);
        let last_y = (y1.ceil() as u32).min(self.height);
        for sy in (y0.floor() as u32)..last_y {
            let wy = (y1.min(sy as f64 + 1.0) - y0.max(sy as f64)).max(0.0);
            for sx in (x0.floor() as u32)..last_x {
                let wx = (x1.min(sx as f64 + 1.0) - x0.max(sx as f64)).max(0.0);
                let w = wx * wy;
                let p = self.get(sx, sy);
                for c in 0..3 {
                    sum[c] += w * p[c] as f64;
                }
                weight += w;
            }
        }
        sum.map(|s| (s / weight.max(1e-12)) as f32)
    }

    /// The contract's camera encoding: every channel clamped to [0, 1] and sRGB-encoded to
    /// 8 bits, row-major RGB (what a PNG or JPEG of the image holds).
    pub fn to_srgb8(&self) -> Vec<u8> {
        // By table and in parallel: a 1080p frame of a live stream is 6 M codes.
        use rayon::prelude::*;
        let encoder = crate::color::SrgbEncoder::new();
        let mut out = vec![0u8; self.pixels.len() * 3];
        out.par_chunks_mut(3 * 4096).zip(self.pixels.par_chunks(4096)).for_each(|(out, pixels)| {
            for (o, &v) in out.iter_mut().zip(pixels.iter().flatten()) {
                *o = encoder.encode(v);
            }
        });
        out
    }

    /// Bilinear lookup between texel centres at `(u, v)` ∈ [0, 1]², for equirectangular maps:
    /// u wraps around, v clamps at the poles (the data contract's probe mapping).
    pub fn equirect_bilinear(&self, u: f32, v: f32) -> [f32; 3] {
        let x = u * self.width as f32 - 0.5;
        let y = (v * self.height as f32 - 0.5).clamp(0.0, self.height as f32 - 1.0);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let xi = |dx: i64| (x0 as i64 + dx).rem_euclid(self.width as i64) as u32;
        let yi = |dy: u32| (y0 as u32 + dy).min(self.height - 1);
        let lerp = |a: [f32; 3], b: [f32; 3], t: f32| std::array::from_fn(|c| a[c] + (b[c] - a[c]) * t);
        let top = lerp(self.get(xi(0), yi(0)), self.get(xi(1), yi(0)), fx);
        let bottom = lerp(self.get(xi(0), yi(1)), self.get(xi(1), yi(1)), fx);
        lerp(top, bottom, fy)
    }

    /// Maximum of every channel of every pixel.
    pub fn max_value(&self) -> f32 {
        self.pixels.iter().flatten().fold(0.0f32, |m, &v| m.max(v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb8_clamps_and_encodes_every_channel() {
        let img = HdrImage { width: 2, height: 1, pixels: vec![[0.0, 1.0, 2.0], [0.5, -1.0, f32::NAN]] };
        assert_eq!(img.to_srgb8(), vec![0, 255, 255, 188, 0, 0]);
    }

    #[test]
    fn halving_averages_2x2_blocks() {
        let mut img = HdrImage::filled(4, 2, [0.0; 3]);
        img.pixels[0] = [4.0, 0.0, 0.0];
        let half = img.resized(2, 1);
        assert_eq!(half.pixels[0], [1.0, 0.0, 0.0]);
        assert_eq!(half.pixels[1], [0.0, 0.0, 0.0]);
    }

    #[test]
    fn non_integer_shrink_keeps_the_mean() {
        let img = HdrImage { width: 5, height: 3, pixels: (0..15).map(|i| [i as f32, 1.0, 2.0]).collect() };
        let small = img.resized(3, 2);
        let mean = |im: &HdrImage| im.pixels.iter().map(|p| p[0]).sum::<f32>() / im.pixels.len() as f32;
        assert!((mean(&small) - mean(&img)).abs() < 1e-4);
        assert!(small.pixels.iter().all(|p| (p[1] - 1.0).abs() < 1e-6));
    }
}
