// Cone tracing through the prefiltered volumes (Franke §2.13.2 step 4, Eq. 5.18–5.19 in the
// premultiplied front-to-back form of [Code]): both solutions along the same cone, the same
// samples, `rv` through the real+virtual volume and `r` through the real-only one.
// The including pass declares `params`, the volume it works in; group 1 is that volume's
// textures (VolumePair::sampled) and those of the coarser outer volume around it (`outer`,
// settings `dvct.outer_scale`) that cones go on through when they leave it (the same volume
// again where there is no outer one: a cone that left it meets nothing there).

@group(1) @binding(0) var volume_rv: texture_3d<f32>;
@group(1) @binding(1) var volume_r: texture_3d<f32>;
@group(1) @binding(2) var volume_sampler: sampler;
@group(1) @binding(3) var volume_rv_x: texture_3d<f32>;
@group(1) @binding(4) var volume_rv_y: texture_3d<f32>;
@group(1) @binding(5) var volume_rv_z: texture_3d<f32>;
@group(1) @binding(6) var volume_r_x: texture_3d<f32>;
@group(1) @binding(7) var volume_r_y: texture_3d<f32>;
@group(1) @binding(8) var volume_r_z: texture_3d<f32>;
@group(1) @binding(9) var<uniform> outer: VolumeParams;
@group(1) @binding(10) var outer_rv: texture_3d<f32>;
@group(1) @binding(11) var outer_r: texture_3d<f32>;
@group(1) @binding(12) var outer_rv_x: texture_3d<f32>;
@group(1) @binding(13) var outer_rv_y: texture_3d<f32>;
@group(1) @binding(14) var outer_rv_z: texture_3d<f32>;
@group(1) @binding(15) var outer_r_x: texture_3d<f32>;
@group(1) @binding(16) var outer_r_y: texture_3d<f32>;
@group(1) @binding(17) var outer_r_z: texture_3d<f32>;

struct Cone {
    // Premultiplied radiance seen along the cone, and its opacity, of each solution.
    rv: vec4f,
    r: vec4f,
    // The most opaque single sample of each solution (rv, r).
    peak: vec2f,
    // rv − r of the radiance seen along the cone if all its samples covered the same part of
    // it, each adding only the opacity it has beyond the most opaque sample before it (`peak`):
    // the correlated bound of the change, whose independent one is `rv.rgb − r.rgb` (cone_seen).
    correlated_change: vec3f,
}

// Enter and exit distances of the ray `o + t·d` through the volume `v` (exit < enter: missed).
fn volume_span(v: VolumeParams, o: vec3f, d: vec3f) -> vec2f {
    let inv = 1.0 / select(d, vec3f(1e-12), abs(d) < vec3f(1e-12));
    let lo = (v.origin.xyz - o) * inv;
    let hi = (v.origin.xyz + v.origin.w * f32(v.info.x) - o) * inv;
    let near = min(lo, hi);
    let far = max(lo, hi);
    return vec2f(max(max(near.x, near.y), near.z), min(min(far.x, far.y), far.z));
}

// A sample of one solution at level `lod` seen along unit `d`: the voxels themselves at level
// 0, above it per axis the chain (mips.wgsl) of the way `d` travels along it (its half of the
// texture along x, Volume::chains), with weights w = |d| / Σ|d|, an axis whose weight is
// negligible not read. fetch_volume issues the reads (VolumeFetch), volume_sample combines
// them. Opacity is the product of the axes' transmittances raised to their weights,
// 1 − Π (1 − α_a)^w_a: a wall that the cone crosses obliquely (opaque along its
// normal, thin edge-on) stops it, where a weighted mean of the opacities let half the probe
// through it at 45°; a blob equally opaque along all axes keeps its opacity. Radiance is the
// weighted mean colour at that opacity (premultiplied).
fn fetch_volume(
    base: texture_3d<f32>,
    x: texture_3d<f32>,
    y: texture_3d<f32>,
    z: texture_3d<f32>,
    uvw: vec3f,
    lod: f32,
    d: vec3f,
) -> VolumeFetch {
    let w = abs(d) / (abs(d.x) + abs(d.y) + abs(d.z));
    let level = max(lod - 1.0, 0.0);
    // Kept half a texel of the coarser level it blends inside its half of the texture, so that
    // the filter does not reach into the other way's (the volume's border is clamped there,
    // as the sampler clamps it on the other axes).
    let coarser = f32(max(textureDimensions(y).y >> u32(ceil(level)), 1u));
    let u = clamp(uvw.x, 0.5 / coarser, 1.0 - 0.5 / coarser);
    let way = 0.5 * (u + select(vec3f(0.0), vec3f(1.0), d < vec3f(0.0)));
    let read = (w >= vec3f(AXIS_WEIGHT_READ)) & vec3<bool>(lod > 0.0);
    var out = VolumeFetch(vec4f(0.0), vec4f(0.0), vec4f(0.0), vec4f(0.0), w, lod);
    if (lod < 1.0) { out.base = textureSampleLevel(base, volume_sampler, uvw, 0.0); }
    if (read.x) { out.x = textureSampleLevel(x, volume_sampler, vec3f(way.x, uvw.yz), level); }
    if (read.y) { out.y = textureSampleLevel(y, volume_sampler, vec3f(way.y, uvw.yz), level); }
    if (read.z) { out.z = textureSampleLevel(z, volume_sampler, vec3f(way.z, uvw.yz), level); }
    return out;
}

// An axis whose weight is below this is not read.
const AXIS_WEIGHT_READ: f32 = 0.03;

// The reads of one fetch_volume, all issued before any is used (a step's reads, up to four
// a solution, then wait on one latency, not four in turn), and what combines them.
struct VolumeFetch {
    base: vec4f,
    x: vec4f,
    y: vec4f,
    z: vec4f,
    w: vec3f,
    lod: f32,
}

struct AxisSum {
    weighted: vec4f,
    log_transmit: f32,
}

fn add_axis(sum: ptr<function, AxisSum>, w: f32, s: vec4f) {
    if (w < AXIS_WEIGHT_READ) { return; }
    (*sum).weighted += vec4f(w * s.rgb, w * s.a);
    (*sum).log_transmit += w * log2(max(1.0 - s.a, 1e-6));
}

// The sample of fetch_volume's reads.
fn volume_sample(f: VolumeFetch) -> vec4f {
    if (f.lod <= 0.0) { return f.base; }
    // (Σ w·colour, Σ w·opacity), Σ w·log₂ transmittance over the axes read, x, y, z in turn.
    var sum = AxisSum(vec4f(0.0), 0.0);
    add_axis(&sum, f.w.x, f.x);
    add_axis(&sum, f.w.y, f.y);
    add_axis(&sum, f.w.z, f.z);
    let alpha = 1.0 - exp2(sum.log_transmit);
    let opacity = sum.weighted.a;
    let coarse = vec4f(select(vec3f(0.0), sum.weighted.rgb / opacity * alpha, opacity > 1e-6), alpha);
    if (f.lod >= 1.0) { return coarse; }
    return mix(f.base, coarse, f.lod);
}

// Side of the voxels a cone's samples read, per cone diameter. A sample blurs its level's
// voxels (a box of side V) by the trilinear tent (±V): σ ≈ V/2, where the cone's own disc of
// diameter D has σ ≈ D/4. Reading voxels of half the diameter matches the two; voxels as wide
// as the cone made every cone act twice as wide, an object beside a surface shadowing it far
// beyond its silhouette.
const SAMPLE_PER_DIAMETER: f32 = 0.5;

// Distance between a cone's samples per cone diameter (at least SAMPLE_PER_DIAMETER): settings
// `dvct.sample_spacing` for the pixels' cones, `dvct.bounce_spacing` for the second bounce's.
fn pixel_spacing() -> f32 { return params.cone.z; }
fn bounce_spacing() -> f32 { return params.cone.w; }

// A sample that stands for `k` samples' length of the cone: its opacity compounds over them
// (1 − (1 − α)^k, as k samples of the same voxels would), its colour keeps its share of it.
fn stretch(s: vec4f, k: f32) -> vec4f {
    let alpha = 1.0 - pow(max(1.0 - s.a, 0.0), k);
    return vec4f(select(s.rgb * k, s.rgb * (alpha / s.a), s.a > 1e-6), alpha);
}

// Marches from `o` along unit `d` with steps of `spacing` × the cone's width (`aperture`: its
// diameter per unit length), sampling the mip level whose voxels are SAMPLE_PER_DIAMETER × it,
// from `start` until both solutions are opaque or the cone leaves the volume (and then the
// outer one, for a cone that starts inside the volume), its samples kept clear of the
// plane of normal `n` through the surface it leaves. Outside the volumes there is nothing:
// what a cone does not hit there is the probe's (its opacity says how much). A cone from
// outside the volume sees only the volume where the virtual objects alone make the change
// (the two solutions differ nowhere else), the pixels that the outer volume alone holds
// costing no more than without it. A virtual light changes every real surface it lights, in
// the volume or not: with one in the scene (VOLUME_VIRTUAL_LIGHTS) such a cone goes through
// the outer volume up to this one, across it, and on through the outer one — the real desk
// around desk-spot-virtual's sphere took none of the light its virtual lamp sends off the
// real box and book beyond the sphere's volume.
fn trace_cone(o: vec3f, d: vec3f, aperture: f32, spacing: f32, start: f32, n: vec3f) -> Cone {
    // Zero-initialised: nothing seen yet.
    var out: Cone;
    let lift = CONE_START_VOXELS * voxel_side();
    let lo = params.origin.xyz;
    let inside = all(o >= lo) && all(o <= lo + volume_side());
    let lit_beyond = (params.info.w & VOLUME_VIRTUAL_LIGHTS) != 0u;
    if (!inside && lit_beyond) {
        let span = volume_span(params, o, d);
        let meets = span.x < span.y && span.y > start;
        march(&out, outer, false, o, d, aperture, spacing, start, select(NO_STOP, span.x, meets), n, lift);
        if (!meets) { return out; }
    }
    let exit = march(&out, params, true, o, d, aperture, spacing, start, NO_STOP, n, lift);
    if (inside || lit_beyond) {
        march(&out, outer, false, o, d, aperture, spacing, max(start, exit), NO_STOP, n, lift);
    }
    return out;
}

// No end to a march but its volume's own.
const NO_STOP: f32 = 3.0e38;

// The part of trace_cone in volume `v` (`inner`: the pass's own volume, else the outer one),
// from `start` to where it leaves `v` or reaches `stop`; returns where it leaves `v`. `lift`:
// the height above the plane of `n` that the cone starts at.
fn march(
    out: ptr<function, Cone>,
    v: VolumeParams,
    inner: bool,
    o: vec3f,
    d: vec3f,
    aperture: f32,
    spacing: f32,
    start: f32,
    stop: f32,
    n: vec3f,
    lift: f32,
) -> f32 {
    let whole = volume_span(v, o, d);
    let span = vec2f(whole.x, min(whole.y, stop));
    let voxel = v.origin.w;
    let max_lod = f32(v.info.y - 1u);
    let extent = 1.0 / (voxel * f32(v.info.x));
    var t = max(start, span.x);
    for (var i = 0u; i < 256u; i++) {
        if (t >= span.y || ((*out).rv.a >= 0.99 && (*out).r.a >= 0.99)) { break; }
        let diameter = max(voxel, aperture * t);
        let side = max(voxel, SAMPLE_PER_DIAMETER * diameter);
        let step = max(side, spacing * diameter);
        let lod = min(log2(side / voxel), max_lod);
        // A sample of the cone, lifted off the plane of the surface it starts from (normal
        // `n`) until its trilinear footprint no longer reaches that plane's voxels: the
        // coarser of the two levels it blends has voxels of side D ≥ the sample's side, its
        // filter reaches one D either side of the sample, and the voxel that holds the plane
        // has its centre within D/2 of it, so the sample's centre goes at least 1.5·D above
        // the plane. A wide cone leaving at 55° from the normal otherwise
        // filters its own surface's voxels in at coarse levels (spec §2.13.9: cones
        // "self-intersect at grazing angles"), the surface shadowing and lighting itself: the
        // desk under desk-spot-virtual's lamp lit itself 2–3 % too bright around the sphere.
        let centre = o + d * t;
        let height = dot(d, n) * t + lift;
        let coarser = voxel * exp2(ceil(lod));
        let uvw = (centre + n * max(1.5 * coarser - height, 0.0) - v.origin.xyz) * extent;
        // Lifted out of the volume: nothing there (the sampler's clamp would repeat the
        // border's voxels, at the coarsest level the whole volume's mean: the floor lit
        // itself through it).
        if (any(uvw < vec3f(0.0)) || any(uvw > vec3f(1.0))) {
            t += step;
            continue;
        }
        var f_rv: VolumeFetch;
        var f_r: VolumeFetch;
        if (inner) {
            f_rv = fetch_volume(volume_rv, volume_rv_x, volume_rv_y, volume_rv_z, uvw, lod, d);
            f_r = fetch_volume(volume_r, volume_r_x, volume_r_y, volume_r_z, uvw, lod, d);
        } else {
            f_rv = fetch_volume(outer_rv, outer_rv_x, outer_rv_y, outer_rv_z, uvw, lod, d);
            f_r = fetch_volume(outer_r, outer_r_x, outer_r_y, outer_r_z, uvw, lod, d);
        }
        var s_rv = volume_sample(f_rv);
        var s_r = volume_sample(f_r);
        // The most opaque single sample is one sample's (probe_occlusion), however long the
        // step; so is what a sample adds beyond it.
        (*out).correlated_change += beyond(s_rv, (*out).peak.x) - beyond(s_r, (*out).peak.y);
        (*out).peak = max((*out).peak, vec2f(s_rv.a, s_r.a));
        if (step > side) {
            s_rv = stretch(s_rv, step / side);
            s_r = stretch(s_r, step / side);
        }
        (*out).rv += (1.0 - (*out).rv.a) * s_rv;
        (*out).r += (1.0 - (*out).r.a) * s_r;
        t += step;
    }
    return whole.y;
}

// The light of sample `s` (premultiplied) on the part of the cone it covers beyond `peak`, the
// most that an earlier sample covered.
fn beyond(s: vec4f, peak: f32) -> vec3f {
    return select(vec3f(0.0), s.rgb * max(1.0 - peak / s.a, 0.0), s.a > 1e-6);
}

// How much of the probe a cone's solutions hide (rv, r). Front to back, the samples' opacities
// multiply as if each hid an independent part of the cone; but one solid object beside the
// surface fills the same part of the cone sample after sample (the cone grows, the object
// stays), and its opacity compounds: half a cone covered by a block read as 7/8 hidden after
// three samples, so a virtual object darkened the real floor around it far beyond its
// silhouette (cornell's floor in front of the tall block kept 35 % of the real-only probe
// light where cosine-weighted ray casting keeps 68 %). Fully correlated samples hide only the most opaque
// one's share; the union of the parts the samples hide lies between, and the mean of the two
// bounds stands for it.
fn probe_occlusion(hit: Cone) -> vec2f {
    return min(0.5 * (vec2f(hit.rv.a, hit.r.a) + hit.peak), vec2f(1.0));
}

// What a diffuse cone gives each solution: its bounce light and how much of the probe it
// hides. The real-only solution composites its samples as independent layers: the real
// scene's surfaces (walls, the floor) cross a cone at different depths and cover different
// parts of it. The virtual content's change to that is mostly one object beside the surface,
// which covers the same part of the cone sample after sample while the cone grows past it:
// compounded as independent layers, a white ball's bounce onto the floor beside it was 1.9–2.9
// times the path tracer's. The change lies between the independent bound and the correlated
// one (each sample adds only what it covers beyond the most opaque before it:
// correlated_change, `peak`); like the probe's occlusion (probe_occlusion, whose change is
// that mean already), its light is now the mean of the two: the ball's bounce 0.9–1.4 times
// the answer's, a virtual wall's beside it 0.8–0.96 (1.0–1.1 before; a wide face is nearer
// the independent bound). Every change takes it, also where only the light differs (a real
// surface in a virtual object's shadow, a virtual lamp's light on the desk): with the mean
// applied only where the samples' opacities differ, cornell's gain was lost (0.1555). Region
// FLIP (lavapipe, 640×480): cornell 0.1425 → 0.1307, two Cornell variants 0.1384 → 0.1302
// and 0.1263 → 0.1201, desk-bunny 0.0729 → 0.0787, desk-spot-virtual 0.0962 →
// 0.1011, desk-spot-real 0.0820 unchanged. The correlated bound for both the light and the
// probe's occlusion scored better still on five of the six (cornell 0.1248) but left the
// floor beside a 20 cm cube 0.07 too much of its sky (ray casting: tests/dvct_cones.rs).
struct ConeSeen {
    rv: vec3f,
    r: vec3f,
    hidden: vec2f,
}

fn cone_seen(hit: Cone) -> ConeSeen {
    let change = mix(hit.rv.rgb - hit.r.rgb, hit.correlated_change, 0.5);
    return ConeSeen(max(hit.r.rgb + change, vec3f(0.0)), hit.r.rgb, probe_occlusion(hit));
}

// The nine diffuse cones of [CNS+11] (spec §2.13.4): the normal and eight around it at 45°
// and 55°, weighted by their cosines so that the weights sum to π (a uniform radiance L
// gives the irradiance πL), the eight placed in the tangent frame `tb` (cones_frame).
const DIFFUSE_CONES: u32 = 9u;

// The tangent frame of normal `n` turned by `turn` (radians) about it: built once per gather,
// not once per cone.
fn cones_frame(n: vec3f, turn: f32) -> mat2x3f {
    let t = tangent_frame(n);
    return mat2x3f(cos(turn) * t[0] + sin(turn) * t[1], cos(turn) * t[1] - sin(turn) * t[0]);
}

fn diffuse_cone(n: vec3f, tb: mat2x3f, k: u32) -> vec4f {
    let offsets = array<vec2f, 9>(
        vec2f(0.0, 0.0), vec2f(1.0, 0.0), vec2f(-1.0, 0.0), vec2f(0.0, 1.0), vec2f(0.0, -1.0),
        vec2f(1.0, 1.0), vec2f(-1.0, 1.0), vec2f(1.0, -1.0), vec2f(-1.0, -1.0),
    );
    let o = offsets[k];
    let d = normalize(n + tb[0] * o.x + tb[1] * o.y);
    // Σ cos = 1 + 4·cos 45° + 4·cos 54.7°.
    let cos_sum = 1.0 + 4.0 * 0.70710678 + 4.0 * 0.57735027;
    return vec4f(d, PI * dot(d, n) / cos_sum);
}

// Where the cones of a surface at `p` with normal `n` start: CONE_START_VOXELS voxels off the
// surface, so that it does not see its own voxels (march lifts the coarser samples further).
// One voxel, as [CNS+11]: two skipped the first centimetre of a virtual object beside a real
// surface, its contact shadow too light (desk-spot-real's region FLIP 0.116 → 0.105, cornell
// 0.158 → 0.155; half a voxel let the desk see its own voxels around the bunny).
fn cone_origin(p: vec3f, n: vec3f) -> vec3f { return p + n * (CONE_START_VOXELS * voxel_side()); }
const CONE_START_VOXELS: f32 = 1.0;

// Roughness of the probe lookup that weighs a diffuse cone's visibility by the probe's light
// in its direction: the widest of the prefiltered chain. The cones shadow the probe's broad
// light (the maps of its lights take the narrow ones, gather.wgsl), and their visibility
// ratio scales the whole probe's shading: weights that follow bright sources the cones cannot
// resolve (a studio lamp behind a wall, which a cone's trilinear samples partly see through)
// skewed it. Lookups at roughness 0.7 → 1: the six diffuse benchmark scenes' region FLIP
// 0.1 – 5 % lower (desk-spot-real 0.105 → 0.100); the probe's irradiance as weights (the
// smoothest) lost on cornell.
const CONE_PROBE_ROUGHNESS: f32 = 1.0;

// How far a trace texel turns its diffuse cones: 0°, 22.5°, 45° or 67.5° over each 2 × 2
// texels, which the per-pixel resolve blends. Nine cones of this aperture cover about half of
// the cosine-weighted hemisphere and each stands for twice the part it sees: whatever is
// smaller than the gaps between them (a lit block's edge, a small bright object beside a
// surface) counts twice where a cone meets it and not at all where it falls between, block
// by block; turned sets spread it over the gaps at no cost (interleaved sampling). Region
// FLIP (lavapipe, 640×480): cornell 0.1508 → 0.1471, cornell-va 0.1470 → 0.1402, cornell-vb
// 0.1344 → 0.1272, desk-spot-real 0.0992 → 0.0986, desk-spot-virtual 0.0931 → 0.0925,
// desk-bunny 0.0751 → 0.0757; 19 cones (rings at 33° and 63°) did better (0.1449 / 0.1375 /
// 0.1245 / 0.1007 / 0.0923 / 0.0731) at twice the cones' time.
fn cone_turn(texel: vec2i) -> f32 {
    return 0.3926991 * f32((texel.x & 1) + 2 * (texel.y & 1));
}

// What the nine diffuse cones of a surface at `p` (normal `n`) gather, turned by `turn`: the
// irradiance of both solutions' bounce light, and the probe's irradiance as each solution's
// cones let it through (per channel: Σw·V_rv, Σw·V_r) and unoccluded (Σw), w being a cone's
// weight times the probe's radiance in its direction.
struct Gathered {
    rv: vec3f,
    r: vec3f,
    env_rv: vec3f,
    env_r: vec3f,
    env: vec3f,
}

fn gather_diffuse(p: vec3f, n: vec3f, spacing: f32, turn: f32) -> Gathered {
    var out = Gathered(vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0));
    let o = cone_origin(p, n);
    let tb = cones_frame(n, turn);
    for (var k = 0u; k < DIFFUSE_CONES; k++) {
        let c = diffuse_cone(n, tb, k);
        gather_seen(&out, c.xyz, c.w, cone_seen(trace_cone(o, c.xyz, params.cone.x, spacing, voxel_side(), n)));
    }
    return out;
}

// Adds what a cone or ray along `d` of weight `weight` saw to `out`.
fn gather_seen(out: ptr<function, Gathered>, d: vec3f, weight: f32, seen: ConeSeen) {
    (*out).rv += weight * seen.rv;
    (*out).r += weight * seen.r;
    let w = weight * env_radiance_at(frame, d, CONE_PROBE_ROUGHNESS);
    (*out).env_rv += w * (1.0 - seen.hidden.x);
    (*out).env_r += w * (1.0 - seen.hidden.y);
    (*out).env += w;
}

// Rays a virtual surface's trace texel gathers with in place of the nine cones (settings
// `dvct.virtual_rays`, which its pipeline sets; 0: the cones).
override VIRTUAL_RAYS: u32 = 0u;

// What VIRTUAL_RAYS thin rays of a surface at `p` (normal `n`) gather, as gather_diffuse's
// cones do: cosine distributed (each of weight π / rays) in a golden-angle spiral turned by
// `turn` as the cones are, marched through the voxels themselves (as wide as a voxel at
// twice the volume's side: level 0 all the way), a voxel at a time. The nine wide cones read
// the room through its prefiltered levels, where the lit wall beside a virtual block, that
// wall's edge against the open sky and the floor in the block's shadow blend into coarse
// cells: a streak ran across the front of cornell's tall block where the cones' coarse
// samples crossed the red wall's front edge, and its face towards the red wall took 0.83 of
// the answer's red (rays: 0.93). Nine thin rays alone scored far worse (cornell 0.159 against
// the cones' 0.132): it takes both the voxels' resolution and a finer spacing than nine
// directions; 32 rays 0.15 wide on every pixel kept little of the gain (0.126 against 0.108
// this thin). They cost what a cone does per voxel they cross: 32 took a moving 1080p cornell
// frame on an H100 from 2.85 to 4.76 ms (docs/benchmarks.md).
fn gather_rays(p: vec3f, n: vec3f, turn: f32) -> Gathered {
    return gather_rays_shifted(p, n, turn, VIRTUAL_RAYS, vec2f(0.5, 0.0));
}

// gather_rays with `rays` rays whose spiral is shifted by `shift`: x the share of a ring the
// radii step on (0.5: the rings' middles), y the share of a turn the angles start at. A still
// view's frames shift it each frame (`dvct.still_rays`: still_rays.wgsl).
fn gather_rays_shifted(p: vec3f, n: vec3f, turn: f32, rays: u32, shift: vec2f) -> Gathered {
    var out = Gathered(vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0));
    let o = p + n * (RAY_START_VOXELS * voxel_side());
    let tb = cones_frame(n, turn + 2.0 * PI * shift.y);
    let aperture = 1.0 / f32(params.info.x);
    let weight = PI / f32(max(rays, 1u));
    for (var k = 0u; k < rays; k++) {
        // Equal areas of the disc that projects onto the cosine-weighted hemisphere.
        let u = (f32(k) + shift.x) / f32(rays);
        let a = f32(k) * GOLDEN_ANGLE;
        let disc = sqrt(u) * vec2f(cos(a), sin(a));
        let d = normalize(tb[0] * disc.x + tb[1] * disc.y + n * sqrt(max(1.0 - u, 0.0)));
        gather_seen(&out, d, weight, cone_seen(trace_cone(o, d, aperture, pixel_spacing(), voxel_side(), n)));
    }
    return out;
}

const GOLDEN_ANGLE: f32 = 2.39996323;

// Where the rays start, in voxels off the surface: a voxelised surface is a shell up to a
// voxel thick around it, and a thin ray's trilinear samples read a voxel either side, so that
// from one voxel off the rays of a ball's rim gathered its own light sideways (twice the path
// tracer's bounce light from the lit floor below it; from 1.5 voxels on, 0.81, 2 voxels 0.79,
// 3 voxels 0.77: tests/dvct_cones.rs). The cones keep CONE_START_VOXELS, which their wider
// samples were tuned with.
const RAY_START_VOXELS: f32 = 1.5;
