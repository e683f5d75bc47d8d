// Where the surface a voxel holds lies, from the triangle the voxelisation kept: the voxel
// centre's closest point on the triangle and its shading normal (voxel_surface.wgsl adds its
// albedo). Group 0 of the passes over the voxels (light, bounce, photo) is theirs, declared
// here.

@group(0) @binding(0) var<uniform> params: VolumeParams;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
@group(0) @binding(2) var<storage, read> vertices: array<f32>;
@group(0) @binding(3) var<storage, read> indices: array<u32>;
@group(0) @binding(4) var<storage, read> triangles: array<vec4u>;
@group(0) @binding(5) var<storage, read> materials: array<Material>;
@group(0) @binding(6) var<storage, read> voxels: array<u32>;

// The passes over the voxels shade only the few that hold a surface (a wall crosses a block
// of voxels in one layer of it): a workgroup of VOXEL_GROUP voxels first lists its occupied
// ones in workgroup memory, so that they are shaded by its first invocations side by side in
// whole warps, not by lanes scattered over every warp (a plane left a quarter to a half of a
// 4×4×4 workgroup's lanes busy through all its cones).
const VOXEL_GROUP: u32 = 256u;
// Voxels whose real (1) or virtual (2) word a pass shades.
const VOXEL_REAL: u32 = 1u;
const VOXEL_VIRTUAL: u32 = 2u;
var<workgroup> group_occupied: array<u32, VOXEL_GROUP>;
var<workgroup> group_occupied_count: atomic<u32>;

struct VoxelJob {
    // This invocation's own voxel is in the volume and holds no surface the pass shades: the
    // pass writes what an empty voxel holds there.
    own_empty: bool,
    // This invocation shades `voxel`.
    busy: bool,
    voxel: vec3u,
}

// Lists the voxels of the workgroup (invocation `local` at voxel `id`) whose words of the
// kinds `kinds` are set, and hands them to its first invocations. Called from uniform control
// flow: it holds the workgroup's barriers.
fn voxel_job(id: vec3u, local: u32, kinds: u32) -> VoxelJob {
    if (local == 0u) { atomicStore(&group_occupied_count, 0u); }
    workgroupBarrier();
    var job: VoxelJob;
    if (all(id < vec3u(params.info.x))) {
        let index = voxel_index(id);
        let real = (kinds & VOXEL_REAL) != 0u && voxels[index * 2u] != 0u;
        let virt = (kinds & VOXEL_VIRTUAL) != 0u && voxels[index * 2u + 1u] != 0u;
        if (real || virt) {
            group_occupied[atomicAdd(&group_occupied_count, 1u)] = index;
        } else {
            job.own_empty = true;
        }
    }
    workgroupBarrier();
    if (local < atomicLoad(&group_occupied_count)) {
        let index = group_occupied[local];
        let res = params.info.x;
        job.busy = true;
        job.voxel = vec3u(index % res, (index / res) % res, index / (res * res));
    }
    return job;
}

struct VoxelPoint {
    position: vec3f,
    normal: vec3f,
    // Barycentric weights of the point on the triangle.
    weights: vec3f,
    // World lengths of the triangle's edges from its first vertex.
    edges: vec2f,
}

// The point of triangle `d` (of instance `inst`) closest to the voxel centre `centre`.
fn voxel_point(d: TriangleData, inst: Instance, centre: vec3f) -> VoxelPoint {
    var p: array<vec3f, 3>;
    for (var k = 0u; k < 3u; k++) {
        p[k] = (inst.world_from_object * vec4f(d.p[k], 1.0)).xyz;
    }
    let e1 = p[1] - p[0];
    let e2 = p[2] - p[0];
    let g = normalize(cross(e1, e2));
    // Barycentrics of the centre's projection, clamped into the triangle.
    let q = centre - g * dot(centre - p[0], g);
    let d00 = dot(e1, e1);
    let d01 = dot(e1, e2);
    let d11 = dot(e2, e2);
    let qp = q - p[0];
    let denom = max(d00 * d11 - d01 * d01, 1e-20);
    var b1 = (d11 * dot(qp, e1) - d01 * dot(qp, e2)) / denom;
    var b2 = (d00 * dot(qp, e2) - d01 * dot(qp, e1)) / denom;
    b1 = clamp(b1, 0.0, 1.0);
    b2 = clamp(b2, 0.0, 1.0 - b1);
    let w = vec3f(1.0 - b1 - b2, b1, b2);
    var out: VoxelPoint;
    out.position = p[0] * w.x + p[1] * w.y + p[2] * w.z;
    let n = d.n[0] * w.x + d.n[1] * w.y + d.n[2] * w.z;
    out.normal = normalize((inst.normal_from_object * vec4f(n, 0.0)).xyz);
    if (dot(out.normal, out.normal) < 0.5 || any(out.normal != out.normal)) { out.normal = g; }
    out.weights = w;
    out.edges = vec2f(sqrt(d00), sqrt(d11));
    return out;
}
