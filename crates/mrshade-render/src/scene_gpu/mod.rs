//! The scene on the GPU: geometry, per-instance transforms and flags, materials with their
//! textures, lights with their shadow-map layers, and the probe's lighting textures.

mod geometry;
mod lights;
pub use lights::FOV_MARGIN;
mod materials;
mod mips;
mod probe;

pub use geometry::{Geometry, GpuInstance, Moved, Vertex};
pub(crate) use lights::MAX_FRUSTUM_HALF_ANGLE;
pub use lights::{GpuLight, ShadowLayer, cube_faces, look_to, pack_lights};
pub use materials::{GpuMaterial, GpuMaterials};
pub use probe::GpuProbe;

use bytemuck::Zeroable;
use mrshade_core::settings::ShadowSettings;
use mrshade_scene::{Light, Session};
use wgpu::util::DeviceExt;

/// Everything of a session that lives on the GPU: uploaded once, moved per frame (instance
/// and light transforms).
pub struct GpuScene {
    /// Vertices, indices, instances, draws.
    pub geometry: Geometry,
    /// Material factors and textures.
    pub materials: GpuMaterials,
    /// `GpuLight` per light (one zeroed entry when there are none).
    pub lights: wgpu::Buffer,
    /// Number of real lights in `lights`.
    pub light_count: u32,
    /// The shadow layers the lights own.
    pub shadow_layers: Vec<ShadowLayer>,
    /// `clip_from_world` per shadow layer (read by shading passes).
    pub shadow_matrices: wgpu::Buffer,
    /// Probe textures.
    pub probe: GpuProbe,
    /// The lights as loaded, moved by `set_light_transforms`.
    source_lights: Vec<Light>,
    /// The scene's box at load time (directional shadow maps cover it).
    bounds: Option<(glam::Vec3, glam::Vec3)>,
    shadow_settings: ShadowSettings,
}

impl GpuScene {
    /// Uploads `session`'s scene and probe.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, session: &Session) -> Self {
        let scene = &session.scene;
        let bounds = scene.bounds();
        let (mut lights, shadow_layers) = pack_lights(&scene.lights, bounds, &session.settings.shadows);
        let light_count = lights.len() as u32;
        if lights.is_empty() {
            lights.push(GpuLight::zeroed());
        }
        let mut matrices: Vec<glam::Mat4> = shadow_layers.iter().map(|l| l.clip_from_world).collect();
        if matrices.is_empty() {
            matrices.push(glam::Mat4::IDENTITY);
        }
        let storage = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            })
        };
        Self {
            geometry: Geometry::new(device, scene),
            materials: GpuMaterials::new(device, queue, scene, &session.settings.specular),
            lights: storage("scene/lights", bytemuck::cast_slice(&lights)),
            light_count,
            shadow_layers,
            shadow_matrices: storage("scene/shadow_matrices", bytemuck::cast_slice(&matrices)),
            probe: GpuProbe::new(device, queue, session.environment.as_ref()),
            source_lights: scene.lights.clone(),
            bounds,
            shadow_settings: session.settings.shadows,
        }
    }

    /// Places light `i` at `world_from_light[i]` and uploads the lights and their shadow
    /// matrices; returns whether anything moved (then the shadow views must follow
    /// `shadow_layers`).
    pub fn set_light_transforms(&mut self, queue: &wgpu::Queue, world_from_light: &[glam::Mat4]) -> bool {
        let mut moved = false;
        for (light, &m) in self.source_lights.iter_mut().zip(world_from_light) {
            moved |= light.world_from_light != m;
            light.world_from_light = m;
        }
        if !moved {
            return false;
        }
        let (lights, layers) = pack_lights(&self.source_lights, self.bounds, &self.shadow_settings);
        if !lights.is_empty() {
            queue.write_buffer(&self.lights, 0, bytemuck::cast_slice(&lights));
            let matrices: Vec<glam::Mat4> = layers.iter().map(|l| l.clip_from_world).collect();
            queue.write_buffer(&self.shadow_matrices, 0, bytemuck::cast_slice(&matrices));
        }
        self.shadow_layers = layers;
        true
    }
}
