// Importance pyramids of the RSM layers for hierarchical sample warping (Clarberg et al.
// 2005): level 0 holds each texel's (importance, coverage), every further level the sums of
// 2×2 texels, down to 1×1. `cs_base` fills level 0; `cs_reduce` one further level.

struct PyramidParams {
    // RSM resolution, layer count, level to write, floats per layer (all levels)
    size: vec4u,
}

@group(0) @binding(0) var<uniform> params: PyramidParams;
@group(0) @binding(1) var<storage, read> rsm: array<RsmTexel>;
@group(0) @binding(2) var<storage, read_write> pyramid: array<vec2f>;

fn level_offset(level: u32) -> u32 {
    var offset = 0u;
    var side = params.size.x;
    for (var l = 0u; l < level; l++) {
        offset += side * side;
        side = side / 2u;
    }
    return offset;
}

@compute @workgroup_size(8, 8)
fn cs_base(@builtin(global_invocation_id) id: vec3u) {
    let res = params.size.x;
    if (id.x >= res || id.y >= res || id.z >= params.size.y) { return; }
    let t = rsm[(id.z * res + id.y) * res + id.x];
    pyramid[id.z * params.size.w + id.y * res + id.x] = vec2f(t.power.w, t.position.w);
}

@compute @workgroup_size(8, 8)
fn cs_reduce(@builtin(global_invocation_id) id: vec3u) {
    let level = params.size.z;
    let side = params.size.x >> level;
    if (id.x >= side || id.y >= side || id.z >= params.size.y) { return; }
    let base = id.z * params.size.w;
    let below = base + level_offset(level - 1u);
    let below_side = side * 2u;
    let x = id.x * 2u;
    let y = id.y * 2u;
    let sum = pyramid[below + y * below_side + x] + pyramid[below + y * below_side + x + 1u]
        + pyramid[below + (y + 1u) * below_side + x] + pyramid[below + (y + 1u) * below_side + x + 1u];
    pyramid[base + level_offset(level) + id.y * side + id.x] = sum;
}
