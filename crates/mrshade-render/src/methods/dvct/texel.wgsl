// The cones are traced once per trace texel, a block of scale × scale pixels (the inner
// volume's `params.cone.y`, `dvct.trace_block`), from one covered pixel of the block, and
// resolved per pixel (resolve.wgsl). Declared by the including pass: frame, params,
// gbuffer_flags.

fn trace_scale() -> i32 { return i32(params.cone.y); }

fn trace_size() -> vec2i { return (vec2i(frame.size.xy) + trace_scale() - 1) / trace_scale(); }

// The pixel that trace texel `texel` was traced from: the first covered one of four in its
// block, at the centres of its quarters (in the order of its diagonal, then the other two;
// a 2 × 2 block's four pixels), or (−1, −1) where none is.
fn representative(texel: vec2i) -> vec2i {
    let offsets = array<vec2i, 4>(vec2i(0, 0), vec2i(1, 1), vec2i(1, 0), vec2i(0, 1));
    let n = select(4, 1, trace_scale() == 1);
    let quarter = max(trace_scale() / 2, 1);
    for (var k = 0; k < n; k++) {
        let pixel = texel * trace_scale() + offsets[k] * quarter + trace_scale() / 4;
        if (any(pixel >= vec2i(frame.size.xy))) { continue; }
        if (is_covered(textureLoad(gbuffer_flags, pixel, 0).r)) { return pixel; }
    }
    return vec2i(-1);
}
