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
    "rsm_pair.wgsl",
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
    "volume_read.wgsl",
    "gather.wgsl",
);

/// The VPLs of the gathered volumes (entry points `aggregate` and `photo_tiles`).
pub const VPL_AGGREGATE_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/lights.wgsl",
    "../../../shaders/lib/rsm_texel.wgsl",
    "../../../shaders/lib/sh.wgsl",
    "volume.wgsl",
    "rsm_pair.wgsl",
    "vpl.wgsl",
    "volume_read.wgsl",
    "flag_blocks.wgsl",
    "vpl_aggregate.wgsl",
    "vpl_photo.wgsl",
);

/// The blocks of cells the pixels read (with the bounce light gathered).
pub const VPL_MARK_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "volume.wgsl",
    "flag_blocks.wgsl",
    "mark_cells.wgsl",
);

/// The gather of the VPLs' light into the cells (entry points `gather` and `gather_sum`).
pub const VPL_GATHER_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/sh.wgsl",
    "../../../shaders/lib/box_span.wgsl",
    "../../../shaders/lib/octahedral.wgsl",
    "volume.wgsl",
    "vpl.wgsl",
    "visibility.wgsl",
    "vpl_gather.wgsl"
);

/// The visibility maps of V_ρ's parts (with `dlpv.virtual_bounce`).
pub const VISIBILITY_MAPS_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/box_span.wgsl",
    "../../../shaders/lib/octahedral.wgsl",
    "volume.wgsl",
    "vpl.wgsl",
    "visibility.wgsl",
    "visibility_maps.wgsl",
);
