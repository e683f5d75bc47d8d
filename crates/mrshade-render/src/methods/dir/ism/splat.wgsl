// ISM splatting (Knecht §2.9): every point of a cloud is splatted into the ISM of the VPL it
// belongs to (point i → VPL i / points_per_vpl) as a quad aligned with its surface: the four
// corners are mapped like the centre (hemispherical mapping for surface VPLs, orthographic for
// directional ones) and the texels they span take the point's distance. A compute pass with
// atomics replaces the thesis's geometry shader.

struct SplatParams {
    // point count of this cloud, 1 if the cloud is the virtual one, unused, unused
    info: vec4u,
}

@group(0) @binding(0) var<uniform> ism: IsmParams;
@group(0) @binding(1) var<uniform> splat: SplatParams;
@group(0) @binding(2) var<storage, read> instances: array<Instance>;
@group(0) @binding(3) var<storage, read> points: array<Point>;
@group(0) @binding(4) var<storage, read> vpls: array<Vpl>;
@group(0) @binding(5) var<storage, read_write> atlas: array<atomic<u32>>;

// Splats larger than this many texels per side are clipped (points very close to a VPL).
const MAX_SPLAT: i32 = 24;

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let index = gid.x + gid.y * groups.x * 64u;
    if (index >= splat.info.x) { return; }
    let vpl_index = index / ism.tile.w;
    if (vpl_index >= ism.tile.z) { return; }
    let v = vpls[vpl_index];
    // Directional VPLs get triangle-rasterised maps (raster.wgsl).
    if (vpl_kind(v) != VPL_SURFACE) { return; }
    let p = points[index];
    let inst = instances[p.instance];
    let world = (inst.world_from_object * vec4f(p.position, 1.0)).xyz;
    let virtual_atlas = splat.info.y == 1u;
    let centre = ism_project(v, world, ism, virtual_atlas);
    if (!centre.valid) { return; }
    let n = normalize((inst.normal_from_object * vec4f(p.normal, 0.0)).xyz);
    // A surface whose plane holds the VPL (the floor a floor VPL lies on) is seen edge-on and
    // hides nothing above it; splatted, its points would still fill their own texels at the
    // map's rim, and shadow every receiver low over that surface.
    if (abs(dot(world - v.position.xyz, n)) < 1e-3 * centre.depth) { return; }
    let tb = tangent_frame(n);
    let r = select(ism.splat.x, ism.splat.y, virtual_atlas);
    let res = f32(ism.tile.x);
    var lo = centre.uv * res;
    var hi = lo;
    for (var k = 0u; k < 4u; k++) {
        let sx = select(-1.0, 1.0, (k & 1u) != 0u);
        let sy = select(-1.0, 1.0, (k & 2u) != 0u);
        let c = ism_project(v, world + (tb[0] * sx + tb[1] * sy) * r, ism, virtual_atlas);
        lo = min(lo, c.uv * res);
        hi = max(hi, c.uv * res);
    }
    // Texels whose centres the splat covers (at least the point's own texel), so that splats
    // do not dilate silhouettes by a texel.
    let centre_texel = vec2i(floor(centre.uv * res));
    let t0 = max(min(vec2i(ceil(lo - 0.5)), centre_texel), max(centre_texel - vec2i(MAX_SPLAT / 2), vec2i(0)));
    let t1 = min(max(vec2i(floor(hi - 0.5)), centre_texel), min(centre_texel + vec2i(MAX_SPLAT / 2), vec2i(i32(ism.tile.x) - 1)));
    let tile = vec2u(vpl_index % ism.tile.y, vpl_index / ism.tile.y);
    let atlas_width = ism.tile.y * ism.tile.x;
    let frame = tangent_frame(v.normal.xyz);
    for (var y = t0.y; y <= t1.y; y++) {
        for (var x = t0.x; x <= t1.x; x++) {
            // The quad's own depth along the texel's direction, and only where the direction
            // meets the quad: a constant depth over a splat seen at a grazing angle would
            // cover the surface behind its nearer edge, so that every surface shadowed itself
            // near its VPL's horizon. The point's own texel is always covered (by the quad's
            // plane, where the texel is larger than the quad).
            let hit = splat_depth(v, frame, (vec2f(vec2i(x, y)) + 0.5) / res, world, n, tb, r);
            let own = all(vec2i(x, y) == centre_texel);
            if (hit.y == 0.0 && !own) { continue; }
            let depth = select(centre.depth, hit.x, hit.x > 0.0);
            let i = (tile.y * ism.tile.x + u32(y)) * atlas_width + tile.x * ism.tile.x + u32(x);
            atomicMax(&atlas[i], ism_encode_caster(depth, p.material));
        }
    }
}

// Distance from surface VPL `v` (its map's frame `frame`) along the direction of map
// coordinate `uv` to the plane of the splat quad (centre `centre`, normal `n`, axes `tb`,
// half-size `r`), 0 where the direction does not meet the plane; y: 1 where it meets the
// quad itself.
fn splat_depth(v: Vpl, frame: mat2x3f, uv: vec2f, centre: vec3f, n: vec3f, tb: mat2x3f, r: f32) -> vec2f {
    let xy = uv * 2.0 - 1.0;
    let z2 = 1.0 - dot(xy, xy);
    if (z2 <= 0.0) { return vec2f(0.0); }
    let dir = frame[0] * xy.x + frame[1] * xy.y + v.normal.xyz * sqrt(z2);
    let denom = dot(dir, n);
    if (abs(denom) < 1e-6) { return vec2f(0.0); }
    let t = dot(centre - v.position.xyz, n) / denom;
    if (t <= 0.0) { return vec2f(0.0); }
    let q = v.position.xyz + dir * t - centre;
    return vec2f(t, select(0.0, 1.0, max(abs(dot(q, tb[0])), abs(dot(q, tb[1]))) <= r));
}
