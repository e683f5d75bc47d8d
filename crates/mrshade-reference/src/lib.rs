//! mrshade-reference: the offline quality bar. An unbiased CPU path tracer that renders `L_rv`
//! and `L_r` from the same light paths (differential path tracing) and composites them with the
//! photo exactly as the real-time methods do (issue 4; Franke's grand comparison).
//!
//! - [`geometry`]: world-space triangles in a BVH (obvhs), queries with and without the
//!   virtual objects;
//! - [`bsdf`]: the glTF metallic-roughness material with specular, transmission, IOR;
//! - [`environment`], [`lights`]: the probe (importance sampled) and punctual lights, with the
//!   data contract's conventions;
//! - [`integrator`]: one path scored twice;
//! - [`caustics`]: punctual lights through mirrors and smooth glass, traced from the lights;
//! - [`render()`]: the image loop on all cores and the composite.

pub mod bsdf;
mod camera;
pub mod caustics;
pub mod environment;
pub mod geometry;
pub mod integrator;
pub mod lights;
mod render;
pub mod sampler;
pub mod surface;
mod texture;

pub use caustics::CausticSettings;
pub use render::{ReferenceImage, render, render_pose, render_with};

/// What the path tracer renders otherwise than `scene` asks, one line each: transmission is
/// always smooth (`bsdf`), so rough glass is rendered as smooth glass.
pub fn warnings(scene: &mrshade_scene::Scene) -> Vec<String> {
    scene
        .materials
        .iter()
        .filter(|m| m.transmission > 0.0 && m.roughness >= 0.03)
        .map(|m| {
            format!(
                "material '{}': rough transmission (roughness {}) is path traced as smooth glass",
                m.name, m.roughness
            )
        })
        .collect()
}
