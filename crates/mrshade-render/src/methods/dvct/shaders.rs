//! The WGSL modules of the `dvct` passes: the shared libraries and the pass's own files, in
//! the order each module needs them.

use mrshade_gpu::wgsl;

/// The voxelisation module (entry points `cs_main` and `clear`).
pub const VOXELIZE_SHADER: &str = wgsl!(
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/instance.wgsl",
    "../../../shaders/lib/triangles.wgsl",
    "volume.wgsl",
    "voxelize.wgsl",
);

/// The first bounce's module.
pub const LIGHT_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/brdf.wgsl",
    "../../../shaders/lib/dfg.wgsl",
    "../../../shaders/lib/env.wgsl",
    "../../../shaders/lib/instance.wgsl",
    "../../../shaders/lib/triangles.wgsl",
    "../../../shaders/lib/material_textures.wgsl",
    "../../../shaders/lib/lights.wgsl",
    "../../../shaders/lib/cube.wgsl",
    "../../../shaders/lib/shadow.wgsl",
    "volume.wgsl",
    "surface.wgsl",
    "voxel_surface.wgsl",
    "photo.wgsl",
    "light.wgsl",
);

/// The second bounce's module.
pub const BOUNCE_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/brdf.wgsl",
    "../../../shaders/lib/dfg.wgsl",
    "../../../shaders/lib/env.wgsl",
    "../../../shaders/lib/instance.wgsl",
    "../../../shaders/lib/triangles.wgsl",
    "../../../shaders/lib/material_textures.wgsl",
    "../../../shaders/lib/sampling.wgsl",
    "volume.wgsl",
    "surface.wgsl",
    "voxel_surface.wgsl",
    "cones.wgsl",
    "bounce.wgsl",
);

/// The photo pass's module (after the second bounce).
pub const PHOTO_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/instance.wgsl",
    "../../../shaders/lib/triangles.wgsl",
    "volume.wgsl",
    "surface.wgsl",
    "photo.wgsl",
    "photo_pass.wgsl",
);

/// The mipmap module.
pub const MIPS_SHADER: &str = wgsl!("mips.wgsl");

/// The pixels' cones module (entry points `cs_main`, once per trace texel, and `cs_retrace`,
/// once per pixel the resolve listed).
pub const GATHER_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/brdf.wgsl",
    "../../../shaders/lib/gbuffer_pixel.wgsl",
    "../../../shaders/lib/indirect_out.wgsl",
    "../../../shaders/lib/dfg.wgsl",
    "../../../shaders/lib/env.wgsl",
    "../../../shaders/lib/sampling.wgsl",
    "../../../shaders/lib/lights.wgsl",
    "../../../shaders/lib/rsm_texel.wgsl",
    "../../../shaders/lib/probe_light.wgsl",
    "../../../shaders/lib/probe_maps.wgsl",
    "volume.wgsl",
    "texel.wgsl",
    "cones.wgsl",
    "still_rays.wgsl",
    "pixel_light.wgsl",
    "gather.wgsl",
);

/// The per-pixel resolve of the traced cones.
pub const RESOLVE_SHADER: &str = wgsl!(
    "../../../shaders/lib/frame.wgsl",
    "../../../shaders/lib/gbuffer.wgsl",
    "../../../shaders/lib/brdf.wgsl",
    "../../../shaders/lib/gbuffer_pixel.wgsl",
    "../../../shaders/lib/indirect_out.wgsl",
    "../../../shaders/lib/dfg.wgsl",
    "../../../shaders/lib/env.wgsl",
    "../../../shaders/lib/geometry_weight.wgsl",
    "volume.wgsl",
    "texel.wgsl",
    "pixel_light.wgsl",
    "resolve.wgsl",
);
