//! Materials on the GPU: factors in one storage buffer (indexed by the material index in the
//! G-buffer flags) and every texture in one of two 2D arrays (sRGB colour, linear data), so
//! that compute passes can sample any material's textures without bindless support (which
//! lavapipe lacks). Textures are resampled to the arrays' common size when they differ.

use super::mips::rgba8_mips;
use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec4};
use mrshade_core::settings::SpecularSettings;
use mrshade_gpu::Target;
use mrshade_gpu::texture::write_level;
use mrshade_scene::{AlphaMode, Scene, Texture, TextureRef};
use wgpu::util::DeviceExt;

/// Marks an absent texture slot.
pub const NO_TEXTURE: u32 = u32::MAX;
/// Side of the texture arrays at most; larger textures are downsampled to it.
pub const MAX_TEXTURE_SIZE: u32 = 2048;

/// Mirrors `struct Material` in shaders/lib/gbuffer.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuMaterial {
    /// Linear base color and alpha.
    pub base_color: Vec4,
    /// Metallic, roughness, normal scale, occlusion strength.
    pub params: Vec4,
    /// Dielectric F0 (rgb), dielectric F90 (= specular factor).
    pub dielectric: Vec4,
    /// Transmission, ior, thickness, attenuation distance.
    pub transmission: Vec4,
    /// Attenuation color, alpha cutoff (< 0: opaque).
    pub attenuation_cutoff: Vec4,
    /// Emitted radiance (rgb).
    pub emissive: Vec4,
    /// Array layers of the base color, metallic-roughness, normal and occlusion textures.
    pub texture_layers: UVec4,
    /// Emissive layer, repeat bits (2 per slot: u then v, slot order as above + emissive),
    /// 1 if double-sided, unused.
    pub texture_info: UVec4,
}

/// Material factors and the texture arrays.
pub struct GpuMaterials {
    /// `GpuMaterial` per material.
    pub buffer: wgpu::Buffer,
    /// sRGB colour textures (base color, emissive).
    pub srgb: Target,
    /// Linear data textures (metallic-roughness, normal, occlusion).
    pub linear: Target,
    /// Trilinear, anisotropic, repeating.
    pub sampler: wgpu::Sampler,
}

impl GpuMaterials {
    /// Uploads every material and texture of `scene`; materials the specular stage traces
    /// (`specular.traces`) are marked so that the other passes leave their reflections to it.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene, specular: &SpecularSettings) -> Self {
        let size = scene.textures.iter().map(|t| t.width.max(t.height)).max().unwrap_or(1).next_power_of_two();
        let size = size.min(MAX_TEXTURE_SIZE);
        // Layer of every texture in its array.
        let mut layers = vec![0u32; scene.textures.len()];
        let (mut srgb, mut linear) = (Vec::new(), Vec::new());
        for (i, t) in scene.textures.iter().enumerate() {
            let list = if t.srgb { &mut srgb } else { &mut linear };
            layers[i] = list.len() as u32;
            list.push(t);
        }
        let gpu: Vec<GpuMaterial> = scene.materials.iter().map(|m| gpu_material(m, scene, &layers, specular)).collect();
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene/materials"),
            contents: bytemuck::cast_slice(&gpu),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("scene/material_sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            anisotropy_clamp: 8,
            ..Default::default()
        });
        Self {
            buffer,
            srgb: upload_array(device, queue, "scene/textures_srgb", &srgb, size, true),
            linear: upload_array(device, queue, "scene/textures_linear", &linear, size, false),
            sampler,
        }
    }

    /// Layout entries of the texture arrays and their sampler at bindings `first`, `first + 1`
    /// and `first + 2` of a group, as the shaders name them: textures_srgb, textures_linear,
    /// texture_sampler (shaders/lib/material_textures.wgsl samples them).
    pub fn texture_entries(first: u32, visibility: wgpu::ShaderStages) -> [wgpu::BindGroupLayoutEntry; 3] {
        use mrshade_gpu::bind;
        let (float, array) = (wgpu::TextureSampleType::Float { filterable: true }, wgpu::TextureViewDimension::D2Array);
        [
            bind::texture(first, visibility, float, array),
            bind::texture(first + 1, visibility, float, array),
            bind::sampler(first + 2, visibility, wgpu::SamplerBindingType::Filtering),
        ]
    }

    /// The resources of [`GpuMaterials::texture_entries`], in binding order.
    pub fn texture_resources(&self) -> [wgpu::BindingResource<'_>; 3] {
        use wgpu::BindingResource::{Sampler, TextureView};
        [TextureView(&self.srgb.view), TextureView(&self.linear.view), Sampler(&self.sampler)]
    }
}

fn gpu_material(
    m: &mrshade_scene::Material,
    scene: &Scene,
    layers: &[u32],
    specular: &SpecularSettings,
) -> GpuMaterial {
    let traced = specular.traces(m.metallic, m.roughness, m.transmission);
    let cutoff = match m.alpha_mode {
        AlphaMode::Mask(c) => c,
        AlphaMode::Opaque | AlphaMode::Blend => -1.0,
    };
    let slots = [
        m.base_color_texture,
        m.metallic_roughness_texture,
        m.normal_texture.map(|n| n.0),
        m.occlusion_texture.map(|o| o.0),
        m.emissive_texture,
    ];
    let layer = |r: Option<TextureRef>| r.map_or(NO_TEXTURE, |r| layers[r.texture]);
    let mut repeat_bits = 0u32;
    for (i, r) in slots.iter().enumerate() {
        if let Some(r) = r {
            let t = &scene.textures[r.texture];
            repeat_bits |= (t.repeat_u as u32) << (2 * i) | (t.repeat_v as u32) << (2 * i + 1);
        }
    }
    GpuMaterial {
        base_color: m.base_color,
        params: Vec4::new(
            m.metallic,
            m.roughness,
            m.normal_texture.map_or(1.0, |n| n.1),
            m.occlusion_texture.map_or(0.0, |o| o.1),
        ),
        dielectric: m.dielectric_f0().extend(m.specular),
        transmission: Vec4::new(m.transmission, m.ior, m.thickness, m.attenuation_distance.min(1e30)),
        attenuation_cutoff: m.attenuation_color.extend(cutoff),
        emissive: m.emissive.extend(0.0),
        texture_layers: UVec4::new(layer(slots[0]), layer(slots[1]), layer(slots[2]), layer(slots[3])),
        texture_info: UVec4::new(layer(slots[4]), repeat_bits, m.double_sided as u32, traced as u32),
    }
}

/// A `size × size` 2D array with full mip chains (one layer when `textures` is empty).
fn upload_array(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    textures: &[&Texture],
    size: u32,
    srgb: bool,
) -> Target {
    let format = if srgb { wgpu::TextureFormat::Rgba8UnormSrgb } else { wgpu::TextureFormat::Rgba8Unorm };
    let mips = 1 + size.ilog2();
    let layers = textures.len().max(1) as u32;
    let target = Target::new(
        device,
        label,
        wgpu::Extent3d { width: size, height: size, depth_or_array_layers: layers },
        mips,
        format,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    let target = Target {
        view: target.texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(label),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        }),
        ..target
    };
    for (layer, t) in textures.iter().enumerate() {
        let level0 = resized(t, size);
        let mut levels = vec![(size, size, level0.clone())];
        levels.extend(rgba8_mips(size, size, &level0, srgb));
        for (level, (w, h, data)) in levels.iter().enumerate() {
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &target.texture,
                    mip_level: level as u32,
                    origin: wgpu::Origin3d { x: 0, y: 0, z: layer as u32 },
                    aspect: wgpu::TextureAspect::All,
                },
                data,
                wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(w * 4), rows_per_image: Some(*h) },
                wgpu::Extent3d { width: *w, height: *h, depth_or_array_layers: 1 },
            );
        }
    }
    if textures.is_empty() {
        write_level(queue, &target.texture, 0, (1, 1), 4, &[255, 255, 255, 255]);
    }
    target
}

/// The texels of `t` at `size × size` (bilinear resampling when the size differs).
fn resized(t: &Texture, size: u32) -> Vec<u8> {
    if t.width == size && t.height == size {
        return t.rgba8.clone();
    }
    let img = image::RgbaImage::from_raw(t.width, t.height, t.rgba8.clone()).expect("texture size");
    image::imageops::resize(&img, size, size, image::imageops::FilterType::Triangle).into_raw()
}
