//! The WGSL modules of the `dlpv` passes: the shared libraries and the pass's own files, in
//! the order each module needs them.

use mrshade_gpu::wgsl;

/// The injection module.
pub const INJECT_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/lights.wgsl",
    "../../../shaders/lib/sh.wgsl",
    "../../../shaders/lib/rsm_texel.wgsl",
    "../../../shaders/lib/probe_light.wgsl",
    "volume.wgsl",
    "inject.wgsl",
);

/// The seeding and propagation module (entry points `seed` and `propagate`).
pub const PROPAGATE_SHADER: &str =
    wgsl!("../../../shaders/lib/frame.wgsl", "../../../shaders/lib/sh.wgsl", "volume.wgsl", "propagate.wgsl",);

/// The per-pixel merge module.
pub const GATHER_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/brdf.wgsl",
    "../../../shaders/lib/gbuffer_pixel.wgsl",
    "../../../shaders/lib/indirect_out.wgsl",
    "../../../shaders/lib/dfg.wgsl",
    "../../../shaders/lib/env.wgsl",
    "../../../shaders/lib/lights.wgsl",
    "../../../shaders/lib/sh.wgsl",
    "../../../shaders/lib/rsm_texel.wgsl",
    "../../../shaders/lib/probe_light.wgsl",
    "../../../shaders/lib/probe_maps.wgsl",
    "../../../shaders/lib/probe_maps_soft.wgsl",
    "volume.wgsl",
    "gather.wgsl",
);
