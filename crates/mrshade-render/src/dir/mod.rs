//! CPU-side inputs of differential instant radiosity (Knecht §2.7–§2.9) that change only
//! with the scene: the surface point clouds of the imperfect shadow maps and the importance
//! pyramid of the probe. The per-frame work is in `crate::passes::{rsm, vpl, ism, indirect,
//! filter}`.

mod passes;
mod points;
mod probe_pyramid;

pub use passes::DirPasses;
pub use points::{GpuPoint, PointCloud};
pub use probe_pyramid::ProbePyramid;
