//! Typed render settings with documented defaults.
//!
//! Sessions (`[composite]`, `[shadows]`, `method`) and the command line fill these; they are
//! validated once (`validate`) and then passed by value to the passes. Every field documents
//! its trade-off and, where the spec gives one, its source.

mod caustics;
mod composite;
mod dir;
mod dlpv;
mod dvct;
mod ibl;
mod limits;
mod reference;
mod shadows;
mod specular;

pub use caustics::{CausticsSettings, Concentration, MAX_SPLAT_RATIO};
pub use composite::{CompositeMode, CompositeSettings};
pub use dir::{BounceMethod, DirSettings, Distribution, MAX_ISM_POINTS, TemporalSettings};
pub use dlpv::{DlpvSettings, DlpvSplat, DlpvTransport};
pub use dvct::DvctSettings;
pub use ibl::{IblSettings, PrtSpecular, VirtualShading};
pub use limits::{DEFAULT_IMAGE_PIXELS, Limits};
pub use reference::{MAX_REFERENCE_SPP, ReferenceSettings};
pub use shadows::ShadowSettings;
pub use specular::{InternalReflections, Intersection, Refraction, RefractionPolicy, SpecularSettings};

use serde::{Deserialize, Serialize};

/// The light-transport method that computes `L_rv` and `L_r`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Direct light only: punctual lights with real-only and virtual-only shadow maps
    /// (Knecht Eq. 5.1–5.5) plus unshadowed image-based light from the probe.
    Direct,
    /// Differential instant radiosity (Knecht §2.7–§2.10): VPLs from reflective shadow maps,
    /// the probe and a multiple-bounce source, imperfect shadow maps, interleaved sampling,
    /// geometry-aware filtering and temporal smoothing; shadows and light both ways between
    /// real and virtual.
    #[default]
    Dir,
    /// Delta voxel cone tracing (Franke §2.13): the scene around the virtual content
    /// voxelised, its first bounce (and a second) injected per voxel for both solutions,
    /// mipmapped, and gathered per pixel by nine diffuse cones and one glossy cone; the
    /// cones' occlusion shadows the probe. Punctual shadows come from the shadow maps.
    Dvct,
    /// Delta light propagation volumes (Franke §2.12): per light (and per directional light
    /// split from the probe) a real-only and a real+virtual reflective shadow map, their
    /// difference injected as signed SH into a volume around the virtual content and
    /// propagated; a regular volume lights the virtual objects. Punctual shadows come from
    /// the shadow maps, the probe's shadow from the volume.
    Dlpv,
}

impl Method {
    /// Every method, for `--help` and error messages.
    pub const ALL: &'static [Method] = &[Method::Dir, Method::Direct, Method::Dvct, Method::Dlpv];

    /// The name used in sessions and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Method::Direct => "direct",
            Method::Dir => "dir",
            Method::Dvct => "dvct",
            Method::Dlpv => "dlpv",
        }
    }

    /// Whether virtual objects shadow the probe's light through directional VPLs (`dir`), which
    /// the probe's photons then complete (`RenderSettings::probe_caustics`); `direct` lights
    /// with the probe unshadowed, `dvct` shadows it by its cones' occlusion.
    pub fn shadows_probe(self) -> bool {
        match self {
            Method::Direct | Method::Dvct | Method::Dlpv => false,
            Method::Dir => true,
        }
    }

    /// Frames a still image takes by default: one for `direct`; 256 for `dir`, whose multiple
    /// bounces build up over the first frames and whose still-scene smoothing then averages
    /// the VPLs of about 250 frames (`dir.temporal.static_confidence`), the last 128 frames'
    /// composites being averaged with sub-pixel jitter. Milliseconds on a GPU; minutes on
    /// lavapipe. Eight for `dlpv`, which draws no random samples: the last four, jittered,
    /// anti-alias the virtual objects' edges and smooth its blocks, as a path tracer's pixel is
    /// a mean over its area (`dvct`'s desk-spot-real 0.121 → 0.114 when it drew none either;
    /// sixteen frames gained nothing more). 64 for `dvct`, whose still frames draw the probe's
    /// lights anew (`dvct.sample_probe_lights`): the last 32 average 1024 directions of the
    /// probe (desk-bunny's region FLIP 0.0618 at 64 frames; with independent random
    /// directions 0.0676 at 32, 0.0615 at 64, 0.0582 at 128).
    pub fn default_still_frames(self) -> u32 {
        match self {
            Method::Direct => 1,
            Method::Dlpv => 8,
            Method::Dvct => 64,
            Method::Dir => 256,
        }
    }

    /// Parses a method name.
    pub fn from_name(name: &str) -> Result<Self, String> {
        Self::ALL.iter().copied().find(|m| m.name() == name).ok_or_else(|| {
            let known: Vec<_> = Self::ALL.iter().map(|m| m.name()).collect();
            format!("unknown method `{name}` (known: {})", known.join(", "))
        })
    }
}

/// Everything that selects how a frame is computed (not what is in it).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RenderSettings {
    /// Light-transport method.
    pub method: Method,
    /// How `L_rv` and `L_r` are merged with the photo.
    pub composite: CompositeSettings,
    /// Shadow maps of punctual lights.
    pub shadows: ShadowSettings,
    /// The `dir` method.
    pub dir: DirSettings,
    /// The `dvct` method.
    pub dvct: DvctSettings,
    /// The `dlpv` method.
    pub dlpv: DlpvSettings,
    /// The probe's light on virtual objects (every method).
    pub ibl: IblSettings,
    /// Reflections and refractions (the specular stage, with every method).
    pub specular: SpecularSettings,
    /// Caustics of the punctual lights through the specular stage's objects.
    pub caustics: CausticsSettings,
    /// The CPU reference path tracer (`mrshade reference`).
    pub reference: ReferenceSettings,
}

impl RenderSettings {
    /// The settings of a still (many frames of one view averaged into one image): those of
    /// frames, but `dir.interleave` is `dir.still_interleave` and `dir.splat_scale` is
    /// `dir.still_splat_scale`.
    pub fn for_still(&self) -> Self {
        let mut still = self.clone();
        still.dir.interleave = self.dir.still_interleave;
        still.dir.splat_scale = self.dir.still_splat_scale;
        still
    }

    /// Whether the probe's light reaches the scene's diffuse surfaces through its mirrors and
    /// glass as photons (`caustics.environment_directions`): only with a method that shadows
    /// the probe (its shadows of transmissive casters are then opaque).
    pub fn probe_caustics(&self) -> bool {
        self.specular.enabled
            && self.caustics.enabled
            && self.caustics.environment_directions > 0
            && self.method.shadows_probe()
    }

    /// Checks every value; the error names the offending field.
    pub fn validate(&self) -> Result<(), String> {
        self.composite.validate()?;
        self.shadows.validate()?;
        self.dir.validate()?;
        self.dvct.validate()?;
        self.dlpv.validate()?;
        self.ibl.validate()?;
        self.specular.validate()?;
        self.caustics.validate()?;
        self.reference.validate()
    }
}

/// `Err` naming `field` unless `ok`.
pub(crate) fn check(ok: bool, field: &str, what: impl std::fmt::Display) -> Result<(), String> {
    if ok { Ok(()) } else { Err(format!("`{field}` {what}")) }
}

/// Checks that `value` is a power of two in `lo..=hi` (`unit`: what it counts, e.g. " texels",
/// or "").
pub(crate) fn check_power_of_two(value: u32, lo: u32, hi: u32, field: &str, unit: &str) -> Result<(), String> {
    check(
        value.is_power_of_two() && (lo..=hi).contains(&value),
        field,
        format!("must be a power of two between {lo} and {hi}{unit}, got {value}"),
    )
}

/// The most directional lights the probe is split into (`dlpv.probe_lights`,
/// `dvct.probe_lights`): the per-pixel passes hold their lookups in a uniform array of as many.
pub const PROBE_LIGHTS_MAX: u32 = 64;

/// Checks a count of directional lights the probe is split into: 0 or a power of two up to
/// `PROBE_LIGHTS_MAX`.
pub(crate) fn check_probe_lights(value: u32, field: &str) -> Result<(), String> {
    check(
        value == 0 || (value.is_power_of_two() && value <= PROBE_LIGHTS_MAX),
        field,
        format!("must be 0 or a power of two up to {PROBE_LIGHTS_MAX}, got {value}"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_documented_values() {
        let s = RenderSettings::default();
        s.validate().unwrap();
        assert_eq!(s.method, Method::Dir);
        assert_eq!(s.composite.mode, CompositeMode::AlphaScaled);
        assert_eq!(s.shadows.resolution, 2048);
    }

    #[test]
    fn unknown_fields_are_rejected() {
        let err = toml::from_str::<RenderSettings>("[shadows]\nresolutoin = 5\n").unwrap_err();
        assert!(err.to_string().contains("resolutoin"), "{err}");
    }

    #[test]
    fn method_names_round_trip() {
        for m in Method::ALL {
            assert_eq!(Method::from_name(m.name()).unwrap(), *m);
        }
        assert!(Method::from_name("magic").unwrap_err().contains("dir, direct, dvct, dlpv"));
    }
}
