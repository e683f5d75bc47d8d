//! mrshade-render: the real-time differential renderer.
//!
//! A frame (`frame.rs`) is one readable function of named passes, each in `passes/<name>/`
//! with its shaders: shadow maps → G-buffer → differential shading into
//! `Differential { rv: L_rv, r: L_r }` → composite with the photo. `Renderer` owns the GPU
//! scene, the passes and their targets for one session.

pub mod dir;
pub mod ibl;
pub mod limits;
pub mod outputs;
pub mod passes;
pub mod raster;
pub mod scene_gpu;
pub mod uniforms;

mod frame;
mod renderer;

pub use outputs::{Aov, AovImage, Composite};
pub use renderer::Renderer;
