//! The passes of a frame, one folder each with its shaders. `crate::frame` calls them in order.

pub mod composite;
pub mod direct;
pub mod filter;
pub mod gbuffer;
pub mod indirect;
pub mod ism;
pub mod rsm;
pub mod shadow;
pub mod vpl;
