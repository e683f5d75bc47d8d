// Compute rasterisation into a 64-bit visibility target: the high word holds the reversed
// depth (nearer = larger, so `atomicMax` keeps the nearest surface), the low word the global
// triangle id + 1 (0 = empty). Rasterising in compute is many times faster than the fixed-
// function path on compute-class GPUs (an H100 fills a full-screen depth-only triangle at
// 1080p in 0.30 ms; compute writes the same bytes in 0.025 ms).
//
// A set of views (a light's shadow-map faces, the 64 maps of the probe's lights) is drawn
// together, view = workgroup z, into layers of one target: a dispatch per view cost 15–20 µs
// of barrier and launch whatever it drew (64 maps of a Cornell box: 2.3 ms).
// cs_small: one thread per triangle and view; clips against the near plane, rasterises
// small triangles itself and hands big ones (bounding box above `limits.y` pixels) to
// cs_big, where 16×16 workgroups share their tiles.

struct RasterView {
    clip_from_world: mat4x4f,
    // width, height, caster filter (0 all, 1 real only, 2 virtual only), end of the triangle range
    size: vec4u,
    // big-record capacity (of the whole set), small-triangle pixel limit, tile stride of
    // cs_big, first triangle
    limits: vec4u,
    // near-plane w (0: no clipping, orthographic), 1 to keep the farthest surface, unused…
    params: vec4f,
    // World-space plane: only points with dot(xyz, p) + w > 0 are drawn (a planar mirror's
    // mirrored camera sees nothing behind the mirror); (0, 0, 0, 1) keeps everything.
    clip_plane: vec4f,
    // first texel of the view's layer in `target_texels`, unused…
    layer: vec4u,
}

@group(0) @binding(0) var<storage, read> views: array<RasterView>;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
@group(0) @binding(2) var<storage, read> vertices: array<f32>;
@group(0) @binding(3) var<storage, read> indices: array<u32>;
@group(0) @binding(4) var<storage, read> triangles: array<vec4u>;
@group(0) @binding(5) var<storage, read_write> target_texels: array<atomic<u64>>;
@group(0) @binding(6) var<storage, read_write> big: array<BigTriangle>;
// Indirect dispatch arguments of cs_big: x counts the big triangles; then the caster filter
// of the views this draw leaves as they are (0: none; raster/mod.rs `Skip`). A group of its
// own, bound only for cs_small, because cs_big's dispatch reads it as arguments.
@group(1) @binding(0) var<storage, read_write> big_args: array<atomic<u32>, 4>;

// The view this invocation draws, and its index (set first thing by each entry point).
var<private> view: RasterView;
var<private> view_index: u32;

const FILTER_REAL: u32 = 1u;
const FILTER_VIRTUAL: u32 = 2u;

// a, b, c: screen x, y, depth, and the clip plane's distance over w (its sign is the side,
// and it interpolates linearly on screen).
fn write_texel(x: u32, y: u32, a: vec4f, b: vec4f, c: vec4f, inv_area: f32, payload: u32) {
    let w = texel_weights(x, y, a.xyz, b.xyz, c.xyz, inv_area);
    if (!covers(w)) { return; }
    let z = w.x * a.z + w.y * b.z + w.z * c.z;
    if (z <= 0.0 || z > 1.0) { return; }
    if (w.x * a.w + w.y * b.w + w.z * c.w <= 0.0) { return; }
    // Reversed depth: the nearest surface has the largest; 1 − z makes atomicMax keep the farthest.
    let kept = select(z, 1.0 - z, view.params.y > 0.0);
    let packed = (u64(bitcast<u32>(kept)) << 32u) | u64(payload);
    atomicMax(&target_texels[view.layer.x + y * view.size.x + x], packed);
}

fn raster_screen_triangle(a: vec4f, b: vec4f, c: vec4f, payload: u32) {
    // Entirely behind the clip plane.
    if (max(a.w, max(b.w, c.w)) <= 0.0) { return; }
    let area = edge(a.xy, b.xy, c.xy);
    if (abs(area) < 1e-12) { return; }
    let bb = texel_bbox(a.xyz, b.xyz, c.xyz, vec2i(view.size.xy) - 1);
    if (bb.x > bb.z || bb.y > bb.w) { return; }
    let count = u32(bb.z - bb.x + 1) * u32(bb.w - bb.y + 1);
    if (count > view.limits.y) {
        let slot = atomicAdd(&big_args[0], 1u);
        if (slot < view.limits.x) {
            big[slot] = BigTriangle(a, b, c, vec4u(bb), vec4u(payload, view_index, 0u, 0u));
            return;
        }
        // Out of records: undo the count so cs_big never reads past the buffer, and draw here.
        atomicSub(&big_args[0], 1u);
    }
    let inv_area = 1.0 / area;
    for (var y = bb.y; y <= bb.w; y++) {
        for (var x = bb.x; x <= bb.z; x++) {
            write_texel(u32(x), u32(y), a, b, c, inv_area, payload);
        }
    }
}

// Clip-space `h` with clip-plane distance `d` on screen (see write_texel).
fn to_screen(h: vec4f, d: f32) -> vec4f {
    let ndc = h.xyz / h.w;
    let size = vec2f(view.size.xy);
    return vec4f((ndc.x * 0.5 + 0.5) * size.x, (0.5 - ndc.y * 0.5) * size.y, clamp(ndc.z, 0.0, 1.0), d / h.w);
}

@compute @workgroup_size(64)
fn cs_small(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    view_index = gid.z;
    view = views[view_index];
    let id = view.limits.w + gid.x + gid.y * groups.x * 64u;
    if (id >= view.size.w) { return; }
    // Views of one kind of caster whose casters did not move keep their texels.
    if (view.size.z != 0u && view.size.z == atomicLoad(&big_args[3])) { return; }
    let tri = triangles[id];
    let inst = instances[tri.x];
    let real = (inst.info.y & SURFACE_REAL) != 0u;
    if ((view.size.z == FILTER_REAL && !real) || (view.size.z == FILTER_VIRTUAL && real)) { return; }
    var v: array<vec4f, 3>;
    var d: array<f32, 3>;
    for (var k = 0u; k < 3u; k++) {
        let world = inst.world_from_object * vec4f(vertex_position(indices[tri.y + k] + tri.z), 1.0);
        v[k] = view.clip_from_world * world;
        d[k] = dot(view.clip_plane, world);
    }
    let payload = id + 1u;
    let near = view.params.x;
    if (near <= 0.0) {
        raster_screen_triangle(to_screen(v[0], d[0]), to_screen(v[1], d[1]), to_screen(v[2], d[2]), payload);
        return;
    }
    // Clip against w ≥ near (the camera's near plane of the reversed infinite projection);
    // the clip-plane distance is carried along.
    var poly: array<vec4f, 4>;
    var poly_d: array<f32, 4>;
    var n = 0u;
    for (var k = 0u; k < 3u; k++) {
        let p = v[k];
        let q = v[(k + 1u) % 3u];
        let p_in = p.w >= near;
        let q_in = q.w >= near;
        if (p_in) { poly[n] = p; poly_d[n] = d[k]; n++; }
        if (p_in != q_in) {
            let t = (near - p.w) / (q.w - p.w);
            poly[n] = mix(p, q, t);
            poly_d[n] = mix(d[k], d[(k + 1u) % 3u], t);
            n++;
        }
    }
    if (n < 3u) { return; }
    let s0 = to_screen(poly[0], poly_d[0]);
    raster_screen_triangle(s0, to_screen(poly[1], poly_d[1]), to_screen(poly[2], poly_d[2]), payload);
    if (n == 4u) {
        raster_screen_triangle(s0, to_screen(poly[2], poly_d[2]), to_screen(poly[3], poly_d[3]), payload);
    }
}

@compute @workgroup_size(16, 16)
fn cs_big(@builtin(workgroup_id) wg: vec3u, @builtin(local_invocation_id) lid: vec3u) {
    let t = big[wg.x];
    view_index = t.payload.y;
    view = views[view_index];
    let bb = vec4i(t.bbox);
    let tiles = big_tiles(bb);
    let inv_area = 1.0 / edge(t.a.xy, t.b.xy, t.c.xy);
    for (var tile = wg.y; tile < tiles.x * tiles.y; tile += view.limits.z) {
        let p = big_texel(bb, tiles, tile, lid.xy);
        if (p.x <= bb.z && p.y <= bb.w) {
            write_texel(u32(p.x), u32(p.y), t.a, t.b, t.c, inv_area, t.payload.x);
        }
    }
}
