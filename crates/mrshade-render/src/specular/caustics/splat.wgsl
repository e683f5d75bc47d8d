// Caustic buffer by quad splatting (reflections spec §2.17.2): every photon that landed is a
// quad on its receiver's plane, of the half-size emit.wgsl's cs_size found (normal.w). Its power is spread
// by a tent kernel that integrates to one over the quad; neighbours one quad half-size apart
// sum to a partition of unity, so the buffer holds irradiance, W/m², and a caustic keeps its
// energy. The photons of L_rv sum in one half, those of L_r in the other (rgb: irradiance;
// a: photon count, for the thesis's k_c). A texel counts only where the camera's surface
// lies on the quad (§2.17.4's depth test, as a fraction of the camera distance) and faces
// the same way.
// Two levels (Wyman's hierarchical caustic maps, in two levels): photons at most `splat_max`
// apart go to the fine buffer, those farther apart (a convex mirror's diverging reflection)
// to a coarse one of 1/COARSE_LEVEL_FACTOR its resolution per axis, where a quad of their own
// size covers few texels.
//
// A compute pass, not the rasteriser (the rays' side job runs it after the photons' sizes):
// a workgroup takes a photon of its level's list at a time, its invocations stride over the
// texels of the quad's box (a texel counts where its centre's ray meets the quad, as the
// rasteriser's coverage), and add to the texels in 64-bit fixed point (FIXED_ONE units):
// sums that do not depend on the order the photons come in, so that both worlds' sums of
// the same photons are the same to the bit. cs_finish turns them into the two levels'
// rgba16f textures and empties them. (Two 32-bit words with the carry by hand waited for
// every atomic's old value: 0.21 ms at 1080p on an H100, as the rasterised splat.)

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> caustics: CausticParams;
@group(0) @binding(2) var<storage, read> photons: array<Photon>;
@group(0) @binding(3) var gbuffer_depth_motion: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal_roughness: texture_2d<f32>;
// cs_size's lists of the landed photons per level, and their lengths (SplatDraw: six
// vertices per photon, as the draws of a rasterised splat count them).
@group(0) @binding(5) var<storage, read> splat_list: array<u32>;
@group(0) @binding(6) var<storage, read> splat_draws: array<vec4u, 2>;
@group(0) @binding(7) var<storage, read_write> sums: array<atomic<u64>>;

// Fixed-point units per unit of irradiance (2^20): at most 1.7·10^13 W/m² a texel, steps of
// 10^-6.
const FIXED_ONE: f32 = 1048576.0;
// The largest irradiance one photon adds to a texel (keeps its fixed point below 2^64).
const FIXED_MAX: f32 = 1e12;
// Sums per texel and differential half: rgba.
const SUM_WORDS: u32 = 4u;

// Texels of caustic level `level` along each axis.
fn level_size(level: u32) -> vec2u {
    let divisor = caustics.info.w * select(1u, COARSE_LEVEL_FACTOR, level == 1u);
    return (frame.size.xy + divisor - 1u) / divisor;
}

// The sum of channel `channel` of `level`'s half `half` (0 L_rv, 1 L_r) at `texel`: one
// plane per level, half and channel (the fine level's eight, then the coarse level's), so
// that neighbouring texels' sums are neighbours (a warp's atomics over a row of a quad's
// texels touch one or two cache lines, not eight).
fn sum_word(level: u32, half: u32, channel: u32, texel: vec2u) -> u32 {
    let fine = level_size(0u);
    let size = level_size(level);
    let base = select(0u, 2u * SUM_WORDS * fine.x * fine.y, level == 1u);
    return base + ((half * SUM_WORDS + channel) * size.y + texel.y) * size.x + texel.x;
}

// Adds `value` (≥ 0) to the fixed-point sum `word`.
fn sum_add(word: u32, value: f32) {
    let v = u64(min(value, FIXED_MAX) * FIXED_ONE);
    if (v != 0lu) { atomicAdd(&sums[word], v); }
}

// Reads the sum `word` and empties it.
fn sum_take(word: u32) -> f32 {
    return f32(atomicExchange(&sums[word], 0lu)) / FIXED_ONE;
}

// Workgroups per level: each takes every SPLAT_GROUPS-th photon of its level's list (mirrors
// caustics::SPLAT_GROUPS). Its 64 invocations add to neighbouring texels of one quad, whose
// sums lie side by side; 8 or 32 invocations per photon, fewer idle on small quads, spread a
// warp's atomics over several quads and were slower (1080p, H100).
const SPLAT_GROUPS: u32 = 4096u;
const SPLAT_LANES: u32 = 64u;

@compute @workgroup_size(64)
fn cs_splat(@builtin(workgroup_id) group: vec3u, @builtin(local_invocation_index) lane: u32) {
    let level = group.y;
    let count = splat_draws[level].x / 6u;
    let size = level_size(level);
    let divisor = f32(caustics.info.w * select(1u, COARSE_LEVEL_FACTOR, level == 1u));
    let last_pixel = vec2i(frame.size.xy) - 1;
    let eye = frame.camera_position.xyz;
    for (var i = group.x; i < count; i += SPLAT_GROUPS) {
        let index = splat_list[level * photon_slots() + i];
        let photon = photons[index];
        let h = photon.normal.w;
        let n = photon.normal.xyz;
        let tb = tangent_frame(n);
        let centre = photon.position.xyz;
        // The quad's box in the level's texels (those whose centres it may cover); a quad
        // that reaches behind the camera is left out.
        var lo = vec2f(3.4e38);
        var hi = vec2f(-3.4e38);
        var behind = false;
        for (var corner = 0u; corner < 4u; corner++) {
            let local = vec2f(select(-1.0, 1.0, (corner & 1u) != 0u), select(-1.0, 1.0, (corner & 2u) != 0u));
            let at = pixel_from_world(frame, centre + (tb[0] * local.x + tb[1] * local.y) * h);
            behind = behind || at.z <= 0.0;
            lo = min(lo, at.xy / divisor);
            hi = max(hi, at.xy / divisor);
        }
        if (behind) { continue; }
        let first = vec2i(max(ceil(lo - 0.5), vec2f(0.0)));
        let past = vec2i(min(floor(hi - 0.5) + 1.0, vec2f(size)));
        if (any(past <= first)) { continue; }
        let width = u32(past.x - first.x);
        let texels = width * u32(past.y - first.y);
        let irradiance = photon.power.rgb / (h * h);
        let kind = (index / (caustics.info.x * caustics.info.x)) % PHOTON_KINDS;
        let half = select(0u, 1u, kind >= 2u);
        let to_centre = dot(centre - eye, n);
        for (var t = lane; t < texels; t += SPLAT_LANES) {
            let texel = vec2u(first) + vec2u(t % width, t / width);
            // This texel's centre on the full-size G-buffer: the camera's surface there, and
            // the point where the ray to it meets the quad's plane (at `along` of the way).
            let at = (vec2f(texel) + 0.5) * divisor;
            let pixel = min(vec2i(at), last_pixel);
            let depth = textureLoad(gbuffer_depth_motion, pixel, 0).x;
            if (depth == 0.0) { continue; }
            let ray = world_from_pixel(frame, at, depth) - eye;
            let along = to_centre / dot(ray, n);
            let offset = eye + ray * along - centre;
            let local = vec2f(dot(offset, tb[0]), dot(offset, tb[1])) / h;
            // (Written so that a ray along the plane, NaN, counts as a miss.)
            if (!all(abs(local) < vec2f(1.0))) { continue; }
            // The surface within depth_epsilon of the camera distance of the quad, facing the
            // same way.
            if (!(abs(1.0 - along) <= caustics.splat.w)) { continue; }
            if (dot(textureLoad(gbuffer_normal_roughness, pixel, 0).xyz, n) < 0.5) { continue; }
            let e = irradiance * quad_tent(local);
            sum_add(sum_word(level, half, 0u, texel), e.r);
            sum_add(sum_word(level, half, 1u, texel), e.g);
            sum_add(sum_word(level, half, 2u, texel), e.b);
            sum_add(sum_word(level, half, 3u, texel), 1.0);
        }
    }
}

@group(1) @binding(0) var fine_rv: texture_storage_2d<rgba16float, write>;
@group(1) @binding(1) var fine_r: texture_storage_2d<rgba16float, write>;
@group(1) @binding(2) var coarse_rv: texture_storage_2d<rgba16float, write>;
@group(1) @binding(3) var coarse_r: texture_storage_2d<rgba16float, write>;
// Where the lights' landed photons per level (their splat draws) stay for the next frame's
// caustic VPLs (dir, reflections spec §2.18), copied here rather than between passes.
@group(1) @binding(4) var<storage, read_write> landed: array<vec4u, 2>;

fn sum_texel(level: u32, half: u32, texel: vec2u) -> vec4f {
    return vec4f(
        sum_take(sum_word(level, half, 0u, texel)),
        sum_take(sum_word(level, half, 1u, texel)),
        sum_take(sum_word(level, half, 2u, texel)),
        sum_take(sum_word(level, half, 3u, texel)),
    );
}

// The sums into both levels' textures, emptied for the next frame. One thread per fine
// texel; the coarse level's texels are the first 1/COARSE_LEVEL_FACTOR² of them.
@compute @workgroup_size(8, 8)
fn cs_finish(@builtin(global_invocation_id) id: vec3u) {
    if (all(id.xy < vec2u(2u, 1u))) { landed[id.x] = splat_draws[id.x]; }
    if (all(id.xy < level_size(0u))) {
        textureStore(fine_rv, id.xy, sum_texel(0u, 0u, id.xy));
        textureStore(fine_r, id.xy, sum_texel(0u, 1u, id.xy));
    }
    if (all(id.xy < level_size(1u))) {
        textureStore(coarse_rv, id.xy, sum_texel(1u, 0u, id.xy));
        textureStore(coarse_r, id.xy, sum_texel(1u, 1u, id.xy));
    }
}
