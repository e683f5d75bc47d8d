//! Differential instant radiosity settings (Knecht §2.7–§2.10; parameter table §2.15).

use super::{check, check_power_of_two};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// How VPL slots are shared among the primary light sources (§2.8).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Distribution {
    /// Every source (each punctual light, the environment, the multi-bounce source) gets the
    /// same share. The thesis: "In practice we use [this] distribution mode".
    #[default]
    Equal,
    /// Shares proportional to `dir.weights`.
    Weighted,
    /// Shares proportional to each source's summed VPL flux in the previous frame.
    Flux,
}

/// How the multiple-bounce light source places its VPLs (§2.8).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BounceMethod {
    /// No multiple-bounce source: one indirect bounce from each primary light.
    Off,
    /// DIR v2: a BRDF-importance direction per slot; the nearest candidate point within
    /// `bounce_cone_deg` of it wins (the thesis's default).
    #[default]
    Importance,
    /// DIR v1: the candidate with the largest outgoing radiance from the source VPL wins
    /// (biased: over-places VPLs where sources "only see" one surface, Fig. 5.18d).
    Fitness,
}

/// Temporal flicker reduction (§2.10, Eq. 5.11–5.15).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TemporalSettings {
    /// Reuse the previous frame's indirect light at all.
    pub enabled: bool,
    /// `w_p`: weights of the screen-position (x, y in [0, 1]) and depth differences;
    /// thesis (Cornell box): (10, 10, 10000). Smaller values ghost.
    pub position_weights: [f32; 3],
    /// `w_n`: weight of the normal difference; thesis 1.0.
    pub normal_weight: f32,
    /// `w_i`: weight of the cubed illumination change; thesis 0.025. Too low: slow updates;
    /// too high: flicker returns.
    pub illumination_weight: f32,
    /// `c_B`: base confidence, the largest share of the previous frame; not in the thesis
    /// (extraction's suggestion 0.8–0.9). Default 0.9.
    pub base_confidence: f32,
    /// Largest share of the previous frame while nothing in the scene moves. Once the scene
    /// has kept still for a few frames (while the bounces build up), the smoothing becomes
    /// a running mean over the frames since the last change, its weight growing from `c_B`
    /// up to this value, and it no longer tests for illumination changes (a still scene has
    /// none; what changes is only the VPLs' noise). Anything moving resets it to the
    /// thesis's smoothing. Not in the thesis. Default 0.996, a window of about 250 frames'
    /// VPLs: 256 VPLs per frame leave low-frequency noise (a VPL near a surface lights a
    /// blob) that the thesis's c_B = 0.9 (about 19 frames) keeps visible in a still; the
    /// Cornell box's region FLIP goes from 0.107 to 0.082 (docs/benchmarks.md). At `c_B` or
    /// below: off, the thesis's smoothing always.
    pub static_confidence: f32,
    /// Largest share of the previous frame while the camera moves (tracked footage): the
    /// history is reprojected every frame, and a long memory of reprojected values keeps
    /// their small misplacements. It also bounds how far back a frame depends on, so that a
    /// range of a sequence rendered on its own (`render --frames A..B`, after a warm-up)
    /// matches the whole run. Not in the thesis. Default 0.95 (a window of about 20 frames).
    pub moving_camera_confidence: f32,
}

impl Default for TemporalSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            position_weights: [10.0, 10.0, 10000.0],
            normal_weight: 1.0,
            illumination_weight: 0.025,
            base_confidence: 0.9,
            static_confidence: 0.996,
            moving_camera_confidence: 0.95,
        }
    }
}

/// Most surface points in each ISM cloud (`vpl_count × points_per_vpl`): 4 Mi points are
/// 128 MiB per cloud on the GPU, what many devices bind in one buffer; the thesis uses
/// 256 × 1024 = 256 Ki.
pub const MAX_ISM_POINTS: u64 = 1 << 22;

/// Settings of the `dir` method.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DirSettings {
    /// VPLs per frame over all sources; thesis 256.
    pub vpl_count: u32,
    /// Imperfect-shadow-map tile side per VPL; thesis 128×128.
    pub ism_resolution: u32,
    /// Surface points splatted into each VPL's ISM; thesis 1024. Each of the two atlases
    /// (real-only, virtual-only) has its own points.
    pub points_per_vpl: u32,
    /// Interleaved sampling: the G-buffer is split into `interleave × interleave` tiles, each
    /// shaded by a different subset of the VPLs; thesis 4 (4×4).
    pub interleave: u32,
    /// The interleave factor of stills (many frames averaged into one image: `render` of a
    /// photo, `eval`, `render --frame`): 1, every pixel lit by every VPL of every frame.
    /// Interleaving is the thesis's way to shade many VPLs within a frame's budget, and the
    /// geometry-aware filter that joins the tiles blurs the light across them (contact
    /// shadows, creases); a still, averaged over its frames, needs neither. Default 1 (region
    /// FLIP at 640×480, 256 frames, H200, against 4: cornell 0.0753 → 0.0696, desk-bunny
    /// 0.0467 → 0.0457, desk-spot-real 0.0617 → 0.0592, desk-spot-virtual 0.0583 → 0.0572,
    /// desk-mirror 0.0815 → 0.0797). Frames (footage, streams, `bench`) use `interleave`.
    pub still_interleave: u32,
    /// Reflective-shadow-map side per light layer; not in the thesis (suggestion 256–512).
    pub rsm_resolution: u32,
    /// How VPL slots are shared among the sources.
    pub distribution: Distribution,
    /// Source weights for `distribution = "weighted"`: light names, "environment",
    /// "environment_bounce", "bounce", "caustics" (the punctual lights' caustic VPLs; any
    /// other name is an error); unlisted sources weigh 1.
    pub weights: BTreeMap<String, f32>,
    /// The multiple-bounce method.
    pub bounce: BounceMethod,
    /// Cone half-angle of the importance-direction bounce; thesis five degrees.
    pub bounce_cone_deg: f32,
    /// Lower bound of the VPL–receiver distance in the geometry term, as a fraction of the
    /// scene's bounding radius; clamps the 1/d² singularity (not in the thesis; suggestion
    /// 5–10 % of the scene). Default 0.025: the still-scene smoothing averages enough VPLs
    /// for a smaller clamp, which loses less of the light between close surfaces (a torus
    /// lit by the desk it stands on; desk-spot-real region FLIP 0.066 → 0.064 at 256 frames).
    /// Larger values trade that bias for less noise while things move.
    pub clamp_distance: f32,
    /// Screen-space samples per pixel and frame of the near-field bounce: light between
    /// surfaces closer than `clamp_distance`, the part of the VPLs' light that clamping
    /// removes, gathered from the neighbouring pixels' radiance of the previous frame (less
    /// their indirect light, which `near_field_radius` gathers; as
    /// SSDO complements ISMs, Ritschel et al. 2009). Not in the thesis; 0 turns it off.
    /// Default 4.
    pub near_field_samples: u32,
    /// Reach of the multiple-bounce near field, as a fraction of the scene's bounding radius
    /// (as `clamp_distance`): within it, light reflected more than once between close
    /// surfaces (the inside corner of a block and the floor it stands on) is gathered from
    /// the neighbouring pixels' indirect light of the previous frame, and the multiple-bounce
    /// VPLs on surfaces the camera sees there are clamped at it instead of at
    /// `clamp_distance`. At most 128 pixels on screen. Not in the thesis; at most
    /// `clamp_distance`, or `bounce = "off"`, turns it off. Default 0.3 (region FLIP over
    /// four seeds at 640×480, H200: cornell 0.0838 → 0.0731, desk-bunny 0.0514 → 0.0488, the
    /// spot scenes 3–4 % lower; docs/benchmarks.md).
    pub near_field_radius: f32,
    /// Screen-space samples per pixel and frame of the multiple-bounce near field (0–64).
    /// Default 2 (4 scored the same at 256 frames and cost 0.03 ms more at 1080p).
    pub near_field_bounce_samples: u32,
    /// Side of an ISM splat relative to the spacing of the points (`sqrt(area / points)`);
    /// not in the thesis (suggestion 1.5–2). Default 1.5.
    pub splat_scale: f32,
    /// The splat side of stills (as `still_interleave`). Splats wider than the points'
    /// spacing close the holes between them within one frame, but fatten every occluder in
    /// every VPL's map alike: a bias that no number of frames averages away, where the holes
    /// of splats of the spacing's size differ from VPL to VPL and average out over a still's
    /// frames. Default 1 (region FLIP at 640×480, 256 frames, H200, against 1.5: cornell
    /// 0.0696 → 0.0638, desk-bunny 0.0457 → 0.0435, desk-spot-real 0.0592 → 0.0584,
    /// desk-spot-virtual 0.0572 → 0.0565, desk-mirror 0.0797 → 0.0786, desk-glass 0.1015 →
    /// 0.1017; 0.75 let light through, cornell 0.0781). Over 16 frames 1 made cornell worse
    /// (0.1168 → 0.1270): frames keep `splat_scale`.
    pub still_splat_scale: f32,
    /// Depth bias of ISM lookups as a fraction of the distance; default 0.03.
    pub ism_bias: f32,
    /// Offset of a receiver along its normal before ISM lookups, in splat half-sizes, so that
    /// the splats of its own surface do not shadow it; default 1.
    pub ism_normal_offset: f32,
    /// Geometry-aware filtering of the interleaved buffers (depth and normal aware).
    pub filter: bool,
    /// Temporal smoothing.
    pub temporal: TemporalSettings,
    /// Which VPLs the sampling sequences draw: renders with different seeds draw independent
    /// VPLs (the sequences otherwise follow the frame index alone), so that a setting can be
    /// scored over independent runs. Default 0.
    pub seed: u32,
}

impl Default for DirSettings {
    fn default() -> Self {
        Self {
            vpl_count: 256,
            ism_resolution: 128,
            points_per_vpl: 1024,
            interleave: 4,
            still_interleave: 1,
            rsm_resolution: 256,
            distribution: Distribution::Equal,
            weights: BTreeMap::new(),
            bounce: BounceMethod::Importance,
            bounce_cone_deg: 5.0,
            clamp_distance: 0.025,
            near_field_samples: 4,
            near_field_radius: 0.3,
            near_field_bounce_samples: 2,
            splat_scale: 1.5,
            still_splat_scale: 1.0,
            ism_bias: 0.03,
            ism_normal_offset: 1.0,
            filter: true,
            temporal: TemporalSettings::default(),
            seed: 0,
        }
    }
}

impl DirSettings {
    /// Checks every value; the error names the offending field.
    pub fn validate(&self) -> Result<(), String> {
        let i = self.interleave;
        check((1..=8).contains(&i), "dir.interleave", format!("must be between 1 and 8, got {i}"))?;
        let s = self.still_interleave;
        check((1..=8).contains(&s), "dir.still_interleave", format!("must be between 1 and 8, got {s}"))?;
        check(
            self.vpl_count >= s * s,
            "dir.vpl_count",
            format!("must be at least still_interleave² ({}), got {}", s * s, self.vpl_count),
        )?;
        check(
            (i * i..=4096).contains(&self.vpl_count),
            "dir.vpl_count",
            format!("must be between interleave² ({}) and 4096, got {}", i * i, self.vpl_count),
        )?;
        check_power_of_two(self.ism_resolution, 16, 512, "dir.ism_resolution", "")?;
        check(
            (16..=65536).contains(&self.points_per_vpl),
            "dir.points_per_vpl",
            format!("must be between 16 and 65536, got {}", self.points_per_vpl),
        )?;
        let points = self.vpl_count as u64 * self.points_per_vpl as u64;
        check(
            points <= MAX_ISM_POINTS,
            "dir.points_per_vpl",
            format!(
                "× dir.vpl_count = {} × {} = {points} points per cloud, more than {MAX_ISM_POINTS} \
                 (each of the two clouds would take {} MiB); lower one of them",
                self.points_per_vpl,
                self.vpl_count,
                (points * 32) >> 20
            ),
        )?;
        check_power_of_two(self.rsm_resolution, 4, 2048, "dir.rsm_resolution", "")?;
        for (name, samples) in [
            ("dir.near_field_samples", self.near_field_samples),
            ("dir.near_field_bounce_samples", self.near_field_bounce_samples),
        ] {
            check(samples <= 64, name, format!("must be at most 64, got {samples}"))?;
        }
        check(
            self.bounce_cone_deg > 0.0 && self.bounce_cone_deg < 90.0,
            "dir.bounce_cone_deg",
            format!("must be in (0, 90), got {}", self.bounce_cone_deg),
        )?;
        for (name, value, range) in [
            ("dir.clamp_distance", self.clamp_distance, 0.0..1.0),
            ("dir.near_field_radius", self.near_field_radius, 0.0..1.0),
            ("dir.splat_scale", self.splat_scale, 0.1..10.0),
            ("dir.still_splat_scale", self.still_splat_scale, 0.1..10.0),
            ("dir.ism_bias", self.ism_bias, 0.0..0.5),
            ("dir.ism_normal_offset", self.ism_normal_offset, 0.0..10.0),
        ] {
            check(range.contains(&value), name, format!("must be in [{}, {}), got {value}", range.start, range.end))?;
        }
        for (name, w) in &self.weights {
            check(w.is_finite() && *w >= 0.0, "dir.weights", format!("weight of '{name}' must be ≥ 0, got {w}"))?;
        }
        let t = &self.temporal;
        check(
            (0.0..1.0).contains(&t.base_confidence),
            "dir.temporal.base_confidence",
            format!("must be in [0, 1), got {}", t.base_confidence),
        )?;
        check(
            (0.0..1.0).contains(&t.static_confidence),
            "dir.temporal.static_confidence",
            format!("must be in [0, 1), got {}", t.static_confidence),
        )?;
        check(
            (0.0..1.0).contains(&t.moving_camera_confidence),
            "dir.temporal.moving_camera_confidence",
            format!("must be in [0, 1), got {}", t.moving_camera_confidence),
        )?;
        check(
            t.position_weights
                .iter()
                .chain([&t.normal_weight, &t.illumination_weight])
                .all(|w| w.is_finite() && *w >= 0.0),
            "dir.temporal",
            "weights must be finite and ≥ 0",
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_thesis_values() {
        let d = DirSettings::default();
        assert_eq!((d.vpl_count, d.ism_resolution, d.points_per_vpl, d.interleave), (256, 128, 1024, 4));
        assert_eq!(d.temporal.position_weights, [10.0, 10.0, 10000.0]);
        assert_eq!((d.temporal.normal_weight, d.temporal.illumination_weight), (1.0, 0.025));
        assert_eq!(d.bounce_cone_deg, 5.0);
        d.validate().unwrap();
    }

    #[test]
    fn a_still_takes_the_still_interleave_and_splat_scale() {
        let settings = crate::settings::RenderSettings::default();
        assert_eq!((settings.dir.interleave, settings.dir.still_interleave), (4, 1));
        assert_eq!((settings.dir.splat_scale, settings.dir.still_splat_scale), (1.5, 1.0));
        let still = settings.for_still();
        assert_eq!((still.dir.interleave, still.dir.splat_scale), (1, 1.0));
        assert_eq!(crate::settings::RenderSettings { dir: settings.dir.clone(), ..still.clone() }, settings);
        let bad = DirSettings { still_interleave: 9, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("dir.still_interleave"));
        let few = DirSettings { vpl_count: 16, still_interleave: 8, interleave: 1, ..Default::default() };
        assert!(few.validate().unwrap_err().contains("dir.vpl_count"));
    }

    #[test]
    fn bad_values_name_their_field() {
        let d = DirSettings { ism_resolution: 100, ..Default::default() };
        assert!(d.validate().unwrap_err().contains("dir.ism_resolution"));
        let d = DirSettings { rsm_resolution: 2, ..Default::default() };
        assert!(d.validate().unwrap_err().contains("dir.rsm_resolution"));
        let d = DirSettings { vpl_count: 8, ..Default::default() };
        assert!(d.validate().unwrap_err().contains("dir.vpl_count"));
        let d = DirSettings { near_field_radius: f32::NAN, ..Default::default() };
        assert!(d.validate().unwrap_err().contains("dir.near_field_radius"));
        let d = DirSettings { still_splat_scale: 0.0, ..Default::default() };
        assert!(d.validate().unwrap_err().contains("dir.still_splat_scale"));
        let d = DirSettings { near_field_bounce_samples: 65, ..Default::default() };
        assert!(d.validate().unwrap_err().contains("dir.near_field_bounce_samples"));
        // Each valid alone, too many together (8 GB of points).
        let d = DirSettings { vpl_count: 4096, points_per_vpl: 65536, ..Default::default() };
        let err = d.validate().unwrap_err();
        assert!(err.contains("dir.points_per_vpl") && err.contains("dir.vpl_count"), "{err}");
        DirSettings { vpl_count: 4096, points_per_vpl: 1024, ..Default::default() }.validate().unwrap();
        let mut d = DirSettings::default();
        d.temporal.base_confidence = 1.0;
        assert!(d.validate().unwrap_err().contains("base_confidence"));
        let mut d = DirSettings::default();
        d.temporal.static_confidence = 1.0;
        assert!(d.validate().unwrap_err().contains("static_confidence"));
        d.temporal.static_confidence = 0.5;
        d.temporal.moving_camera_confidence = f32::NAN;
        assert!(d.validate().unwrap_err().contains("moving_camera_confidence"));
    }

    #[test]
    fn parses_strictly_from_toml() {
        let d: DirSettings =
            toml::from_str("vpl_count = 64\nbounce = \"fitness\"\n[temporal]\nbase_confidence = 0.5\n").unwrap();
        assert_eq!((d.vpl_count, d.bounce, d.temporal.base_confidence), (64, BounceMethod::Fitness, 0.5));
        assert!(toml::from_str::<DirSettings>("vpl = 64").is_err());
        assert!(toml::from_str::<DirSettings>("bounce = \"sideways\"").is_err());
    }
}
