//! The probe's nine SH coefficients on the GPU, every frame (Franke §2.1): what the `sh` and
//! `fis` shading of virtual objects (`[ibl] virtual`) reads for their diffuse light.
//! Inputs: the probe's box-filtered pyramid. Output: `coefficients` (nine RGB, probe frame).

use crate::scene_gpu::GpuProbe;
use glam::UVec4;
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, bind, wgsl};
use wgpu::util::DeviceExt;

/// Widest pyramid level projected: band 2 needs no finer texels.
const SOURCE_WIDTH: u32 = 128;

/// The projection pass and its output.
pub struct ProbeShPass {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    /// Nine `vec4f` (rgb: radiance coefficient `c_i` of the unrotated, unscaled probe).
    pub coefficients: wgpu::Buffer,
}

impl ProbeShPass {
    /// GPU timing label.
    pub const LABEL: &'static str = "probe-sh";

    /// Binds `probe`'s pyramid.
    pub fn new(ctx: &GpuContext, probe: &GpuProbe) -> Self {
        let device = &ctx.device;
        let cs = wgpu::ShaderStages::COMPUTE;
        let size = probe.pyramid.size();
        let level = (0..probe.pyramid_mips).find(|l| size.0 >> l <= SOURCE_WIDTH).unwrap_or(probe.pyramid_mips - 1);
        let source = UVec4::new(level, (size.0 >> level).max(1), (size.1 >> level).max(1), 0);
        let source = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("probe_sh/source"),
            contents: bytemuck::bytes_of(&source),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let coefficients = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("probe_sh/coefficients"),
            size: 9 * 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let layout = bind::layout(
            device,
            "probe_sh/layout",
            &[
                bind::texture(
                    0,
                    cs,
                    wgpu::TextureSampleType::Float { filterable: false },
                    wgpu::TextureViewDimension::D2,
                ),
                bind::storage_rw(1, cs),
                bind::uniform(2, cs),
            ],
        );
        let group = bind::group(
            device,
            "probe_sh/group",
            &layout,
            &[
                wgpu::BindingResource::TextureView(&probe.pyramid.view),
                coefficients.as_entire_binding(),
                source.as_entire_binding(),
            ],
        );
        let pipeline = mrshade_gpu::shader::compute_pipeline(device, "probe_sh", SHADER, &[&layout]);
        Self { pipeline, group, coefficients }
    }

    /// Projects the probe.
    pub fn record(&self, rec: &mut Recorder) {
        rec.compute(Self::LABEL, |pass| {
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.group, &[]);
            pass.dispatch_workgroups(1, 1, 1);
        });
    }
}

/// The projection module.
pub const SHADER: &str = wgsl!("../../../shaders/lib/frame.wgsl", "../../../shaders/lib/sh.wgsl", "probe_sh.wgsl");
