//! Delta voxel cone tracing, the `dvct` method (Franke §2.13, [Fra14a]): the real and virtual
//! scene voxelised around the virtual content, its first bounce injected per voxel, 3D mipmaps
//! and per-pixel cone tracing.

use super::{check, check_power_of_two, check_probe_lights};
use serde::{Deserialize, Serialize};

/// Settings of the `dvct` method.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DvctSettings {
    /// Voxels along each side of the volumes (a power of two, 16–512). The thesis's standard
    /// is 256³ (tested 64³–512³, spec §2.13.7); default 128³, the resolution the speed target
    /// is set at, an eighth of the memory and of the voxelisation and mipmapping time.
    pub resolution: u32,
    /// Side of the cubic volume as a multiple of the virtual content's largest bounding-box
    /// edge, centred on it. Default 2 (spec §2.13.1: "twice the largest bounding box edge").
    pub extent: f32,
    /// Side of a second, coarser volume around the first, as a multiple of the first's side
    /// (`outer_resolution` voxels per side): cones that leave the first go on through it, so
    /// real surfaces beyond the thesis's volume (a desk, a room's walls) still hide the probe
    /// and send their bounce light. 1 turns it off (the thesis's single volume). Default 4.
    pub outer_scale: f32,
    /// Voxels along each side of the outer volume (a power of two, 16–512; `resolution` if
    /// that is smaller). Default 64: its voxels are then 8 × the inner ones, about as wide as the
    /// narrowest cone that leaves the inner volume reads (half a diameter of 0.6 × half the
    /// inner side), so cones from the inner volume see the same light; voxelising, lighting and
    /// bouncing it takes an eighth of the work of 128³ when the content moves.
    pub outer_resolution: u32,
    /// Diameter-to-length ratio of the nine diffuse cones. Default 0.6 (spec §2.13.7, [Code]).
    pub diffuse_aperture: f32,
    /// Distance between the samples of the pixels' cones, in cone diameters (0.5–2). Each
    /// sample reads voxels half the cone's diameter wide (its trilinear blur then matches the
    /// cone's width) and compounds its opacity over the length it stands for. Default 0.5, a
    /// sample per voxel side read; larger is faster and coarser.
    pub sample_spacing: f32,
    /// The same for the cones the second bounce gathers with per voxel (`bounces` = 2), whose
    /// light the pixels' cones blur again. Default 1.5: the second bounce of a moving cornell
    /// frame in 0.78 of the time of 1 (0.57 ms on an H200), the eight benchmark scenes' region
    /// FLIP equal or lower (at most 0.7 %); the samples' footprints still meet near the surface
    /// (a voxel apart), farther out a thin wall between two samples counts only in part
    /// (docs/benchmarks.md).
    pub bounce_spacing: f32,
    /// Injected bounces: 1 is the thesis's single bounce (spec §2.13.9: the unlit side of a
    /// virtual object is black); 2 re-injects the first bounce, gathered per voxel by the nine
    /// diffuse cones, so light that reached a surface indirectly bounces on; 3 gathers the
    /// second bounce once more, so that the light the virtual content sends bounces off the
    /// real surfaces back onto it and on to the others (a virtual block beside a red wall and
    /// the wall light each other: cornell's block face towards the red wall took 0.85 of the
    /// answer's light with two, 0.89 with three; region FLIP on lavapipe 0.1219 → 0.1046 at
    /// 16 frames). The third is gathered in the frames in which the content and the lights
    /// rest (unless `third_bounce_moving`): a frame in which they move has two. Default 3.
    pub bounces: u32,
    /// Whether the frames in which the content or a light moves gather the third bounce too
    /// (`bounces` = 3): a bounce pass, its photo pass and the mipmaps more in each such frame,
    /// 0.50–0.73 ms at 1080p on an H100 (cornell's moving frame 2.66 → 3.40 ms, past the
    /// method's 3 ms; docs/benchmarks.md). Default false.
    pub third_bounce_moving: bool,
    /// Pixels per side of the blocks the pixels' cones are traced once for (1, 2, 4 or 8), from
    /// a covered pixel of the block; each pixel then takes the light of the blocks around it
    /// that lie on the same surface (depth and normal alike), under its own material (diffuse
    /// light and the probe's shadow vary slowly, as in [CNS+11]). 1 traces every pixel.
    /// Default 4: a sixteenth of the cones, the four diffuse benchmark scenes' region FLIP
    /// within 1 % of every pixel's and of 2 × 2 blocks' at 640×480 (8 brightens the edges of
    /// small faces; docs/benchmarks.md).
    pub trace_block: u32,
    /// Whether real voxels whose surface the camera sees take their light from the photo (with
    /// the virtual content's change on top) rather than from their own two bounces: the photo
    /// holds every bounce of the real scene's light (spec §2.11: "in practice Σ T_μ^i L_e is the
    /// camera image"), where the voxels' own bounces hold about 70 % of a cornell wall's; both
    /// bounces' (the second gathers the first). The last bounce's voxels take a new photo or
    /// camera (a stream's frames) at once; the second bounce gathers the photo of the frame the
    /// scene's light or content last changed in. Default true.
    pub photo_voxels: bool,
    /// Directional lights the probe is split into (median cut; 0 or a power of two up to 64)
    /// whose real-only and virtual-only maps around the volume shadow the probe's light on
    /// the pixels they cover, sharp where the probe's light comes from a small bright source
    /// (a window, a lamp) that the nine wide cones blur (spec §2.3's directional occlusion;
    /// as `dlpv.probe_lights`). 0 leaves the probe's shadow to the cones. Default 32.
    pub probe_lights: u32,
    /// Whether, while the view holds still (no camera, content, light or photo change since
    /// the last frame), each frame draws the probe's lights anew: one direction per
    /// median-cut region, drawn in proportion to its texels' power, every one a point whose
    /// maps shadow both the real and the virtual surfaces sharply (no cones). The frames'
    /// mean (a still's) is then each region's power-weighted visibility: the soft shadow of
    /// a broad sky that 32 fixed directions band and nine wide cones blur (the bunny's on its
    /// desk too dark around it and too light at its foot). Moving frames keep the fixed
    /// lights. A still of 64 frames (`output.frames`, the default for `dvct`): desk-bunny's
    /// region FLIP 0.0795 → 0.0618, desk-spot-real 0.0786 → 0.0761, desk-spot-virtual 0.0909
    /// → 0.0857, cornell 0.1322 → 0.1351 (docs/benchmarks.md); a still frame's maps cost
    /// about 0.2 ms at 1080p on an H100. Default true.
    pub sample_probe_lights: bool,
    /// Side of the maps of the probe's lights (a power of two, 32–2048). Default 128 (as
    /// `dlpv.probe_rsm_resolution`; 256 needs 336 MB in one buffer, more than many devices bind).
    pub probe_map_resolution: u32,
    /// Rays (0–256) each trace texel of a virtual surface gathers the room's light with, in
    /// place of the nine diffuse cones: thin rays through the voxels themselves, cosine
    /// distributed and turned from one texel to the next as the cones are. Nine wide cones read
    /// the room through its prefiltered levels, where a lit wall beside the object, its edge
    /// against the open sky, the floor in the object's shadow blend into coarse cells: cornell's
    /// blocks took 0.93 / 0.99 / 1.02 of the answer's light with them, 0.97 / 1.00 / 1.02 with
    /// 32 rays, and the six diffuse benchmark scenes' region FLIP came down 1–10 % (cornell
    /// 0.132 → 0.119). Real surfaces, most of the frame, keep the cones. The rays cost what a
    /// cone does per voxel they cross: 32 took a moving 1080p frame on an H100 1.8–3.0 ms
    /// longer (16: 0.8–1.4 ms), past the method's 3 ms. Default 0: the cones (the thesis).
    pub virtual_rays: u32,
    /// Thin rays (0–64) each virtual trace texel gathers with per frame while the view holds
    /// still (as `sample_probe_lights`), shifted anew each frame, keeping the running mean of
    /// the still's frames: the light of `virtual_rays` at the cost of a few rays per frame (a
    /// still of 64 frames gathers 252 per texel). Region FLIP on lavapipe at 640×480, 0 → 4:
    /// cornell 0.1351 → 0.1191, desk-bunny 0.0569 → 0.0529, desk-spot-real 0.0750 → 0.0719,
    /// desk-spot-virtual 0.0858 → 0.0846 (128 rays every frame: 0.0521 / 0.0716 / 0.0845); a
    /// still 1080p frame on an H100 0.20–0.30 ms longer (docs/benchmarks.md, 2026-12-07). A
    /// live still view shows its first frames' few rays as noise on the virtual surfaces,
    /// which settles within a few frames; moving frames keep the cones (or `virtual_rays`).
    /// 0 turns it off. Default 4.
    pub still_rays: u32,
    /// A pixel whose likest trace texel around it (of those the resolve blends:
    /// `geometry_weight` of depth and normal, 1 for the texel traced from the pixel itself)
    /// is less alike than this traces its own cones after the resolve. The texels are traced
    /// from one pixel of each `trace_block`² block; at a silhouette, a crease or an object's
    /// rim where it meets the desk the texels around a pixel face elsewhere, and the blend
    /// gave a bunny's underside the light of its front (desk-bunny's region FLIP 0.0618;
    /// traced per pixel 0.0568). 0.8 lists about 1 % of the pixels at 640 × 480; 0 turns it
    /// off. Only while the view holds still (as `sample_probe_lights`): at 1080p the pixels
    /// it lists, mostly surfaces seen at grazing angles, cost a moving cornell frame 0.25 ms
    /// on an H100, past the method's 3 ms, so a moving view's frames keep the blend.
    pub retrace_likeness: f32,
}

impl Default for DvctSettings {
    fn default() -> Self {
        Self {
            resolution: 128,
            extent: 2.0,
            outer_scale: 4.0,
            outer_resolution: 64,
            diffuse_aperture: 0.6,
            sample_spacing: 0.5,
            bounce_spacing: 1.5,
            bounces: 3,
            third_bounce_moving: false,
            trace_block: 4,
            photo_voxels: true,
            probe_lights: 32,
            sample_probe_lights: true,
            probe_map_resolution: 128,
            virtual_rays: 0,
            still_rays: 4,
            retrace_likeness: 0.8,
        }
    }
}

impl DvctSettings {
    /// Voxels per side of the outer volume: `outer_resolution`, at most `resolution`.
    pub fn outer_voxels(&self) -> u32 {
        self.outer_resolution.min(self.resolution)
    }

    /// Whether the last bounce is written apart before the photo's light goes in (with two
    /// bounces and `photo_voxels`), or because a third bounce reads the first's volumes that
    /// it then goes into.
    pub fn raw_volumes(&self) -> bool {
        self.bounces >= 2 && self.photo_voxels || self.bounces >= 3
    }

    /// Checks every value; the error names the offending field.
    pub fn validate(&self) -> Result<(), String> {
        check_power_of_two(self.resolution, 16, 512, "dvct.resolution", " voxels")?;
        check(
            self.extent.is_finite() && (1.0..=64.0).contains(&self.extent),
            "dvct.extent",
            format!("must be between 1 and 64 times the virtual content's size, got {}", self.extent),
        )?;
        check(
            self.outer_scale.is_finite() && (1.0..=16.0).contains(&self.outer_scale),
            "dvct.outer_scale",
            format!("must be between 1 and 16 times the inner volume's side, got {}", self.outer_scale),
        )?;
        check_power_of_two(self.outer_resolution, 16, 512, "dvct.outer_resolution", " voxels")?;
        check(
            self.diffuse_aperture.is_finite() && (0.05..=2.0).contains(&self.diffuse_aperture),
            "dvct.diffuse_aperture",
            format!("must be between 0.05 and 2, got {}", self.diffuse_aperture),
        )?;
        for (value, name) in
            [(self.sample_spacing, "dvct.sample_spacing"), (self.bounce_spacing, "dvct.bounce_spacing")]
        {
            check(
                value.is_finite() && (0.5..=2.0).contains(&value),
                name,
                format!("must be between 0.5 and 2 cone diameters, got {value}"),
            )?;
        }
        check((1..=3).contains(&self.bounces), "dvct.bounces", format!("must be 1, 2 or 3, got {}", self.bounces))?;
        check(
            matches!(self.trace_block, 1 | 2 | 4 | 8),
            "dvct.trace_block",
            format!("must be 1, 2, 4 or 8 pixels, got {}", self.trace_block),
        )?;
        check_probe_lights(self.probe_lights, "dvct.probe_lights")?;
        check(
            self.virtual_rays <= 256,
            "dvct.virtual_rays",
            format!("must be at most 256 rays (0: the nine cones), got {}", self.virtual_rays),
        )?;
        check(
            self.still_rays <= 64,
            "dvct.still_rays",
            format!("must be at most 64 rays per frame (0: off), got {}", self.still_rays),
        )?;
        check(
            (0.0..=1.0).contains(&self.retrace_likeness),
            "dvct.retrace_likeness",
            format!("must be from 0 (off) to 1, got {}", self.retrace_likeness),
        )?;
        check_power_of_two(self.probe_map_resolution, 32, 2048, "dvct.probe_map_resolution", " texels")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_values_are_named() {
        let bad = DvctSettings { resolution: 100, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("dvct.resolution"));
        let bad = DvctSettings { extent: 0.5, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("dvct.extent"));
        let bad = DvctSettings { outer_scale: 0.5, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("dvct.outer_scale"));
        let bad = DvctSettings { outer_resolution: 48, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("dvct.outer_resolution"));
        let bad = DvctSettings { still_rays: 65, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("dvct.still_rays"));
        let bad = DvctSettings { sample_spacing: 0.1, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("dvct.sample_spacing"));
        let bad = DvctSettings { bounce_spacing: f32::NAN, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("dvct.bounce_spacing"));
        let bad = DvctSettings { bounces: 4, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("dvct.bounces"));
        let bad = DvctSettings { trace_block: 3, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("dvct.trace_block"));
        let bad = DvctSettings { probe_lights: 6, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("dvct.probe_lights"));
        let bad = DvctSettings { probe_map_resolution: 100, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("dvct.probe_map_resolution"));
        let bad = DvctSettings { virtual_rays: 257, ..Default::default() };
        assert!(bad.validate().unwrap_err().contains("dvct.virtual_rays"));
        for likeness in [-0.1, 1.5, f32::NAN] {
            let bad = DvctSettings { retrace_likeness: likeness, ..Default::default() };
            assert!(bad.validate().unwrap_err().contains("dvct.retrace_likeness"));
        }
        DvctSettings::default().validate().unwrap();
    }
}
