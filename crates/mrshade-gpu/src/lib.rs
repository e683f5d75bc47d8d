//! mrshade-gpu: the GPU context and the plumbing every pass shares. It knows wgpu and no
//! rendering algorithm.

pub mod bind;
pub mod context;
pub mod readback;
pub mod shader;
pub mod texture;
pub mod timing;

pub use context::{GpuContext, GpuOptions, NO_ADAPTER_HELP, REQUIRED_FEATURES};
pub use texture::Target;
pub use wgpu;
