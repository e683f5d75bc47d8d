// ISM points on skinned and morphing instances follow the deformed surface (the deformation
// pass has just written the vertices): each anchored point is re-evaluated from its
// triangle's deformed corners, position and normal, in the instance's object space.

struct Anchor {
    point: u32,
    // The corners, as indices into the scene's vertex buffer.
    a: u32,
    b: u32,
    c: u32,
    weights: vec2f,
    _pad: vec2u,
}

// Layout of `struct Point` (lib/ism.wgsl): position, instance, normal, material.
struct FollowPoint {
    position: vec3f,
    instance: u32,
    normal: vec3f,
    material: u32,
}

@group(0) @binding(0) var<storage, read> vertices: array<f32>;
@group(0) @binding(1) var<storage, read> anchors: array<Anchor>;
@group(0) @binding(2) var<storage, read_write> points: array<FollowPoint>;
@group(0) @binding(3) var<uniform> params: vec4u; // x: anchor count

fn corner(v: u32) -> array<vec3f, 2> {
    let o = 8u * v;
    return array<vec3f, 2>(
        vec3f(vertices[o], vertices[o + 1u], vertices[o + 2u]),
        vec3f(vertices[o + 3u], vertices[o + 4u], vertices[o + 5u]),
    );
}

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) id: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let i = id.x + id.y * groups.x * 64u;
    if i >= params.x {
        return;
    }
    let anchor = anchors[i];
    let a = corner(anchor.a);
    let b = corner(anchor.b);
    let c = corner(anchor.c);
    let w = anchor.weights;
    let u = 1.0 - w.x - w.y;
    points[anchor.point].position = a[0] * u + b[0] * w.x + c[0] * w.y;
    let n = a[1] * u + b[1] * w.x + c[1] * w.y;
    let length_n = length(n);
    points[anchor.point].normal = select(vec3f(0.0, 1.0, 0.0), n / length_n, length_n > 1e-20);
}
