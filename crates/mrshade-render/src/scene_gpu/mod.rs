//! The scene on the GPU: geometry, per-instance transforms and flags, materials with their
//! textures, lights with their shadow-map layers, and the probe's lighting textures.

mod geometry;
mod lights;
pub use lights::FOV_MARGIN;
mod materials;
mod mips;
mod probe;

pub use geometry::{Geometry, GpuInstance, Vertex};
pub(crate) use lights::MAX_FRUSTUM_HALF_ANGLE;
pub use lights::{GpuLight, ShadowLayer, pack_lights};
pub use materials::{GpuMaterial, GpuMaterials};
pub use probe::GpuProbe;

use bytemuck::Zeroable;
use mrshade_scene::Session;
use wgpu::util::DeviceExt;

/// Everything of a session that lives on the GPU and does not change per frame.
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
}

impl GpuScene {
    /// Uploads `session`'s scene and probe.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, session: &Session) -> Self {
        let scene = &session.scene;
        let (mut lights, shadow_layers) = pack_lights(scene, &session.settings.shadows);
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
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        Self {
            geometry: Geometry::new(device, scene),
            materials: GpuMaterials::new(device, queue, scene),
            lights: storage("scene/lights", bytemuck::cast_slice(&lights)),
            light_count,
            shadow_layers,
            shadow_matrices: storage("scene/shadow_matrices", bytemuck::cast_slice(&matrices)),
            probe: GpuProbe::new(device, queue, session.environment.as_ref()),
        }
    }
}
