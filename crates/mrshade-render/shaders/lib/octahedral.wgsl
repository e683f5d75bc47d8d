// The octahedral map of the unit sphere onto the unit square (Engelhardt & Dachsbacher 2008,
// "Octahedron environment maps"; Cigolle et al. 2014): texels of like solid angle, no seam
// inside the square, a direction's texel found without trigonometry.

// The point of [0, 1]² of unit direction `d`.
fn octahedral_uv(d: vec3f) -> vec2f {
    let n = d / (abs(d.x) + abs(d.y) + abs(d.z));
    var p = n.xy;
    if (n.z < 0.0) {
        p = (1.0 - abs(n.yx)) * select(vec2f(-1.0), vec2f(1.0), n.xy >= vec2f(0.0));
    }
    return p * 0.5 + 0.5;
}

// The unit direction of point `uv` of [0, 1]² (`octahedral_uv`'s inverse).
fn octahedral_direction(uv: vec2f) -> vec3f {
    let p = uv * 2.0 - 1.0;
    var n = vec3f(p, 1.0 - abs(p.x) - abs(p.y));
    if (n.z < 0.0) {
        n = vec3f((1.0 - abs(n.yx)) * select(vec2f(-1.0), vec2f(1.0), n.xy >= vec2f(0.0)), n.z);
    }
    return normalize(n);
}
