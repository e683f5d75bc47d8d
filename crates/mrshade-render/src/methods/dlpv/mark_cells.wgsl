// The blocks of the volume's cells that the pixels read (`dlpv.bounce_light = "gathered"`).

@group(0) @binding(0) var<uniform> params: DlpvParams;
// Per block of 4³ cells of the volume, bit 0 where a pixel reads one of its cells (bit 1:
// vpl_aggregate.wgsl `cell_vpls`).
@group(0) @binding(1) var<storage, read_write> blocks_read: array<u32>;
@group(1) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(1) var gbuffer_depth_motion: texture_2d<f32>;
@group(1) @binding(2) var gbuffer_normal_roughness: texture_2d<f32>;
@group(1) @binding(3) var gbuffer_flags: texture_2d<u32>;
// `mark_cells`, with the bounce light gathered (vpl_gather.wgsl `block_read`): one invocation
// per pixel, flagging the blocks of 4³ cells that hold the eight cells the merge reads for it
// (gather.wgsl `volume_irradiance`), so that the gather sums the VPLs' light only there: the
// surfaces the camera sees cross a few of the volume's blocks (a desk's plane an eighth of
// them), and the gather's time is its cells' count times the VPLs'.
@compute @workgroup_size(8, 8)
fn mark_cells(@builtin(global_invocation_id) id: vec3u) {
    let q = vec2i(id.xy);
    if (any(q >= vec2i(frame.size.xy))) { return; }
    let flags = textureLoad(gbuffer_flags, q, 0).r;
    if (!is_covered(flags)) { return; }
    let p = world_from_pixel(frame, vec2f(q) + 0.5, textureLoad(gbuffer_depth_motion, q, 0).x);
    let n = textureLoad(gbuffer_normal_roughness, q, 0).xyz;
    let x = cell_coords(p + 0.5 * cell_side() * n) - 0.5;
    // The eight cells read lie in one block along an axis or straddle two.
    let base = vec3i(floor(x));
    // Outside the volume the merge reads nothing.
    if (any(base + 1 < vec3i(0)) || any(base > vec3i(i32(params.info.x) - 1))) { return; }
    flag_blocks(base, base + 1, BLOCK_READ);
}
