// `visibility_maps` (visibility.wgsl): per part of V_ρ's blocks and pair of texels of its
// octahedral map, how far from the part's centre the ray through the texel's centre first
// crosses a virtual surface, from a cell and a half on (a VPL's path is tested from either
// end so: `blocked` in vpl_gather.wgsl). 1 024 rays per part, once per gather, in place of
// one march per VPL and part: cornell's 12 000 VPLs and 700 parts made 8.4 million.
@group(0) @binding(0) var<uniform> params: DlpvParams;
@group(0) @binding(1) var<uniform> gather_info: GatherInfo;
@group(0) @binding(2) var<storage, read> planes: array<vec4f>;
@group(0) @binding(3) var<storage, read_write> visibility: array<u32>;
// Per block of 4³ cells, `BLOCK_*` bits (volume.wgsl): the gather reads the maps of the parts
// of those a pixel reads or beside a virtual surface only.
@group(0) @binding(4) var<storage, read> blocks_read: array<u32>;

// x: the word of the map; y, z: the part (y along x, z along y and z, in the maps' room).
@compute @workgroup_size(64)
fn visibility_maps(@builtin(global_invocation_id) id: vec3u) {
    let room = gather_info.size.w;
    let p = vec3u(id.y, id.z % room, id.z / room);
    let part = map_parts_first() + p;
    if (id.x >= MAP_WORDS || any(part >= map_parts_end())) { return; }
    let block = part * PART_CELLS / 4u;
    let blocks = (gather_info.size.xyz + 3u) / 4u;
    if ((block_bits(block, blocks) & (BLOCK_READ | BLOCK_NEAR_VIRTUAL)) == 0u) { return; }
    // Past the maps' room (content grown since the maps were sized): the gather marches.
    let map = part_map(part);
    if (map == 0xffffffffu) { return; }
    let centre = part_centre(part);
    var word = 0u;
    for (var k = 0u; k < 2u; k++) {
        let texel = 2u * id.x + k;
        let uv = (vec2f(f32(texel % MAP_SIDE), f32(texel / MAP_SIDE)) + 0.5) / f32(MAP_SIDE);
        let t = first_crossing(centre, octahedral_direction(uv), 1.5, 1e30, false);
        let q = u32(min(round(t * MAP_UNITS), f32(NO_CROSSING)));
        word |= q << (16u * k);
    }
    visibility[map * MAP_WORDS + id.x] = word;
}
