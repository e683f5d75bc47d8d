// The surface a voxel holds, from the triangle the voxelisation kept: the voxel centre's
// closest point on the triangle, its shading normal and its diffuse albedo (base color
// texture prefiltered over about a voxel). Group 0 of the passes over the voxels (light,
// bounce, photo) is theirs, declared here; the including pass declares textures_srgb,
// textures_linear and texture_sampler.

@group(0) @binding(0) var<uniform> params: VolumeParams;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
@group(0) @binding(2) var<storage, read> vertices: array<f32>;
@group(0) @binding(3) var<storage, read> indices: array<u32>;
@group(0) @binding(4) var<storage, read> triangles: array<vec4u>;
@group(0) @binding(5) var<storage, read> materials: array<Material>;
@group(0) @binding(6) var<storage, read> voxels: array<u32>;

struct VoxelSurface {
    position: vec3f,
    normal: vec3f,
    // Diffuse albedo ρ (the part of the base color that is not metal or transmitted).
    albedo: vec3f,
}

fn voxel_surface(triangle: u32, centre: vec3f) -> VoxelSurface {
    let d = load_triangle(triangle);
    let inst = instances[d.instance];
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
    var s: VoxelSurface;
    s.position = p[0] * w.x + p[1] * w.y + p[2] * w.z;
    let n = d.n[0] * w.x + d.n[1] * w.y + d.n[2] * w.z;
    s.normal = normalize((inst.normal_from_object * vec4f(n, 0.0)).xyz);
    if (dot(s.normal, s.normal) < 0.5 || any(s.normal != s.normal)) { s.normal = g; }
    let uv = d.uv[0] * w.x + d.uv[1] * w.y + d.uv[2] * w.z;
    // Texture footprint of a voxel: the triangle's texture extent per metre times a voxel.
    let uv_per_metre = (length(d.uv[1] - d.uv[0]) + length(d.uv[2] - d.uv[0])) / max(sqrt(d00) + sqrt(d11), 1e-9);
    let footprint = vec2f(uv_per_metre * voxel_side(), 0.0);
    let m = materials[inst.info.x];
    let bits = m.texture_info.y;
    let base = m.base_color * sample_slot(true, m.texture_layers.x, bits, 0u, uv, footprint, footprint.yx, vec4f(1.0));
    let mr = sample_slot(false, m.texture_layers.y, bits, 1u, uv, footprint, footprint.yx, vec4f(1.0));
    let metallic = clamp(m.params.x * mr.b, 0.0, 1.0);
    s.albedo = vpl_base_color(m, base.rgb, metallic) * (1.0 - metallic);
    return s;
}
