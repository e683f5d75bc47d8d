// The probe's SH radiance coefficients c_i = Σ L(t)·y_i(ω_t)·dω_t over every texel of a
// coarse level of its box-filtered pyramid (Franke §2.1, Eq. 4.8, by summation), 9 or 16
// (bands 0–3, for 16-coefficient PRT) per frame, unscaled
// (intensity applies at lookup). Workgroup 0 projects in the probe's own frame (rotation
// applies at lookup); workgroup k > 0 in the object frame of the k-th instance with baked
// transfer (PRT, spec §2.4: "SH light vector with rotation into object space"). Each
// invocation sums a stride of texels, then a tree reduction per coefficient. Run every
// frame, so a probe that changes on the GPU and objects that turn are followed.

@group(0) @binding(0) var pyramid: texture_2d<f32>;
// COEFFICIENTS per workgroup.
@group(0) @binding(1) var<storage, read_write> coefficients: array<vec4f>;
// level, width, height, unused
@group(0) @binding(2) var<uniform> source: vec4u;
@group(0) @binding(3) var<uniform> frame: Frame;
@group(0) @binding(4) var<storage, read> instances: array<Instance>;
// The instance of workgroup k + 1.
@group(0) @binding(5) var<storage, read> prt_instances: array<u32>;

const THREADS: u32 = 256u;
// 9 or 16, set when the pipeline is made (a constant to the driver: the loops over it unroll
// into registers; a uniform bound cost the 9-coefficient projection half again).
override COEFFICIENTS: u32 = 9u;

var<workgroup> partial: array<vec4f, THREADS>;

fn dir_from_equirect(uv: vec2f) -> vec3f {
    let phi = uv.x * 2.0 * PI;
    let theta = uv.y * PI;
    return vec3f(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
}

// Object-frame direction of a probe-frame one for workgroup `k` (identity for k = 0).
fn frame_dir(k: u32, d: vec3f) -> vec3f {
    if (k == 0u) { return d; }
    let world = transpose(mat3x3f(frame.probe_from_world[0].xyz, frame.probe_from_world[1].xyz, frame.probe_from_world[2].xyz)) * d;
    let n = instances[prt_instances[k - 1u]].normal_from_object;
    // normal_from_object is the inverse transpose: its transpose takes world directions to
    // object space.
    return normalize(transpose(mat3x3f(n[0].xyz, n[1].xyz, n[2].xyz)) * world);
}

// The sum of `value` over the workgroup's invocations (tree reduction), in invocation 0.
fn workgroup_sum(t: u32, value: vec3f) -> vec4f {
    partial[t] = vec4f(value, 0.0);
    workgroupBarrier();
    for (var stride = THREADS / 2u; stride > 0u; stride /= 2u) {
        if (t < stride) {
            partial[t] += partial[t + stride];
        }
        workgroupBarrier();
    }
    let sum = partial[0];
    workgroupBarrier();
    return sum;
}

@compute @workgroup_size(256)
fn cs_main(@builtin(local_invocation_index) t: u32, @builtin(workgroup_id) group: vec3u) {
    let w = source.y;
    let h = source.z;

    // Bands 0–2 and band 3 apart: nine accumulators, as many registers, when band 3 is off.
    var c: array<vec3f, 9>;
    var c3: array<vec3f, 7>;
    for (var i = t; i < w * h; i += THREADS) {
        let x = i % w;
        let y = i / w;
        let l = textureLoad(pyramid, vec2i(i32(x), i32(y)), i32(source.x)).rgb;
        let d_omega = 2.0 * PI / f32(w) * (cos(PI * f32(y) / f32(h)) - cos(PI * f32(y + 1u) / f32(h)));
        let d = frame_dir(group.x, dir_from_equirect((vec2f(f32(x), f32(y)) + 0.5) / vec2f(f32(w), f32(h))));
        let b = sh9(d);
        for (var k = 0u; k < 9u; k++) {
            c[k] += l * (b[k] * d_omega);
        }
        if (COEFFICIENTS == 16u) {
            let b16 = sh16(d);
            for (var k = 0u; k < 7u; k++) {
                c3[k] += l * (b16[9u + k] * d_omega);
            }
        }
    }
    let first = group.x * COEFFICIENTS;
    for (var k = 0u; k < 9u; k++) {
        let sum = workgroup_sum(t, c[k]);
        if (t == 0u) { coefficients[first + k] = sum; }
    }
    if (COEFFICIENTS == 16u) {
        for (var k = 0u; k < 7u; k++) {
            let sum = workgroup_sum(t, c3[k]);
            if (t == 0u) { coefficients[first + 9u + k] = sum; }
        }
    }
}
