//! Real/virtual flags (Knecht §2.7): which buffer a surface or light contributes to.
//!
//! The G-buffer stores them per pixel as bits of a `u32`; the constants here are mirrored in
//! `shaders/lib/gbuffer.wgsl` and checked against it by a test in `mrshade-render`.

use serde::{Deserialize, Serialize};

/// Whether a node, light or surface belongs to the real scene (the photo) or is inserted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Realness {
    /// Part of the photographed scene: a proxy of something the camera already sees.
    Real,
    /// Inserted content: appears only in `L_rv`.
    Virtual,
}

impl Realness {
    /// `r(x)` of the thesis: 1 for real, 0 for virtual.
    pub fn r(self) -> f32 {
        match self {
            Realness::Real => 1.0,
            Realness::Virtual => 0.0,
        }
    }

    /// From the glTF contract's boolean `extras.real`.
    pub fn from_real(real: bool) -> Self {
        if real { Realness::Real } else { Realness::Virtual }
    }
}

/// G-buffer flag bit: a surface covers this pixel (clear: background / probe).
pub const SURFACE_COVERED: u32 = 1;
/// G-buffer flag bit: the surface is real (`r(p) = 1`).
pub const SURFACE_REAL: u32 = 2;
/// The material index is stored in the flag word above this shift.
pub const SURFACE_MATERIAL_SHIFT: u32 = 8;
