//! The output's size: what was asked (`[output]`, `--width`/`--height`) checked as asked,
//! the rest derived from the photo's aspect ratio, within the limits.

use super::SessionOverrides;
use crate::budget::Budget;
use anyhow::{Context, Result, bail};
use mrshade_core::HdrImage;
use mrshade_core::settings::Method;
use serde::Deserialize;

/// Largest accepted output side, in pixels.
pub const MAX_OUTPUT_SIDE: u32 = 16384;
/// Smallest accepted output side, in pixels. The real-time methods shade one sample at the
/// centre of each pixel (× supersample²) while the photo is averaged over it; a pixel that
/// covers much of the scene shows whatever lies at its centre (a 1×1 render of a desk was the
/// white of a lamp-lit torus). Render larger and downscale.
pub const MIN_OUTPUT_SIDE: u32 = 16;
/// Relative aspect-ratio mismatch tolerated between photo, camera and output size.
const ASPECT_TOLERANCE: f32 = 0.01;

/// Output resolution and shading rate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OutputSize {
    /// Output width in pixels.
    pub width: u32,
    /// Output height in pixels.
    pub height: u32,
    /// Shading samples per output pixel along each axis (1 = none).
    pub supersample: u32,
    /// Frames rendered for one still image. Temporal methods converge over the first half;
    /// the still is the mean of the second half (VPL sampling then averages out).
    pub frames: u32,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct OutputFile {
    pub(super) width: Option<u32>,
    pub(super) height: Option<u32>,
    pub(super) supersample: Option<u32>,
    pub(super) frames: Option<u32>,
}

/// Whether aspect ratios `a` and `b` agree within [`ASPECT_TOLERANCE`].
pub(super) fn check_aspect(a: f32, b: f32) -> Result<()> {
    if (a / b - 1.0).abs() > ASPECT_TOLERANCE {
        bail!("aspect ratios {a:.4} and {b:.4} differ");
    }
    Ok(())
}

/// The output size of `file` and `overrides` for `photo`.
pub(super) fn output_size(
    file: &OutputFile,
    overrides: &SessionOverrides,
    photo: &HdrImage,
    method: Method,
    budget: &Budget,
) -> Result<OutputSize> {
    let width = overrides.width.or(file.width);
    let height = overrides.height.or(file.height);
    // What was asked for is checked as asked, before anything is derived from it.
    for (name, v) in [("width", width), ("height", height)] {
        if let Some(v) = v
            && !(MIN_OUTPUT_SIDE..=MAX_OUTPUT_SIDE).contains(&v)
        {
            bail!("{name} must be between {MIN_OUTPUT_SIDE} and {MAX_OUTPUT_SIDE}, got {v}");
        }
    }
    let aspect = photo.aspect();
    let derived = |v: f32, name: &str, from: &str, given: u32| -> Result<u32> {
        let v = v.round() as u32;
        if !(MIN_OUTPUT_SIDE..=MAX_OUTPUT_SIDE).contains(&v) {
            bail!(
                "{from} {given} gives a {name} of {v} at the photo's aspect ratio ({}×{}), outside \
                 {MIN_OUTPUT_SIDE}..={MAX_OUTPUT_SIDE}",
                photo.width,
                photo.height
            );
        }
        Ok(v)
    };
    let (width, height) = match (width, height) {
        (None, None) => {
            if photo.width.min(photo.height) < MIN_OUTPUT_SIDE {
                bail!(
                    "the photo is {}×{}; outputs are at least {MIN_OUTPUT_SIDE} pixels a side: give --width",
                    photo.width,
                    photo.height
                );
            }
            (photo.width, photo.height)
        }
        (Some(w), None) => (w, derived(w as f32 / aspect, "height", "width", w)?),
        (None, Some(h)) => (derived(h as f32 * aspect, "width", "height", h)?, h),
        (Some(w), Some(h)) => {
            if !overrides.stretch_photo {
                check_aspect(w as f32 / h as f32, aspect).with_context(|| {
                    format!("{w}×{h} does not have the photo's aspect ratio ({}×{})", photo.width, photo.height)
                })?;
            }
            (w, h)
        }
    };
    budget.check_image(width, height).context("the output size")?;
    let supersample = file.supersample.unwrap_or(1);
    if !(1..=4).contains(&supersample) {
        bail!("supersample must be between 1 and 4, got {supersample}");
    }
    let frames = file.frames.unwrap_or(method.default_still_frames());
    if !(1..=10_000).contains(&frames) {
        bail!("frames must be between 1 and 10000, got {frames}");
    }
    Ok(OutputSize { width, height, supersample, frames })
}
