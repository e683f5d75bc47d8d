// Shadow-map visibility. Each light owns a real-only and a virtual-only set of layers in
// `shadow_maps` (Knecht §2.7: separate maps so shadows are never doubled). A set is one layer
// (spot, directional) or six cube faces (point, wide spot). Depth is reversed (near = 1).
// Bindings are declared by the including pass: shadow_maps, shadow_sampler, shadow_clip_from_world.

// Which of the six cube faces (+X, −X, +Y, −Y, +Z, −Z) sees direction `d`.
fn cube_face(d: vec3f) -> u32 {
    let a = abs(d);
    if (a.x >= a.y && a.x >= a.z) { return select(1u, 0u, d.x > 0.0); }
    if (a.y >= a.z) { return select(3u, 2u, d.y > 0.0); }
    return select(5u, 4u, d.z > 0.0);
}

// Fraction of light `light` reaching `p` (normal `n`) past the casters of one layer set.
fn shadow_visibility(light: Light, first_layer: u32, p: vec3f, n: vec3f, pcf_radius: i32, normal_offset: f32) -> f32 {
    var layer = first_layer;
    var distance = 1.0;
    if (light.info.z == 6u) {
        layer += cube_face(p - light.position.xyz);
    }
    if (light.info.x != LIGHT_DIRECTIONAL) {
        distance = length(light.position.xyz - p);
    }
    // Offset along the normal by a few texels at this distance: no acne at grazing angles.
    let offset_p = p + n * (normal_offset * light.cone.z * distance);
    let clip = shadow_clip_from_world[layer] * vec4f(offset_p, 1.0);
    if (clip.w <= 0.0) { return 1.0; }
    let ndc = clip.xyz / clip.w;
    let uv = vec2f(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (any(uv < vec2f(0.0)) || any(uv > vec2f(1.0))) { return 1.0; }
    let texel = 1.0 / vec2f(textureDimensions(shadow_maps).xy);
    var lit = 0.0;
    var taps = 0.0;
    for (var y = -pcf_radius; y <= pcf_radius; y++) {
        for (var x = -pcf_radius; x <= pcf_radius; x++) {
            lit += textureSampleCompareLevel(shadow_maps, shadow_sampler, uv + vec2f(f32(x), f32(y)) * texel, layer, ndc.z);
            taps += 1.0;
        }
    }
    return lit / taps;
}
