// Sampling material textures from the two texture arrays (sRGB colour, linear data) with an
// explicit footprint. Bindings are declared by the including pass: textures_srgb,
// textures_linear, texture_sampler.

fn wrap(uv: vec2f, bits: u32, slot: u32) -> vec2f {
    let repeat_u = ((bits >> (2u * slot)) & 1u) != 0u;
    let repeat_v = ((bits >> (2u * slot + 1u)) & 1u) != 0u;
    return vec2f(select(clamp(uv.x, 0.0, 1.0), uv.x, repeat_u), select(clamp(uv.y, 0.0, 1.0), uv.y, repeat_v));
}

fn sample_slot(srgb: bool, layer: u32, bits: u32, slot: u32, uv: vec2f, dx: vec2f, dy: vec2f, fallback: vec4f) -> vec4f {
    if (layer == NO_TEXTURE) { return fallback; }
    let st = wrap(uv, bits, slot);
    if (srgb) { return textureSampleGrad(textures_srgb, texture_sampler, st, layer, dx, dy); }
    return textureSampleGrad(textures_linear, texture_sampler, st, layer, dx, dy);
}
