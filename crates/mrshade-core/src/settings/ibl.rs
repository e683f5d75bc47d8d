//! How virtual objects are shaded by the real probe (Franke §2.1–§2.2): the image-based
//! light that every method's direct pass gives them.

use super::check;
use serde::{Deserialize, Serialize};

/// The probe's light on virtual surfaces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum VirtualShading {
    /// Irradiance map and GGX-prefiltered radiance chain, prepared once on the CPU (split
    /// sum, Karis 2013); the default.
    #[default]
    #[serde(rename = "prefiltered")]
    Prefiltered,
    /// Diffuse light from the probe's nine SH irradiance coefficients (spec §2.1),
    /// recomputed on the GPU every frame; specular as `prefiltered`.
    #[serde(rename = "sh")]
    Sh,
    /// SH diffuse light and GGX filtered importance sampling of the probe per pixel
    /// (Křivánek & Colbert 2008, spec §2.2): any roughness, no prefiltered chain.
    #[serde(rename = "fis")]
    Fis,
    /// Precomputed radiance transfer (spec §2.4): rigid virtual objects take diffuse light
    /// with self-shadowing from transfer vectors baked per vertex on first use (cached next
    /// to the session as prt_cache.bin), deforming ones SH irradiance; specular by
    /// `ibl.prt_specular`.
    #[serde(rename = "prt")]
    Prt,
}

impl VirtualShading {
    /// The name used in sessions.
    pub fn name(self) -> &'static str {
        match self {
            VirtualShading::Prefiltered => "prefiltered",
            VirtualShading::Sh => "sh",
            VirtualShading::Fis => "fis",
            VirtualShading::Prt => "prt",
        }
    }
}

/// The glossy part of `prt` shading.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum PrtSpecular {
    /// Sum of Gaussians (spec §2.5, [GKD07a]): three lookups into the probe's pyramid per
    /// pixel, at the directions and widths of the GGX lobe's fit, shadowed by the PRT
    /// visibility; the default, as in the thesis.
    #[default]
    #[serde(rename = "sog")]
    Sog,
    /// Filtered importance sampling with `ibl.samples` samples, unshadowed (as `fis`).
    #[serde(rename = "fis")]
    Fis,
}

/// Settings of image-based light on virtual objects.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct IblSettings {
    /// How virtual surfaces take the probe's light. Default `prefiltered`.
    #[serde(rename = "virtual")]
    pub virtual_shading: VirtualShading,
    /// GGX samples per pixel of filtered importance sampling (1–256). Default 32 (the
    /// thesis's code samples 16–64).
    pub samples: u32,
    /// Rays per vertex when baking PRT transfer (16–65536). Default 256.
    pub prt_samples: u32,
    /// SH coefficients of PRT transfer and of the probe it is lit by: 9 (bands 0–2) or 16
    /// (bands 0–3: sharper self-shadowing from a dominant light, spec §2.4, Franke Fig.
    /// 4.11). Default 9.
    pub prt_coefficients: u32,
    /// The glossy part of `prt` shading: `sog` (default) or `fis`.
    pub prt_specular: PrtSpecular,
}

impl Default for IblSettings {
    fn default() -> Self {
        Self {
            virtual_shading: VirtualShading::Prefiltered,
            samples: 32,
            prt_samples: 256,
            prt_coefficients: 9,
            prt_specular: PrtSpecular::Sog,
        }
    }
}

impl IblSettings {
    /// Checks every value; the error names the offending field.
    pub fn validate(&self) -> Result<(), String> {
        check(
            (1..=256).contains(&self.samples),
            "ibl.samples",
            format!("must be between 1 and 256, got {}", self.samples),
        )?;
        check(
            (16..=65536).contains(&self.prt_samples),
            "ibl.prt_samples",
            format!("must be between 16 and 65536, got {}", self.prt_samples),
        )?;
        check(
            matches!(self.prt_coefficients, 9 | 16),
            "ibl.prt_coefficients",
            format!("must be 9 or 16, got {}", self.prt_coefficients),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_values_are_named() {
        let bad = IblSettings { samples: 0, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("ibl.samples"));
        let bad = IblSettings { prt_samples: 8, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("ibl.prt_samples"));
        let bad = IblSettings { prt_coefficients: 4, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("ibl.prt_coefficients"));
        IblSettings::default().validate().unwrap();
    }
}
