//! Bind-group-layout entries, named for what they bind.

use wgpu::{BindGroupLayoutEntry as Entry, BindingType, ShaderStages};

/// A uniform buffer.
pub fn uniform(binding: u32, visibility: ShaderStages) -> Entry {
    Entry {
        binding,
        visibility,
        ty: BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A uniform buffer bound with a dynamic offset.
pub fn uniform_dynamic(binding: u32, visibility: ShaderStages) -> Entry {
    Entry {
        binding,
        visibility,
        ty: BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: true,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A read-only storage buffer.
pub fn storage(binding: u32, visibility: ShaderStages) -> Entry {
    Entry {
        binding,
        visibility,
        ty: BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A read-write storage buffer.
pub fn storage_rw(binding: u32, visibility: ShaderStages) -> Entry {
    Entry {
        binding,
        visibility,
        ty: BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: false },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A sampled 2D texture of float texels (filterable).
pub fn texture_float(binding: u32, visibility: ShaderStages) -> Entry {
    texture(binding, visibility, wgpu::TextureSampleType::Float { filterable: true }, wgpu::TextureViewDimension::D2)
}

/// A sampled texture of any type and dimension.
pub fn texture(
    binding: u32,
    visibility: ShaderStages,
    sample_type: wgpu::TextureSampleType,
    view_dimension: wgpu::TextureViewDimension,
) -> Entry {
    Entry {
        binding,
        visibility,
        ty: BindingType::Texture { sample_type, view_dimension, multisampled: false },
        count: None,
    }
}

/// A write-only 2D storage texture.
pub fn storage_texture(binding: u32, format: wgpu::TextureFormat) -> Entry {
    storage_texture_of(binding, format, wgpu::TextureViewDimension::D2)
}

/// A write-only storage texture of any dimension.
pub fn storage_texture_of(
    binding: u32,
    format: wgpu::TextureFormat,
    view_dimension: wgpu::TextureViewDimension,
) -> Entry {
    Entry {
        binding,
        visibility: ShaderStages::COMPUTE,
        ty: BindingType::StorageTexture { access: wgpu::StorageTextureAccess::WriteOnly, format, view_dimension },
        count: None,
    }
}

/// A sampler.
pub fn sampler(binding: u32, visibility: ShaderStages, ty: wgpu::SamplerBindingType) -> Entry {
    Entry { binding, visibility, ty: BindingType::Sampler(ty), count: None }
}

/// Creates a bind group whose entries are `resources` at bindings 0, 1, 2, …
pub fn group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource],
) -> wgpu::BindGroup {
    let at: Vec<(u32, wgpu::BindingResource)> =
        resources.iter().enumerate().map(|(i, r)| (i as u32, r.clone())).collect();
    group_at(device, label, layout, &at)
}

/// Creates a bind group of `(binding, resource)` entries: where a layout leaves bindings out.
pub fn group_at(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[(u32, wgpu::BindingResource)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> =
        resources.iter().map(|(binding, r)| wgpu::BindGroupEntry { binding: *binding, resource: r.clone() }).collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some(label), layout, entries: &entries })
}

/// Creates a bind group layout from entries.
pub fn layout(device: &wgpu::Device, label: &str, entries: &[Entry]) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries })
}
