//! The photo's upload: each frame's photo into the texture the composite reads, as half
//! floats (`Rgba16Float`, 8 bytes a pixel: half of an `Rgba32Float` upload, which at 1080p
//! kept the CPU busier than the GPU's whole frame). Every 8-bit sRGB value survives the
//! round trip exactly (half floats keep 11 significant bits; neighbouring sRGB codes differ by
//! more than 0.4 %), and HDR photos are half floats in most EXRs already. A texture write has
//! no buffer-binding limit, so any output size the device's textures hold uploads.

use half::f16;
use mrshade_core::HdrImage;
use mrshade_gpu::{GpuContext, Target};

/// A photo packed for upload: RGBA half floats at a given size.
pub struct PackedPhoto {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    texels: Vec<f16>,
}

impl PackedPhoto {
    /// Packs `image`.
    pub fn new(image: &HdrImage) -> Self {
        let rgba: Vec<f32> = image.pixels.iter().flat_map(|p| [p[0], p[1], p[2], 1.0]).collect();
        let mut texels = vec![f16::ZERO; rgba.len()];
        half::slice::HalfFloatSliceExt::convert_from_f32_slice(&mut texels[..], &rgba);
        Self { width: image.width, height: image.height, texels }
    }

    /// Bytes uploaded.
    pub fn bytes(&self) -> u64 {
        self.texels.len() as u64 * 2
    }
}

/// The photo texture.
pub struct PhotoUpload {
    /// Linear `Rgba16Float` photo at the output size (read by the composite).
    pub photo: Target,
}

impl PhotoUpload {
    /// Format of the photo texture.
    pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

    /// The photo texture of `size` (output pixels).
    pub fn new(ctx: &GpuContext, size: (u32, u32)) -> Self {
        let usage = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST;
        Self { photo: Target::new_2d(&ctx.device, "upload/photo", size, Self::FORMAT, usage) }
    }

    /// Uploads `photo` before the next frame; one of another size is resized first.
    pub fn write(&mut self, queue: &wgpu::Queue, photo: &PackedPhoto) {
        let (w, h) = self.photo.size();
        if (photo.width, photo.height) != (w, h) {
            let image = HdrImage {
                width: photo.width,
                height: photo.height,
                pixels: photo.texels.chunks_exact(4).map(|t| [t[0].to_f32(), t[1].to_f32(), t[2].to_f32()]).collect(),
            };
            return self.write(queue, &PackedPhoto::new(&image.resized(w, h)));
        }
        mrshade_gpu::texture::write_level(
            queue,
            &self.photo.texture,
            0,
            (w, h),
            8,
            bytemuck::cast_slice(&photo.texels),
        );
    }

    /// Bytes one photo upload moves.
    pub fn bytes(&self) -> u64 {
        let (w, h) = self.photo.size();
        w as u64 * h as u64 * 8
    }
}
