//! mrshade-core: the types every other mrshade crate speaks.
//!
//! No I/O and no GPU here: colour transfer functions, the HDR image type, the
//! `Differential { rv, r }` pair of differential rendering, surface flags, projection and
//! environment-map conventions, CPU BRDF math, the benchmark's changed region and the typed render settings with the spec's
//! defaults.

pub mod brdf;
pub mod camera;
pub mod color;
pub mod differential;
pub mod flags;
pub mod image;
pub mod math;
pub mod region;
pub mod settings;
pub mod sh;
pub mod sog;
pub mod text;

pub use differential::Differential;
pub use image::HdrImage;
