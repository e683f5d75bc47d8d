//! Materials on the GPU: factors in one storage buffer (indexed by the material index stored
//! in the G-buffer), textures in one bind group per material.

use super::mips::rgba8_mips;
use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec4};
use mrshade_gpu::{bind, texture::write_level};
use mrshade_scene::{AlphaMode, Scene, Texture, TextureRef};
use wgpu::util::DeviceExt;

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
    /// Bit 0: has a normal map.
    pub texture_flags: UVec4,
}

impl GpuMaterial {
    fn new(m: &mrshade_scene::Material) -> Self {
        let cutoff = match m.alpha_mode {
            AlphaMode::Mask(c) => c,
            AlphaMode::Opaque | AlphaMode::Blend => -1.0,
        };
        Self {
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
            texture_flags: UVec4::new(m.normal_texture.is_some() as u32, 0, 0, 0),
        }
    }
}

/// The five texture slots of a material, in binding order.
const SLOTS: usize = 5;

/// Material factors and per-material texture bind groups.
pub struct GpuMaterials {
    /// `GpuMaterial` per material.
    pub buffer: wgpu::Buffer,
    /// Layout of one material's textures (G-buffer group 1).
    pub layout: wgpu::BindGroupLayout,
    /// One bind group per material.
    pub bind_groups: Vec<wgpu::BindGroup>,
}

impl GpuMaterials {
    /// Uploads every material and texture of `scene`.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene) -> Self {
        let gpu: Vec<GpuMaterial> = scene.materials.iter().map(GpuMaterial::new).collect();
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene/materials"),
            contents: bytemuck::cast_slice(&gpu),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let fragment = wgpu::ShaderStages::FRAGMENT;
        let mut entries = Vec::new();
        for slot in 0..SLOTS as u32 {
            entries.push(bind::texture_float(slot, fragment));
        }
        for slot in 0..SLOTS as u32 {
            entries.push(bind::sampler(SLOTS as u32 + slot, fragment, wgpu::SamplerBindingType::Filtering));
        }
        let layout = bind::layout(device, "gbuffer/material_layout", &entries);

        let views: Vec<wgpu::TextureView> = scene.textures.iter().map(|t| upload(device, queue, t)).collect();
        let white = upload(device, queue, &solid("default/white", [255, 255, 255, 255]));
        let flat_normal = upload(device, queue, &solid("default/normal", [128, 128, 255, 255]));
        let samplers: Vec<wgpu::Sampler> = (0..4).map(|i| sampler(device, i & 1 != 0, i & 2 != 0)).collect();
        let sampler_of = |r: Option<TextureRef>| {
            r.map_or(&samplers[3], |r| {
                let t = &scene.textures[r.texture];
                &samplers[t.repeat_u as usize | (t.repeat_v as usize) << 1]
            })
        };
        let bind_groups = scene
            .materials
            .iter()
            .map(|m| {
                let slots = [
                    (m.base_color_texture, &white),
                    (m.metallic_roughness_texture, &white),
                    (m.normal_texture.map(|n| n.0), &flat_normal),
                    (m.occlusion_texture.map(|o| o.0), &white),
                    (m.emissive_texture, &white),
                ];
                let mut resources: Vec<wgpu::BindingResource> = slots
                    .iter()
                    .map(|(r, default)| wgpu::BindingResource::TextureView(r.map_or(*default, |r| &views[r.texture])))
                    .collect();
                resources.extend(slots.iter().map(|(r, _)| wgpu::BindingResource::Sampler(sampler_of(*r))));
                bind::group(device, &format!("gbuffer/material/{}", m.name), &layout, &resources)
            })
            .collect();
        Self { buffer, layout, bind_groups }
    }
}

fn solid(name: &str, rgba: [u8; 4]) -> Texture {
    Texture {
        name: name.into(),
        width: 1,
        height: 1,
        rgba8: rgba.to_vec(),
        srgb: false,
        repeat_u: true,
        repeat_v: true,
    }
}

fn upload(device: &wgpu::Device, queue: &wgpu::Queue, t: &Texture) -> wgpu::TextureView {
    let mips = rgba8_mips(t.width, t.height, &t.rgba8, t.srgb);
    let format = if t.srgb { wgpu::TextureFormat::Rgba8UnormSrgb } else { wgpu::TextureFormat::Rgba8Unorm };
    let target = mrshade_gpu::Target::new(
        device,
        &format!("scene/texture/{}", t.name),
        wgpu::Extent3d { width: t.width, height: t.height, depth_or_array_layers: 1 },
        1 + mips.len() as u32,
        format,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    write_level(queue, &target.texture, 0, (t.width, t.height), 4, &t.rgba8);
    for (level, (w, h, data)) in mips.iter().enumerate() {
        write_level(queue, &target.texture, level as u32 + 1, (*w, *h), 4, data);
    }
    target.view
}

fn sampler(device: &wgpu::Device, repeat_u: bool, repeat_v: bool) -> wgpu::Sampler {
    let mode = |r: bool| if r { wgpu::AddressMode::Repeat } else { wgpu::AddressMode::ClampToEdge };
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("scene/material_sampler"),
        address_mode_u: mode(repeat_u),
        address_mode_v: mode(repeat_v),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        anisotropy_clamp: 8,
        ..Default::default()
    })
}
