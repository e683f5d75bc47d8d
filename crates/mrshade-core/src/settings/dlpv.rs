//! Delta light propagation volumes, the `dlpv` method (Franke §2.12, [Fra13a]): per light a
//! real-only and a real+virtual reflective shadow map, their difference injected as signed
//! second-order SH into a volume around the virtual content and propagated, plus a regular
//! volume for the virtual objects' own indirect light.

use super::{check, check_power_of_two, check_probe_lights};
use serde::{Deserialize, Serialize};

/// How a VPL is added to the volume.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum DlpvSplat {
    /// Into the one cell it lies in, after the half-cell shift along its lobe (spec §2.12.2:
    /// "shift the VPL by half the size of a voxel along its normal before determining the
    /// voxel", [KD10]); the default, as in the thesis.
    #[default]
    #[serde(rename = "cell")]
    Cell,
    /// Shared among the eight cells around it by trilinear weights: smoother as a VPL
    /// crosses cells, eight times the atomic additions.
    #[serde(rename = "trilinear")]
    Trilinear,
}

/// How a volume's bounce light reaches its cells (`dlpv.virtual_light`, `dlpv.bounce_light`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum DlpvTransport {
    /// Summed over the lights' VPLs at every cell (the maps' texels gathered in blocks of
    /// `dlpv.gather_block`²): the inverse-square falloff at every distance; the default.
    #[default]
    #[serde(rename = "gathered")]
    Gathered,
    /// Injected and propagated (the thesis's): light walks about √steps cells and pools near
    /// its source (docs/benchmarks.md, 2026-12-04).
    #[serde(rename = "propagated")]
    Propagated,
}

/// Settings of the `dlpv` method. Defaults are the thesis's (spec §2.12.7).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DlpvSettings {
    /// Cells along each side of the volumes (a power of two, 8–64: 128³ cells' injection
    /// buffer, 400 MB, is past what a GPU binds at once). Default 32 (spec §2.12.7: "32³ …
    /// typically in the range of 32³ to 64³").
    pub resolution: u32,
    /// Side of the cubic volume as a multiple of the virtual content's largest bounding-box
    /// edge, centred on it. Default 2 ("twice the largest bounding box axis").
    pub extent: f32,
    /// Propagation steps of the volumes that are propagated (`virtual_light`, `bounce_light`;
    /// 1–256). Default 32.
    pub propagation_steps: u32,
    /// Propagation steps of the direct change (0–256). Default 0: the thesis's code
    /// propagates it 5 steps (`render_direct(…, 5, …)`), but with nothing in the volume to
    /// stop it the antiradiance then spreads through and beside the shadowed surface (region
    /// FLIP on desk-bunny 0.187 with 5 steps, 0.148 with none).
    pub direct_steps: u32,
    /// Side of the scene lights' reflective shadow maps, every texel injected as a VPL (a
    /// power of two, 32–2048). Default 512 (spec §2.12.7).
    pub rsm_resolution: u32,
    /// Side of the maps of the probe's directional lights (a power of two, 32–2048). Default
    /// 64: 0.13–0.21 ms less per moving frame than 128 on an H100 at 1080p (maps, injection,
    /// the gathered V_ρ's VPLs), at region FLIP on lavapipe 0.1744 → 0.1745 (cornell), 0.1243
    /// → 0.1263 (desk-bunny), 0.1649 → 0.1670 (desk-spot-real), 0.1019 → 0.1042
    /// (desk-spot-virtual); 512² maps cost 3.3 ms to draw and 3 ms to inject on the H200.
    pub probe_rsm_resolution: u32,
    /// Directional lights the probe is split into (median cut; 0 or a power of two up to 64):
    /// their maps carry the probe's light into both volumes and its shadow into the direct
    /// change, and shadow the probe on virtual surfaces (spec §2.12.1: lights "extracted from
    /// a hemispherical image"; not in the thesis's setups). Default 32 (desk-bunny region
    /// FLIP 0.353 / 0.303 / 0.311 with 8 / 32 / 64).
    pub probe_lights: u32,
    /// How each VPL enters the volume: `cell` (default, the thesis's) or `trilinear`.
    pub splat: DlpvSplat,
    /// Angular radius (degrees) up to which a probe light casts the virtual content's shadow
    /// on real surfaces through its maps (`soft_probe_shadows`: hard or soft); from twice it
    /// on, through the volume's direct change (soft, 32³ cells, and only inside the volume);
    /// in between, both by weight. 0 leaves every light to the volume (the thesis's). Default
    /// 15: the volume blurred the bunny's contact shadow over its cells and ends a shadow at
    /// its own edge, and hard shadows of lights broader than that draw a star of edges where
    /// the answer's shadow is soft — the more since the model of the photo holds no
    /// self-light (`bounce_light`). Region FLIP on lavapipe, 640×480, with 8.4 / 12 / 15 / 18 /
    /// 30°: desk-bunny 0.1149 / 0.1112 / 0.1057 / 0.1044 / 0.1171 (paste 0.114),
    /// desk-spot-virtual 0.1007 / 0.1095 / 0.1141 / 0.1164 / 0.1179, cornell 0.160–0.161 and
    /// desk-spot-real 0.131–0.133 with all (docs/benchmarks.md, 2026-12-06).
    pub sharp_probe_shadows_deg: f32,
    /// Those lights' shadows soft by each light's angular radius (percentage-closer soft
    /// shadows over the maps) or, by default, hard (one map texel per light). Soft costs 0.17–
    /// 0.47 ms more per moving 1080p frame on an H100 (the merge; desk-spot-real 1.50 → 1.96
    /// ms, past the method's 1.5 ms), for region FLIP desk-bunny 0.1094 → 0.1045,
    /// desk-spot-virtual 0.1021 → 0.0954, cornell and desk-spot-real alike (H100, 640×480).
    pub soft_probe_shadows: bool,
    /// The probe's shadows on virtual surfaces soft by each light's angular radius, both the
    /// real scene's and the virtual content's, or, by default, hard (one map texel per light).
    /// Each of the probe's lights stands for a patch of the probe: hard, the edges of the
    /// patches a wall lets through draw stripes across cornell's blocks (the probe lights
    /// through the box's open side). Region FLIP on lavapipe, 640×480, hard → soft: cornell
    /// 0.1547 → 0.1500, desk-bunny 0.1066 → 0.1044, desk-spot-real 0.1312 → 0.1127,
    /// desk-spot-virtual 0.1132 → 0.1137; it costs 0.12–0.41 ms more per moving 1080p frame
    /// on an H100 (the merge; cornell 1.35 → 1.79 ms, past the method's 1.5 ms): an option for
    /// stills and comparisons (docs/benchmarks.md, 2026-12-06).
    pub soft_virtual_probe_shadows: bool,
    /// Where V_ρ, the virtual objects' light from the real scene, comes from: `gathered`
    /// (default) or `propagated` (the thesis's).
    pub virtual_light: DlpvTransport,
    /// Where the real surfaces' bounce light comes from: V_μ, the real scene's own (the model
    /// of the photo), and the indirect change of V_Δ (the virtual surfaces' bounce light, less
    /// that of the real surfaces they hide from a light): `gathered` (default; the signed
    /// VPLs of the change summed at every cell, V_μ's VPLs with the photo's light as V_ρ's)
    /// or `propagated` (the thesis's). Propagated, a floor lights itself through its own
    /// cells (spec §2.12.9): in cornell's shadows V_μ held twice the photo's bounce light,
    /// grey where the answer's is the red wall's, and V_Δ took that self-light away with the
    /// floor a block hides; and the light of the blocks' lit tops never reached the back wall
    /// (docs/benchmarks.md, 2026-12-06).
    pub bounce_light: DlpvTransport,
    /// With the gathered volumes: the virtual surfaces pass on the light they take from the
    /// real scene, and stand in the way of the light they pass on. The virtual surfaces the
    /// maps see mark the cells they lie in with their mean plane per way they face; each
    /// sends the light its surface takes from V_ρ on as a VPL (vpl_aggregate.wgsl
    /// `cell_vpls`), into V_ρ (one virtual surface lights another: the red wall's light off
    /// cornell's cube onto the tall block's foot, a third of the light there in the path
    /// tracer's answer) and, where the paths are tested, into V_Δ (the content's own bounce
    /// light on the real surfaces); in V_ρ's cells a VPL's light that crosses a marked plane on
    /// its way is left out (the added light without it came through the blocks). Region FLIP
    /// on lavapipe, 640×480, off → on: cornell 0.1547 → 0.1282 (paste 0.135), desk-bunny
    /// 0.1066 → 0.1091 (0.114), desk-spot-real 0.1312 → 0.1295, desk-spot-virtual 0.1132 →
    /// 0.1110, and three Cornell variants 0.1395 / 0.1286 / 0.1391 → 0.1103 / 0.1135 / 0.1079
    /// (paste 0.1146 / 0.1412 / 0.1371): below paste on all. The paths are tested against
    /// per-part visibility maps (1 024 directions per 2³ cells, visibility.wgsl), which costs a
    /// little of that: cornell 0.1310, desk-bunny 0.1100, desk-spot-real 0.1302,
    /// desk-spot-virtual 0.1110, the variants 0.1130 / 0.1200 / 0.1114. It costs 0.17–0.32 ms
    /// more per 1080p frame in which the content moves on an H100 (cornell 1.26 → 1.46 ms,
    /// desk-bunny 1.00 → 1.18, desk-spot-real 1.31 → 1.48, desk-spot-virtual 1.32 → 1.64; a
    /// march per path instead of the maps cost 0.5 ms more again), past the method's 1.5 ms
    /// on desk-spot-virtual: such frames leave it out unless `virtual_bounce_moving` (the
    /// frames after the content and the lights came to rest gather it again, twice, as the
    /// surfaces' light converges). Default true.
    pub virtual_bounce: bool,
    /// With `dlpv.virtual_bounce`: whether the frames in which the virtual content or a light
    /// moves gather the virtual surfaces' bounce too (0.17–0.32 ms more per such frame on an
    /// H100, past the method's 1.5 ms on desk-spot-virtual), rather than only the frames of a
    /// content at rest. Default false.
    pub virtual_bounce_moving: bool,
    /// With `dlpv.virtual_bounce`: the paths' test in every cell, not only in V_ρ's; a VPL's
    /// light to a cell that crosses a virtual surface on the way also leaves V_Δ (the real
    /// bounce light the content blocks: the tall block's shadow of cornell's red wall on the
    /// back wall). It costs the gather 0.5–0.9 ms more per moving 1080p frame on an H100
    /// (vpl_gather.wgsl `VISIBILITY_PARTS`), past the method's 1.5 ms: an option for stills and
    /// comparisons (docs/benchmarks.md, 2026-12-06). Default false.
    pub bounce_visibility: bool,
    /// Texels per side of the blocks of a map summed into one VPL of the gathered V_ρ (a
    /// power of two, 8–256; at most a map's side). Default 16: 1024 VPLs per 512² map, 16 per
    /// probe light's 64². With the photo's light the maps light only what the camera does not
    /// see, and 8 scores alike (region FLIP on lavapipe, desk-spot-real 0.1641 / 0.1649 with 8 /
    /// 16, cornell 0.1743 / 0.1744) at 0.07 ms more on an H100 (desk-spot-virtual, 1080p);
    /// without it 8 scored best (cornell 0.2141 / 0.1904 / 0.1861 with 32 / 16 / 8).
    pub gather_block: u32,
    /// In the gathered volumes (V_ρ, V_μ): the real surfaces the camera sees light the other
    /// surfaces with the radiance the photo shows of them (every bounce of the real scene),
    /// the maps' VPLs the surfaces it does not see. Default true.
    pub photo_bounce: bool,
}

impl Default for DlpvSettings {
    fn default() -> Self {
        Self {
            resolution: 32,
            extent: 2.0,
            propagation_steps: 32,
            direct_steps: 0,
            rsm_resolution: 512,
            probe_rsm_resolution: 64,
            probe_lights: 32,
            splat: DlpvSplat::Cell,
            sharp_probe_shadows_deg: 15.0,
            virtual_light: DlpvTransport::Gathered,
            bounce_light: DlpvTransport::Gathered,
            gather_block: 16,
            photo_bounce: true,
            soft_probe_shadows: false,
            soft_virtual_probe_shadows: false,
            virtual_bounce: true,
            virtual_bounce_moving: false,
            bounce_visibility: false,
        }
    }
}

impl DlpvSettings {
    /// Checks every value; the error names the offending field.
    pub fn validate(&self) -> Result<(), String> {
        check_power_of_two(self.resolution, 8, 64, "dlpv.resolution", " cells")?;
        check(
            self.extent.is_finite() && (1.0..=64.0).contains(&self.extent),
            "dlpv.extent",
            format!("must be between 1 and 64 times the virtual content's size, got {}", self.extent),
        )?;
        check(
            (1..=256).contains(&self.propagation_steps),
            "dlpv.propagation_steps",
            format!("must be between 1 and 256, got {}", self.propagation_steps),
        )?;
        check(
            self.direct_steps <= 256,
            "dlpv.direct_steps",
            format!("must be between 0 and 256, got {}", self.direct_steps),
        )?;
        check_power_of_two(self.rsm_resolution, 32, 2048, "dlpv.rsm_resolution", " texels")?;
        check_power_of_two(self.probe_rsm_resolution, 32, 2048, "dlpv.probe_rsm_resolution", " texels")?;
        check(
            self.sharp_probe_shadows_deg.is_finite() && (0.0..=90.0).contains(&self.sharp_probe_shadows_deg),
            "dlpv.sharp_probe_shadows_deg",
            format!("must be between 0 and 90 degrees, got {}", self.sharp_probe_shadows_deg),
        )?;
        check_power_of_two(self.gather_block, 8, 256, "dlpv.gather_block", " texels")?;
        check(
            self.virtual_bounce || !self.bounce_visibility,
            "dlpv.bounce_visibility",
            "needs `dlpv.virtual_bounce` (the planes it tests the paths against)",
        )?;
        check_probe_lights(self.probe_lights, "dlpv.probe_lights")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_values_are_named() {
        let cases: [(DlpvSettings, &str); 7] = [
            (DlpvSettings { resolution: 48, ..Default::default() }, "dlpv.resolution"),
            (DlpvSettings { propagation_steps: 0, ..Default::default() }, "dlpv.propagation_steps"),
            (DlpvSettings { rsm_resolution: 4096, ..Default::default() }, "dlpv.rsm_resolution"),
            (DlpvSettings { probe_lights: 6, ..Default::default() }, "dlpv.probe_lights"),
            (DlpvSettings { sharp_probe_shadows_deg: f32::NAN, ..Default::default() }, "dlpv.sharp_probe_shadows_deg"),
            (DlpvSettings { gather_block: 4, ..Default::default() }, "dlpv.gather_block"),
            (
                DlpvSettings { virtual_bounce: false, bounce_visibility: true, ..Default::default() },
                "dlpv.bounce_visibility",
            ),
        ];
        for (bad, name) in cases {
            assert!(bad.validate().unwrap_err().contains(name), "{name}");
        }
        DlpvSettings::default().validate().unwrap();
    }
}
