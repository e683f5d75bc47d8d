// The highest surface of each map near each of its texels (ProbeMaps::near): the maximum of
// rsm_height over the square of ±`size.z` texels around it, as a row pass and then a column
// pass. The soft shadow test (shaders/lib/probe_maps_soft.wgsl) reads it first: where nothing
// near a point stands above it, there is no blocker to search for, one read instead of
// thirteen (most of a frame's pixels).

@group(0) @binding(0) var<storage, read> source: array<f32>;
@group(0) @binding(1) var<storage, read_write> highest_near: array<f32>;
// Map side, layers, the square's half side (texels), 0 along rows / 1 along columns.
@group(0) @binding(2) var<uniform> size: vec4u;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    let res = size.x;
    if (any(id.xy >= vec2u(res)) || id.z >= size.y) { return; }
    let reach = i32(size.z);
    let along = select(vec2i(1, 0), vec2i(0, 1), size.w == 1u);
    // What a texel that sees nothing holds, where nothing is near.
    var highest = NO_RSM_HEIGHT;
    for (var k = -reach; k <= reach; k++) {
        let c = vec2i(id.xy) + k * along;
        if (any(c < vec2i(0)) || any(c >= vec2i(i32(res)))) { continue; }
        highest = max(highest, source[(id.z * res + u32(c.y)) * res + u32(c.x)]);
    }
    highest_near[(id.z * res + id.y) * res + id.x] = highest;
}
