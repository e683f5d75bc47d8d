//! WGSL modules. WGSL has no `#include`; a module is the concatenation of shared library
//! files and the pass's own file, checked at compile time to exist (`include_str!`) and at
//! test time to validate (`naga`).

/// Concatenates WGSL files (paths relative to the invoking source file) into one string.
#[macro_export]
macro_rules! wgsl {
    ($($file:literal),+ $(,)?) => {
        concat!($(include_str!($file), "\n"),+)
    };
}

/// Creates a labelled shader module from WGSL source.
pub fn create_module(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}

/// A compute pipeline running `cs_main` of `source` with the given bind group layouts
/// (labels `<label>/shader`, `<label>/pipeline_layout`, `<label>/pipeline`).
pub fn compute_pipeline(
    device: &wgpu::Device,
    label: &str,
    source: &str,
    layouts: &[&wgpu::BindGroupLayout],
) -> wgpu::ComputePipeline {
    compute_pipeline_entry(device, label, source, "cs_main", layouts)
}

/// A compute pipeline running `entry` of `source`.
pub fn compute_pipeline_entry(
    device: &wgpu::Device,
    label: &str,
    source: &str,
    entry: &str,
    layouts: &[&wgpu::BindGroupLayout],
) -> wgpu::ComputePipeline {
    compute_pipeline_with(device, label, source, entry, layouts, &[])
}

/// A compute pipeline running `entry` of `source` with its pipeline-overridable constants
/// (`override NAME: T = …;`) set to `constants`: compile-time values to the driver, so that
/// loops bounded by them unroll.
pub fn compute_pipeline_with(
    device: &wgpu::Device,
    label: &str,
    source: &str,
    entry: &str,
    layouts: &[&wgpu::BindGroupLayout],
    constants: &[(&str, f64)],
) -> wgpu::ComputePipeline {
    let module = create_module(device, &format!("{label}/shader"), source);
    let layouts: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(|l| Some(*l)).collect();
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(&format!("{label}/pipeline_layout")),
        bind_group_layouts: &layouts,
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(&format!("{label}/pipeline")),
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions { constants, ..Default::default() },
        cache: None,
    })
}

/// Most workgroups a dispatch may have along one dimension (WebGPU's default limit).
pub const MAX_WORKGROUPS_PER_DIMENSION: u32 = 65535;

/// Dispatches `count` invocations of a one-dimensional compute shader of `workgroup` threads:
/// rows of up to [`MAX_WORKGROUPS_PER_DIMENSION`] workgroups. The shader's index is then
/// `id.x + id.y * num_workgroups.x * workgroup`, and it returns for indices `≥ count`.
pub fn dispatch_linear(pass: &mut wgpu::ComputePass, count: u32, workgroup: u32) {
    let groups = count.div_ceil(workgroup);
    pass.dispatch_workgroups(
        groups.min(MAX_WORKGROUPS_PER_DIMENSION),
        groups.div_ceil(MAX_WORKGROUPS_PER_DIMENSION),
        1,
    );
}
