// The composite encoded to 8-bit sRGB on the GPU, for a live stream: what
// `HdrImage::to_srgb8` computes on the CPU, by the same table (`SrgbEncoder`'s 255 linear
// thresholds, searched the same way, so the codes are identical), packed one pixel a word
// (r | g << 8 | b << 16), a quarter of the composite's bytes to read back. Non-finite
// pixels are counted: a stream never writes a silent black frame.

@group(0) @binding(0) var composite: texture_2d<f32>;
@group(0) @binding(1) var<storage, read> thresholds: array<f32, 255>;
@group(0) @binding(2) var<storage, read_write> codes: array<u32>;
@group(0) @binding(3) var<storage, read_write> non_finite: atomic<u32>;

// The number of thresholds ≤ v (`partition_point`): its 8-bit sRGB code. NaN compares false
// everywhere and gets 0, as on the CPU.
fn encode(v: f32) -> u32 {
    var lo = 0u;
    var hi = 255u;
    while lo < hi {
        let mid = (lo + hi) / 2u;
        if thresholds[mid] <= v {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return lo;
}

fn is_finite(v: f32) -> bool {
    // Infinity and NaN have all exponent bits set.
    return (bitcast<u32>(v) & 0x7f800000u) != 0x7f800000u;
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    let size = textureDimensions(composite);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let c = textureLoad(composite, vec2i(id.xy), 0).rgb;
    if !(is_finite(c.r) && is_finite(c.g) && is_finite(c.b)) {
        atomicAdd(&non_finite, 1u);
    }
    codes[id.y * size.x + id.x] = encode(c.r) | (encode(c.g) << 8u) | (encode(c.b) << 16u);
}
