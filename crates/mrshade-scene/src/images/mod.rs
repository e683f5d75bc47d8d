//! Photos, light probes and textures into linear [`HdrImage`]s (or RGBA8 texels).
//!
//! Photos: PNG/JPEG are sRGB-encoded (decoded exactly through the 8-bit table, so that an
//! untouched pixel re-encodes to its own code); EXR and Radiance HDR are linear.
//! Probes: EXR or HDR only, equirectangular (2:1), every value finite and ≥ 0.
//!
//! Every image is sized from its header and checked against `limits.image_pixels` before it
//! is decoded (a 62 kB 1-bit PNG can claim 26000 × 19500 pixels), and the decoder runs under
//! a matching allocation limit. OpenEXR files are checked further by [`exr_guard`].

mod exr_guard;

use crate::budget::Budget;
use anyhow::{Context, Result, bail};
use image::{DynamicImage, ImageFormat, ImageReader};
use mrshade_core::HdrImage;
use mrshade_core::color::{srgb_to_linear, srgb_u8_decode_table};
use std::io::Cursor;

/// Largest radiometric value accepted anywhere (probe texels × intensity, light
/// intensities, emission): about 10¹⁸. Larger finite values overflow single precision in the
/// renderers' sums of squares and turn pixels black; no real camera or lamp comes near.
pub const MAX_RADIANCE: f32 = 1e18;

/// Decodes a camera photo (PNG, JPEG, EXR or Radiance HDR) to linear RGB.
pub fn decode_photo(bytes: &[u8], budget: &Budget) -> Result<HdrImage> {
    let format = guess(bytes)?;
    let img = decode(bytes, format, budget).context("cannot decode the image")?;
    let mut out = match format {
        ImageFormat::Png | ImageFormat::Jpeg => srgb_to_hdr(img),
        _ => linear_to_hdr(img),
    };
    check_finite(&out)?;
    check_magnitude(&out, "pixel value")?;
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
pub fn decode_probe(bytes: &[u8], budget: &Budget) -> Result<(HdrImage, Option<String>)> {
    let format = guess(bytes)?;
    if !matches!(format, ImageFormat::OpenExr | ImageFormat::Hdr) {
        bail!("a light probe must be an HDR image (OpenEXR or Radiance .hdr), not {format:?}");
    }
    let img = decode(bytes, format, budget).context("cannot decode the probe")?;
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
    if positive_sum <= 0.0 {
        bail!("the probe holds no light: no value is above 0");
    }
    check_magnitude(&out, "probe value")?;
    // As a share of all the energy, negative included, it cannot pass 100 %.
    let warning = (negative_sum > 1e-3 * positive_sum).then(|| {
        format!(
            "{negative_pixels} probe value(s) were negative ({:.2} % of the probe's energy); clamped to 0",
            100.0 * negative_sum / (positive_sum + negative_sum)
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

/// Decodes `bytes` after checking its size from the header against the budget, with the
/// decoder's own allocations limited to what that size needs.
fn decode(bytes: &[u8], format: ImageFormat, budget: &Budget) -> Result<DynamicImage> {
    let (width, height) = dimensions(bytes, format)?;
    budget.check_image(width, height)?;
    if format == ImageFormat::OpenExr {
        exr_guard::check_dwa_chunks(bytes)?;
    }
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(width);
    limits.max_image_height = Some(height);
    // RGBA, 32-bit float at most, plus the decoder's working rows.
    limits.max_alloc = Some(width as u64 * height as u64 * 16 + (64 << 20));
    let mut reader = ImageReader::with_format(Cursor::new(bytes), format);
    reader.limits(limits);
    let img = reader.decode()?;
    if (img.width(), img.height()) != (width, height) {
        bail!("the image decodes to {}×{} but its header says {width}×{height}", img.width(), img.height());
    }
    Ok(img)
}

/// `width × height` from the image's header alone (non-zero).
fn dimensions(bytes: &[u8], format: ImageFormat) -> Result<(u32, u32)> {
    let (width, height) = match format {
        ImageFormat::OpenExr => exr_guard::largest_layer(bytes)?,
        _ => ImageReader::with_format(Cursor::new(bytes), format)
            .into_dimensions()
            .context("cannot read the image header")?,
    };
    if width == 0 || height == 0 {
        bail!("the image is empty ({width}×{height})");
    }
    Ok((width, height))
}

/// A texture for the GPU and the path tracer: 8-bit RGBA (PNG or JPEG, as glTF allows), its
/// texels charged to the scene's budget before it is decoded.
pub fn decode_rgba8(bytes: &[u8], budget: &mut Budget) -> Result<image::RgbaImage> {
    let format = guess(bytes)?;
    let (width, height) = dimensions(bytes, format)?;
    budget.check_image(width, height)?;
    budget.charge("the decoded texture", width as u64 * height as u64, 4)?;
    Ok(decode(bytes, format, budget)?.to_rgba8())
}

/// An 8-bit sRGB image as stored (for scoring with `compare`; alpha dropped).
pub fn decode_rgb8(bytes: &[u8], budget: &Budget) -> Result<image::RgbImage> {
    let format = guess(bytes)?;
    Ok(decode(bytes, format, budget)?.to_rgb8())
}

/// Rejects finite values so large that the renderers' arithmetic overflows.
fn check_magnitude(img: &HdrImage, what: &str) -> Result<()> {
    if let Some(i) = img.pixels.iter().position(|p| p.iter().any(|v| v.abs() > MAX_RADIANCE)) {
        let (x, y) = (i as u32 % img.width, i as u32 / img.width);
        bail!("a {what} at ({x}, {y}) is larger than {MAX_RADIANCE:e}, beyond what mrshade computes with");
    }
    Ok(())
}

/// Rejects NaN and infinities, naming the first offending pixel (not its value: the value is
/// bytes of the file).
fn check_finite(img: &HdrImage) -> Result<()> {
    if let Some((count, (x, y))) = img.non_finite() {
        bail!("{count} pixel(s) hold NaN or infinite values, the first at ({x}, {y})");
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
