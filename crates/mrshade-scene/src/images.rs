//! Photos and light probes into linear [`HdrImage`]s.
//!
//! Photos: PNG/JPEG are sRGB-encoded (decoded exactly through the 8-bit table, so that an
//! untouched pixel re-encodes to its own code); EXR and Radiance HDR are linear.
//! Probes: EXR or HDR only, equirectangular (2:1), every value finite and ≥ 0.

use anyhow::{Context, Result, bail};
use image::{DynamicImage, ImageFormat};
use mrshade_core::HdrImage;
use mrshade_core::color::{srgb_to_linear, srgb_u8_decode_table};

/// Decodes a camera photo (PNG, JPEG, EXR or Radiance HDR) to linear RGB.
pub fn decode_photo(bytes: &[u8]) -> Result<HdrImage> {
    let format = guess(bytes)?;
    let img = image::load_from_memory_with_format(bytes, format).context("cannot decode the image")?;
    check_size(&img)?;
    let mut out = match format {
        ImageFormat::Png | ImageFormat::Jpeg => srgb_to_hdr(img),
        _ => linear_to_hdr(img),
    };
    check_finite(&out)?;
    // Camera values cannot be negative; EXR photos from resampling may hold tiny ones.
    for p in &mut out.pixels {
        *p = p.map(|v| v.max(0.0));
    }
    Ok(out)
}

/// Decodes an equirectangular light probe (EXR or Radiance HDR, linear radiance).
///
/// NaN and infinities are errors. Small negative values are common in real probes (ringing
/// of the resampling filter that made them); they are clamped to 0, with a warning when they
/// held more than 0.1 % of the probe's energy.
pub fn decode_probe(bytes: &[u8]) -> Result<(HdrImage, Option<String>)> {
    let format = guess(bytes)?;
    if !matches!(format, ImageFormat::OpenExr | ImageFormat::Hdr) {
        bail!("a light probe must be an HDR image (OpenEXR or Radiance .hdr), not {format:?}");
    }
    let img = image::load_from_memory_with_format(bytes, format).context("cannot decode the probe")?;
    check_size(&img)?;
    let mut out = linear_to_hdr(img);
    if out.width != 2 * out.height {
        bail!("an equirectangular probe is twice as wide as high; this one is {}×{}", out.width, out.height);
    }
    check_finite(&out)?;
    let (negative_pixels, negative_sum, positive_sum) =
        out.pixels.iter().flatten().fold((0, 0.0f64, 0.0f64), |(n, neg, pos), &v| {
            if v < 0.0 { (n + 1, neg - v as f64, pos) } else { (n, neg, pos + v as f64) }
        });
    for p in &mut out.pixels {
        *p = p.map(|v| v.max(0.0));
    }
    // Tiny negative lobes are normal in resampled probes; say so only when clamping them
    // changes the probe's energy noticeably (more than 0.1 %).
    let warning = (negative_sum > 1e-3 * positive_sum).then(|| {
        format!(
            "{negative_pixels} probe value(s) were negative ({:.2} % of the probe's energy); clamped to 0",
            100.0 * negative_sum / positive_sum.max(1e-30)
        )
    });
    Ok((out, warning))
}

fn guess(bytes: &[u8]) -> Result<ImageFormat> {
    if bytes.is_empty() {
        bail!("the file is empty");
    }
    let format = image::guess_format(bytes).context("unrecognised image format (expected PNG, JPEG, EXR or HDR)")?;
    if !matches!(format, ImageFormat::Png | ImageFormat::Jpeg | ImageFormat::OpenExr | ImageFormat::Hdr) {
        bail!("unsupported image format {format:?} (expected PNG, JPEG, EXR or HDR)");
    }
    Ok(format)
}

fn check_size(img: &DynamicImage) -> Result<()> {
    if img.width() == 0 || img.height() == 0 {
        bail!("the image is empty ({}×{})", img.width(), img.height());
    }
    Ok(())
}

/// Rejects NaN and infinities, naming the first offending pixel.
fn check_finite(img: &HdrImage) -> Result<()> {
    let bad = |p: &[f32; 3]| p.iter().any(|v| !v.is_finite());
    if let Some(i) = img.pixels.iter().position(bad) {
        let count = img.pixels.iter().filter(|p| bad(p)).count();
        let (x, y) = (i as u32 % img.width, i as u32 / img.width);
        bail!("{count} pixel(s) hold NaN or infinite values, the first at ({x}, {y}): {:?}", img.pixels[i]);
    }
    Ok(())
}

fn srgb_to_hdr(img: DynamicImage) -> HdrImage {
    let (width, height) = (img.width(), img.height());
    let pixels = match img {
        DynamicImage::ImageRgb16(_)
        | DynamicImage::ImageRgba16(_)
        | DynamicImage::ImageLuma16(_)
        | DynamicImage::ImageLumaA16(_) => img.to_rgb32f().pixels().map(|p| p.0.map(srgb_to_linear)).collect(),
        _ => {
            let table = srgb_u8_decode_table();
            img.to_rgb8().pixels().map(|p| p.0.map(|c| table[c as usize])).collect()
        }
    };
    HdrImage { width, height, pixels }
}

fn linear_to_hdr(img: DynamicImage) -> HdrImage {
    let (width, height) = (img.width(), img.height());
    HdrImage { width, height, pixels: img.to_rgb32f().pixels().map(|p| p.0).collect() }
}

/// Encodes linear RGB as an sRGB 8-bit PNG (clamped), the contract's camera encoding.
pub fn encode_png_srgb(img: &HdrImage) -> Result<Vec<u8>> {
    encode_png_rgb8(img.width, img.height, img.to_srgb8())
}

/// Encodes 8-bit RGB bytes as PNG.
pub fn encode_png_rgb8(width: u32, height: u32, rgb: Vec<u8>) -> Result<Vec<u8>> {
    let buf = image::RgbImage::from_raw(width, height, rgb).context("pixel buffer size mismatch")?;
    let mut out = std::io::Cursor::new(Vec::new());
    buf.write_to(&mut out, ImageFormat::Png)?;
    Ok(out.into_inner())
}

/// Encodes linear RGB as a float OpenEXR (unclamped), the contract's linear camera value.
pub fn encode_exr(img: &HdrImage) -> Result<Vec<u8>> {
    let flat: Vec<f32> = img.pixels.iter().flatten().copied().collect();
    let buf = image::Rgb32FImage::from_raw(img.width, img.height, flat).context("pixel buffer size mismatch")?;
    let mut out = std::io::Cursor::new(Vec::new());
    DynamicImage::ImageRgb32F(buf).write_to(&mut out, ImageFormat::OpenExr)?;
    Ok(out.into_inner())
}
