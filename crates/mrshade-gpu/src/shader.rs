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
