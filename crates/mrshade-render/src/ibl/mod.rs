//! Image-based light from the real probe, prepared on the CPU once per probe: a GGX-
//! prefiltered radiance chain (one mip per roughness step) and a cosine-convolved irradiance
//! map, both equirectangular in the data contract's mapping, plus the split-sum DFG table.
//!
//! The probes are real (peaks from ~9 to ~3700): prefiltering uses filtered importance
//! sampling (Křivánek & Colbert 2008), reading a solid-angle-weighted box pyramid at the
//! footprint of each sample, so a sun pixel spreads smoothly instead of producing fireflies.

mod irradiance;
mod lights;
mod prefilter;
mod pyramid;

pub use irradiance::irradiance_map;
pub use lights::{ProbeRegions, probe_lights, probe_lights_with_spread};
pub use prefilter::prefiltered_radiance;
pub use pyramid::EquirectPyramid;

use mrshade_core::HdrImage;

/// Number of roughness levels of the prefiltered chain: roughness = level / (LEVELS − 1).
pub const RADIANCE_LEVELS: u32 = 6;
/// Largest width of level 0 of the prefiltered chain (larger probes are box-filtered down).
pub const RADIANCE_WIDTH: u32 = 512;
/// Smallest width of level 0, so that every roughness level has at least 2×1 texels.
const MIN_RADIANCE_WIDTH: u32 = 2 << RADIANCE_LEVELS;
/// Width of the irradiance map.
pub const IRRADIANCE_WIDTH: u32 = 64;
/// Side of the DFG table.
pub const DFG_SIZE: u32 = 32;

/// Everything the GPU needs from one probe.
pub struct PreparedProbe {
    /// `RADIANCE_LEVELS` images, each half the size of the previous.
    pub radiance: Vec<HdrImage>,
    /// Irradiance `E(n)`, `IRRADIANCE_WIDTH × IRRADIANCE_WIDTH/2`.
    pub irradiance: HdrImage,
    /// The probe box-filtered (solid-angle weighted), level 0 the probe at the radiance
    /// chain's width, down to 2×1: what filtered importance sampling and the SH projection
    /// read on the GPU.
    pub pyramid: Vec<HdrImage>,
}

impl PreparedProbe {
    /// Prefilters `probe` (unrotated, unscaled: rotation and intensity apply at lookup).
    pub fn new(probe: &HdrImage) -> Self {
        let width = probe.width.clamp(MIN_RADIANCE_WIDTH, RADIANCE_WIDTH);
        let base = probe.resized(width, width / 2);
        let pyramid = EquirectPyramid::new(&base);
        let radiance = prefiltered_radiance(&pyramid, RADIANCE_LEVELS);
        let irradiance = irradiance_map(&pyramid, IRRADIANCE_WIDTH);
        Self { radiance, irradiance, pyramid: pyramid.levels }
    }
}
