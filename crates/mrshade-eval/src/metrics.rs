//! Image metrics between two 8-bit sRGB images of the same size: LDR FLIP (NVIDIA ꟻLIP,
//! default viewing conditions, the benchmark's metric), PSNR and RMSE of the [0, 1]-scaled
//! values, and SSIM (Wang et al. 2004: 11×11 Gaussian window with σ = 1.5, K1 = 0.01,
//! K2 = 0.03, per channel, averaged). With a mask, every score is a mean over its pixels.
//!
//! FLIP comes twice: the mean FLIP error (what FLIP's own tools report), and the mean of
//! FLIP's magma heat map over its three channels (in [0, 1]), which is what the team's
//! scorer (`shared/tools/score.py`, flip-evaluator with its default `applyMagma=True`) and so
//! the scores of `shared/data/scenes/CALIBRATION.md` are. The second is a monotone but
//! nonlinear function of the error (4/765 for identical images); only it can be put beside
//! those tables.

/// Largest image `compare` and `eval` score by default: FLIP holds about 120 bytes per pixel
/// (126 MB measured at 1024 × 1024), so 16 Mi pixels (4096 × 4096) take about 2 GiB.
pub const DEFAULT_MAX_PIXELS: u64 = 1 << 24;

/// An RGB8 image, row-major.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rgb8 {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height × 3` bytes.
    pub rgb: Vec<u8>,
}

/// The scores of `test` against `reference`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scores {
    /// Mean FLIP error (0: identical, 1: most different).
    pub flip: f64,
    /// Mean of FLIP's magma heat map (channels in [0, 1]): the benchmark scorer's "FLIP".
    pub flip_heatmap_mean: f64,
    /// Peak signal-to-noise ratio (dB) of the [0, 1] values; infinite for identical images.
    pub psnr: f64,
    /// Root mean square error of the [0, 1] values.
    pub rmse: f64,
    /// Mean structural similarity (1: identical).
    pub ssim: f64,
    /// Pixels scored.
    pub pixels: usize,
}

/// The per-pixel errors of `test` against `reference`, computed once; [`Comparison::scores`]
/// averages them over the whole image or a mask (the frame and the changed region of one
/// result need one FLIP and one SSIM evaluation, not two).
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// FLIP's error map as a magma heat map (RGB8, the whole image), as FLIP's own tool shows it.
    pub heatmap: Rgb8,
    /// Squared error of the [0, 1] values, mean over channels.
    squared: Vec<f32>,
    /// FLIP error.
    flip: Vec<f32>,
    /// The heat map's value, mean over channels, in [0, 1].
    heat: Vec<f32>,
    /// SSIM, mean over channels.
    ssim: Vec<f32>,
}

/// Compares `test` with `reference` pixel by pixel. Errors name what does not fit.
pub fn compare(reference: &Rgb8, test: &Rgb8) -> Result<Comparison, String> {
    let (w, h) = (reference.width, reference.height);
    if (test.width, test.height) != (w, h) {
        return Err(format!("the images differ in size: {w}×{h} and {}×{}", test.width, test.height));
    }
    let n = (w * h) as usize;
    if reference.rgb.len() != 3 * n || test.rgb.len() != 3 * n {
        return Err("image data does not match its size".into());
    }
    let squared = reference
        .rgb
        .chunks_exact(3)
        .zip(test.rgb.chunks_exact(3))
        .map(|(a, b)| a.iter().zip(b).map(|(x, y)| ((*x as f32 - *y as f32) / 255.0).powi(2)).sum::<f32>() / 3.0)
        .collect();
    let r = nv_flip::FlipImageRgb8::with_data(w, h, &reference.rgb);
    let t = nv_flip::FlipImageRgb8::with_data(w, h, &test.rgb);
    let flip = nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let heatmap = Rgb8 { width: w, height: h, rgb: flip.apply_color_lut(&nv_flip::magma_lut()).to_vec() };
    let heat = heatmap.rgb.chunks_exact(3).map(|p| p.iter().map(|&c| c as f32).sum::<f32>() / 765.0).collect();
    Ok(Comparison { heatmap, squared, flip: flip.to_vec(), heat, ssim: ssim_map(reference, test) })
}

impl Comparison {
    /// The scores over `mask` (row-major, one flag per pixel; `None`: every pixel). Errors
    /// name what does not fit: the mask's size, an empty mask.
    pub fn scores(&self, mask: Option<&[bool]>) -> Result<Scores, String> {
        let n = self.squared.len();
        if let Some(m) = mask.filter(|m| m.len() != n) {
            return Err(format!("the mask has {} pixels, the images {n}", m.len()));
        }
        let inside = |i: usize| mask.is_none_or(|m| m[i]);
        let pixels = (0..n).filter(|&i| inside(i)).count();
        if pixels == 0 {
            return Err("the mask selects no pixel".into());
        }
        let mean =
            |values: &[f32]| (0..n).filter(|&i| inside(i)).map(|i| values[i] as f64).sum::<f64>() / pixels as f64;
        let mse = mean(&self.squared);
        Ok(Scores {
            flip: mean(&self.flip),
            flip_heatmap_mean: mean(&self.heat),
            psnr: if mse == 0.0 { f64::INFINITY } else { -10.0 * mse.log10() },
            rmse: mse.sqrt(),
            ssim: mean(&self.ssim),
            pixels,
        })
    }
}

/// Half-width of SSIM's Gaussian window (11×11).
const SSIM_RADIUS: i64 = 5;
/// σ of SSIM's Gaussian window, in pixels.
const SSIM_SIGMA: f64 = 1.5;
/// SSIM's stabilising constants for a dynamic range of 1: (0.01)², (0.03)².
const SSIM_C1: f64 = 0.01 * 0.01;
const SSIM_C2: f64 = 0.03 * 0.03;

/// The SSIM of every pixel (mean over the three channels). The window is clamped at the
/// image's edges (edge pixels repeat), so every pixel has a value.
pub fn ssim_map(reference: &Rgb8, test: &Rgb8) -> Vec<f32> {
    let (w, h) = (reference.width as i64, reference.height as i64);
    let taps: Vec<f64> =
        (-SSIM_RADIUS..=SSIM_RADIUS).map(|d| (-(d * d) as f64 / (2.0 * SSIM_SIGMA * SSIM_SIGMA)).exp()).collect();
    let norm: f64 = taps.iter().sum();
    let taps: Vec<f64> = taps.iter().map(|t| t / norm).collect();
    let mut out = vec![0.0f32; (w * h) as usize];
    for c in 0..3 {
        let channel = |img: &Rgb8| -> Vec<f64> { img.rgb.chunks_exact(3).map(|p| p[c] as f64 / 255.0).collect() };
        let (x, y) = (channel(reference), channel(test));
        let xx: Vec<f64> = x.iter().map(|v| v * v).collect();
        let yy: Vec<f64> = y.iter().map(|v| v * v).collect();
        let xy: Vec<f64> = x.iter().zip(&y).map(|(a, b)| a * b).collect();
        let [mx, my, sxx, syy, sxy] = [&x, &y, &xx, &yy, &xy].map(|v| gaussian_blur(v, w, h, &taps));
        for i in 0..out.len() {
            let (vx, vy, cov) = (sxx[i] - mx[i] * mx[i], syy[i] - my[i] * my[i], sxy[i] - mx[i] * my[i]);
            let s = ((2.0 * mx[i] * my[i] + SSIM_C1) * (2.0 * cov + SSIM_C2))
                / ((mx[i] * mx[i] + my[i] * my[i] + SSIM_C1) * (vx + vy + SSIM_C2));
            out[i] += (s / 3.0) as f32;
        }
    }
    out
}

/// Separable blur of a `w × h` plane with normalised `taps`, edges clamped.
fn gaussian_blur(v: &[f64], w: i64, h: i64, taps: &[f64]) -> Vec<f64> {
    let r = (taps.len() / 2) as i64;
    let mut rows = vec![0.0; v.len()];
    for y in 0..h {
        for x in 0..w {
            rows[(y * w + x) as usize] =
                (-r..=r).map(|d| taps[(d + r) as usize] * v[(y * w + (x + d).clamp(0, w - 1)) as usize]).sum();
        }
    }
    let mut out = vec![0.0; v.len()];
    for y in 0..h {
        for x in 0..w {
            out[(y * w + x) as usize] =
                (-r..=r).map(|d| taps[(d + r) as usize] * rows[((y + d).clamp(0, h - 1) * w + x) as usize]).sum();
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(w: u32, h: u32, value: [u8; 3]) -> Rgb8 {
        Rgb8 { width: w, height: h, rgb: value.repeat((w * h) as usize) }
    }

    fn noise(w: u32, h: u32, seed: u32) -> Rgb8 {
        let mut s = seed;
        let rgb = (0..w * h * 3)
            .map(|_| {
                s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (s >> 24) as u8
            })
            .collect();
        Rgb8 { width: w, height: h, rgb }
    }

    #[test]
    fn identical_images_score_perfectly() {
        let a = noise(24, 16, 7);
        let s = compare(&a, &a).unwrap().scores(None).unwrap();
        assert_eq!((s.flip, s.rmse, s.pixels), (0.0, 0.0, 24 * 16));
        // The magma map's darkest entry is (0, 0, 4).
        assert!((s.flip_heatmap_mean - 4.0 / 765.0).abs() < 1e-9, "heat map mean {}", s.flip_heatmap_mean);
        assert!(s.psnr.is_infinite());
        assert!((s.ssim - 1.0).abs() < 1e-6, "ssim {}", s.ssim);
    }

    #[test]
    fn a_constant_offset_has_its_exact_rmse_psnr_and_ssim() {
        // 100 vs 110 everywhere: RMSE 10/255, PSNR −20 log10(10/255); flat images have no
        // variance, so SSIM is the luminance term (2ab + C1) / (a² + b² + C1).
        let (a, b) = (flat(16, 16, [100; 3]), flat(16, 16, [110; 3]));
        let s = compare(&a, &b).unwrap().scores(None).unwrap();
        let d = 10.0 / 255.0;
        assert!((s.rmse - d).abs() < 1e-6, "rmse {}", s.rmse);
        assert!((s.psnr + 20.0 * f64::log10(d)).abs() < 1e-4, "psnr {}", s.psnr);
        let (x, y) = (100.0 / 255.0, 110.0 / 255.0);
        let expected = (2.0 * x * y + SSIM_C1) / (x * x + y * y + SSIM_C1);
        assert!((s.ssim - expected).abs() < 1e-6, "ssim {} vs {expected}", s.ssim);
        assert!(s.flip > 0.0 && s.flip < 0.2, "flip {}", s.flip);
    }

    #[test]
    fn a_mask_scores_only_its_pixels() {
        // The right half differs; the left half is identical.
        let a = flat(16, 8, [80; 3]);
        let mut b = a.clone();
        for y in 0..8 {
            for x in 8..16 {
                b.rgb[3 * (y * 16 + x)..3 * (y * 16 + x) + 3].copy_from_slice(&[200; 3]);
            }
        }
        let left: Vec<bool> = (0..16 * 8).map(|i| i % 16 < 4).collect();
        let right: Vec<bool> = (0..16 * 8).map(|i| i % 16 >= 12).collect();
        let c = compare(&a, &b).unwrap();
        let l = c.scores(Some(&left)).unwrap();
        let r = c.scores(Some(&right)).unwrap();
        assert_eq!((l.rmse, l.pixels), (0.0, 32));
        assert!((r.rmse - 120.0 / 255.0).abs() < 1e-6, "rmse {}", r.rmse);
        assert!(r.flip > 0.5 && l.flip < r.flip, "flip {} / {}", l.flip, r.flip);
    }

    #[test]
    fn misfits_are_errors_that_name_them() {
        let a = flat(8, 8, [0; 3]);
        assert!(compare(&a, &flat(8, 4, [0; 3])).unwrap_err().contains("8×8 and 8×4"));
        let c = compare(&a, &a).unwrap();
        assert!(c.scores(Some(&[true; 10])).unwrap_err().contains("mask has 10 pixels"));
        assert!(c.scores(Some(&[false; 64])).unwrap_err().contains("no pixel"));
    }

    #[test]
    fn the_heat_map_has_the_image_size() {
        let (a, b) = (noise(10, 6, 1), noise(10, 6, 2));
        let m = compare(&a, &b).unwrap().heatmap;
        assert_eq!((m.width, m.height, m.rgb.len()), (10, 6, 180));
    }
}
