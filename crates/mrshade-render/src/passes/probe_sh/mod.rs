//! The probe's SH coefficients on the GPU, every frame (Franke §2.1): what the `sh`, `fis`
//! and `prt` shading of virtual objects (`[ibl] virtual`) reads for their diffuse light.
//! Inputs: the probe's box-filtered pyramid, the frame (probe rotation), the instances (their
//! rotation). Output: `coefficients`, 9 or 16 (`ibl.prt_coefficients`) RGB in the probe's
//! frame, then as many per PRT instance in its object frame.

use crate::scene_gpu::GpuProbe;
use glam::UVec4;
use mrshade_gpu::timing::{Dispatch, Recorder};
use mrshade_gpu::{GpuContext, bind, wgsl};
use wgpu::util::DeviceExt;

/// Widest pyramid level projected: bands 2 and 3 need no finer texels.
const SOURCE_WIDTH: u32 = 128;

/// The projection pass and its output.
pub struct ProbeShPass {
    /// One workgroup per frame (the probe's, then each PRT instance's).
    dispatch: Dispatch,
    /// 9 or 16 `vec4f` per frame (rgb: radiance coefficient `c_i` of the unscaled probe),
    /// the probe's own first, then each of `prt_instances`' object frames.
    pub coefficients: wgpu::Buffer,
}

impl ProbeShPass {
    /// GPU timing label.
    pub const LABEL: &'static str = "probe-sh";

    /// Binds `probe`'s pyramid; projects it onto `coefficients` (9 or 16) SH functions, also
    /// into the object frames of `prt_instances` (indices into `instances`, the scene's
    /// `GpuInstance`s).
    pub fn new(
        ctx: &GpuContext,
        probe: &GpuProbe,
        frame: &wgpu::Buffer,
        instances: &wgpu::Buffer,
        prt_instances: &[u32],
        coefficients: usize,
    ) -> Self {
        assert!(coefficients == 9 || coefficients == 16, "9 or 16 SH coefficients");
        let device = &ctx.device;
        let cs = wgpu::ShaderStages::COMPUTE;
        let size = probe.pyramid.size();
        let level = (0..probe.pyramid_mips).find(|l| size.0 >> l <= SOURCE_WIDTH).unwrap_or(probe.pyramid_mips - 1);
        let n = coefficients as u32;
        let source = UVec4::new(level, (size.0 >> level).max(1), (size.1 >> level).max(1), 0);
        let source = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("probe_sh/source"),
            contents: bytemuck::bytes_of(&source),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let frames = 1 + prt_instances.len() as u32;
        let mut list = prt_instances.to_vec();
        list.push(0);
        let prt_instances = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("probe_sh/prt_instances"),
            contents: bytemuck::cast_slice(&list),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let coefficients = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("probe_sh/coefficients"),
            size: (frames * n) as u64 * 16,
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
                bind::uniform(3, cs),
                bind::storage(4, cs),
                bind::storage(5, cs),
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
                frame.as_entire_binding(),
                instances.as_entire_binding(),
                prt_instances.as_entire_binding(),
            ],
        );
        let pipeline = mrshade_gpu::shader::compute_pipeline_with(
            device,
            "probe_sh",
            SHADER,
            "cs_main",
            &[&layout],
            &[("COEFFICIENTS", n as f64)],
        );
        Self { dispatch: Dispatch { pipeline, groups: vec![group], workgroups: [frames, 1, 1] }, coefficients }
    }

    /// Projects the probe.
    pub fn record(&self, rec: &mut Recorder) {
        rec.compute(Self::LABEL, |pass| self.dispatch.record(pass));
    }
}

/// The projection module.
pub const SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/instance.wgsl",
    "../../../shaders/lib/sh.wgsl",
    "probe_sh.wgsl"
);
