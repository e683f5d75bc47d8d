// Low-discrepancy numbers and direction sampling.

// Radical inverse in base 2 (the first Halton dimension).
fn halton2(i: u32) -> f32 {
    return f32(reverseBits(i)) * 2.3283064365386963e-10;
}

// Radical inverse of `i` in a small prime `base` (Halton dimensions 2, 3, …).
fn halton(base: u32, index: u32) -> f32 {
    var i = index;
    var f = 1.0;
    var r = 0.0;
    let inv = 1.0 / f32(base);
    loop {
        if (i == 0u) { break; }
        f *= inv;
        r += f * f32(i % base);
        i /= base;
    }
    return min(r, 0.99999994);
}

fn hash_u32(x: u32) -> u32 {
    var h = x * 747796405u + 2891336453u;
    h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    return (h >> 22u) ^ h;
}

// Two uniform numbers in [0, 1) from the hashes of `seed` and `seed + 1`.
fn hash_uniform2(seed: u32) -> vec2f {
    return vec2f(f32(hash_u32(seed)), f32(hash_u32(seed + 1u))) * 2.3283064365386963e-10;
}

// An orthonormal frame (t, b) around unit `n` (Duff et al. 2017).
fn tangent_frame(n: vec3f) -> mat2x3f {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return mat2x3f(vec3f(1.0 + s * n.x * n.x * a, s * b, -s * n.x), vec3f(b, s + n.y * n.y * a, -n.y));
}

// Cosine-weighted direction around +Z; pdf = cos θ / π.
fn cosine_hemisphere(u: vec2f) -> vec3f {
    let r = sqrt(u.x);
    let phi = 2.0 * PI * u.y;
    return vec3f(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u.x)));
}

// Phong-lobe direction around +Z with exponent `k`: cos θ = u^(1/(k+1)); pdf = (k+1)/(2π) cos^k θ.
fn phong_lobe(u: vec2f, k: f32) -> vec3f {
    let c = pow(u.x, 1.0 / (k + 1.0));
    let s = sqrt(max(0.0, 1.0 - c * c));
    let phi = 2.0 * PI * u.y;
    return vec3f(s * cos(phi), s * sin(phi), c);
}

fn to_world(local: vec3f, n: vec3f) -> vec3f {
    let tb = tangent_frame(n);
    return tb[0] * local.x + tb[1] * local.y + n * local.z;
}
