//! Colour transfer functions and luminance.
//!
//! Photos arrive sRGB-encoded; all shading and compositing happens in linear Rec.709 and the
//! result is encoded back (data contract: "the PNG is the sRGB encoding of that value clamped
//! to [0, 1]").

/// sRGB electro-optical transfer: encoded value in [0, 1] → linear.
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) }
}

/// Inverse of [`srgb_to_linear`]; clamps to [0, 1] first.
pub fn linear_to_srgb(v: f32) -> f32 {
    let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    if v <= 0.003_130_8 { v * 12.92 } else { 1.055 * v.powf(1.0 / 2.4) - 0.055 }
}

/// Linear value → 8-bit sRGB code, rounded to nearest.
pub fn linear_to_srgb_u8(v: f32) -> u8 {
    (linear_to_srgb(v) * 255.0 + 0.5).floor() as u8
}

/// [`linear_to_srgb_u8`] by table, for whole images: the smallest linear value of each code
/// 1..=255, found once by bisection over the (ordered) bit patterns of `f32`, so that a code
/// is a binary search over 255 thresholds instead of a `powf`, and the same code as the
/// formula's for every input (the formula is monotone; a test checks the thresholds and a
/// sweep of values).
pub struct SrgbEncoder {
    thresholds: [f32; 255],
}

impl Default for SrgbEncoder {
    fn default() -> Self {
        Self::new()
    }
}

impl SrgbEncoder {
    /// Finds the thresholds (about 8000 evaluations of the formula).
    pub fn new() -> Self {
        let thresholds = std::array::from_fn(|i| {
            let code = i as u8 + 1;
            // Non-negative floats order as their bits: bisect for the first one of `code`.
            let (mut lo, mut hi) = (0u32, 1.0f32.to_bits());
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if linear_to_srgb_u8(f32::from_bits(mid)) >= code { hi = mid } else { lo = mid + 1 }
            }
            f32::from_bits(lo)
        });
        Self { thresholds }
    }

    /// The smallest linear value of each code 1..=255 (the GPU's encode pass searches them).
    pub fn thresholds(&self) -> &[f32; 255] {
        &self.thresholds
    }

    /// The 8-bit sRGB code of linear `v`: `linear_to_srgb_u8(v)`.
    pub fn encode(&self, v: f32) -> u8 {
        self.thresholds.partition_point(|&t| t <= v) as u8
    }
}

/// The 256 linear values of the 8-bit sRGB codes, so that decoding a photo is exact and
/// identical everywhere (a decode/encode round trip returns every code unchanged).
pub fn srgb_u8_decode_table() -> [f32; 256] {
    std::array::from_fn(|i| srgb_to_linear(i as f32 / 255.0))
}

/// Rec.709 luminance of a linear RGB triple.
pub fn luminance(rgb: [f32; 3]) -> f32 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_encoder_table_gives_the_formula_s_codes() {
        let encoder = SrgbEncoder::new();
        for v in [f32::NAN, f32::NEG_INFINITY, -1.0, -0.0, 0.0, 1.0, 2.0, f32::INFINITY] {
            assert_eq!(encoder.encode(v), linear_to_srgb_u8(v), "{v}");
        }
        for &t in &encoder.thresholds {
            let below = f32::from_bits(t.to_bits() - 1);
            assert_eq!(encoder.encode(t), linear_to_srgb_u8(t), "{t}");
            assert_eq!(encoder.encode(below), linear_to_srgb_u8(below), "{below}");
        }
        // A sweep of about a million values over [0, 1].
        for bits in (0..=1.0f32.to_bits()).step_by(1063) {
            let v = f32::from_bits(bits);
            assert_eq!(encoder.encode(v), linear_to_srgb_u8(v), "{v}");
        }
    }

    #[test]
    fn every_8bit_code_survives_a_round_trip() {
        let table = srgb_u8_decode_table();
        for (code, &lin) in table.iter().enumerate() {
            assert_eq!(linear_to_srgb_u8(lin) as usize, code);
        }
    }

    #[test]
    fn encode_clamps_and_handles_nan() {
        assert_eq!(linear_to_srgb_u8(-1.0), 0);
        assert_eq!(linear_to_srgb_u8(7.0), 255);
        assert_eq!(linear_to_srgb_u8(f32::NAN), 0);
    }

    #[test]
    fn known_values() {
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
        assert!((linear_to_srgb(0.18) - 0.461_356).abs() < 1e-5);
        assert!((luminance([1.0, 1.0, 1.0]) - 1.0).abs() < 1e-6);
    }
}
