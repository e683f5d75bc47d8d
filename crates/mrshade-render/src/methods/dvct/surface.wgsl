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
