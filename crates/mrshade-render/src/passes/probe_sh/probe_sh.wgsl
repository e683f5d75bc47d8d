// The probe's SH radiance coefficients c_i = Σ L(t)·y_i(ω_t)·dω_t over every texel of a
// coarse level of its box-filtered pyramid (Franke §2.1, Eq. 4.8, by summation), in the
// probe's own frame and unscaled (rotation and intensity apply at lookup). One workgroup:
// each invocation sums a stride of texels, then a tree reduction per coefficient. Run every
// frame, so a probe that changes on the GPU is followed.

@group(0) @binding(0) var pyramid: texture_2d<f32>;
@group(0) @binding(1) var<storage, read_write> coefficients: array<vec4f, 9>;
// level, width, height, unused
@group(0) @binding(2) var<uniform> source: vec4u;

const THREADS: u32 = 256u;

var<workgroup> partial: array<vec4f, THREADS>;

fn dir_from_equirect(uv: vec2f) -> vec3f {
    let phi = uv.x * 2.0 * PI;
    let theta = uv.y * PI;
    return vec3f(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

@compute @workgroup_size(256)
fn cs_main(@builtin(local_invocation_index) t: u32) {
    let w = source.y;
    let h = source.z;
    var c: array<vec3f, 9>;
    for (var i = t; i < w * h; i += THREADS) {
        let x = i % w;
        let y = i / w;
        let l = textureLoad(pyramid, vec2i(i32(x), i32(y)), i32(source.x)).rgb;
        let d_omega = 2.0 * PI / f32(w) * (cos(PI * f32(y) / f32(h)) - cos(PI * f32(y + 1u) / f32(h)));
        let b = sh9(dir_from_equirect((vec2f(f32(x), f32(y)) + 0.5) / vec2f(f32(w), f32(h))));
        for (var k = 0u; k < 9u; k++) {
            c[k] += l * (b[k] * d_omega);
        }
    }
    for (var k = 0u; k < 9u; k++) {
        partial[t] = vec4f(c[k], 0.0);
        workgroupBarrier();
        for (var stride = THREADS / 2u; stride > 0u; stride /= 2u) {
            if (t < stride) {
                partial[t] += partial[t + stride];
            }
            workgroupBarrier();
        }
        if (t == 0u) {
            coefficients[k] = partial[0];
        }
        workgroupBarrier();
    }
}
