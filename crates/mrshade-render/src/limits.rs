//! Fitting the memory-heavy settings to the device: shadow maps, RSMs and ISM atlases each
//! live in one storage buffer, which a device binds only up to
//! `max_storage_buffer_binding_size` (128 MiB on many). A setting that would exceed it is
//! halved until it fits, with a warning that names it, instead of failing validation.

use crate::passes::rsm;
use mrshade_core::settings::RenderSettings;
use mrshade_scene::{LightKind, Scene};

/// Shadow-map layers of `scene`'s lights: real-only and virtual-only sets, six faces for
/// point lights and wide spots.
pub fn shadow_layer_count(scene: &Scene) -> u64 {
    scene
        .lights
        .iter()
        .map(|l| match l.kind {
            LightKind::Directional => 2,
            LightKind::Spot { outer_cone, .. } if outer_cone <= crate::scene_gpu::MAX_FRUSTUM_HALF_ANGLE => 2,
            _ => 12,
        })
        .sum()
}

/// `settings` with every buffer within `max_binding` bytes; the warnings say what changed.
pub fn fit_to_device(settings: &RenderSettings, scene: &Scene, max_binding: u64) -> (RenderSettings, Vec<String>) {
    let mut fitted = settings.clone();
    let mut warnings = Vec::new();
    let layers = shadow_layer_count(scene).max(1);
    let mut shrink = |name: &str, value: &mut u32, bytes_per_unit: u64, minimum: u32| {
        let requested = *value;
        while *value > minimum && bytes_per_unit * (*value as u64).pow(2) > max_binding {
            *value /= 2;
        }
        if *value != requested {
            warnings.push(format!(
                "{name} = {requested} needs more GPU memory in one buffer than this device binds ({} MiB); using {}",
                max_binding >> 20,
                *value
            ));
        }
    };
    shrink("shadows.resolution", &mut fitted.shadows.resolution, layers * 8, 64);
    let dir = &mut fitted.dir;
    shrink("dir.rsm_resolution", &mut dir.rsm_resolution, layers * rsm::TEXEL_BYTES, 16);
    let tiles_per_row = (dir.vpl_count as f64).sqrt().ceil() as u64;
    shrink("dir.ism_resolution", &mut dir.ism_resolution, tiles_per_row * tiles_per_row * 4, 16);
    (fitted, warnings)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn oversized_maps_are_halved_with_a_warning() {
        let mut scene = Scene::default();
        scene.lights.push(mrshade_scene::Light {
            name: "lamp".into(),
            kind: LightKind::Point,
            intensity: glam::Vec3::ONE,
            world_from_light: glam::Mat4::IDENTITY,
            realness: mrshade_core::flags::Realness::Real,
        });
        let settings = RenderSettings::default();
        let (fitted, warnings) = fit_to_device(&settings, &scene, 128 << 20);
        // 12 layers × 2048² × 8 B = 384 MiB > 128 MiB: 1024² (96 MiB) fits.
        assert_eq!(fitted.shadows.resolution, 1024);
        assert!(warnings.iter().any(|w| w.contains("shadows.resolution = 2048")), "{warnings:?}");
        let (same, none) = fit_to_device(&settings, &Scene::default(), 128 << 20);
        assert_eq!(same, settings);
        assert!(none.is_empty());
    }
}
