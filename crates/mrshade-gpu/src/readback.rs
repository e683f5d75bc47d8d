//! Texture → CPU copies, for saving outputs and for tests.

use crate::GpuContext;
use anyhow::{Context, Result};

/// Reads mip 0, layer 0 of `texture` into tightly packed rows.
pub fn read_texture(ctx: &GpuContext, texture: &wgpu::Texture) -> Result<Vec<u8>> {
    read_level(ctx, texture, 0, 1)
}

/// Reads mip `level` of the 3D `texture`, every slice, into tightly packed rows (slice-major).
pub fn read_volume_level(ctx: &GpuContext, texture: &wgpu::Texture, level: u32) -> Result<Vec<u8>> {
    read_level(ctx, texture, level, (texture.depth_or_array_layers() >> level).max(1))
}

/// Reads `depth` slices (or layers) of mip `level` of `texture`.
fn read_level(ctx: &GpuContext, texture: &wgpu::Texture, level: u32, depth: u32) -> Result<Vec<u8>> {
    let (width, height) = ((texture.width() >> level).max(1), (texture.height() >> level).max(1));
    let texel = texture.format().block_copy_size(None).context("format cannot be copied")?;
    let row = width * texel;
    let padded_row = row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback/staging"),
        size: (padded_row * height * depth) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("readback") });
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: level,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_row),
                rows_per_image: Some(height),
            },
        },
        wgpu::Extent3d { width, height, depth_or_array_layers: depth },
    );
    ctx.queue.submit([encoder.finish()]);
    map_read(ctx, &buffer, |mapped| {
        let mut out = Vec::with_capacity((row * height * depth) as usize);
        for y in 0..height * depth {
            let start = (y * padded_row) as usize;
            out.extend_from_slice(&mapped[start..start + row as usize]);
        }
        out
    })
}

/// Waits for the work submitted so far, maps `buffer` (`MAP_READ`) and hands its bytes to
/// `read`; unmaps it after, so that a buffer kept from frame to frame can be read again.
pub fn map_read<T>(ctx: &GpuContext, buffer: &wgpu::Buffer, read: impl FnOnce(&[u8]) -> T) -> Result<T> {
    let slice = buffer.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    ctx.wait_idle()?;
    rx.recv().context("readback callback lost")?.context("mapping the readback buffer failed")?;
    let out = {
        let mapped = slice.get_mapped_range().map_err(|e| anyhow::anyhow!("readback buffer not mapped: {e:?}"))?;
        read(&mapped)
    };
    buffer.unmap();
    Ok(out)
}

/// Reads an `Rgba32Float` texture as RGBA texels.
pub fn read_rgba32f(ctx: &GpuContext, texture: &wgpu::Texture) -> Result<Vec<[f32; 4]>> {
    anyhow::ensure!(texture.format() == wgpu::TextureFormat::Rgba32Float, "expected Rgba32Float");
    Ok(bytemuck::cast_slice(&read_texture(ctx, texture)?).to_vec())
}

/// Reads an `R32Uint` texture.
pub fn read_r32u(ctx: &GpuContext, texture: &wgpu::Texture) -> Result<Vec<u32>> {
    anyhow::ensure!(texture.format() == wgpu::TextureFormat::R32Uint, "expected R32Uint");
    Ok(bytemuck::cast_slice(&read_texture(ctx, texture)?).to_vec())
}

/// Reads a whole buffer (it needs `COPY_SRC`).
pub fn read_buffer(ctx: &GpuContext, source: &wgpu::Buffer) -> Result<Vec<u8>> {
    let size = source.size();
    let staging = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback/buffer_staging"),
        size,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("readback") });
    encoder.copy_buffer_to_buffer(source, 0, &staging, 0, size);
    ctx.queue.submit([encoder.finish()]);
    map_read(ctx, &staging, <[u8]>::to_vec)
}
