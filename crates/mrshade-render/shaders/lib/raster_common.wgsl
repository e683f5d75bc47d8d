// Shared pieces of the compute rasterisers (src/raster/raster.wgsl for the camera and the
// shadow maps, src/passes/ism/raster.wgsl for the directional VPLs' maps). Both declare the
// `vertices` buffer that `vertex_position` reads.

// Side of the tiles the 16×16 workgroups of `cs_big` fill.
const TILE: u32 = 16u;

// A triangle too big for one thread, handed to `cs_big` (screen or texel coordinates, depth).
struct BigTriangle {
    a: vec4f,
    b: vec4f,
    c: vec4f,
    // min x, min y, max x, max y (inclusive texels)
    bbox: vec4u,
    // payload (triangle id + 1, or VPL index and caster material), unused…
    payload: vec4u,
}

fn vertex_position(index: u32) -> vec3f {
    return vec3f(vertices[index * 8u], vertices[index * 8u + 1u], vertices[index * 8u + 2u]);
}

fn edge(a: vec2f, b: vec2f, p: vec2f) -> f32 {
    return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}

// Barycentric weights of texel (x, y)'s centre in triangle a, b, c (`inv_area` = 1 / its
// signed area); `covers` says whether the centre is inside.
fn texel_weights(x: u32, y: u32, a: vec3f, b: vec3f, c: vec3f, inv_area: f32) -> vec3f {
    let p = vec2f(f32(x) + 0.5, f32(y) + 0.5);
    return vec3f(edge(b.xy, c.xy, p), edge(c.xy, a.xy, p), edge(a.xy, b.xy, p)) * inv_area;
}

// Inclusive edges (with a hair of tolerance): shared edges may be covered twice, which the
// depth test resolves, but never left open.
fn covers(w: vec3f) -> bool {
    return min(w.x, min(w.y, w.z)) >= -1e-6;
}

// Texels whose centres (i + 0.5) fall inside the triangle's bounding box, within
// [0, last] (inclusive); empty when x0 > x1 or y0 > y1.
fn texel_bbox(a: vec3f, b: vec3f, c: vec3f, last: vec2i) -> vec4i {
    let lo = min(a.xy, min(b.xy, c.xy));
    let hi = max(a.xy, max(b.xy, c.xy));
    let x0 = max(i32(ceil(lo.x - 0.5)), 0);
    let y0 = max(i32(ceil(lo.y - 0.5)), 0);
    let x1 = min(i32(floor(hi.x - 0.5)), last.x);
    let y1 = min(i32(floor(hi.y - 0.5)), last.y);
    return vec4i(x0, y0, x1, y1);
}

// Tiles of a big triangle's box.
fn big_tiles(bb: vec4i) -> vec2u {
    return vec2u((u32(bb.z - bb.x) + TILE) / TILE, (u32(bb.w - bb.y) + TILE) / TILE);
}

// The texel invocation `lid` of a `cs_big` workgroup handles in tile `tile` of box `bb`
// (outside the box where x > bb.z or y > bb.w).
fn big_texel(bb: vec4i, tiles: vec2u, tile: u32, lid: vec2u) -> vec2i {
    return bb.xy + vec2i(vec2u(tile % tiles.x, tile / tiles.x) * TILE + lid);
}
