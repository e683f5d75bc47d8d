//! What the `dir` method allocates beyond the frame's shared targets, and how it shrinks to a
//! device (`crate::limits` calls these through the method registry).

use super::GpuPoint;
use super::rsm;
use crate::limits::Fit;
use anyhow::{Result, bail};
use mrshade_core::settings::RenderSettings;

/// Bytes of an ISM point.
const POINT_BYTES: u64 = std::mem::size_of::<GpuPoint>() as u64;
/// Bytes per internal pixel: four sets of five RGBA16F indirect targets (interleaved, two
/// histories, merged) and the previous depth and normal (16).
const SCREEN_BYTES: u64 = 4 * 5 * 8 + 16;

/// Halves the RSMs, ISM tiles and ISM points until each fits one buffer binding.
pub(crate) fn fit(settings: &mut RenderSettings, fit: &mut Fit) -> Result<()> {
    let dir = &mut settings.dir;
    let (layers, max_binding) = (fit.shadow_layers, fit.max_binding);
    let rsm_fits = |res: u64| layers * res * res * rsm::TEXEL_BYTES <= max_binding;
    if !fit.shrink("dir.rsm_resolution", &mut dir.rsm_resolution, &rsm_fits, 16) {
        bail!(
            "the scene's {} lights need {layers} RSM layers, more than one GPU buffer of this device holds ({} MiB) \
             even at 16×16 texels; remove lights",
            fit.lights,
            max_binding >> 20
        );
    }
    let tiles_per_row = (dir.vpl_count as f64).sqrt().ceil() as u64;
    let ism_fits = |res: u64| tiles_per_row * tiles_per_row * res * res * 4 <= max_binding;
    fit.shrink("dir.ism_resolution", &mut dir.ism_resolution, &ism_fits, 16);
    let vpls = dir.vpl_count as u64;
    let points_fit = |points: u64| vpls * points * POINT_BYTES <= max_binding;
    fit.shrink("dir.points_per_vpl", &mut dir.points_per_vpl, &points_fit, 16);
    Ok(())
}

/// GPU bytes of the method, item by item.
pub(crate) fn estimate(settings: &RenderSettings, internal_pixels: u64, layers: u64) -> Vec<(&'static str, u64)> {
    let d = &settings.dir;
    let rsm = d.rsm_resolution as u64;
    let tiles = ((d.vpl_count as f64).sqrt().ceil() as u64).pow(2);
    let ism = d.ism_resolution as u64;
    vec![
        ("dir screen targets (output size × supersample²)", internal_pixels * SCREEN_BYTES),
        (
            "RSMs (lights × dir.rsm_resolution²)",
            layers * (rsm * rsm * (8 + rsm::TEXEL_BYTES + 11) + crate::limits::VIEW_BYTES),
        ),
        ("ISM atlases (dir.vpl_count × dir.ism_resolution²)", 2 * tiles * ism * ism * 4),
        (
            "ISM points (dir.vpl_count × dir.points_per_vpl)",
            2 * d.vpl_count as u64 * d.points_per_vpl as u64 * POINT_BYTES,
        ),
    ]
}
