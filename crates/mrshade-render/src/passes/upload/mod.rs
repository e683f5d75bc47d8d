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
    /// Packs `image` at `(width, height)`, resizing it when it has another size.
    pub fn new(image: &HdrImage, (width, height): (u32, u32)) -> Self {
        let resized;
        let image = if (image.width, image.height) == (width, height) {
            image
        } else {
            resized = image.resized(width, height);
            &resized
        };
        let rgba: Vec<f32> = image.pixels.iter().flat_map(|p| [p[0], p[1], p[2], 1.0]).collect();
        let mut texels = vec![f16::ZERO; rgba.len()];
        half::slice::HalfFloatSliceExt::convert_from_f32_slice(&mut texels[..], &rgba);
        Self { width: image.width, height: image.height, texels }
    }

    /// 8-bit sRGB RGB rows (a live stream's frame, ffmpeg's `rgb24`) of `width × height`
    /// pixels, decoded as a PNG photo is (`srgb_u8_decode_table`) straight to half floats:
    /// one pass, in parallel, the same texels as [`PackedPhoto::new`] of the decoded image.
    pub fn from_srgb8(rgb: &[u8], (width, height): (u32, u32)) -> Self {
        use rayon::prelude::*;
        assert_eq!(rgb.len(), width as usize * height as usize * 3, "a {width}×{height} RGB frame");
        let table = mrshade_core::color::srgb_u8_decode_table().map(f16::from_f32);
        let mut texels = vec![f16::ONE; width as usize * height as usize * 4];
        texels.par_chunks_mut(4 * 4096).zip(rgb.par_chunks(3 * 4096)).for_each(|(texels, rgb)| {
            for (t, p) in texels.chunks_exact_mut(4).zip(rgb.chunks_exact(3)) {
                t[..3].copy_from_slice(&[table[p[0] as usize], table[p[1] as usize], table[p[2] as usize]]);
            }
        });
        Self { width, height, texels }
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

    /// Uploads `photo`, packed at the output size, before the next frame.
    pub fn write(&mut self, queue: &wgpu::Queue, photo: &PackedPhoto) {
        let (w, h) = self.photo.size();
        assert_eq!((photo.width, photo.height), (w, h), "a photo is packed at the renderer's output size");
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb8_frames_pack_as_their_decoded_images() {
        let rgb: Vec<u8> = (0..5 * 3 * 3).map(|i| (i * 37 % 256) as u8).collect();
        let table = mrshade_core::color::srgb_u8_decode_table();
        let pixels = rgb.chunks_exact(3).map(|p| [0, 1, 2].map(|c| table[p[c] as usize])).collect();
        let image = HdrImage { width: 5, height: 3, pixels };
        assert_eq!(PackedPhoto::from_srgb8(&rgb, (5, 3)).texels, PackedPhoto::new(&image, (5, 3)).texels);
    }
}
