//! The lights whose maps `dlpv` injects: the scene's own, and the directional lights the
//! probe is split into (`probe_maps`), and the power bound that sizes the fixed point.

use mrshade_scene::{Light, LightKind};

/// One injection dispatch: a set of lights' pairs of maps.
pub(super) struct InjectSet {
    pub(super) group: wgpu::BindGroup,
    /// Pairs of maps (real-only, virtual-only).
    pub(super) pairs: u32,
    /// Side of the maps.
    pub(super) resolution: u32,
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
