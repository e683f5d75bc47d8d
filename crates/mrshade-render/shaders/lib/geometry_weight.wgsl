// How much a neighbouring pixel's light may stand for a pixel's (a geometry-aware filter's
// weight): 0 across a depth edge (3 % of the distance) or a crease. Reversed depth is inversely
// proportional to distance: its relative difference is the relative difference of distances.
fn geometry_weight(depth: f32, n: vec3f, depth_q: f32, n_q: vec3f) -> f32 {
    let w_depth = max(0.0, 1.0 - abs(depth_q - depth) / (0.03 * depth));
    let w_normal = pow(max(dot(n, n_q), 0.0), 8.0);
    return w_depth * w_normal;
}
