// Voxelisation of the real and the virtual scene (Franke §2.13.2 step 1, like Schwarz &
// Seidel [SS10]): each triangle is rasterised along its dominant axis, one workgroup per
// triangle, into every voxel its plane crosses within a cell's column, with a conservative
// coverage test (a thin wall leaves no holes). A voxel keeps one real and one virtual
// triangle: one that faces the volume's centre before one that does not, then the
// highest-numbered (atomicMax on the word of volume.wgsl: the same every run); the light pass
// derives the surface's point, normal and albedo from it. Occupancy is whether a triangle is
// kept. A real wall thinner than two voxels (cornell's, 1 cm in 6 mm voxels) puts its inner and
// outer faces in the same voxels: the outer face, unlit and unseen by the camera, left them
// dark where the virtual content's cones gather the wall's bounce (the side that faces the
// centre is the content's).

@group(0) @binding(0) var<uniform> params: VolumeParams;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
@group(0) @binding(2) var<storage, read> vertices: array<f32>;
@group(0) @binding(3) var<storage, read> indices: array<u32>;
@group(0) @binding(4) var<storage, read> triangles: array<vec4u>;
// Per voxel: the real and the virtual triangle kept (words of volume.wgsl; 0: none).
@group(0) @binding(5) var<storage, read_write> voxels: array<atomic<u32>>;

// `p` with the axis `axis` moved last: (u, v, w).
fn to_uvw(p: vec3f, axis: u32) -> vec3f {
    if (axis == 0u) { return p.yzx; }
    if (axis == 1u) { return p.zxy; }
    return p;
}

fn from_uvw(q: vec3f, axis: u32) -> vec3f {
    if (axis == 0u) { return q.zxy; }
    if (axis == 1u) { return q.yzx; }
    return q;
}

// Slack (in cells) of the boundary tests. A surface that lies exactly on a cell boundary (a
// desk at y = 0 in a volume placed around an object resting on it, so the boundary lands on
// a whole number of cells) fell on either side depending on how the GPU rounds the division
// into cells (lavapipe and NVIDIA differed). Layers are nudged up by the slack, so such a
// plane lands in the cell above it on every GPU (marking both made the desk two cells thick
// and its cones start inside it); the coverage in u, v is widened by it.
const BOUNDARY_SLACK: f32 = 1e-3;

fn edge(a: vec2f, b: vec2f, q: vec2f) -> f32 {
    return (b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x);
}

// Whether the cell centred on `q` (unit cells) touches the triangle a, b, c (orientation
// `s`): each edge function is relaxed by the cell's half extent (and the slack) along the
// edge's normal.
fn covers(q: vec2f, a: vec2f, b: vec2f, c: vec2f, s: f32) -> bool {
    let ea = s * edge(a, b, q) + (0.5 + BOUNDARY_SLACK) * (abs(b.x - a.x) + abs(b.y - a.y));
    let eb = s * edge(b, c, q) + (0.5 + BOUNDARY_SLACK) * (abs(c.x - b.x) + abs(c.y - b.y));
    let ec = s * edge(c, a, q) + (0.5 + BOUNDARY_SLACK) * (abs(a.x - c.x) + abs(a.y - c.y));
    return ea >= 0.0 && eb >= 0.0 && ec >= 0.0;
}

@compute @workgroup_size(64)
fn cs_main(
    @builtin(workgroup_id) group: vec3u,
    @builtin(num_workgroups) groups: vec3u,
    @builtin(local_invocation_index) lane: u32,
) {
    let triangle = group.x + group.y * groups.x;
    if (triangle >= params.info.z) { return; }
    let d = load_triangle(triangle);
    let inst = instances[d.instance];
    let slot = select(1u, 0u, (inst.info.y & SURFACE_REAL) != 0u);
    let res = f32(params.info.x);
    var v: array<vec3f, 3>;
    for (var k = 0u; k < 3u; k++) {
        v[k] = ((inst.world_from_object * vec4f(d.p[k], 1.0)).xyz - params.origin.xyz) / voxel_side();
    }
    let normal = cross(v[1] - v[0], v[2] - v[0]);
    let an = abs(normal);
    if (max(max(an.x, an.y), an.z) < 1e-12) { return; }
    var axis = 2u;
    if (an.x >= an.y && an.x >= an.z) { axis = 0u; } else if (an.y >= an.z) { axis = 1u; }
    let a = to_uvw(v[0], axis);
    let b = to_uvw(v[1], axis);
    let c = to_uvw(v[2], axis);
    let n = to_uvw(normal, axis);
    let w_lo = min(min(a.z, b.z), c.z);
    let w_hi = max(max(a.z, b.z), c.z);
    if (w_hi < 0.0 || w_lo >= res) { return; }
    let lo = max(floor(min(min(a.xy, b.xy), c.xy) - BOUNDARY_SLACK), vec2f(0.0));
    let hi = min(floor(max(max(a.xy, b.xy), c.xy) + BOUNDARY_SLACK), vec2f(res - 1.0));
    if (any(lo > hi)) { return; }
    let size = vec2u(hi - lo) + 1u;
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let centroid = params.origin.xyz + (v[0] + v[1] + v[2]) / 3.0 * voxel_side();
    let word = (triangle + 1u) | select(0u, VOXEL_FACES_CENTRE, dot(normal, toward_centre(centroid)) > 0.0);
    // The plane w(u, v) and how much it rises across half a cell.
    let slope = -n.xy / n.z;
    let rise = 0.5 * (abs(slope.x) + abs(slope.y));
    for (var i = lane; i < size.x * size.y; i += 64u) {
        let cell = lo + vec2f(f32(i % size.x), f32(i / size.x));
        let q = cell + 0.5;
        if (!covers(q, a.xy, b.xy, c.xy, s)) { continue; }
        let w = a.z + dot(slope, q - a.xy);
        let w0 = max(floor(max(w - rise, w_lo) + BOUNDARY_SLACK), 0.0);
        let w1 = min(floor(min(w + rise, w_hi) + BOUNDARY_SLACK), res - 1.0);
        for (var z = w0; z <= w1; z += 1.0) {
            let voxel = vec3u(from_uvw(vec3f(cell, z), axis));
            atomicMax(&voxels[voxel_index(voxel) * 2u + slot], word);
        }
    }
}

// Empties every voxel before the scene is voxelised again.
@compute @workgroup_size(64)
fn clear(@builtin(global_invocation_id) id: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = id.x + id.y * groups.x * 64u;
    if (i < arrayLength(&voxels)) { atomicStore(&voxels[i], 0u); }
}
