// The cones are traced once per trace texel, a block of scale × scale pixels (the inner
// volume's `params.cone.y`, `dvct.trace_block`), from one covered pixel of the block, and
// resolved per pixel (resolve.wgsl). Declared by the including pass: frame, params,
// gbuffer_flags.

fn trace_scale() -> i32 { return i32(params.cone.y); }

fn trace_size() -> vec2i { return (vec2i(frame.size.xy) + trace_scale() - 1) / trace_scale(); }

// The pixel that trace texel `texel` was traced from: one of the block's middle pixels if it
// is covered (the one above and left of the block's centre on even texels, below and right on
// odd ones, so that the samples sit at the blocks' centres on average), else the first
// covered one of four at the centres of its quarters (in the order of its diagonal, then the
// other two), or (−1, −1) where none is. Always the top-left middle pixel (as the first
// quarter's centre was) put every block's sample half a pixel up and left of its centre: the
// floor beside a cube at 48 × 48 pixels was 0.06–0.08 more open on one side than traced per
// pixel (tests/dvct_cones.rs, ray casting).
fn representative(texel: vec2i) -> vec2i {
    let scale = trace_scale();
    if (scale == 1) {
        if (is_covered(textureLoad(gbuffer_flags, texel, 0).r)) { return texel; }
        return vec2i(-1);
    }
    let middle = texel * scale + scale / 2 - 1 + ((texel.x + texel.y) & 1);
    if (all(middle < vec2i(frame.size.xy)) && is_covered(textureLoad(gbuffer_flags, middle, 0).r)) {
        return middle;
    }
    let offsets = array<vec2i, 4>(vec2i(0, 0), vec2i(1, 1), vec2i(1, 0), vec2i(0, 1));
    for (var k = 0; k < 4; k++) {
        let pixel = texel * scale + offsets[k] * (scale / 2) + scale / 4;
        if (any(pixel >= vec2i(frame.size.xy))) { continue; }
        if (is_covered(textureLoad(gbuffer_flags, pixel, 0).r)) { return pixel; }
    }
    return vec2i(-1);
}
