//! The volumes of delta voxel cone tracing: their uniform and the prefiltered 3D textures of
//! both solutions (where the cube lies: `methods::around`).

use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec4};

/// Mirrors `VolumeParams` in volume.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct VolumeParams {
    /// xyz: world position of the lower corner; w: voxel side (m).
    pub origin: Vec4,
    /// Voxels per side, mip levels, triangles, unused.
    pub info: UVec4,
    /// Diffuse cone aperture, unused…
    pub cone: Vec4,
}

/// Format of the volumes: premultiplied radiance and opacity.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Mip levels of a volume of `resolution` voxels per side (down to 1³).
pub fn levels(resolution: u32) -> u32 {
    resolution.max(1).ilog2() + 1
}

/// A pair of prefiltered volumes, one per solution (`rv`: real and virtual surfaces; `r`:
/// real ones only).
pub struct VolumePair {
    /// Real+virtual volume.
    pub rv: wgpu::Texture,
    /// Real-only volume.
    pub r: wgpu::Texture,
    /// Views of every level of each (for sampling): `[rv, r]`.
    pub sampled: [wgpu::TextureView; 2],
}

impl VolumePair {
    /// Two `resolution`³ volumes with their mip chains, labelled `<label>/rv` and `<label>/r`.
    pub fn new(device: &wgpu::Device, label: &str, resolution: u32) -> Self {
        let volume = |name: &str| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(&format!("{label}/{name}")),
                size: wgpu::Extent3d { width: resolution, height: resolution, depth_or_array_layers: resolution },
                mip_level_count: levels(resolution),
                sample_count: 1,
                dimension: wgpu::TextureDimension::D3,
                format: FORMAT,
                usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
        };
        let rv = volume("rv");
        let r = volume("r");
        let sampled = [&rv, &r].map(|t| t.create_view(&wgpu::TextureViewDescriptor::default()));
        Self { rv, r, sampled }
    }

    /// Views of level `level` of both volumes, `[rv, r]`.
    pub fn level(&self, level: u32) -> [wgpu::TextureView; 2] {
        [&self.rv, &self.r].map(|t| {
            t.create_view(&wgpu::TextureViewDescriptor {
                label: Some("dvct/volume_level"),
                base_mip_level: level,
                mip_level_count: Some(1),
                ..Default::default()
            })
        })
    }

    /// Bytes of both volumes with their chains.
    pub fn bytes(resolution: u32) -> u64 {
        let voxels = (resolution as u64).pow(3);
        2 * voxels * 8 * 8 / 7
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_go_down_to_one_voxel() {
        assert_eq!(levels(128), 8);
    }
}
