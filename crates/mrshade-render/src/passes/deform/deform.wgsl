// Skinning and morphing (glTF 2.0 §3.7.3, §3.7.2.2): rest vertices of every deformed
// instance in, its deformed vertices written into the scene's vertex buffer, before any
// pass reads geometry. The same math as `mrshade_scene::deform_vertices` (the CPU answer
// the tests compare against): morph displacements first, then the blended joint matrix,
// normals by its cofactor matrix, renormalised.

struct Range {
    // First vertex of the range in `rest`, `skins` and `range_of` (deformed-vertex index).
    first: u32,
    count: u32,
    // Its first vertex in the scene's vertex buffer.
    destination: u32,
    // First joint matrix in `joints`, or 0xffffffff when not skinned.
    joint_base: u32,
    // First weight in `weights`.
    weight_base: u32,
    target_count: u32,
    // First displacement (vec4 pairs: position, normal) in `deltas`.
    delta_base: u32,
    _pad: u32,
}

struct VertexSkin {
    joints: vec4<u32>,
    weights: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> rest: array<f32>;
@group(0) @binding(1) var<storage, read> skins: array<VertexSkin>;
@group(0) @binding(2) var<storage, read> range_of: array<u32>;
@group(0) @binding(3) var<storage, read> ranges: array<Range>;
@group(0) @binding(4) var<storage, read> deltas: array<vec4<f32>>;
@group(0) @binding(5) var<storage, read> joints: array<mat4x4<f32>>;
@group(0) @binding(6) var<storage, read> weights: array<f32>;
@group(0) @binding(7) var<storage, read_write> vertices: array<f32>;
@group(0) @binding(8) var<uniform> params: vec4<u32>; // x: deformed vertex count

const NOT_SKINNED: u32 = 0xffffffffu;

fn cofactor(m: mat3x3<f32>) -> mat3x3<f32> {
    return mat3x3<f32>(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1]));
}

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let v = id.x + id.y * groups.x * 64u;
    if v >= params.x {
        return;
    }
    let range = ranges[range_of[v]];
    let local = v - range.first;
    var p = vec3<f32>(rest[8u * v], rest[8u * v + 1u], rest[8u * v + 2u]);
    var n = vec3<f32>(rest[8u * v + 3u], rest[8u * v + 4u], rest[8u * v + 5u]);
    for (var t = 0u; t < range.target_count; t++) {
        let w = weights[range.weight_base + t];
        if w != 0.0 {
            let d = range.delta_base + 2u * (t * range.count + local);
            p += w * deltas[d].xyz;
            n += w * deltas[d + 1u].xyz;
        }
    }
    if range.joint_base != NOT_SKINNED {
        let s = skins[v];
        var m = mat4x4<f32>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
        for (var j = 0u; j < 4u; j++) {
            if s.weights[j] != 0.0 {
                m += joints[range.joint_base + s.joints[j]] * s.weights[j];
            }
        }
        p = (m * vec4<f32>(p, 1.0)).xyz;
        n = cofactor(mat3x3<f32>(m[0].xyz, m[1].xyz, m[2].xyz)) * n;
    }
    let length_n = length(n);
    n = select(vec3<f32>(0.0, 1.0, 0.0), n / length_n, length_n > 1e-20);
    let o = 8u * (range.destination + local);
    vertices[o] = p.x;
    vertices[o + 1u] = p.y;
    vertices[o + 2u] = p.z;
    vertices[o + 3u] = n.x;
    vertices[o + 4u] = n.y;
    vertices[o + 5u] = n.z;
}
