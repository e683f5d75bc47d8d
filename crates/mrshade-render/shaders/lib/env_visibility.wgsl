// The probe's visibility ratio per color channel (indirect.wgsl writes the sums): the share
// Σw_c·V / Σw_c of channel c's cosine-weighted environment light that reaches a point; 1
// where no environment VPL reached it.

fn visibility_ratio(visible: vec3f, weight: vec3f) -> vec3f {
    return select(vec3f(1.0), visible / weight, weight > vec3f(0.0));
}
