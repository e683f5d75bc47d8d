//! Helpers of the `dvct` tests (tests/dvct.rs: its volumes; tests/dvct_cones.rs: what its
//! cones see).

use super::{Rendered, Setup};
use mrshade_core::Differential;
use mrshade_render::methods::dvct::DvctMethod;

/// Makes `s` a `dvct` session of `resolution`³ voxels, rendered for eight frames (a still's
/// 64 are for the mean of its last half; these tests read the last frame).
pub fn dvct(s: &mut Setup, resolution: u32) {
    s.top_toml = "method = \"dvct\"\n".into();
    s.extra_toml += &format!("[output]\nframes = 8\n[dvct]\nresolution = {resolution}\n");
}

/// The `dvct` method of a render.
pub fn dvct_method(r: &Rendered) -> &DvctMethod {
    r.renderer.method_as::<DvctMethod>().expect("the dvct method")
}

/// The probe's visibility per pixel of a `dvct` render (its AOVs), both solutions.
pub fn probe_visibility(r: &Rendered) -> Differential<Vec<[f32; 3]>> {
    dvct_method(r).indirect.read_probe_visibility(&r.ctx).unwrap()
}
