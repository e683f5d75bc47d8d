// Where the virtual surfaces stand in a VPL's way (`dlpv.virtual_bounce`; vpl_gather.wgsl,
// visibility_maps.wgsl): their cells' planes (vpl_aggregate.wgsl `planes`) crossed on the
// path, and per part of 2³ cells of V_ρ's blocks a map of how far the first one lies in
// every direction, so that a path's test is one read instead of a march. The including module
// binds `params`, `gather_info`, `planes` and `blocks_read`.

// Texels per side of a part's map (octahedral.wgsl): 1 024 directions, 0.1 rad apart — a
// cell's width at ten cells.
const MAP_SIDE: u32 = 32u;
// A map's words: two texels a word, each the distance in 1/`MAP_UNITS` cells (`NO_CROSSING`:
// none before the box's edge).
const MAP_WORDS: u32 = MAP_SIDE * MAP_SIDE / 2u;
const MAP_UNITS: f32 = 32.0;
const NO_CROSSING: u32 = 0xffffu;
// Cells per side of a part.
const PART_CELLS: u32 = 2u;

// How far along the ray `co + t·dir` (cell coordinates, `dir` a unit vector), t ∈ [`t_first`,
// `t_last`], it first crosses a virtual surface (a large number: never): at every half cell
// inside V_ρ's box (where the virtual surfaces lie), whether the points half a cell before and
// after lie on either side of the plane of the cell there (`planes`). A path that only grazes
// a surface's cell (along a face, over a contact) crosses no plane: marking the cells alone
// blocked it, and a floor beside a block lost its light. (Every cell instead missed crossings:
// the light of the floor behind a cube came through it, test
// `a_virtual_face_lit_only_by_the_floor_lights_the_virtual_face_before_it`.)
// With `skip_empty`, a block of 4³ cells without `BLOCK_NEAR_VIRTUAL` (a virtual surface's
// cell flags the blocks within a cell of it, vpl_aggregate.wgsl `cell_vpls`), which holds no
// plane, is left at once: the march goes on from its first half-cell step past the block,
// which finds what stepping through it would. The gather's marches (the parts without a map)
// skip: 0.04 ms less on desk-bunny and desk-spot-real at 1080p on an H100; the maps' rays do
// not: their pass took 0.09 → 0.12 ms on desk-spot-virtual with it (the rays of a part start
// among the virtual surfaces, where few blocks are empty and every step read its block's
// bits; docs/benchmarks.md, 2026-12-07).
fn first_crossing(co: vec3f, dir: vec3f, t_first: f32, t_last: f32, skip_empty: bool) -> f32 {
    let span = box_span(co, dir, vec3f(gather_info.rho_first.xyz), vec3f(gather_info.rho_end.xyz), t_last);
    let h = cell_side();
    let start = max(span.x, t_first);
    // The gathered box is the whole volume wherever paths are tested (the bounce gathered), so
    // the march's cells index its blocks as they are (as visibility_maps.wgsl reads them).
    let blocks = (gather_info.size.xyz + 3u) / 4u;
    // Steps of half a cell from `start`: t = start + step / 2.
    var step = 0.0;
    for (var t = start; t <= span.y; t = start + 0.5 * step) {
        step += 1.0;
        let c = vec3i(floor(co + t * dir));
        if (!cell_inside(c)) { continue; }
        let b = c / 4;
        if (skip_empty && (block_bits(vec3u(b), blocks) & BLOCK_NEAR_VIRTUAL) == 0u) {
            // The step at or after the ray's exit from the block (a hair early: a step that
            // still falls in it comes here again and moves one on).
            let exit = box_span(co, dir, vec3f(b * 4), vec3f(b * 4 + 4), 1e30).y;
            step = max(step, ceil(2.0 * (exit - start) - 1e-3));
            continue;
        }
        let plane = planes[2u * cell_index(c)];
        if (dot(plane.xyz, plane.xyz) < 0.25) { continue; }
        let before = params.origin.xyz + (co + (t - 0.5) * dir) * h;
        let after = params.origin.xyz + (co + (t + 0.5) * dir) * h;
        if ((dot(plane.xyz, before) - plane.w) * (dot(plane.xyz, after) - plane.w) < 0.0) { return t; }
    }
    return 1e30;
}

// The parts with maps: those of the blocks of 4³ cells that hold V_ρ's cells, from the first
// (in parts) to one past the last; at most `gather_info.size.w` along each axis (the maps'
// room, `VisibilityMaps`).
fn map_parts_first() -> vec3u { return gather_info.rho_first.xyz / 4u * (4u / PART_CELLS); }
fn map_parts_end() -> vec3u { return (gather_info.rho_end.xyz + 3u) / 4u * (4u / PART_CELLS); }

// The index of part `part`'s map (in parts of the volume), or none (0xffffffff): outside V_ρ's
// blocks, or past the maps' room.
fn part_map(part: vec3u) -> u32 {
    let first = map_parts_first();
    let room = gather_info.size.w;
    if (any(part < first) || any(part >= map_parts_end()) || any(part - first >= vec3u(room))) { return 0xffffffffu; }
    let p = part - first;
    return (p.z * room + p.y) * room + p.x;
}

// The centre of part `part`, in cell coordinates.
fn part_centre(part: vec3u) -> vec3f { return vec3f(part * PART_CELLS) + 0.5 * f32(PART_CELLS); }

// The `BLOCK_*` bits (volume.wgsl) of block `block` of 4³ cells of the gathered box, `blocks`
// blocks along each axis: the gather sums the blocks a pixel reads or beside a virtual surface,
// and the maps are written for theirs.
fn block_bits(block: vec3u, blocks: vec3u) -> u32 {
    return blocks_read[(block.z * blocks.y + block.y) * blocks.x + block.x];
}
