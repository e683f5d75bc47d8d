// A still view's thin rays for the virtual trace texels (`dvct.still_rays`, pixels.rs
// StillRays): each frame while nothing changes, a virtual texel gathers with a few thin rays
// (cones.wgsl gather_rays_shifted), their spiral shifted anew each frame, and keeps the
// running mean over the still's frames, so that a still gathers the rays of
// `dvct.virtual_rays` at a few rays' cost per frame. Declared after cones.wgsl; group 2's
// bindings 8 and 9 are the trace's own (gather.wgsl cs_main).

// Per trace texel, five vec4s: (rv, env.x), (r, env.y), (env_rv, env.z), (env_r, 0) as f32
// bits, and (the G-buffer flags of the surface it gathered for, frames in the mean, 0, 0).
// Words, not f32s: a small integer's bits are a denormal f32, which a GPU may flush to 0.
@group(2) @binding(8) var<storage, read_write> still_history: array<vec4u>;
// x: rays per frame (0: a moving view's frame, or off), y: the frame's number in the still
// (1 for its first).
@group(2) @binding(9) var<uniform> still_rays: vec4u;

const STILL_HISTORY_VEC4S: u32 = 5u;

fn still_rays_active() -> bool { return still_rays.x > 0u; }

// The spiral's shift at trace texel `texel` in still frame `n`: the plastic-number sequence
// (R2, low discrepancy in two dimensions) over the frames, so that a texel's rays fill the
// hemisphere evenly, rotated by a hash of the texel (Cranley–Patterson) so that neighbouring
// texels sample other directions in the same frame: with one shift for all, the rays of every
// texel of a ball's rim met the lit floor below it alike, frame after frame, and the mean
// over 32 frames still missed a fifth of its light (tests/dvct_cones.rs).
fn still_shift(texel: vec2i, n: u32) -> vec2f {
    let scramble = hash_uniform2(u32(texel.x) * 0x9e3779b9u ^ u32(texel.y));
    return fract(scramble + f32(n) * vec2f(0.7548776662, 0.5698402910));
}

// The running mean of what the rays of the still's frames gathered at trace texel `texel`
// (surface `s` of G-buffer `flags`), this frame's included. A texel whose surface changed
// (another object or realness under a jittered frame's sample) starts its mean again.
fn still_gather(texel: vec2i, flags: u32, s: Surface, turn: f32) -> Gathered {
    let e = gather_rays_shifted(s.position, s.normal, turn, still_rays.x, still_shift(texel, still_rays.y));
    let base = (u32(texel.y) * u32(trace_size().x) + u32(texel.x)) * STILL_HISTORY_VEC4S;
    let tag = still_history[base + 4u];
    var frames = 0u;
    if (still_rays.y > 1u && tag.x == flags) { frames = tag.y; }
    let w = 1.0 / f32(frames + 1u);
    let h0 = still_mean(base, vec4f(e.rv, e.env.x), w);
    let h1 = still_mean(base + 1u, vec4f(e.r, e.env.y), w);
    let h2 = still_mean(base + 2u, vec4f(e.env_rv, e.env.z), w);
    let h3 = still_mean(base + 3u, vec4f(e.env_r, 0.0), w);
    still_history[base + 4u] = vec4u(flags, frames + 1u, 0u, 0u);
    return Gathered(h0.xyz, h1.xyz, h2.xyz, h3.xyz, vec3f(h0.w, h1.w, h2.w));
}

// The mean in word `i` of the history moved towards `value` by `w` (1: `value` alone, whatever
// the words held), stored and returned.
fn still_mean(i: u32, value: vec4f, w: f32) -> vec4f {
    let mean = select(mix(bitcast<vec4f>(still_history[i]), value, w), value, w >= 1.0);
    still_history[i] = bitcast<vec4u>(mean);
    return mean;
}
