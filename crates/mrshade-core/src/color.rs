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
