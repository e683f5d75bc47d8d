//! Test helpers shared by mrshade's crates.
//!
//! - [`gpu`]: the test GPU. It must exist: without an adapter a GPU test fails (never skips),
//!   telling how to install lavapipe.
//! - [`flip`] and [`golden`]: FLIP (NVIDIA ꟻLIP, via nv-flip) comparisons and golden images.
//! - [`gltf`]: a small glTF writer for synthetic test scenes and malformed inputs.
//! - [`deform`]: skinned and morphing test models (Khronos `SimpleSkin`, `AnimatedMorphCube`
//!   style) with their vertex positions computed by hand.

pub mod deform;
pub mod flip;
pub mod gltf;
pub mod golden;

use mrshade_gpu::{GpuContext, GpuOptions};

/// The GPU for tests: the preferred adapter, or a panic that says how to get one.
pub fn gpu() -> GpuContext {
    match GpuContext::new(&GpuOptions::default()) {
        Ok(ctx) => {
            eprintln!("test adapter: {}", ctx.describe());
            ctx
        }
        Err(e) => panic!("GPU tests need an adapter and never skip: {e:#}"),
    }
}

/// Whether this run is CI (`CI=true`), where missing goldens are failures.
pub fn is_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true" || v == "1")
}

/// Runs `cs_main` of the WGSL `source` over `count` invocations (workgroup size 1) with
/// `input` bound as a read-only storage buffer at binding 0 and a `vec4f` per invocation
/// at binding 1, and returns binding 1: a harness for known-answer tests of shader functions.
pub fn run_kernel(ctx: &mrshade_gpu::GpuContext, source: &str, input: &[u8], count: u32) -> Vec<f32> {
    use mrshade_gpu::bind;
    use wgpu::util::DeviceExt;
    let device = &ctx.device;
    let cs = wgpu::ShaderStages::COMPUTE;
    let layout = bind::layout(device, "test_kernel/layout", &[bind::storage(0, cs), bind::storage_rw(1, cs)]);
    let pipeline = mrshade_gpu::shader::compute_pipeline(device, "test_kernel", source, &[&layout]);
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("test_kernel/input"),
        contents: input,
        usage: wgpu::BufferUsages::STORAGE,
    });
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("test_kernel/output"),
        size: 16 * count as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let group =
        bind::group(device, "test_kernel/group", &layout, &[input.as_entire_binding(), output.as_entire_binding()]);
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("test_kernel") });
    {
        let mut pass = encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("test_kernel"), timestamp_writes: None });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(count, 1, 1);
    }
    ctx.queue.submit([encoder.finish()]);
    let bytes = mrshade_gpu::readback::read_buffer(ctx, &output).expect("reading the kernel's output");
    bytemuck::cast_slice(&bytes).to_vec()
}
