// One level of the volumes' prefiltered chain (Franke §2.13.2 step 3). A plain mean (the
// thesis's hardware mipmaps) makes a wall one voxel thick half as opaque at every level, so
// that a wide cone sees through it and gathers a fraction of its light (the cornell blocks lit
// by a quarter of the walls' bounce). Here each parent voxel composites its children front to
// back along each axis, averages the four columns, and keeps the axis along which it is most
// opaque: a surface crossing the parent stays opaque at every level, an empty parent stays
// empty, and radiance keeps its ratio to opacity (premultiplied).

@group(0) @binding(0) var finer_rv: texture_3d<f32>;
@group(0) @binding(1) var finer_r: texture_3d<f32>;
@group(0) @binding(2) var out_rv: texture_storage_3d<rgba16float, write>;
@group(0) @binding(3) var out_r: texture_storage_3d<rgba16float, write>;

// Front-to-back "over" of premultiplied samples.
fn over(front: vec4f, back: vec4f) -> vec4f { return front + (1.0 - front.a) * back; }

fn parent(children: array<vec4f, 8>) -> vec4f {
    var best = vec4f(0.0);
    // Child k sits at (k & 1, (k >> 1) & 1, k >> 2); along axis a, pairs differ in bit a.
    for (var axis = 0u; axis < 3u; axis++) {
        let bit = 1u << axis;
        var sum = vec4f(0.0);
        for (var k = 0u; k < 8u; k++) {
            if ((k & bit) != 0u) { continue; }
            // Both viewing directions along the axis, averaged.
            sum += 0.5 * (over(children[k], children[k | bit]) + over(children[k | bit], children[k]));
        }
        let column = sum * 0.25;
        best += column / 3.0;
    }
    return best;
}

@compute @workgroup_size(4, 4, 4)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id >= textureDimensions(out_rv))) { return; }
    var rv: array<vec4f, 8>;
    var r: array<vec4f, 8>;
    for (var k = 0u; k < 8u; k++) {
        let child = id * 2u + vec3u(k & 1u, (k >> 1u) & 1u, k >> 2u);
        rv[k] = textureLoad(finer_rv, child, 0);
        r[k] = textureLoad(finer_r, child, 0);
    }
    textureStore(out_rv, id, parent(rv));
    textureStore(out_r, id, parent(r));
}
