//! Settings of the CPU differential path tracer (`mrshade reference`, issue 4).

use super::check;
use serde::{Deserialize, Serialize};

/// Largest sample count per pixel: the Owen-scrambled Sobol sequence has 2^16 points.
pub const MAX_REFERENCE_SPP: u32 = 65536;

/// How the reference path tracer samples. The defaults are the settings of the benchmark's
/// independent answers (Mitsuba 3, `../shared/data/README.md`): 12 bounces, Russian roulette
/// from the 5th, 256 samples per pixel as CALIBRATION.md's "ideal" differential rendering.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ReferenceSettings {
    /// Paths per pixel. Noise falls as 1/√spp; 256 takes minutes at 640×480 on a few cores.
    pub spp: u32,
    /// Longest path, in surface interactions after the camera (Mitsuba's `max_depth` − 1 = 11
    /// for its 12). Glass needs several: in, out, and the bounce on the desk below.
    pub max_bounces: u32,
    /// Russian roulette starts after this many bounces (unbiased: survivors are reweighted).
    pub roulette_from: u32,
    /// Seed of the sample sequence; another seed gives another, equally valid noise pattern.
    pub seed: u32,
}

impl Default for ReferenceSettings {
    fn default() -> Self {
        Self { spp: 256, max_bounces: 11, roulette_from: 4, seed: 0 }
    }
}

impl ReferenceSettings {
    /// Checks every value; the error names the offending field.
    pub fn validate(&self) -> Result<(), String> {
        check(
            (1..=MAX_REFERENCE_SPP).contains(&self.spp),
            "reference.spp",
            format!("must be in 1..={MAX_REFERENCE_SPP}, got {}", self.spp),
        )?;
        check(
            (1..=64).contains(&self.max_bounces),
            "reference.max_bounces",
            format!("must be in 1..=64, got {}", self.max_bounces),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid() {
        ReferenceSettings::default().validate().unwrap();
    }

    #[test]
    fn zero_samples_names_the_field() {
        let s = ReferenceSettings { spp: 0, ..Default::default() };
        assert!(s.validate().unwrap_err().contains("reference.spp"));
        let s = ReferenceSettings { spp: MAX_REFERENCE_SPP + 1, ..Default::default() };
        assert!(s.validate().is_err());
    }
}
