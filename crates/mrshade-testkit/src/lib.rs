//! Test helpers shared by mrshade's crates.
//!
//! - [`gpu`]: the test GPU. It must exist: without an adapter a GPU test fails (never skips),
//!   telling how to install lavapipe.
//! - [`flip`] and [`golden`]: FLIP (NVIDIA ꟻLIP, via nv-flip) comparisons and golden images.
//! - [`gltf`]: a small glTF writer for synthetic test scenes and malformed inputs.

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
