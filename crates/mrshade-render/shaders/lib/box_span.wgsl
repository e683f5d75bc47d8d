// Where a ray runs inside an axis-aligned box (the slab test): the specular stage's impostor
// and BVH boxes (src/specular/tracing.wgsl), `dlpv`'s paths through the virtual content's
// cells (src/methods/dlpv/vpl_gather.wgsl `blocked`).

// The part [t0, t1] of the ray (o, 1/inv_d), t ∈ [0, t_max], inside box [lo, hi] (the slab
// test; t0 > t1: none).
fn slab_span(o: vec3f, inv_d: vec3f, lo: vec3f, hi: vec3f, t_max: f32) -> vec2f {
    let a = (lo - o) * inv_d;
    let b = (hi - o) * inv_d;
    let t0 = max(max(min(a.x, b.x), min(a.y, b.y)), max(min(a.z, b.z), 0.0));
    let t1 = min(min(max(a.x, b.x), max(a.y, b.y)), min(max(a.z, b.z), t_max));
    return vec2f(t0, t1);
}

// The part [t0, t1] of the ray `co + cd·t`, t ∈ [0, t_max], inside the box `lo`…`hi`
// (t0 > t1: none); axes the ray runs parallel to are handled by a tiny stand-in slope.
fn box_span(co: vec3f, cd: vec3f, lo: vec3f, hi: vec3f, t_max: f32) -> vec2f {
    let slope = select(cd, vec3f(1e-20), abs(cd) < vec3f(1e-20));
    return slab_span(co, 1.0 / slope, lo, hi, t_max);
}
