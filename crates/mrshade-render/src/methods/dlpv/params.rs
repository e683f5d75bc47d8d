//! The volumes' uniform (`DlpvParams`, volume.wgsl) built from the settings, and the sizes
//! and sources the method's buffers share.

use super::vpl_gather::{GATHERED_BOUNCE, GATHERED_RHO};
use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec3, Vec4};
use mrshade_core::settings::{DlpvSettings, DlpvSplat, DlpvTransport};

/// The bit of `DlpvParams::gathered.w` that turns on the virtual surfaces' bounce (volume.wgsl
/// `virtual_bounce`).
pub const VIRTUAL_BOUNCE_BIT: u32 = 4;

/// Mirrors `DlpvParams` in volume.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct DlpvParams {
    /// xyz: world position of the lower corner; w: cell side (m).
    pub origin: Vec4,
    /// Cells per side, cells in all, propagation step (0: seeding, injection), splat (0: into
    /// the cell, 1: trilinear).
    pub info: UVec4,
    /// Fixed-point units per watt; the angular radius (rad) below which a probe light shadows
    /// real surfaces through its maps (`dlpv.sharp_probe_shadows_deg`), unused…
    pub scale: Vec4,
    /// Propagation steps per source.
    pub steps: UVec4,
    /// x: 1 when V_ρ is gathered from VPLs (the propagation writes the accumulated volumes
    /// from the second on); y: 1 when the photo's light is in it (`dlpv.photo_bounce`); z: bit
    /// 0 when the probe's shadows on real surfaces are soft (`dlpv.soft_probe_shadows`), bit 1
    /// on virtual ones (`dlpv.soft_virtual_probe_shadows`; volume.wgsl `SOFT_*`).
    pub gathered: UVec4,
}

impl DlpvParams {
    /// Whether the virtual content stands in the gathered bounce light's paths in every cell
    /// (`dlpv.bounce_visibility`; volume.wgsl `bounce_visible`).
    pub fn bounce_visible(&self) -> bool {
        self.gathered.w & 2 != 0
    }

    /// Whether the virtual surfaces pass on their light and stand in its way in V_ρ's cells
    /// (`dlpv.virtual_bounce`; volume.wgsl `virtual_bounce`).
    pub fn virtual_bounce(&self) -> bool {
        self.gathered.w & VIRTUAL_BOUNCE_BIT != 0
    }

    /// The volumes' uniform for `settings`: the cube of side `side` at `origin`, its fixed
    /// point scaled so that `flux_bound` (the most flux all lights inject, W) fits.
    pub(super) fn new(settings: &DlpvSettings, origin: Vec3, side: f32, flux_bound: f32) -> Self {
        let res = settings.resolution;
        let splat = match settings.splat {
            DlpvSplat::Cell => 0,
            DlpvSplat::Trilinear => 1,
        };
        let gathered = gathered_volumes(settings);
        let rho_gathered = gathered & GATHERED_RHO != 0;
        let bounce_gathered = gathered & GATHERED_BOUNCE != 0;
        Self {
            origin: origin.extend(side / res as f32),
            info: UVec4::new(res, res * res * res, 0, splat),
            scale: Vec4::new(
                FIXED_POINT_RANGE / flux_bound.max(1e-12),
                settings.sharp_probe_shadows_deg.to_radians(),
                0.0,
                0.0,
            ),
            steps: {
                // A gathered volume's sources are neither injected nor propagated.
                let propagated = |gathered: bool| if gathered { 0 } else { settings.propagation_steps };
                let mut steps = [0; SOURCES as usize];
                steps[SOURCE_RHO] = propagated(rho_gathered);
                steps[SOURCE_MU] = propagated(bounce_gathered);
                steps[SOURCE_INDIRECT] = propagated(bounce_gathered);
                steps[SOURCE_DIRECT] = settings.direct_steps;
                UVec4::from_array(steps)
            },
            gathered: UVec4::new(
                rho_gathered as u32,
                (gathered != 0 && settings.photo_bounce) as u32,
                settings.soft_probe_shadows as u32 | (settings.soft_virtual_probe_shadows as u32) << 1,
                bounce_gathered as u32
                    | ((bounce_gathered && settings.bounce_visibility) as u32) << 1
                    | if bounce_gathered && settings.virtual_bounce { VIRTUAL_BOUNCE_BIT } else { 0 },
            ),
        }
    }

    /// The same at propagation step `step` (0: seeding, injection).
    pub(super) fn at_step(&self, step: u32) -> Self {
        Self { info: UVec4::new(self.info.x, self.info.y, step, self.info.w), ..*self }
    }
}

/// The sources of injection, in the order of `SOURCE_*` in volume.wgsl.
pub(super) const SOURCES: u32 = 4;
pub(super) const SOURCE_RHO: usize = 0;
pub(super) const SOURCE_INDIRECT: usize = 1;
pub(super) const SOURCE_DIRECT: usize = 2;
pub(super) const SOURCE_MU: usize = 3;
/// Accumulated volumes: V_ρ, V_Δ (both changes), V_μ.
pub(super) const VOLUMES: u64 = 3;

/// Bytes of one cell of one float volume: four coefficients × three channels.
pub(super) const CELL_BYTES: u64 = 48;
/// Bytes of one cell of V_ρ's band 2 (volume.wgsl `rho_band2`): four vec4f.
pub(super) const BAND2_CELL_BYTES: u64 = 64;
/// Bytes of one cell of one source's scratch volume: four half-float coefficients × three
/// channels (propagate.wgsl).
pub const SCRATCH_CELL_BYTES: u64 = 24;
/// Fixed-point headroom: all injected flux of a source, times the largest coefficient
/// magnitude, stays below 2³¹ units.
const FIXED_POINT_RANGE: f32 = (1u32 << 29) as f32;

/// The volumes `settings` gathers from VPLs (vpl_gather.rs `GATHERED_*` bits; 0: none).
pub(super) fn gathered_volumes(settings: &DlpvSettings) -> u32 {
    let bit = |transport, bit| if transport == DlpvTransport::Gathered { bit } else { 0 };
    bit(settings.virtual_light, GATHERED_RHO) | bit(settings.bounce_light, GATHERED_BOUNCE)
}
