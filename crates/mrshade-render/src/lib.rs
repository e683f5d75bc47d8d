//! mrshade-render: the real-time differential renderer.
//!
//! A frame (`frame.rs`) is one readable function of named passes: shadow maps → G-buffer →
//! the light-transport method (`methods/<name>/`, behind one seam) → direct light into
//! `Differential { rv: L_rv, r: L_r }` → composite with the photo. Shared passes live in
//! `passes/<name>/` with their shaders. `Renderer` owns the GPU scene, the passes and their
//! targets for one session and renders frames from per-frame inputs ([`FrameInputs`]: camera,
//! photo, transforms); still images accumulate frames outside the frame (`still.rs`), and a
//! live stream feeds it one frame of RGB bytes and poses at a time ([`stream`]).

pub mod footage;
pub mod ibl;
pub mod limits;
pub mod methods;
pub mod outputs;
pub mod passes;
pub mod prt;
pub mod raster;
pub mod scene_gpu;
pub mod specular;
pub mod stream;
pub mod uniforms;

mod frame;
mod random;
mod renderer;
mod still;

pub use frame::FrameInputs;
pub use outputs::{Aov, AovImage, Composite};
pub use renderer::Renderer;
pub use still::check_finite;
