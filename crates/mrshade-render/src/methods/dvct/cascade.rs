//! One volume of delta voxel cone tracing with what is drawn into it: its uniform, its
//! voxelisation and the light volumes of its bounces. The method has the thesis's volume around
//! the virtual content and, with `dvct.outer_scale` > 1, a coarser one around it of
//! `dvct.outer_resolution` voxels per side, that cones go on through when they leave the first
//! (cones.wgsl).

use super::volume::{RawPair, VolumePair, VolumeParams, VoxelNormals, levels};
use crate::methods::around::place;
use glam::{UVec4, Vec3, Vec4};
use mrshade_core::settings::DvctSettings;
use wgpu::util::DeviceExt;

/// The virtual content's box and the scene's, that a cascade is placed by (`around::place`).
pub type Boxes = (Option<(Vec3, Vec3)>, Option<(Vec3, Vec3)>);

/// Bytes per voxel of the voxelisation (a real and a virtual triangle).
pub const VOXEL_BYTES: u64 = 8;

/// A volume, its voxels and its light.
pub struct Cascade {
    pub params: VolumeParams,
    pub params_buffer: wgpu::Buffer,
    /// Side as a multiple of the virtual content's largest bounding-box edge.
    extent: f32,
    /// Per voxel: the real and the virtual triangle kept (volume.wgsl's words; 0: empty).
    pub voxels: wgpu::Buffer,
    pub voxel_words: u32,
    /// The first bounce's volumes and, with `dvct.bounces` ≥ 2, the second's. A third bounce
    /// goes into the first's volumes again (it gathers the second's: mod.rs `third`).
    pub first: VolumePair,
    pub second: Option<VolumePair>,
    /// With two bounces and `dvct.photo_voxels`, or three: the last bounce's light before the
    /// photo's (a third bounce's pass reads the first bounce's volumes and cannot write them).
    pub raw: Option<RawPair>,
    /// Per voxel, the side of its surface that sends out its light in each solution (rv, r):
    /// the light pass writes them, the mipmaps read them (mips.wgsl).
    pub normals: VoxelNormals,
}

impl Cascade {
    /// The cascade of `extent` × the virtual content's largest edge and `res` voxels per side
    /// (`label`: its GPU objects' prefix), `flags` its uniform's bits (`volume::flags`).
    pub fn new(
        device: &wgpu::Device,
        label: &str,
        settings: &DvctSettings,
        (extent, res): (f32, u32),
        boxes: Boxes,
        triangles: u32,
        flags: u32,
    ) -> Self {
        let (origin, side) = place(boxes.0, boxes.1, extent);
        let params = VolumeParams {
            origin: origin.extend(side / res as f32),
            info: UVec4::new(res, levels(res), triangles, flags),
            cone: Vec4::new(
                settings.diffuse_aperture,
                settings.trace_block as f32,
                settings.sample_spacing,
                settings.bounce_spacing,
            ),
        };
        let params_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(&format!("{label}/params")),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let voxel_words = res * res * res * 2;
        let voxels = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(&format!("{label}/voxels")),
            size: voxel_words as u64 * 4,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let first = VolumePair::new(device, &format!("{label}/first_bounce"), res);
        let second = (settings.bounces >= 2).then(|| VolumePair::new(device, &format!("{label}/second_bounce"), res));
        let raw = settings.raw_volumes().then(|| RawPair::new(device, &format!("{label}/last_bounce_raw"), res));
        let normals = VoxelNormals::new(device, &format!("{label}/normals"), res);
        Self { params, params_buffer, extent, voxels, voxel_words, first, second, raw, normals }
    }

    /// Voxels per side.
    pub fn resolution(&self) -> u32 {
        self.params.info.x
    }

    /// The volumes the pixels' cones read after two bounces (the second bounce's, else the
    /// first's; a third bounce goes into the first's).
    pub fn lit(&self) -> &VolumePair {
        self.second.as_ref().unwrap_or(&self.first)
    }

    /// The volume's box (lower and upper corner).
    pub fn cube(&self) -> (Vec3, Vec3) {
        let lo = self.params.origin.truncate();
        (lo, lo + Vec3::splat(self.params.origin.w * self.params.info.x as f32))
    }

    /// Follows the virtual content (spec §2.12.7: "kept synchronous").
    pub fn follow(&mut self, queue: &wgpu::Queue, boxes: Boxes) {
        let res = self.params.info.x;
        let (origin, side) = place(boxes.0, boxes.1, self.extent);
        self.params.origin = origin.extend(side / res as f32);
        queue.write_buffer(&self.params_buffer, 0, bytemuck::bytes_of(&self.params));
    }
}
