// Shadow-map visibility. Each light owns a real-only and a virtual-only set of layers
// (Knecht §2.7: separate maps so shadows are never doubled). A set is one layer (spot,
// directional) or six cube faces (point, wide spot). Texels are packed u64 of the compute
// rasteriser: reversed depth in the high word. Bindings are declared by the including pass:
// shadow_texels (array<vec2u>), shadow_clip_from_world, and `shadow_params`.

struct ShadowParams {
    // resolution, PCF radius, unused, unused
    size: vec4u,
    // normal offset (texels), relative depth bias, unused, unused
    bias: vec4f,
}

// 1 where the receiver at reversed depth `depth` is not behind the caster in texel (x, y).
fn shadow_test(layer: u32, x: i32, y: i32, depth: f32) -> f32 {
    let res = i32(shadow_params.size.x);
    let xc = clamp(x, 0, res - 1);
    let yc = clamp(y, 0, res - 1);
    let stored = bitcast<f32>(shadow_texels[layer * u32(res * res) + u32(yc * res + xc)].y);
    // Reversed depth: nearer casters store larger values. The bias is relative, i.e. a
    // fraction of the distance for perspective maps.
    return select(0.0, 1.0, stored <= depth * (1.0 + shadow_params.bias.y));
}

// Fraction of light `light` reaching `p` (normal `n`) past the casters of one layer set.
fn shadow_visibility(light: Light, first_layer: u32, p: vec3f, n: vec3f) -> f32 {
    var layer = first_layer;
    var distance = 1.0;
    if (light.info.z == 6u) {
        layer += cube_face(p - light.position.xyz);
    }
    if (light.info.x != LIGHT_DIRECTIONAL) {
        distance = length(light.position.xyz - p);
    }
    // Offset along the normal by a few texels at this distance: no acne at grazing angles.
    let offset_p = p + n * (shadow_params.bias.x * light.cone.z * distance);
    let clip = shadow_clip_from_world[layer] * vec4f(offset_p, 1.0);
    if (clip.w <= 0.0) { return 1.0; }
    let ndc = clip.xyz / clip.w;
    let uv = vec2f(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (any(uv < vec2f(0.0)) || any(uv > vec2f(1.0))) { return 1.0; }
    // Bilinear percentage-closer filtering over (2r+1)² texels.
    let st = uv * f32(shadow_params.size.x) - 0.5;
    let base = vec2i(floor(st));
    let f = fract(st);
    let r = i32(shadow_params.size.y);
    var lit = 0.0;
    for (var y = -r; y <= r; y++) {
        for (var x = -r; x <= r; x++) {
            let b = base + vec2i(x, y);
            let top = mix(shadow_test(layer, b.x, b.y, ndc.z), shadow_test(layer, b.x + 1, b.y, ndc.z), f.x);
            let bottom = mix(shadow_test(layer, b.x, b.y + 1, ndc.z), shadow_test(layer, b.x + 1, b.y + 1, ndc.z), f.x);
            lit += mix(top, bottom, f.y);
        }
    }
    return lit / f32((2 * r + 1) * (2 * r + 1));
}
