//! Shadow maps of punctual lights. Knecht keeps a real-only and a virtual-only map per real
//! light (§2.7, "double shadowing"); their resolution is not given in the thesis.

use super::check;
use serde::{Deserialize, Serialize};

/// Settings of the shadow pass.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ShadowSettings {
    /// Side of each shadow map in texels (a point light uses six). Higher is sharper and
    /// slower; the thesis does not specify it (its RSM suggestion: 256–512). Default 2048,
    /// enough for a hard desk-lamp shadow at 1080p.
    pub resolution: u32,
    /// Percentage-closer filter radius in texels (0 = one bilinear compare tap). Default 1:
    /// 3×3 bilinear taps, which hides texel stairs without visibly softening contact shadows.
    pub pcf_radius: u32,
    /// Receiver offset along the surface normal, in shadow-map texels at the receiver's
    /// distance. Removes acne on surfaces at grazing angles to the light. Default 1.5.
    pub normal_offset: f32,
    /// Depth bias as a fraction of the receiver's distance to the light (perspective maps) or
    /// of the map's depth range (directional maps). Default 0.002: 2 mm at 1 m.
    pub depth_bias: f32,
}

impl Default for ShadowSettings {
    fn default() -> Self {
        Self { resolution: 2048, pcf_radius: 1, normal_offset: 1.5, depth_bias: 0.002 }
    }
}

impl ShadowSettings {
    /// Checks every value; the error names the offending field.
    pub fn validate(&self) -> Result<(), String> {
        check(
            (64..=8192).contains(&self.resolution),
            "shadows.resolution",
            format!("must be between 64 and 8192 texels, got {}", self.resolution),
        )?;
        check(
            self.pcf_radius <= 4,
            "shadows.pcf_radius",
            format!("must be at most 4 texels, got {}", self.pcf_radius),
        )?;
        check(
            self.normal_offset.is_finite() && self.normal_offset >= 0.0,
            "shadows.normal_offset",
            format!("must be a number ≥ 0, got {}", self.normal_offset),
        )?;
        check(
            self.depth_bias.is_finite() && (0.0..0.5).contains(&self.depth_bias),
            "shadows.depth_bias",
            format!("must be a number in [0, 0.5), got {}", self.depth_bias),
        )
    }
}
