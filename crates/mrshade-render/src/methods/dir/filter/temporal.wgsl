// Temporal flicker reduction (Knecht §2.10, Eq. 5.11–5.15), applied identically to the
// indirect buffers L_rv, L_r and the environment visibility sums, so that ΔL stays
// consistent. The previous frame's value is found through the G-buffer's motion; its weight
// (confidence) drops with position, depth, normal and illumination changes:
//   ε_pos = |(Δx, Δy, Δd) ⊙ w_p|,  ε_n = (1 − n·n_prev) w_n,  ε_i = sat(|I − I_prev|³) w_i
//   c = sat(1 − max(ε_pos, ε_n, ε_i)) · c_B,   I = c·I_prev + (1 − c)·I_new
// Beyond the thesis, on frames where geometry moved the history is first clamped to the
// range of the new values in the I×I window around the pixel (which holds every VPL subset
// once): where a virtual object moved away, its old shadow lies outside that range and is
// dropped at once. ε_i alone (w_i = 0.025) lets the history outlive such a change by many
// frames, a visible trail. Static frames keep the plain smoothing: the range of one frame's
// interleaved values is noisy, and clamping to it costs accuracy where nothing changed.
// Also beyond the thesis (on by default; off when dir.temporal.static_confidence ≤ c_B):
// once nothing has moved for a few frames the CPU raises c_B toward a running mean over the
// still frames (filter/mod.rs, `history_weight`) and ε_i is left out, as a still scene's only
// change from frame to frame is the VPLs' noise. With 256 VPLs that noise is low-frequency (a
// VPL near a surface lights a blob); c_B = 0.9 averages about 19 frames' VPLs, too few for a
// still Cornell box (region FLIP 0.107 on a 48-frame still; 0.082 at 256 frames).

struct TemporalParams {
    // w_p (x, y in [0, 1] screen units, reversed depth), w_n
    weights: vec4f,
    // w_i, c_B (or the still scene's weight), exposure, 1 if a history exists
    values: vec4f,
    // interleave I, 1 if geometry moved, 1 while a still scene accumulates, unused
    block: vec4u,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: TemporalParams;
@group(0) @binding(2) var gbuffer_depth_motion: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_normal_roughness: texture_2d<f32>;
@group(0) @binding(4) var previous_depth_motion: texture_2d<f32>;
@group(0) @binding(5) var previous_normal_roughness: texture_2d<f32>;

@group(1) @binding(0) var new_rv: texture_2d<f32>;
@group(1) @binding(1) var new_r: texture_2d<f32>;
@group(1) @binding(2) var new_env_rv: texture_2d<f32>;
@group(1) @binding(3) var new_env_r: texture_2d<f32>;
@group(1) @binding(4) var new_env_weight: texture_2d<f32>;
@group(1) @binding(5) var history_rv: texture_2d<f32>;
@group(1) @binding(6) var history_r: texture_2d<f32>;
@group(1) @binding(7) var history_env_rv: texture_2d<f32>;
@group(1) @binding(8) var history_env_r: texture_2d<f32>;
@group(1) @binding(9) var history_env_weight: texture_2d<f32>;

@group(2) @binding(0) var out_rv: texture_storage_2d<rgba16float, write>;
@group(2) @binding(1) var out_r: texture_storage_2d<rgba16float, write>;
@group(2) @binding(2) var out_env_rv: texture_storage_2d<rgba16float, write>;
@group(2) @binding(3) var out_env_r: texture_storage_2d<rgba16float, write>;
@group(2) @binding(4) var out_env_weight: texture_storage_2d<rgba16float, write>;

// Scale of the confidence on frames where geometry moved.
const MOVING_CONFIDENCE: f32 = 0.5;
// History length of a pixel whose history was never rejected (exact in f16).
const ESTABLISHED: f32 = 4096.0;

// d(previous depth)/d(pixel) of this pixel's surface, from its neighbours on the same
// surface (the smaller one-sided difference per axis, so that an edge does not count).
fn previous_depth_slope(pixel: vec2i, depth: f32) -> vec2f {
    var slope = vec2f(0.0);
    for (var axis = 0; axis < 2; axis++) {
        var step = vec2i(0);
        step[axis] = 1;
        let ahead = textureLoad(gbuffer_depth_motion, clamp(pixel + step, vec2i(0), vec2i(frame.size.xy) - 1), 0);
        let behind = textureLoad(gbuffer_depth_motion, clamp(pixel - step, vec2i(0), vec2i(frame.size.xy) - 1), 0);
        let forward = select(0.0, ahead.w - depth, ahead.x != 0.0);
        let backward = select(0.0, depth - behind.w, behind.x != 0.0);
        slope[axis] = select(backward, forward, abs(forward) < abs(backward));
    }
    return slope;
}

fn confidence(pixel: vec2i) -> f32 {
    if (params.values.w == 0.0) { return 0.0; }
    let dm = textureLoad(gbuffer_depth_motion, pixel, 0);
    if (dm.x == 0.0) { return 0.0; }
    let size = vec2f(frame.size.xy);
    let previous_pixel = vec2f(pixel) + 0.5 + dm.yz;
    let q = vec2i(floor(previous_pixel));
    if (any(q < vec2i(0)) || any(q >= vec2i(frame.size.xy))) { return 0.0; }
    let stored = textureLoad(previous_depth_motion, q, 0).x;
    if (stored == 0.0) { return 0.0; }
    // The history is read at the nearest pixel centre q, up to half a pixel from where this
    // point was: on a surface seen at a grazing angle the depth stored there differs from the
    // point's own by the depth's slope × that offset, which the thesis's w_d = 10000 (a
    // still camera: offset 0) would take for a disocclusion. The point's previous depth is
    // carried to q along the slope first (beyond the thesis; for a moving camera).
    let offset = vec2f(q) + 0.5 - previous_pixel;
    let predicted = dm.w + dot(previous_depth_slope(pixel, dm.w), offset);
    let delta = vec3f(-offset / size, predicted - stored);
    let e_pos = length(delta * params.weights.xyz);
    let n = textureLoad(gbuffer_normal_roughness, pixel, 0).xyz;
    let n_prev = textureLoad(previous_normal_roughness, q, 0).xyz;
    let e_n = (1.0 - dot(n, n_prev)) * params.weights.w;
    let exposure = params.values.z;
    let i_new = luminance(exposure * textureLoad(new_rv, pixel, 0).rgb);
    let i_prev = luminance(exposure * textureLoad(history_rv, q, 0).rgb);
    let change = clamp(abs(i_new - i_prev), 0.0, 1.0);
    let e_i = select(change * change * change * params.values.x, 0.0, params.block.z == 1u);
    return clamp(1.0 - max(e_pos, max(e_n, e_i)), 0.0, 1.0) * params.values.y;
}

struct Window {
    lo_rv: vec4f,
    hi_rv: vec4f,
    lo_r: vec4f,
    hi_r: vec4f,
    // The environment's visibility ratios per channel (Σw_c·V_rv / Σw_c, Σw_c·V_r / Σw_c): one
    // subset of the environment VPLs may hold the sun and the next none, so Σw_c·V itself
    // ranges widely over a window even where nothing is shadowed; its ratios do not.
    lo_env_rv: vec3f,
    hi_env_rv: vec3f,
    lo_env_r: vec3f,
    hi_env_r: vec3f,
}


// Per-channel range of the new values over the I×I window around `pixel` (same surface only).
fn new_range(pixel: vec2i) -> Window {
    let i = i32(params.block.x);
    let start = pixel - vec2i(i / 2);
    let depth = textureLoad(gbuffer_depth_motion, pixel, 0).x;
    var w: Window;
    w.lo_rv = vec4f(3.0e38);
    w.hi_rv = vec4f(-3.0e38);
    w.lo_r = w.lo_rv;
    w.hi_r = w.hi_rv;
    w.lo_env_rv = vec3f(3.0e38);
    w.hi_env_rv = vec3f(-3.0e38);
    w.lo_env_r = w.lo_env_rv;
    w.hi_env_r = w.hi_env_rv;
    for (var y = 0; y < i; y++) {
        for (var x = 0; x < i; x++) {
            let q = clamp(start + vec2i(x, y), vec2i(0), vec2i(frame.size.xy) - 1);
            let dq = textureLoad(gbuffer_depth_motion, q, 0).x;
            if (dq == 0.0 || abs(dq - depth) > 0.05 * depth) { continue; }
            let rv = textureLoad(new_rv, q, 0);
            let r = textureLoad(new_r, q, 0);
            let weight = textureLoad(new_env_weight, q, 0).rgb;
            w.lo_rv = min(w.lo_rv, rv);
            w.hi_rv = max(w.hi_rv, rv);
            w.lo_r = min(w.lo_r, r);
            w.hi_r = max(w.hi_r, r);
            if (any(weight > vec3f(0.0))) {
                let ratio_rv = visibility_ratio(textureLoad(new_env_rv, q, 0).rgb, weight);
                let ratio_r = visibility_ratio(textureLoad(new_env_r, q, 0).rgb, weight);
                w.lo_env_rv = min(w.lo_env_rv, ratio_rv);
                w.hi_env_rv = max(w.hi_env_rv, ratio_rv);
                w.lo_env_r = min(w.lo_env_r, ratio_r);
                w.hi_env_r = max(w.hi_env_r, ratio_r);
            }
        }
    }
    return w;
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id.xy >= frame.size.xy)) { return; }
    let pixel = vec2i(id.xy);
    let dm = textureLoad(gbuffer_depth_motion, pixel, 0);
    let q = clamp(vec2i(floor(vec2f(pixel) + 0.5 + dm.yz)), vec2i(0), vec2i(frame.size.xy) - 1);
    let old_env_weight = textureLoad(history_env_weight, q, 0);
    // Beyond the thesis: the history's length per pixel (in the environment weight's alpha).
    // A surface newly seen by a moving camera (a disocclusion: the confidence tests rejected
    // its history) starts a running mean, c ≤ 1 − 1/n over its n frames, instead of keeping
    // its first, noisy frame at the scene-wide weight (up to 0.996 while nothing moves).
    // Pixels whose history was never rejected count as long-established, so a still camera
    // smooths exactly as the thesis does.
    let c_tests = confidence(pixel);
    var n = ESTABLISHED;
    if (params.values.w != 0.0) {
        n = select(1.0, min(old_env_weight.w + 1.0, ESTABLISHED), c_tests > 0.0);
    }
    let c = min(c_tests, 1.0 - 1.0 / n);
    let new_rv_value = textureLoad(new_rv, pixel, 0);
    let new_r_value = textureLoad(new_r, pixel, 0);
    let new_env_rv_value = textureLoad(new_env_rv, pixel, 0);
    let new_env_r_value = textureLoad(new_env_r, pixel, 0);
    let new_env_weight_value = textureLoad(new_env_weight, pixel, 0);
    if (c == 0.0 || params.block.y == 0u) {
        textureStore(out_rv, pixel, mix(new_rv_value, textureLoad(history_rv, q, 0), c));
        textureStore(out_r, pixel, mix(new_r_value, textureLoad(history_r, q, 0), c));
        textureStore(out_env_rv, pixel, mix(new_env_rv_value, textureLoad(history_env_rv, q, 0), c));
        textureStore(out_env_r, pixel, mix(new_env_r_value, textureLoad(history_env_r, q, 0), c));
        textureStore(out_env_weight, pixel, vec4f(mix(new_env_weight_value.rgb, old_env_weight.rgb, c), n));
        return;
    }
    // While geometry moves, shadows and bounces move over still surfaces, whose history the
    // position and normal tests keep: besides the clamp, the history weighs less, so that a
    // moving object's shadows lag by about a frame instead of ~1 / (1 − c).
    let c_moving = c * MOVING_CONFIDENCE;
    let w = new_range(pixel);
    let old_rv = clamp(textureLoad(history_rv, q, 0), w.lo_rv, w.hi_rv);
    let old_r = clamp(textureLoad(history_r, q, 0), w.lo_r, w.hi_r);
    // The history's visibility sums with their ratios clamped to the window's range; the
    // weights (the ratios' denominators, the probe's light) are kept.
    var old_env_rv = textureLoad(history_env_rv, q, 0);
    var old_env_r = textureLoad(history_env_r, q, 0);
    if (w.lo_env_rv.x <= w.hi_env_rv.x) {
        let weight = old_env_weight.rgb;
        old_env_rv = vec4f(clamp(visibility_ratio(old_env_rv.rgb, weight), w.lo_env_rv, w.hi_env_rv) * weight, 1.0);
        old_env_r = vec4f(clamp(visibility_ratio(old_env_r.rgb, weight), w.lo_env_r, w.hi_env_r) * weight, 1.0);
    }
    textureStore(out_rv, pixel, mix(new_rv_value, old_rv, c_moving));
    textureStore(out_r, pixel, mix(new_r_value, old_r, c_moving));
    textureStore(out_env_rv, pixel, mix(new_env_rv_value, old_env_rv, c_moving));
    textureStore(out_env_r, pixel, mix(new_env_r_value, old_env_r, c_moving));
    textureStore(out_env_weight, pixel, vec4f(mix(new_env_weight_value.rgb, old_env_weight.rgb, c_moving), n));
}
