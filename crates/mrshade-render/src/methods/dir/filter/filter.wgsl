// Merge of the interleaved buffers with a geometry-aware filter (Knecht §2.10; kernel not
// given in the thesis): an I×I window around each pixel, which holds every VPL subset once,
// weighted by depth and normal similarity so that light does not leak across edges.

struct FilterParams {
    // interleave I, 1 to filter (0: copy), unused, unused
    info: vec4u,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: FilterParams;
@group(0) @binding(2) var gbuffer_depth_motion: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_normal_roughness: texture_2d<f32>;
// This frame's depth and normals, kept for the next frame's temporal step.
@group(0) @binding(4) var keep_depth_motion: texture_storage_2d<rgba32float, write>;
@group(0) @binding(5) var keep_normal_roughness: texture_storage_2d<rgba16float, write>;

@group(1) @binding(0) var in_rv: texture_2d<f32>;
@group(1) @binding(1) var in_r: texture_2d<f32>;
@group(1) @binding(2) var in_env_rv: texture_2d<f32>;
@group(1) @binding(3) var in_env_r: texture_2d<f32>;
@group(1) @binding(4) var in_env_weight: texture_2d<f32>;

@group(2) @binding(0) var out_rv: texture_storage_2d<rgba16float, write>;
@group(2) @binding(1) var out_r: texture_storage_2d<rgba16float, write>;
@group(2) @binding(2) var out_env_rv: texture_storage_2d<rgba16float, write>;
@group(2) @binding(3) var out_env_r: texture_storage_2d<rgba16float, write>;
@group(2) @binding(4) var out_env_weight: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id.xy >= frame.size.xy)) { return; }
    let pixel = vec2i(id.xy);
    let depth_motion = textureLoad(gbuffer_depth_motion, pixel, 0);
    let depth = depth_motion.x;
    let n = textureLoad(gbuffer_normal_roughness, pixel, 0);
    textureStore(keep_depth_motion, pixel, depth_motion);
    textureStore(keep_normal_roughness, pixel, n);
    if (depth == 0.0 || params.info.y == 0u) {
        textureStore(out_rv, pixel, textureLoad(in_rv, pixel, 0));
        textureStore(out_r, pixel, textureLoad(in_r, pixel, 0));
        textureStore(out_env_rv, pixel, textureLoad(in_env_rv, pixel, 0));
        textureStore(out_env_r, pixel, textureLoad(in_env_r, pixel, 0));
        textureStore(out_env_weight, pixel, textureLoad(in_env_weight, pixel, 0));
        return;
    }
    let size = i32(params.info.x);
    let lo = -size / 2;
    var rv = vec4f(0.0);
    var r = vec4f(0.0);
    var env_rv = vec4f(0.0);
    var env_r = vec4f(0.0);
    var env_weight = vec4f(0.0);
    var total = 0.0;
    for (var dy = lo; dy < lo + size; dy++) {
        for (var dx = lo; dx < lo + size; dx++) {
            let q = clamp(pixel + vec2i(dx, dy), vec2i(0), vec2i(frame.size.xy) - 1);
            let dq = textureLoad(gbuffer_depth_motion, q, 0).x;
            if (dq == 0.0) { continue; }
            let w = geometry_weight(depth, n.xyz, dq, textureLoad(gbuffer_normal_roughness, q, 0).xyz);
            if (w <= 0.0) { continue; }
            rv += w * textureLoad(in_rv, q, 0);
            r += w * textureLoad(in_r, q, 0);
            env_rv += w * textureLoad(in_env_rv, q, 0);
            env_r += w * textureLoad(in_env_r, q, 0);
            env_weight += w * textureLoad(in_env_weight, q, 0);
            total += w;
        }
    }
    let inv = 1.0 / max(total, 1e-8);
    textureStore(out_rv, pixel, rv * inv);
    textureStore(out_r, pixel, r * inv);
    textureStore(out_env_rv, pixel, env_rv * inv);
    textureStore(out_env_r, pixel, env_r * inv);
    textureStore(out_env_weight, pixel, env_weight * inv);
}
