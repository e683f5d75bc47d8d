//! Caustics of punctual lights through mirror-like and transmissive objects (reflections spec
//! §2.17: photon G-buffers, splatting into a caustic buffer, routing of §2.17.5).

use super::check;
use serde::{Deserialize, Serialize};

/// How the splatted photons become irradiance (spec §2.17.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Concentration {
    /// Each photon's power spread over its quad by a tent kernel that integrates to one, and
    /// the quads sized from the neighbouring photons: their sum is irradiance, and a caustic
    /// keeps the energy that reaches it (what the reference path tracer measures). Not in
    /// the documents.
    #[default]
    Energy,
    /// The thesis's empirical scaling (Eq. T6.2): the mean photon irradiance times
    /// k_c = (b^min(n, n_max) − 1) / (b^n_max − 1) for n photons in the pixel.
    Thesis,
}

/// Largest ratio of `splat_far_max` to `splat_min`: the photons' world-space grid has 32
/// levels of quad size √2 apart (√2^31 ≈ 46341).
pub const MAX_SPLAT_RATIO: f32 = 32768.0;

/// Settings of the caustics (part of the specular stage).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CausticsSettings {
    /// Trace photons from every punctual light (and the probe) through the traced objects.
    /// Default on. They cost (1080p, NVIDIA H100, glass + mirror + spot, `dir`): 0.35 ms at
    /// the defaults (frame 2.98 ms, 2.63 without; docs/benchmarks.md).
    pub enabled: bool,
    /// Side of each light's photon map (one photon per texel and branch, aimed at the
    /// bounding sphere of the traced objects). The thesis used 512 and 256 [T §7]; default
    /// 128 (the bench scene's frame at 1080p on an H100: 2.94 ms at 64², 2.98 at 128², 3.20
    /// at 256²).
    pub photon_resolution: u32,
    /// Smallest half-size of a photon's quad, metres (spec §2.17.2: "a user-defined minimum
    /// and maximum", 0.005 and 0.007 in the thesis's scene). Default 0.002.
    pub splat_min: f32,
    /// Largest half-size of a photon's quad, metres: the quads are sized from the
    /// neighbouring photons, which a diverging reflection (a convex mirror) spreads far apart. Default
    /// 0.02: larger quads cost fill rate (1080p on the H200: 24 ms of splatting at 0.05 with the
    /// farther neighbour sizing the quads).
    pub splat_max: f32,
    /// Largest half-size, metres, of the quads of photons farther apart than `splat_max`:
    /// those (a convex mirror's diverging reflection of a lamp or of the sky) are drawn at
    /// their own spacing into a coarse caustic buffer of 1/8 the fine one's resolution per
    /// axis, where big quads cost few texels (Wyman's hierarchical caustic maps, in two
    /// levels). Clamped to `splat_max` they kept their energy in separate dots. Default 0.05
    /// (region FLIP desk-glass / desk-mirror and splat ms at 1080p on the H200: 0.02, i.e.
    /// no coarse level, 0.107 / 0.113 and 1.04 ms; 0.05: 0.108 / 0.112 and 0.35 ms; 0.1:
    /// 0.109 / 0.111 and 0.64 ms; 0.3: 0.110 / 0.110 and 1.66 ms).
    pub splat_far_max: f32,
    /// A photon lights a pixel when its quad lies within this fraction of the camera distance
    /// of the pixel's surface (spec §2.17.4: "a specified epsilon range"). Default 0.02.
    pub depth_epsilon: f32,
    /// Directions of the probe's upper hemisphere that shoot photons each frame (a spherical
    /// Fibonacci set, rotated every frame): the light a glass focuses from the sky onto the
    /// desk, which the documents do not render (their caustics are of spot lights only).
    /// Each direction stands for 2π/n sr of the probe, looked up prefiltered over about that
    /// much. Only with a method that shadows the probe (`dir`), whose directional VPLs then
    /// treat transmissive casters as opaque: the photons carry the light that passes (what
    /// mirrors reflect, the VPLs on them carry). 0: off. Default 64 (desk-glass region FLIP
    /// 0.170 without, 0.146 with 16, 0.143 with 64 and 128, before internal reflections were
    /// sampled).
    pub environment_directions: u32,
    /// Side of each probe direction's photon map (orthographic over the traced objects).
    /// Default 32.
    pub environment_resolution: u32,
    /// The caustic buffer has 1/divisor of the frame's pixels along each axis: the splat's
    /// work falls with its square, the resolve reads it bilinearly. Default 2 (the bench
    /// scene's frame at 1080p on an H100: 3.17 ms at 1, 2.98 at 2, 2.94 at 4).
    pub buffer_divisor: u32,
    /// Irradiance from the photons. Default `energy`.
    pub concentration: Concentration,
    /// `n_max` of k_c (thesis mode): photons for full intensity. Default 32 [T §7].
    pub thesis_photons: u32,
    /// `b` of k_c (thesis mode). Default 1.3 [T §7].
    pub thesis_base: f32,
}

impl Default for CausticsSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            photon_resolution: 128,
            splat_min: 0.002,
            splat_max: 0.02,
            splat_far_max: 0.05,
            depth_epsilon: 0.02,
            environment_directions: 64,
            environment_resolution: 32,
            buffer_divisor: 2,
            concentration: Concentration::Energy,
            thesis_photons: 32,
            thesis_base: 1.3,
        }
    }
}

impl CausticsSettings {
    /// Checks every value; the error names the offending field.
    pub fn validate(&self) -> Result<(), String> {
        check(
            (8..=2048).contains(&self.photon_resolution),
            "caustics.photon_resolution",
            format!("must be between 8 and 2048 texels, got {}", self.photon_resolution),
        )?;
        check(
            self.splat_min.is_finite() && self.splat_min > 0.0 && self.splat_min < 10.0,
            "caustics.splat_min",
            format!("must be a number of metres in (0, 10), got {}", self.splat_min),
        )?;
        check(
            self.splat_max.is_finite() && self.splat_max >= self.splat_min && self.splat_max < 10.0,
            "caustics.splat_max",
            format!("must be a number of metres in [splat_min, 10), got {}", self.splat_max),
        )?;
        check(
            self.splat_far_max.is_finite() && self.splat_far_max >= self.splat_max && self.splat_far_max < 10.0,
            "caustics.splat_far_max",
            format!("must be a number of metres in [splat_max, 10), got {}", self.splat_far_max),
        )?;
        // The photons' world-space grid has a level per √2 of quad size, 32 of them
        // (shaders/lib/photon_grid.wgsl): larger quads would spill out of their cells.
        check(
            self.splat_far_max <= MAX_SPLAT_RATIO * self.splat_min,
            "caustics.splat_far_max",
            format!(
                "must be at most {MAX_SPLAT_RATIO} × splat_min ({} m), got {}",
                MAX_SPLAT_RATIO * self.splat_min,
                self.splat_far_max
            ),
        )?;
        check(
            self.depth_epsilon.is_finite() && self.depth_epsilon > 0.0 && self.depth_epsilon < 1.0,
            "caustics.depth_epsilon",
            format!("must be a number in (0, 1), got {}", self.depth_epsilon),
        )?;
        check(
            self.environment_directions <= 1024,
            "caustics.environment_directions",
            format!("must be at most 1024, got {}", self.environment_directions),
        )?;
        check(
            (4..=512).contains(&self.environment_resolution),
            "caustics.environment_resolution",
            format!("must be between 4 and 512 texels, got {}", self.environment_resolution),
        )?;
        check(
            (1..=8).contains(&self.buffer_divisor),
            "caustics.buffer_divisor",
            format!("must be between 1 and 8, got {}", self.buffer_divisor),
        )?;
        check(
            (1..=256).contains(&self.thesis_photons),
            "caustics.thesis_photons",
            format!("must be between 1 and 256, got {}", self.thesis_photons),
        )?;
        check(
            self.thesis_base.is_finite() && self.thesis_base > 1.0 && self.thesis_base < 10.0,
            "caustics.thesis_base",
            format!("must be a number in (1, 10), got {}", self.thesis_base),
        )
    }

    /// The thesis's k_c (Eq. T6.2) for `n` photons.
    pub fn k_c(&self, n: f32) -> f32 {
        let b = self.thesis_base;
        let n_max = self.thesis_photons as f32;
        (b.powf(n.min(n_max)) - 1.0) / (b.powf(n_max) - 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_validate_and_k_c_matches_the_thesis_table() {
        let c = CausticsSettings::default();
        c.validate().unwrap();
        // Spec §2.17.3's table for b = 1.3, n_max = 32.
        assert!((c.k_c(16.0) - 0.01481).abs() < 1e-4);
        assert!((c.k_c(28.0) - 0.34998).abs() < 1e-4);
        assert_eq!(c.k_c(40.0), 1.0);
    }

    #[test]
    fn bad_values_name_their_field() {
        let bad = [
            CausticsSettings { photon_resolution: 4, ..Default::default() },
            CausticsSettings { splat_min: 0.0, ..Default::default() },
            CausticsSettings { splat_max: 0.001, ..Default::default() },
            CausticsSettings { splat_far_max: 0.01, ..Default::default() },
            CausticsSettings { splat_min: 1e-7, splat_max: 1e-6, ..Default::default() },
            CausticsSettings { depth_epsilon: f32::NAN, ..Default::default() },
            CausticsSettings { thesis_photons: 0, ..Default::default() },
            CausticsSettings { thesis_base: 1.0, ..Default::default() },
            CausticsSettings { environment_directions: 5000, ..Default::default() },
            CausticsSettings { environment_resolution: 2, ..Default::default() },
            CausticsSettings { buffer_divisor: 0, ..Default::default() },
        ];
        let fields = [
            "photon_resolution",
            "splat_min",
            "splat_max",
            "splat_far_max",
            "splat_far_max",
            "depth_epsilon",
            "thesis_photons",
            "thesis_base",
            "environment_directions",
            "environment_resolution",
            "buffer_divisor",
        ];
        for (s, field) in bad.iter().zip(fields) {
            assert!(s.validate().unwrap_err().contains(&format!("caustics.{field}")), "{field}");
        }
    }
}
