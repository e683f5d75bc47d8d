//! `mrshade compare`: how far an image is from a reference (issue 4's metrics).

use crate::args::CompareArgs;
use anyhow::{Context, Result};
use mrshade_eval::metrics::{self, Rgb8};
use mrshade_scene::AssetSource;
use mrshade_scene::assets::{DEFAULT_MAX_FILE_BYTES, ReadPolicy};
use mrshade_scene::budget::Budget;
use std::path::Path;

/// Prints FLIP, PSNR, RMSE and SSIM of `args.test` against `args.reference`.
pub fn compare(args: &CompareArgs) -> Result<()> {
    let max_pixels = args.max_pixels;
    let reference = load(&args.reference, max_pixels)?;
    let test = load(&args.test, max_pixels)?;
    let mask = match &args.mask {
        Some(path) => {
            Some(load(path, max_pixels)?.rgb.chunks_exact(3).map(|p| p.iter().any(|&c| c > 0)).collect::<Vec<bool>>())
        }
        None => None,
    };
    let misfit = |e: String| anyhow::anyhow!("{} against {}: {e}", args.test.display(), args.reference.display());
    let comparison = metrics::compare(&reference, &test).map_err(misfit)?;
    let scores = comparison.scores(mask.as_deref()).map_err(misfit)?;
    let heatmap = &comparison.heatmap;
    if let Some(path) = &args.heatmap {
        image::save_buffer(path, &heatmap.rgb, heatmap.width, heatmap.height, image::ExtendedColorType::Rgb8)
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    if args.json {
        // JSON has no infinity: identical images get a PSNR of null.
        let psnr = if scores.psnr.is_finite() { serde_json::json!(scores.psnr) } else { serde_json::Value::Null };
        let json = serde_json::json!({
            "flip": scores.flip, "flip_heatmap_mean": scores.flip_heatmap_mean, "psnr_db": psnr, "rmse": scores.rmse, "ssim": scores.ssim, "pixels": scores.pixels,
        });
        println!("{json}");
    } else {
        println!(
            "FLIP {:.4} (heat-map mean {:.4}, as the benchmark's score.py)  PSNR {:.2} dB  RMSE {:.4}  SSIM {:.4}  ({} pixels{})",
            scores.flip,
            scores.flip_heatmap_mean,
            scores.psnr,
            scores.rmse,
            scores.ssim,
            scores.pixels,
            if mask.is_some() { " in the mask" } else { "" }
        );
    }
    Ok(())
}

/// An 8-bit sRGB image (alpha dropped) of at most `max_pixels`, checked from its header
/// before it is decoded.
pub fn load(path: &Path, max_pixels: u64) -> Result<Rgb8> {
    let what = || format!("cannot read image {}", path.display());
    // The user named this file: any folder may hold it.
    let folder = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new(".")).to_path_buf();
    let name = path.file_name().with_context(|| format!("{} names no file", path.display()))?;
    let source =
        AssetSource::dir_with_policy(&folder, ReadPolicy::new(std::slice::from_ref(&folder), DEFAULT_MAX_FILE_BYTES));
    let bytes = source.read(&name.to_string_lossy()).with_context(what)?;
    let budget = Budget::images(max_pixels, "--max-pixels");
    let img = mrshade_scene::images::decode_rgb8(&bytes, &budget).with_context(what)?;
    Ok(Rgb8 { width: img.width(), height: img.height(), rgb: img.into_raw() })
}
