// Temporal smoothing of the specular stage's light (reflections spec §2.19: the paper smooths
// L'_rv and L'_r "to avoid flickering artifacts" and does not state the filter; ours). Each
// pixel's value of the last frame is found through the G-buffer's motion and blended in:
//   out = mix(new, history, weight)
// On frames where something changed (camera, objects, lights, photo) the history is first
// clipped to the spread of this frame's values in the 3×3 window around the pixel, so that a
// reflection that moves across a mirror, or a caustic that moves with its light, does not
// trail; while nothing changes the CPU passes the running mean's weight n / (n + 1), which
// averages the frames since the last change without bias. Traced pixels (a = 1) and diffuse
// ones (caustics, a ≤ 0) hold different things: each takes history of its own kind only.

struct TemporalParams {
    // history weight, 1 to clamp the history to the window, 1 if a history exists, unused
    info: vec4f,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: TemporalParams;
@group(0) @binding(2) var gbuffer_depth_motion: texture_2d<f32>;
@group(0) @binding(3) var new_light: texture_2d<f32>;
@group(0) @binding(4) var history: texture_2d<f32>;
@group(0) @binding(5) var out_light: texture_storage_2d<rgba16float, write>;
// The same result, read as `history` next frame.
@group(0) @binding(6) var out_history: texture_storage_2d<rgba16float, write>;

fn store(pixel: vec2i, v: vec4f) {
    textureStore(out_light, pixel, v);
    textureStore(out_history, pixel, v);
}

fn is_traced_value(v: vec4f) -> bool {
    return v.a > 0.5;
}

// The history clipped to this frame's values of the same kind in the 3×3 window around
// `pixel`: to their mean ± one standard deviation per channel (Salvi's variance clipping;
// their min–max box is wide where a mirror magnifies a textured surface, and let an old
// reflection through), within that box.
fn clamp_to_window(pixel: vec2i, value: vec4f, h: vec4f) -> vec4f {
    var lo = value;
    var hi = value;
    var sum = vec4f(0.0);
    var sum2 = vec4f(0.0);
    var n = 0.0;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let q = clamp(pixel + vec2i(dx, dy), vec2i(0), vec2i(frame.size.xy) - 1);
            let v = textureLoad(new_light, q, 0);
            if (is_traced_value(v) == is_traced_value(value)) {
                lo = min(lo, v);
                hi = max(hi, v);
                sum += v;
                sum2 += v * v;
                n += 1.0;
            }
        }
    }
    let mean = sum / n;
    let sigma = sqrt(max(sum2 / n - mean * mean, vec4f(0.0)));
    return clamp(h, max(lo, mean - sigma), min(hi, mean + sigma));
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id.xy >= frame.size.xy)) { return; }
    let pixel = vec2i(id.xy);
    let value = textureLoad(new_light, pixel, 0);
    let dm = textureLoad(gbuffer_depth_motion, pixel, 0);
    // No history, or no surface here (the stage wrote nothing of its own).
    if (params.info.z == 0.0 || dm.x == 0.0) {
        store(pixel, value);
        return;
    }
    let q = vec2i(floor(vec2f(pixel) + 0.5 + dm.yz));
    if (any(q < vec2i(0)) || any(q >= vec2i(frame.size.xy))) {
        store(pixel, value);
        return;
    }
    var h = textureLoad(history, q, 0);
    if (is_traced_value(h) != is_traced_value(value)) {
        store(pixel, value);
        return;
    }
    if (params.info.y > 0.5) {
        h = clamp_to_window(pixel, value, h);
    }
    store(pixel, mix(value, h, params.info.x));
}
