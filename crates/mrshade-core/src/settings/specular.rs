//! The specular stage: reflections and refractions of mirror-like and transmissive surfaces,
//! seen through impostors and looked up in the photo (Winklhofer's thesis [T] and the TVCG
//! paper [P]; extraction `reflections-refractions-caustics.md`, defaults from its §3.2).

use super::check;
use serde::{Deserialize, Serialize};

/// How a reflected or refracted ray finds the surface it hits (spec §2.13–§2.16).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Intersection {
    /// Depth-refined impostors (spec §2.16, the thesis's default): every other object seen
    /// from the specular object's centre through an orthographic camera, marched linearly and
    /// refined by bisection; the hit texel's triangle is then intersected exactly.
    #[default]
    Impostor,
    /// Standard cubic environment mapping (spec §2.14): a 90° cube of every other object seen
    /// from the specular object's centre; the texel in the ray's *direction* gives the
    /// surface (its plane then meets the ray), whatever the ray's origin, as the thesis's
    /// baseline does ("the captured environment is only accurate at its center"). One
    /// bounce of the cube; self-reflections from the object's own triangles.
    Cube,
    /// Layered cubic environment mapping (spec §2.15, Umenhoffer et al.): the same cubes
    /// marched along the ray (`linear_steps`, then `binary_steps` of bisection on the first
    /// under/overshoot pair), one layer per other object; the object's own front- and
    /// back-face layers are replaced by the exact intersection of its own triangles.
    LayeredCube,
    /// Planar reflection (spec §2.13): every flat mirror-like object draws the scene seen
    /// from the camera mirrored about its plane (clipped at the plane) into a texture of the
    /// frame's size, and its smooth camera reflections read their surface at their own pixel,
    /// exact to the pixel. Redrawn whenever the camera or an object moves. What it cannot
    /// serve (curved or rough reflectors, refractions, further bounces, photons) is marched
    /// through impostors, as `impostor` does (the thesis's planar method has none of these).
    Planar,
}

/// How a refracted ray finds where it leaves a transmissive object.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Refraction {
    /// Traced exactly through the object's own triangles (a BVH per rigid object): the true
    /// exit, total internal reflection and several internal bounces. Beyond the documents,
    /// which name this their future work (spec §5.2); deforming objects use
    /// `two-interfaces`.
    #[default]
    Traced,
    /// Wyman's image-space two-interface approximation (spec §2.12): the exit estimated from
    /// the object's farthest surface along the view ray; no total internal reflection.
    TwoInterfaces,
}

/// What a traced refraction does with the share F that an interface reflects back inside.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum InternalReflections {
    /// At each internal hit the ray stays inside with probability F (Schlick's Fresnel from
    /// the outside angle), else leaves, a different choice per pixel and frame: unbiased,
    /// and still images and the temporal smoothing average the choices. The longer paths
    /// carry more of the glass's colour. Beyond the documents.
    #[default]
    Sampled,
    /// Every ray leaves at its first internal hit that lets it out, weighted by 1 − F; the
    /// share F is lost (total internal reflection is still followed). No noise.
    Dropped,
}

/// What a refractive pixel shows when one of its two back-projections fails (spec §2.8).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RefractionPolicy {
    /// Policy B, the paper's: keep the refracted photo and drop the photo in the reflection
    /// ("creates less artifacts" [T Fig. 4.15b]); the reflection is then rendered.
    #[default]
    KeepRefraction,
    /// Policy A: both parts rendered (`L'_rv`) as soon as either back-projection fails
    /// ("from a formal point of view … more appropriate").
    Rendered,
}

/// Settings of the specular stage.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SpecularSettings {
    /// Trace reflections and refractions of mirror-like and transmissive materials. The stage
    /// runs only when the scene holds such a material; off, they reflect and refract the
    /// probe alone. Default on.
    pub enabled: bool,
    /// Ray intersection technique: `impostor`, `cube`, `layered-cube` or `planar`. Default
    /// `impostor`.
    pub intersection: Intersection,
    /// Side of each cube-map face of `cube` and `layered-cube`, texels. Default 512 [T §7:
    /// 512×512×6].
    pub cube_resolution: u32,
    /// Side of each impostor texture, texels. Default 512 [T §7, P §7].
    pub impostor_resolution: u32,
    /// Linear search steps of the impostor march. Default 64 [T §7].
    pub linear_steps: u32,
    /// Binary refinement steps after the first under/overshoot pair. Default 8 [T §7].
    pub binary_steps: u32,
    /// Specular surfaces a ray may pass through after the first one, before the surface it
    /// reaches is shaded as if diffuse. The thesis shows 0–3 ("more than three bounces are
    /// barely recognisable"); default 2.
    pub max_bounces: u32,
    /// Materials up to this roughness are traced (rougher ones keep the probe's prefiltered
    /// reflection). Glossy ones are traced with one GGX-sampled ray per pixel and frame, which
    /// still images and temporal smoothing average. Not in the documents, which are
    /// mirror-only [T §3.4, limitation L17]; default 0.5.
    pub max_roughness: f32,
    /// A glossy ray that leaves the scene reads the probe prefiltered for the surface's
    /// roughness times this, around its own sampled direction (the rays are drawn from the
    /// GGX normals visible from the eye, Heitz 2018): 0 reads one unfiltered direction (exact
    /// over many frames, sparkling in each), 1 a lobe as wide as the surface's around each
    /// sample (smooth, the highlight about 40 % too wide). Not in the documents. Default 0.6
    /// (about 6 % too wide).
    pub probe_lobe: f32,
    /// A reflected or refracted point is the photo's pixel it projects to when its depth is
    /// within this fraction of the camera's depth there (spec §2.8; the documents set it by
    /// hand). Default 0.02.
    pub backprojection_epsilon: f32,
    /// Refractive failure policy. Default `keep-refraction` (B).
    pub refraction_policy: RefractionPolicy,
    /// How refracted rays leave transmissive objects. Default `traced`.
    pub refraction: Refraction,
    /// Partial internal reflections of traced refractions (and of photons). Default
    /// `sampled`.
    pub internal_reflections: InternalReflections,
    /// Temporal smoothing of the stage's light (spec §2.19: the paper smooths `L'_rv` and
    /// `L'_r` against flicker, filter not stated): each pixel's last value, found through the
    /// G-buffer's motion, is blended in with this weight on frames where the camera, an
    /// object, a light or the photo changed, after clamping it to the range of this frame's
    /// values around the pixel (so that what the change uncovers or moves does not trail);
    /// while nothing changes, the frames since the last change are averaged. It calms the
    /// one glossy ray and the one internal-reflection choice per pixel and frame, and the
    /// photons' per-frame directions, in a live stream. 0: off. Default 0.8 (ours).
    pub temporal_weight: f32,
}

impl Default for SpecularSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            intersection: Intersection::Impostor,
            cube_resolution: 512,
            impostor_resolution: 512,
            linear_steps: 64,
            binary_steps: 8,
            max_bounces: 2,
            max_roughness: 0.5,
            probe_lobe: 0.6,
            backprojection_epsilon: 0.02,
            refraction_policy: RefractionPolicy::KeepRefraction,
            refraction: Refraction::Traced,
            internal_reflections: InternalReflections::Sampled,
            temporal_weight: 0.8,
        }
    }
}

impl SpecularSettings {
    /// Whether the stage traces a material of these factors: transmissive ones, and metals up
    /// to `max_roughness`.
    pub fn traces(&self, metallic: f32, roughness: f32, transmission: f32) -> bool {
        self.enabled && roughness <= self.max_roughness && (transmission > 0.0 || metallic > 0.0)
    }

    /// Checks every value; the error names the offending field.
    pub fn validate(&self) -> Result<(), String> {
        check(
            (16..=4096).contains(&self.impostor_resolution),
            "specular.impostor_resolution",
            format!("must be between 16 and 4096 texels, got {}", self.impostor_resolution),
        )?;
        check(
            (16..=4096).contains(&self.cube_resolution),
            "specular.cube_resolution",
            format!("must be between 16 and 4096 texels, got {}", self.cube_resolution),
        )?;
        check(
            (1..=1024).contains(&self.linear_steps),
            "specular.linear_steps",
            format!("must be between 1 and 1024, got {}", self.linear_steps),
        )?;
        check(
            self.binary_steps <= 32,
            "specular.binary_steps",
            format!("must be at most 32, got {}", self.binary_steps),
        )?;
        check(self.max_bounces <= 8, "specular.max_bounces", format!("must be at most 8, got {}", self.max_bounces))?;
        check(
            self.max_roughness.is_finite() && (0.0..=1.0).contains(&self.max_roughness),
            "specular.max_roughness",
            format!("must be a number in [0, 1], got {}", self.max_roughness),
        )?;
        check(
            self.probe_lobe.is_finite() && (0.0..=1.0).contains(&self.probe_lobe),
            "specular.probe_lobe",
            format!("must be a number in [0, 1], got {}", self.probe_lobe),
        )?;
        check(
            self.backprojection_epsilon.is_finite()
                && self.backprojection_epsilon > 0.0
                && self.backprojection_epsilon < 1.0,
            "specular.backprojection_epsilon",
            format!("must be a number in (0, 1), got {}", self.backprojection_epsilon),
        )?;
        check(
            self.temporal_weight.is_finite() && (0.0..1.0).contains(&self.temporal_weight),
            "specular.temporal_weight",
            format!("must be a number in [0, 1), got {}", self.temporal_weight),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_documents_values() {
        let s = SpecularSettings::default();
        s.validate().unwrap();
        assert_eq!((s.impostor_resolution, s.linear_steps, s.binary_steps), (512, 64, 8));
        assert_eq!(s.intersection, Intersection::Impostor);
        assert_eq!(s.cube_resolution, 512);
        assert_eq!(s.refraction_policy, RefractionPolicy::KeepRefraction);
    }

    #[test]
    fn traces_mirrors_and_glass_only() {
        let s = SpecularSettings::default();
        assert!(s.traces(1.0, 0.0, 0.0));
        assert!(s.traces(0.0, 0.0, 1.0));
        assert!(!s.traces(0.0, 0.0, 0.0), "a smooth dielectric keeps the probe");
        assert!(!s.traces(1.0, 0.9, 0.0), "rough metal keeps the prefiltered probe");
        assert!(!SpecularSettings { enabled: false, ..s }.traces(1.0, 0.0, 0.0));
    }

    #[test]
    fn bad_values_are_named() {
        let bad = SpecularSettings { linear_steps: 0, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("specular.linear_steps"));
        let bad = SpecularSettings { probe_lobe: 1.5, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("specular.probe_lobe"));
        let bad = SpecularSettings { backprojection_epsilon: f32::NAN, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("backprojection_epsilon"));
        let err = toml::from_str::<SpecularSettings>("refraction_policy = \"c\"").unwrap_err();
        assert!(err.to_string().contains("keep-refraction"), "{err}");
        let bad = SpecularSettings { temporal_weight: 1.0, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("specular.temporal_weight"));
        let bad = SpecularSettings { cube_resolution: 8, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("specular.cube_resolution"));
        let err = toml::from_str::<SpecularSettings>("intersection = \"planar-cube\"").unwrap_err();
        assert!(err.to_string().contains("layered-cube"), "{err}");
        let parsed: SpecularSettings = toml::from_str("intersection = \"layered-cube\"").unwrap();
        assert_eq!(parsed.intersection, Intersection::LayeredCube);
        let parsed: SpecularSettings = toml::from_str("intersection = \"planar\"").unwrap();
        assert_eq!(parsed.intersection, Intersection::Planar);
        let err = toml::from_str::<SpecularSettings>("internal_reflections = \"kept\"").unwrap_err();
        assert!(err.to_string().contains("sampled") && err.to_string().contains("dropped"), "{err}");
    }
}
