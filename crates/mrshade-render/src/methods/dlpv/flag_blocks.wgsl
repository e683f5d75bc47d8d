// Flagging the blocks of 4³ cells in `blocks_read` (`BLOCK_*` bits, volume.wgsl): the blocks
// the pixels read (mark_cells.wgsl) and those beside a virtual surface (vpl_aggregate.wgsl
// `cell_vpls`). The including module binds `blocks_read` read-write.

// Sets `bit` on the blocks that hold the cells from `first` to `last` (clamped to the volume).
// A word that has it is not written again (a million pixels storing to a few hundred words
// wait on each other); invocations that write a word in one pass write the same bits.
fn flag_blocks(first: vec3i, last: vec3i, bit: u32) {
    let end = vec3i(i32(params.info.x) - 1);
    let lo = clamp(first, vec3i(0), end) / 4;
    let hi = clamp(last, vec3i(0), end) / 4;
    let blocks = i32(params.info.x / 4u);
    for (var bz = lo.z; bz <= hi.z; bz++) {
        for (var by = lo.y; by <= hi.y; by++) {
            for (var bx = lo.x; bx <= hi.x; bx++) {
                let k = (bz * blocks + by) * blocks + bx;
                let v = blocks_read[k];
                if ((v & bit) == 0u) { blocks_read[k] = v | bit; }
            }
        }
    }
}
