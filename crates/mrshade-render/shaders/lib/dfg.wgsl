// The split-sum table of the probe (Karis 2013): ∫ f_spec cos ≈ F0·A + F90·B, by n·v and
// roughness. Bindings declared by the including pass: env_dfg_table, env_sampler.

fn env_dfg(n_dot_v: f32, roughness: f32) -> vec2f {
    // The probe's sampler repeats (the equirect wraps in u): keep the lookup half a texel
    // inside, or n·v = 1 would blend in the grazing column.
    let half = 0.5 / vec2f(textureDimensions(env_dfg_table));
    let uv = clamp(vec2f(n_dot_v, roughness), half, vec2f(1.0) - half);
    return textureSampleLevel(env_dfg_table, env_sampler, uv, 0.0).rg;
}
