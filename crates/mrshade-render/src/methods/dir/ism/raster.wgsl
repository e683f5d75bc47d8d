// Shadow maps of the directional (environment) VPLs, rasterised from triangles into their
// tiles of the ISM atlases. Knecht's system offers "standard shadow maps for VPLs instead of
// ISMs" (§6 of the extraction); for the probe's direct light, whose shadows are the most
// visible ones a virtual object casts, exact maps avoid the ISMs' splat dilation and holes.
// Orthographic maps are linear, so a triangle stays a triangle; surface VPLs keep their
// hemispherical ISMs (splat.wgsl). Small triangles are rasterised by their own thread, big ones
// by 16×16 workgroups (cs_big), as in the camera's rasteriser.

struct RasterParams {
    // triangle count, 1 for the virtual atlas, big-record capacity, tile stride of cs_big
    info: vec4u,
}

@group(0) @binding(0) var<uniform> ism: IsmParams;
@group(0) @binding(1) var<uniform> params: RasterParams;
@group(0) @binding(2) var<storage, read> instances: array<Instance>;
@group(0) @binding(3) var<storage, read> vertices: array<f32>;
@group(0) @binding(4) var<storage, read> indices: array<u32>;
@group(0) @binding(5) var<storage, read> triangles: array<vec4u>;
@group(0) @binding(6) var<storage, read> vpls: array<Vpl>;
@group(0) @binding(7) var<storage, read_write> atlas: array<atomic<u32>>;
@group(0) @binding(8) var<storage, read_write> big: array<BigTriangle>;
@group(1) @binding(0) var<storage, read_write> big_args: array<atomic<u32>, 3>;

const SMALL: u32 = 256u;

fn write_texel(vpl: u32, x: u32, y: u32, a: vec3f, b: vec3f, c: vec3f, inv_area: f32, material: u32) {
    let w = texel_weights(x, y, a, b, c, inv_area);
    if (!covers(w)) { return; }
    let depth = max(w.x * a.z + w.y * b.z + w.z * c.z, 0.0);
    let res = ism.tile.x;
    let tile = vec2u(vpl % ism.tile.y, vpl / ism.tile.y);
    let i = (tile.y * res + y) * (ism.tile.y * res) + tile.x * res + x;
    atomicMax(&atlas[i], ism_encode_caster(depth, material));
}

@compute @workgroup_size(64)
fn cs_small(@builtin(global_invocation_id) gid: vec3u) {
    let id = gid.x;
    let vpl = gid.y;
    if (id >= params.info.x) { return; }
    let v = vpls[vpl];
    if (vpl_kind(v) != VPL_DIRECTIONAL) { return; }
    let tri = triangles[id];
    let inst = instances[tri.x];
    let virtual_atlas = params.info.y == 1u;
    if (((inst.info.y & SURFACE_REAL) != 0u) == virtual_atlas) { return; }
    let res = f32(ism.tile.x);
    var s: array<vec3f, 3>;
    for (var k = 0u; k < 3u; k++) {
        let world = (inst.world_from_object * vec4f(vertex_position(indices[tri.y + k] + tri.z), 1.0)).xyz;
        let c = ism_project(v, world, ism, virtual_atlas);
        s[k] = vec3f(c.uv * res, c.depth);
    }
    let area = edge(s[0].xy, s[1].xy, s[2].xy);
    if (abs(area) < 1e-12) { return; }
    let bb = texel_bbox(s[0], s[1], s[2], vec2i(i32(ism.tile.x) - 1));
    if (bb.x > bb.z || bb.y > bb.w) { return; }
    if (u32(bb.z - bb.x + 1) * u32(bb.w - bb.y + 1) > SMALL) {
        let slot = atomicAdd(&big_args[0], 1u);
        if (slot < params.info.z) {
            big[slot] = BigTriangle(vec4f(s[0], 0.0), vec4f(s[1], 0.0), vec4f(s[2], 0.0), vec4u(bb), vec4u(vpl, inst.info.x, 0u, 0u));
            return;
        }
        atomicSub(&big_args[0], 1u);
    }
    let inv_area = 1.0 / area;
    for (var y = bb.y; y <= bb.w; y++) {
        for (var x = bb.x; x <= bb.z; x++) {
            write_texel(vpl, u32(x), u32(y), s[0], s[1], s[2], inv_area, inst.info.x);
        }
    }
}

@compute @workgroup_size(16, 16)
fn cs_big(@builtin(workgroup_id) wg: vec3u, @builtin(local_invocation_id) lid: vec3u) {
    let t = big[wg.x];
    let bb = vec4i(t.bbox);
    let tiles = big_tiles(bb);
    let inv_area = 1.0 / edge(t.a.xy, t.b.xy, t.c.xy);
    for (var tile = wg.y; tile < tiles.x * tiles.y; tile += params.info.w) {
        let p = big_texel(bb, tiles, tile, lid.xy);
        if (p.x <= bb.z && p.y <= bb.w) {
            write_texel(t.payload.x, u32(p.x), u32(p.y), t.a.xyz, t.b.xyz, t.c.xyz, inv_area, t.payload.y);
        }
    }
}
