//! The volumes of delta voxel cone tracing: their uniform and the prefiltered 3D textures of
//! both solutions (where the cube lies: `methods::around`).

use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec4};
use mrshade_core::settings::DvctSettings;

/// Mirrors `VolumeParams` in volume.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct VolumeParams {
    /// xyz: world position of the lower corner; w: voxel side (m).
    pub origin: Vec4,
    /// Voxels per side, mip levels, triangles, [`flags`].
    pub info: UVec4,
    /// Diffuse cone aperture, pixels per side of a trace texel (texel.wgsl), the pixels' and the
    /// second bounce's cone sample spacing (cones.wgsl).
    pub cone: Vec4,
}

/// `VolumeParams.info.w` (volume.wgsl's bits): 1 when the first bounce is the last (it then
/// takes the probe's light), 2 when the real voxels the camera sees take the photo's light, 4
/// when the scene holds a virtual light (`virtual_lights`): cones from surfaces outside the
/// volume then go through the outer one too, where that light's change also lies.
pub fn flags(settings: &DvctSettings, virtual_lights: bool) -> u32 {
    (settings.bounces == 1) as u32 | (settings.photo_voxels as u32) << 1 | (virtual_lights as u32) << 2
}

/// Format of the volumes: premultiplied radiance and opacity.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Mip levels of a volume of `resolution` voxels per side (down to 1³).
pub fn levels(resolution: u32) -> u32 {
    resolution.max(1).ilog2() + 1
}

/// One solution's volume: the voxels themselves and, from the second level on, one prefiltered
/// chain per direction of travel along the axes, each seen by cones travelling that way
/// (anisotropic voxels, [CNS+11] §4: a wall one voxel thick stays opaque to a cone that
/// crosses it at every level, where one mean over the three axes lets a wide cone see the probe
/// through it; and a cone sees the face of a block that faces it, not the one behind it).
pub struct Volume {
    /// `resolution`³, one level.
    pub base: wgpu::Texture,
    /// Per axis x, y, z, the chains of both ways side by side along x: the cones travelling
    /// towards + in the first half, towards − in the second (one texture read per axis
    /// whichever way a cone goes: a branch per way made the lanes of a warp whose cones went
    /// different ways read both). `resolution × (resolution/2)²` with `levels(resolution) − 1`
    /// levels.
    pub chains: [wgpu::Texture; 3],
}

/// A 3D texture of `format`, `width × side × side` voxels and `levels` levels.
fn volume_texture(
    device: &wgpu::Device,
    name: &str,
    (width, side): (u32, u32),
    levels: u32,
    format: wgpu::TextureFormat,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(name),
        size: wgpu::Extent3d { width, height: side, depth_or_array_layers: side },
        mip_level_count: levels,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D3,
        format,
        usage: wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// A bounce's light of both solutions before the photo's (photo_pass.wgsl), one level each.
pub struct RawPair {
    /// Real+virtual.
    pub rv: wgpu::Texture,
    /// Real-only.
    pub r: wgpu::Texture,
    /// Views of `rv` and `r`: the bounce writes through them, the photo pass reads.
    pub views: [wgpu::TextureView; 2],
}

impl RawPair {
    /// Two `resolution`³ textures, labelled `<label>/rv` and `<label>/r`.
    pub fn new(device: &wgpu::Device, label: &str, resolution: u32) -> Self {
        let texture = |s: &str| volume_texture(device, &format!("{label}/{s}"), (resolution, resolution), 1, FORMAT);
        let (rv, r) = (texture("rv"), texture("r"));
        let views = [&rv, &r].map(|t| t.create_view(&wgpu::TextureViewDescriptor::default()));
        Self { rv, r, views }
    }

    /// Bytes of both.
    pub fn bytes(resolution: u32) -> u64 {
        2 * (resolution as u64).pow(3) * 8
    }
}

/// Per voxel, the unit normal of the side of its surface that sends out its light, of each
/// solution (`rv`: the virtual surface where there is one, else the real; `r`: the real), xyz
/// in [`NORMAL_FORMAT`].
pub struct VoxelNormals {
    /// The real+virtual and the real-only normals.
    pub textures: [wgpu::Texture; 2],
    /// Their views.
    pub views: [wgpu::TextureView; 2],
}

/// Format of [`VoxelNormals`].
pub const NORMAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Snorm;

impl VoxelNormals {
    /// Two `resolution`³ textures, labelled `<label>/rv` and `<label>/r`.
    pub fn new(device: &wgpu::Device, label: &str, resolution: u32) -> Self {
        let textures = ["rv", "r"]
            .map(|s| volume_texture(device, &format!("{label}/{s}"), (resolution, resolution), 1, NORMAL_FORMAT));
        let views = textures.each_ref().map(|t| t.create_view(&wgpu::TextureViewDescriptor::default()));
        Self { textures, views }
    }

    /// Bytes of both.
    pub fn bytes(resolution: u32) -> u64 {
        2 * (resolution as u64).pow(3) * 4
    }
}

impl Volume {
    fn new(device: &wgpu::Device, label: &str, resolution: u32) -> Self {
        let chain = levels(resolution).saturating_sub(1).max(1);
        let side = (resolution / 2).max(1);
        let chains =
            ["x", "y", "z"].map(|a| volume_texture(device, &format!("{label}/{a}"), (2 * side, side), chain, FORMAT));
        let base = volume_texture(device, &format!("{label}/base"), (resolution, resolution), 1, FORMAT);
        Self { base, chains }
    }

    /// Views for sampling: the base, then the chains.
    fn sampled(&self) -> [wgpu::TextureView; 4] {
        let view = |t: &wgpu::Texture| t.create_view(&wgpu::TextureViewDescriptor::default());
        [view(&self.base), view(&self.chains[0]), view(&self.chains[1]), view(&self.chains[2])]
    }

    /// Level `level` (from 1) of the chains, or the base three times for level 0.
    pub fn level(&self, level: u32) -> [wgpu::TextureView; 3] {
        let single = |t: &wgpu::Texture, mip: u32| {
            t.create_view(&wgpu::TextureViewDescriptor {
                label: Some("dvct/volume_level"),
                base_mip_level: mip,
                mip_level_count: Some(1),
                ..Default::default()
            })
        };
        if level == 0 {
            [(); 3].map(|_| single(&self.base, 0))
        } else {
            self.chains.each_ref().map(|t| single(t, level - 1))
        }
    }
}

/// A pair of prefiltered volumes, one per solution (`rv`: real and virtual surfaces; `r`:
/// real ones only).
pub struct VolumePair {
    /// Real+virtual volume.
    pub rv: Volume,
    /// Real-only volume.
    pub r: Volume,
    /// Views for sampling, in the order of cones.wgsl's bindings: the bases of `rv` and `r`,
    /// then the chains of `rv`, then those of `r`.
    pub sampled: Vec<wgpu::TextureView>,
}

impl VolumePair {
    /// Two `resolution`³ volumes with their chains, labelled `<label>/rv/…` and `<label>/r/…`.
    pub fn new(device: &wgpu::Device, label: &str, resolution: u32) -> Self {
        let rv = Volume::new(device, &format!("{label}/rv"), resolution);
        let r = Volume::new(device, &format!("{label}/r"), resolution);
        let [rv_base, rv_chains @ ..] = rv.sampled();
        let [r_base, r_chains @ ..] = r.sampled();
        let sampled = [rv_base, r_base].into_iter().chain(rv_chains).chain(r_chains).collect();
        Self { rv, r, sampled }
    }

    /// Voxels per side (the base texture's).
    pub fn resolution(&self) -> u32 {
        self.rv.base.width()
    }

    /// Bytes of both volumes with their chains.
    pub fn bytes(resolution: u32) -> u64 {
        let voxels = (resolution as u64).pow(3);
        // The base, and three chains of a quarter of it each (both ways), 8/7 with their levels.
        2 * (voxels * 8 + 3 * voxels * 8 * 8 / 7 / 4)
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
