//! The lights whose maps `dlpv` injects: the scene's own, and the directional lights the
//! probe is split into (their maps sized to the volume, reaching back to the scene's bounds),
//! with how each set's real-only and virtual-only layers pair up and the power bound that
//! sizes the fixed point.

use super::super::rsm::RsmPass;
use crate::scene_gpu::{GpuLight, ShadowLayer, pack_lights};
use glam::{UVec4, Vec3};
use mrshade_core::flags::Realness;
use mrshade_core::settings::ShadowSettings;
use mrshade_scene::{Light, LightKind};
use wgpu::util::DeviceExt;

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

/// The probe's directional lights on the GPU.
pub(super) struct ProbeSet {
    pub(super) lights: Vec<Light>,
    /// Their `GpuLight`s.
    pub(super) buffer: wgpu::Buffer,
    /// `clip_from_world` of their layers (the merge looks up visibility).
    pub(super) clip_from_world: wgpu::Buffer,
}

/// The probe's lights and their layers: maps as wide as the cube's bounding sphere (where
/// their texels matter) but deep enough toward the light to hold everything of the scene
/// there (the walls and ceiling of a room hide the sky from what is inside).
pub(super) fn probe_layers(
    lights: &[Light],
    cube: (Vec3, Vec3),
    scene_box: Option<(Vec3, Vec3)>,
    shadows: &ShadowSettings,
) -> (Vec<GpuLight>, Vec<ShadowLayer>) {
    let (gpu_lights, mut layers) = pack_lights(lights, Some(cube), shadows);
    let center = (cube.0 + cube.1) * 0.5;
    let radius = bounding_radius(Some(cube));
    for layer in &mut layers {
        let dir = lights[layer.light as usize].direction();
        let toward_light = scene_box.map_or(0.0, |b| {
            mrshade_core::math::box_corners(b).iter().map(|c| (*c - center).dot(-dir)).fold(0.0, f32::max)
        });
        let back = toward_light.max(radius) * 1.01 + 1e-3;
        let eye = center - dir * back;
        let proj = glam::camera::rh::proj::directx::orthographic(-radius, radius, -radius, radius, back + radius, 0.0);
        layer.clip_from_world = proj * crate::scene_gpu::look_to(eye, dir);
    }
    (gpu_lights, layers)
}

impl ProbeSet {
    pub(super) fn new(
        device: &wgpu::Device,
        lights: Vec<Light>,
        cube: (Vec3, Vec3),
        scene_box: Option<(Vec3, Vec3)>,
        shadows: &ShadowSettings,
    ) -> (Self, Vec<ShadowLayer>) {
        let (gpu_lights, layers) = probe_layers(&lights, cube, scene_box, shadows);
        let storage = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            })
        };
        let clips: Vec<glam::Mat4> = layers.iter().map(|l| l.clip_from_world).collect();
        let set = Self {
            lights,
            buffer: storage("dlpv/probe_lights", bytemuck::cast_slice(&gpu_lights)),
            clip_from_world: storage("dlpv/probe_clip_from_world", bytemuck::cast_slice(&clips)),
        };
        (set, layers)
    }

    /// Moves the maps to cover `cube`; the layers for the RSM pass.
    pub(super) fn follow(
        &self,
        queue: &wgpu::Queue,
        cube: (Vec3, Vec3),
        scene_box: Option<(Vec3, Vec3)>,
        shadows: &ShadowSettings,
    ) -> Vec<ShadowLayer> {
        let (gpu_lights, layers) = probe_layers(&self.lights, cube, scene_box, shadows);
        let clips: Vec<glam::Mat4> = layers.iter().map(|l| l.clip_from_world).collect();
        queue.write_buffer(&self.buffer, 0, bytemuck::cast_slice(&gpu_lights));
        queue.write_buffer(&self.clip_from_world, 0, bytemuck::cast_slice(&clips));
        layers
    }
}

/// Pairs of a set's layers: (real-only layer, virtual-only layer, light, 1 if the light's
/// direct change is injected), face by face.
pub(super) fn layer_pairs(layers: &[ShadowLayer], direct: bool) -> Vec<UVec4> {
    let real = layers.iter().enumerate().filter(|(_, l)| l.casters == Realness::Real);
    real.map(|(i, l)| {
        let face = layers[..i].iter().filter(|o| o.light == l.light && o.casters == Realness::Real).count();
        let virtual_layer = layers
            .iter()
            .enumerate()
            .filter(|(_, o)| o.light == l.light && o.casters == Realness::Virtual)
            .nth(face)
            .map(|(j, _)| j)
            .expect("every real layer has a virtual twin");
        UVec4::new(i as u32, virtual_layer as u32, l.light, direct as u32)
    })
    .collect()
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

/// Half the diagonal of a box (what `pack_lights` covers a directional map with).
pub(super) fn bounding_radius(bounds: Option<(Vec3, Vec3)>) -> f32 {
    bounds.map_or(1.0, |(lo, hi)| ((hi - lo).length() * 0.5).max(1e-3))
}
