//! The passes every method shares, one folder each with its shaders: the photo's upload,
//! shadow maps, the G-buffer, direct light and the composite. A method's own passes live in `crate::methods`.
//! `crate::frame` calls them in order.

pub mod composite;
pub mod deform;
pub mod direct;
pub mod encode;
pub mod gbuffer;
pub mod probe_sh;
pub mod shadow;
pub mod upload;
