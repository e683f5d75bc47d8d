// Surface points from visibility targets: the triangle behind a texel, intersected with the
// texel's ray, with interpolated attributes. Bindings are declared by the including pass:
// instances, vertices (8 floats per vertex), indices, triangles.

struct Hit {
    // World-space position, geometric normal (unit, any side), shading normal (unit, object's side).
    position: vec3f,
    geometric_normal: vec3f,
    normal: vec3f,
    uv: vec2f,
    // Barycentrics (of vertices 1 and 2) and the ray parameter.
    bary: vec2f,
    t: f32,
    // Object-space position (for motion vectors).
    object_position: vec3f,
    instance: u32,
}

struct TriangleData {
    p: array<vec3f, 3>,
    n: array<vec3f, 3>,
    uv: array<vec2f, 3>,
    instance: u32,
}

fn load_triangle(triangle: u32) -> TriangleData {
    let tri = triangles[triangle];
    var d: TriangleData;
    d.instance = tri.x;
    for (var k = 0u; k < 3u; k++) {
        let v = (indices[tri.y + k] + tri.z) * 8u;
        d.p[k] = vec3f(vertices[v], vertices[v + 1u], vertices[v + 2u]);
        d.n[k] = vec3f(vertices[v + 3u], vertices[v + 4u], vertices[v + 5u]);
        d.uv[k] = vec2f(vertices[v + 6u], vertices[v + 7u]);
    }
    return d;
}

// Barycentrics (b1, b2) and distance t of the ray `origin + t·dir` on the plane of triangle a, b, c.
fn ray_plane_barycentrics(origin: vec3f, dir: vec3f, a: vec3f, b: vec3f, c: vec3f) -> vec3f {
    let e1 = b - a;
    let e2 = c - a;
    let pv = cross(dir, e2);
    let det = dot(e1, pv);
    let inv = 1.0 / select(det, 1e-20, abs(det) < 1e-20);
    let tv = origin - a;
    let qv = cross(tv, e1);
    return vec3f(dot(tv, pv) * inv, dot(dir, qv) * inv, dot(e2, qv) * inv);
}

// The hit of ray `origin + t·dir` with triangle `triangle`.
fn intersect(triangle: u32, origin: vec3f, dir: vec3f) -> Hit {
    let d = load_triangle(triangle);
    let inst = instances[d.instance];
    let a = (inst.world_from_object * vec4f(d.p[0], 1.0)).xyz;
    let b = (inst.world_from_object * vec4f(d.p[1], 1.0)).xyz;
    let c = (inst.world_from_object * vec4f(d.p[2], 1.0)).xyz;
    let bt = ray_plane_barycentrics(origin, dir, a, b, c);
    let w = vec3f(1.0 - bt.x - bt.y, bt.x, bt.y);
    var h: Hit;
    h.bary = bt.xy;
    h.t = bt.z;
    h.position = origin + dir * bt.z;
    h.object_position = d.p[0] * w.x + d.p[1] * w.y + d.p[2] * w.z;
    h.geometric_normal = normalize(cross(b - a, c - a));
    let n = d.n[0] * w.x + d.n[1] * w.y + d.n[2] * w.z;
    h.normal = normalize((inst.normal_from_object * vec4f(n, 0.0)).xyz);
    h.uv = d.uv[0] * w.x + d.uv[1] * w.y + d.uv[2] * w.z;
    h.instance = d.instance;
    return h;
}

// The shading normal turned to the side of the surface that `toward` (a direction from the
// surface) lies on. Triangle winding is not trusted: the geometric normal decides the side.
fn facing_normal(h: Hit, toward: vec3f) -> vec3f {
    let side = select(-1.0, 1.0, dot(h.geometric_normal, toward) >= 0.0);
    let g = h.geometric_normal * side;
    return select(-h.normal, h.normal, dot(h.normal, g) >= 0.0);
}

// Unpacks a visibility texel: (payload = triangle + 1, reversed depth).
fn visibility_triangle(texel: vec2u) -> u32 { return texel.x; }
fn visibility_depth(texel: vec2u) -> f32 { return bitcast<f32>(texel.y); }
