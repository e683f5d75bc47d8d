//! Writing images: the format follows the extension.

use anyhow::{Context, Result, bail};
use mrshade_core::HdrImage;
use mrshade_render::{Aov, AovImage};
use mrshade_scene::images::{encode_exr, encode_png_rgb8, encode_png_srgb};
use std::path::Path;

/// Fails early for an extension we cannot write.
pub fn check_extension(path: &Path) -> Result<()> {
    match ext(path).as_str() {
        "png" | "exr" | "jpg" | "jpeg" => Ok(()),
        other => bail!("cannot write '{}': unknown image extension '{other}' (use .png, .exr or .jpg)", path.display()),
    }
}

fn ext(path: &Path) -> String {
    path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default()
}

/// Writes linear camera values: PNG/JPEG sRGB-encoded and clamped, EXR linear.
pub fn write_image(path: &Path, img: &HdrImage) -> Result<()> {
    check_extension(path)?;
    let bytes = match ext(path).as_str() {
        "exr" => encode_exr(img)?,
        "png" => encode_png_srgb(img)?,
        _ => {
            let buf = image::RgbImage::from_raw(img.width, img.height, img.to_srgb8()).context("pixel buffer size")?;
            let mut out = std::io::Cursor::new(Vec::new());
            image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, 95).encode_image(&buf)?;
            out.into_inner()
        }
    };
    write(path, &bytes)
}

fn write(path: &Path, bytes: &[u8]) -> Result<()> {
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).with_context(|| format!("cannot create {}", parent.display()))?;
    }
    std::fs::write(path, bytes).with_context(|| format!("cannot write {}", path.display()))
}

/// Writes every AOV into `dir`, plus `side_by_side.png` (photo | composite).
pub fn write_aovs(dir: &Path, aovs: &[Aov], photo: &HdrImage, composite: &HdrImage) -> Result<()> {
    for aov in aovs {
        match &aov.image {
            AovImage::Linear(img) => write(&dir.join(format!("{}.exr", aov.name)), &encode_exr(img)?)?,
            AovImage::Display { width, height, rgb } => {
                write(&dir.join(format!("{}.png", aov.name)), &encode_png_rgb8(*width, *height, rgb.clone())?)?
            }
            AovImage::Table(text) => write(&dir.join(format!("{}.csv", aov.name)), text.as_bytes())?,
        }
    }
    write(&dir.join("side_by_side.png"), &encode_png_srgb(&side_by_side(photo, composite))?)
}

/// `a` and `b` next to each other.
pub fn side_by_side(a: &HdrImage, b: &HdrImage) -> HdrImage {
    let (w, h) = (a.width + b.width, a.height.max(b.height));
    let mut out = HdrImage::filled(w, h, [0.0; 3]);
    for y in 0..h {
        for x in 0..w {
            let p = if x < a.width {
                (y < a.height).then(|| a.get(x, y))
            } else {
                (y < b.height).then(|| b.get(x - a.width, y))
            };
            out.pixels[(y * w + x) as usize] = p.unwrap_or([0.0; 3]);
        }
    }
    out
}
