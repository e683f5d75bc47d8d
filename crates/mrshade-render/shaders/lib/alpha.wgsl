// α of the α-scaled differential composite (TVCG Eq. 2): α = (photo + ε) / (exposure·L_r + ε)
// per channel, clamped to [0, α_max]; 1 in the additive mode. Mirrors the composite's params.

struct CompositeParams {
    // 1 = α-scaled, 0 = additive; ε; α_max; unused
    mode_epsilon_max: vec4f,
}

fn alpha_of(params: CompositeParams, photo: vec3f, exposed_l_r: vec3f) -> vec3f {
    if (params.mode_epsilon_max.x == 0.0) { return vec3f(1.0); }
    let eps = params.mode_epsilon_max.y;
    return clamp((photo + eps) / (max(exposed_l_r, vec3f(0.0)) + eps), vec3f(0.0), vec3f(params.mode_epsilon_max.z));
}
