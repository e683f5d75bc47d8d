//! The lights whose maps `dlpv` injects: the scene's own, and the directional lights the
//! probe is split into (`probe_maps`), and the power bound that sizes the fixed point.

use super::super::probe_maps::ProbeSet;
use super::super::rsm::RsmPass;
use mrshade_scene::{Light, LightKind};

/// One light set's maps and how their layers pair up.
pub(super) struct LightSet {
    pub(super) rsm: RsmPass,
    pub(super) inject_group: wgpu::BindGroup,
    pub(super) pairs: u32,
    pub(super) pairs_buffer: wgpu::Buffer,
    /// The set's lights (the probe's follow the volume; the scene's are the scene's).
    pub(super) layers_of: LayersOf,
}

/// Where a set's layers come from.
pub(super) enum LayersOf {
    /// The scene's lights: the frame's shadow layers.
    Scene,
    /// Directional lights split from the probe, their maps around the volume.
    Probe(ProbeSet),
}

/// Upper bound of the power all of `lights`' map texels receive (W), for the fixed point:
/// intensity × 4π for lights at a point, irradiance × the map's square for directional ones
/// (of side `2·radius`).
pub(super) fn power_bound(lights: &[Light], radius: f32) -> f32 {
    lights
        .iter()
        .map(|l| {
            let i = l.intensity.max_element().max(0.0);
            match l.kind {
                LightKind::Directional => i * 4.0 * radius * radius,
                _ => i * 4.0 * std::f32::consts::PI,
            }
        })
        .sum()
}
