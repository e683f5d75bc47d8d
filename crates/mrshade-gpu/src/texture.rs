//! Labelled render targets and sampled textures.

/// A texture with its default view.
pub struct Target {
    /// The texture.
    pub texture: wgpu::Texture,
    /// A view of all of it.
    pub view: wgpu::TextureView,
    /// Its label, for views and messages.
    pub label: String,
}

impl Target {
    /// A 2D texture of `width × height` with one mip level.
    pub fn new_2d(
        device: &wgpu::Device,
        label: &str,
        (width, height): (u32, u32),
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> Self {
        Self::new(device, label, wgpu::Extent3d { width, height, depth_or_array_layers: 1 }, 1, format, usage)
    }

    /// A texture of the given extent and mip count (layers become a 2D array).
    pub fn new(
        device: &wgpu::Device,
        label: &str,
        size: wgpu::Extent3d,
        mip_level_count: u32,
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> Self {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size,
            mip_level_count,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(label),
            dimension: Some(if size.depth_or_array_layers > 1 {
                wgpu::TextureViewDimension::D2Array
            } else {
                wgpu::TextureViewDimension::D2
            }),
            ..Default::default()
        });
        Self { texture, view, label: label.to_string() }
    }

    /// A 2D array texture of `layers` layers (viewed as an array even with one layer).
    pub fn new_array(
        device: &wgpu::Device,
        label: &str,
        (width, height, layers): (u32, u32, u32),
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> Self {
        let size = wgpu::Extent3d { width, height, depth_or_array_layers: layers };
        let mut target = Self::new(device, label, size, 1, format, usage);
        target.view = target.texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(label),
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        target
    }

    /// A view of one layer, for rendering into it.
    pub fn layer_view(&self, layer: u32) -> wgpu::TextureView {
        self.texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(&format!("{}/layer{layer}", self.label)),
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_array_layer: layer,
            array_layer_count: Some(1),
            ..Default::default()
        })
    }

    /// (width, height) of mip 0.
    pub fn size(&self) -> (u32, u32) {
        (self.texture.width(), self.texture.height())
    }
}

/// Uploads `data` (tightly packed rows) into mip `level` of `texture`.
pub fn write_level(
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    level: u32,
    (width, height): (u32, u32),
    bytes_per_texel: u32,
    data: &[u8],
) {
    queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: level,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        data,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(width * bytes_per_texel),
            rows_per_image: Some(height),
        },
        wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
    );
}
