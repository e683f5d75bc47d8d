//! Encode pass: the composite to 8-bit sRGB on the GPU, read back into a buffer kept from
//! frame to frame, for live streams (`crate::stream`), where reading back the linear
//! composite (16 bytes a pixel) and encoding it on the CPU took most of a frame's time at
//! 720p. The codes are those of `HdrImage::to_srgb8` (the same thresholds, searched the same
//! way: a test compares them). Input: the composite. Output: RGB bytes.

use anyhow::{Result, bail};
use mrshade_core::color::SrgbEncoder;
use mrshade_gpu::{GpuContext, Target, bind, readback, wgsl};
use wgpu::util::DeviceExt;

/// The pass's WGSL.
pub const SHADER: &str = wgsl!("encode.wgsl");

/// The pass and its read-back buffers.
pub struct EncodePass {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    codes: wgpu::Buffer,
    non_finite: wgpu::Buffer,
    /// `codes` then the non-finite count, mapped for reading.
    readback: wgpu::Buffer,
    size: (u32, u32),
}

impl EncodePass {
    /// Binds `composite` (`Rgba32Float`, with texture binding).
    pub fn new(ctx: &GpuContext, composite: &Target) -> Self {
        let device = &ctx.device;
        let size = composite.size();
        let code_bytes = size.0 as u64 * size.1 as u64 * 4;
        let thresholds = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("encode/thresholds"),
            contents: bytemuck::cast_slice(SrgbEncoder::new().thresholds()),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let buffer = |label: &str, size: u64, usage| {
            device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false })
        };
        let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
        let codes = buffer("encode/codes", code_bytes, storage);
        let non_finite = buffer("encode/non_finite", 4, storage);
        let readback =
            buffer("encode/readback", code_bytes + 4, wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ);
        let cs = wgpu::ShaderStages::COMPUTE;
        let layout = bind::layout(
            device,
            "encode/layout",
            &[
                bind::texture(
                    0,
                    cs,
                    wgpu::TextureSampleType::Float { filterable: false },
                    wgpu::TextureViewDimension::D2,
                ),
                bind::storage(1, cs),
                bind::storage_rw(2, cs),
                bind::storage_rw(3, cs),
            ],
        );
        let group = bind::group(
            device,
            "encode/group",
            &layout,
            &[
                wgpu::BindingResource::TextureView(&composite.view),
                thresholds.as_entire_binding(),
                codes.as_entire_binding(),
                non_finite.as_entire_binding(),
            ],
        );
        let pipeline = mrshade_gpu::shader::compute_pipeline(device, "encode", SHADER, &[&layout]);
        Self { pipeline, group, codes, non_finite, readback, size }
    }

    /// Encodes the composite as it is now (after the frames submitted so far) and reads it
    /// back as `width × height × 3` RGB bytes; a composite holding NaN or infinite values is
    /// an error, never a silent black frame.
    pub fn read(&self, ctx: &GpuContext) -> Result<Vec<u8>> {
        let (w, h) = self.size;
        let code_bytes = w as u64 * h as u64 * 4;
        let mut encoder = ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("encode") });
        encoder.clear_buffer(&self.non_finite, 0, None);
        {
            let mut pass = encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("encode"), timestamp_writes: None });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.group, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
        encoder.copy_buffer_to_buffer(&self.codes, 0, &self.readback, 0, code_bytes);
        encoder.copy_buffer_to_buffer(&self.non_finite, 0, &self.readback, code_bytes, 4);
        ctx.queue.submit([encoder.finish()]);
        let (rgb, non_finite) = readback::map_read(ctx, &self.readback, |mapped| {
            let words: &[u32] = bytemuck::cast_slice(mapped);
            let (codes, bad) = words.split_at(words.len() - 1);
            (if bad[0] == 0 { unpack(codes) } else { Vec::new() }, bad[0])
        })?;
        if non_finite > 0 {
            bail!("the frame has {non_finite} pixels that are NaN or infinite (not written as black)");
        }
        Ok(rgb)
    }
}

/// `r | g << 8 | b << 16` words to RGB bytes, in parallel.
fn unpack(codes: &[u32]) -> Vec<u8> {
    use rayon::prelude::*;
    let mut rgb = vec![0u8; codes.len() * 3];
    rgb.par_chunks_mut(3 * 4096).zip(codes.par_chunks(4096)).for_each(|(rgb, codes)| {
        for (p, &c) in rgb.chunks_exact_mut(3).zip(codes) {
            p.copy_from_slice(&c.to_le_bytes()[..3]);
        }
    });
    rgb
}
