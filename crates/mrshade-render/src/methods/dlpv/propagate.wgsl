// Propagation (Franke §2.12.2 step 2, Kaplanyan & Dachsbacher 2010), as a gather: every cell
// collects, from each of its six neighbours, the flux through the five faces of its own that
// the shared face does not hide: flux = ΔΩ·I_neighbour(direction of the face's centre), ΔΩ
// the face's solid angle from the neighbour's centre (0.4007 for the far face, 0.4234 for a
// side face; the 30 sum to 4π, so an isotropic cell passes on all its flux), re-emitted
// from the face as a point light ⟨n_face, ω⟩₊·flux/π. V_ρ clamps negative flux (a regular
// LPV); the delta volume keeps it (antiradiance). Each step's result is added to the
// accumulated volume (by every second dispatch, `adds_to_sums`). Every source moves in the
// same dispatch, one dispatch per step (two steps a dispatch in tiles cost more than the
// launches they saved: docs/benchmarks.md, 2026-12-03 and 2026-12-05). `seed` turns the
// fixed-point injection into the first step; only the direct change keeps the injected cells
// themselves in the result (the shadow lies on the surface it was injected at). Bounce light
// is read from the first propagation on, so a VPL does not light the cell it lies in, its own
// surface (self-illumination, spec §2.12.9).

@group(0) @binding(0) var<uniform> params: DlpvParams;
@group(0) @binding(1) var<storage, read> injected: array<i32>;
// Every source's volume, source-major, then channel, then cell: four coefficients as half
// floats (two words) in scratch units (`SCRATCH_UNITS`): half the bytes of f32, 0.012 of the
// 32 steps' 0.30 ms on an H100 (the steps wait on their reads' latency more than on their
// bytes: gather_from).
@group(0) @binding(2) var<storage, read> source: array<vec2u>;
@group(0) @binding(3) var<storage, read_write> destination: array<vec2u>;
// The sums so far of V_ρ, V_Δ, V_μ (volume-major), and where the sums with this dispatch's
// results go (two buffers: one read-write buffer added to by consecutive dispatches raced on
// the H200, see mod.rs).
@group(0) @binding(4) var<storage, read> sum_in: array<vec4f>;
@group(0) @binding(5) var<storage, read_write> sum_out: array<vec4f>;

// Fixed-point units (injected, `params.scale.x` per watt) per scratch unit: injected values
// stay below 2³¹ units (FIXED_POINT_RANGE in mod.rs bounds all of a source's flux by 2²⁹), so
// scratch values stay below 2¹⁵, inside f16's range (65504), and one fixed-point unit is
// 1.5·10⁻⁵, near f16's smallest normal number: the halves lose nothing the injection kept.
const SCRATCH_UNITS: f32 = 65536.0;

fn scratch_load(i: u32) -> vec4f {
    let w = source[i];
    return vec4f(unpack2x16float(w.x), unpack2x16float(w.y));
}

// Stores `c` rounded to halves and returns what was stored.
fn scratch_store(i: u32, c: vec4f) -> vec4f {
    let w = vec2u(pack2x16float(c.xy), pack2x16float(c.zw));
    destination[i] = w;
    return vec4f(unpack2x16float(w.x), unpack2x16float(w.y));
}

// Watts per scratch unit, for the sums.
fn scratch_watts() -> f32 { return SCRATCH_UNITS / params.scale.x; }

const FAR_FACE_SOLID_ANGLE: f32 = 0.4006696846;
const SIDE_FACE_SOLID_ANGLE: f32 = 0.4234413544;
const SOURCES: u32 = 4u;
const VOLUMES: u32 = 3u;

// The sources accumulated in volume `v` (V_ρ, V_Δ, V_μ), as a mask of 1 << SOURCE_*.
fn sources_of(v: u32) -> u32 {
    switch v {
        case 0u: { return 1u << SOURCE_RHO; }
        case 1u: { return (1u << SOURCE_INDIRECT) | (1u << SOURCE_DIRECT); }
        default: { return 1u << SOURCE_MU; }
    }
}

// The three axes.
const AXES = array<vec3f, 3>(vec3f(1.0, 0.0, 0.0), vec3f(0.0, 1.0, 0.0), vec3f(0.0, 0.0, 1.0));
// A side face's centre seen from the neighbour's centre: (flow + ½·face) / |…| = 0.894·flow
// + 0.447·face.
const SIDE_ALONG: f32 = 0.8944272;
const SIDE_ACROSS: f32 = 0.4472136;
// The clamped-cosine lobe of a face, over π: (Y0, ⅔·Y1·face) (sh4_clamped_cosine / π).
const LOBE_BAND1: f32 = 0.6666667 * SH_Y1;

fn at(source_or_volume: u32, ch: u32, cell: u32) -> u32 {
    return (source_or_volume * 3u + ch) * cells() + cell;
}

// What one face of the receiving cell passes on, with normal `face` (a signed axis), for
// flux `flux` through it: its lobe times the flux, as (Σ flux, Σ flux·face) (the lobe's
// bands 0 and 1 up to constant factors, applied once in gather_from).
fn add_face(flux: f32, face: vec3f, clamp_negative: bool, sum: ptr<function, vec4f>) {
    let f = select(flux, max(flux, 0.0), clamp_negative);
    *sum += vec4f(f, f * face);
}

// What a neighbour of coefficients `c` sends through the five faces of the receiving cell
// that the face they share does not hide, the light flowing along axis `i` (`k` = 0: toward
// +, from the neighbour behind; 1: toward −), as (Σ flux, Σ flux·face). Each neighbour's
// intensity toward a face centre is Y0·c0 + Y1·⟨(c3, c1, c2), ω⟩; with ω = flow (the far
// face) or 0.894·flow + 0.447·face (a side face) it needs no normalising: dot products of
// axes, not normalised directions and SH evaluations (the step took 39 µs at 32³ on an
// H200, its arithmetic rather than its memory).
fn flow_in(c: vec4f, i: u32, k: u32, clamp_negative: bool) -> vec4f {
    let axis = AXES[i];
    let across_a = AXES[(i + 1u) % 3u];
    let across_b = AXES[(i + 2u) % 3u];
    let flow = select(axis, -axis, k == 1u);
    let band1 = SH_Y1 * vec3f(c.w, c.y, c.z);
    let base = SH_Y0 * c.x;
    let along = dot(band1, flow);
    var sum = vec4f(0.0);
    add_face(FAR_FACE_SOLID_ANGLE * (base + along), flow, clamp_negative, &sum);
    let side = base + SIDE_ALONG * along;
    let a = SIDE_ACROSS * dot(band1, across_a);
    let b = SIDE_ACROSS * dot(band1, across_b);
    add_face(SIDE_FACE_SOLID_ANGLE * (side + a), across_a, clamp_negative, &sum);
    add_face(SIDE_FACE_SOLID_ANGLE * (side - a), -across_a, clamp_negative, &sum);
    add_face(SIDE_FACE_SOLID_ANGLE * (side + b), across_b, clamp_negative, &sum);
    add_face(SIDE_FACE_SOLID_ANGLE * (side - b), -across_b, clamp_negative, &sum);
    return sum;
}

// The light of source `s`, channel `ch`, that the six neighbours send into `cell` in one
// step. The six loads come first, each neighbour outside the volume standing in by the cell
// itself and its light then left out, so that they overlap: a step waits on them, not on its
// arithmetic.
fn gather_from(s: u32, ch: u32, cell: vec3i) -> vec4f {
    let clamp_negative = s == SOURCE_RHO || s == SOURCE_MU;
    let last = i32(params.info.x) - 1;
    let res = u32(last + 1);
    let volume = at(s, ch, 0u);
    let here = volume + cell_index(cell);
    let strides = vec3u(1u, res, res * res);
    let behind = cell > vec3i(0);
    let ahead = cell < vec3i(last);
    let c_xb = scratch_load(select(here, here - strides.x, behind.x));
    let c_xa = scratch_load(select(here, here + strides.x, ahead.x));
    let c_yb = scratch_load(select(here, here - strides.y, behind.y));
    let c_ya = scratch_load(select(here, here + strides.y, ahead.y));
    let c_zb = scratch_load(select(here, here - strides.z, behind.z));
    let c_za = scratch_load(select(here, here + strides.z, ahead.z));
    // (Σ flux, Σ flux·face) over the faces, in the order +x, −x, +y, −y, +z, −z of the flow.
    var sum = vec4f(0.0);
    if (behind.x) { sum += flow_in(c_xb, 0u, 0u, clamp_negative); }
    if (ahead.x) { sum += flow_in(c_xa, 0u, 1u, clamp_negative); }
    if (behind.y) { sum += flow_in(c_yb, 1u, 0u, clamp_negative); }
    if (ahead.y) { sum += flow_in(c_ya, 1u, 1u, clamp_negative); }
    if (behind.z) { sum += flow_in(c_zb, 2u, 0u, clamp_negative); }
    if (ahead.z) { sum += flow_in(c_za, 2u, 1u, clamp_negative); }
    // SH order (Y0, y, z, x).
    return vec4f(SH_Y0 * sum.x, LOBE_BAND1 * vec3f(sum.z, sum.w, sum.y));
}

// The injected coefficients of source `s`, channel `ch`, in `cell` (fixed-point units).
fn injected_at(s: u32, ch: u32, cell: u32) -> vec4i {
    let word = at(s, ch, cell) * 4u;
    return vec4i(injected[word], injected[word + 1u], injected[word + 2u], injected[word + 3u]);
}

// The invocation of cell (x, y, z mod res) and of accumulated volume × channel z / res
// (3·v + ch, from the first volume propagated): a cell's work spread over nine invocations, so a 32³ volume is more than one
// wave of the GPU, and 4³ cells a workgroup, whose neighbours' reads mostly fall in the same
// workgroup (alone it measured no faster than rows of 64 cells, docs/benchmarks.md r40).
struct Invocation {
    cell: vec3i,
    index: u32,
    v: u32,
    ch: u32,
}

fn invocation(id: vec3u) -> Invocation {
    let res = params.info.x;
    let cell = vec3u(id.xy, id.z % res);
    let vc = id.z / res;
    return Invocation(vec3i(cell), (cell.z * res + cell.y) * res + cell.x, vc / 3u + params.gathered.x, vc % 3u);
}

@compute @workgroup_size(4, 4, 4)
fn seed(@builtin(global_invocation_id) id: vec3u) {
    let here = invocation(id);
    if (here.v >= VOLUMES) { return; }
    let cell = here.index;
    let v = here.v;
    let ch = here.ch;
    var added = vec4f(0.0);
    for (var s = 0u; s < SOURCES; s++) {
        if ((sources_of(v) & (1u << s)) == 0u) { continue; }
        var q = injected_at(s, ch, cell);
        // V_ρ's slot holds what differs from V_μ (inject.wgsl).
        if (s == SOURCE_RHO) { q += injected_at(SOURCE_MU, ch, cell); }
        scratch_store(at(s, ch, cell), vec4f(q) / SCRATCH_UNITS);
        // The direct change's own cells go to the sums as injected, unrounded.
        if (s == SOURCE_DIRECT) { added += vec4f(q) / params.scale.x; }
    }
    sum_out[at(v, ch, cell)] = sum_in[at(v, ch, cell)] + added;
}

// The last propagation step of any source.
fn last_step() -> u32 {
    return max(max(params.steps.x, params.steps.y), max(params.steps.z, params.steps.w));
}

// Whether step `step`'s dispatch adds to the sums: every second one (it adds the step before
// it, read from its source, and its own), and the last: half the sums' reads and writes
// (alone it measured no faster either, r40).
fn adds_to_sums(step: u32) -> bool {
    return step % 2u == 0u || step == last_step();
}

@compute @workgroup_size(4, 4, 4)
fn propagate(@builtin(global_invocation_id) id: vec3u) {
    let here = invocation(id);
    if (here.v >= VOLUMES) { return; }
    let index = here.index;
    let v = here.v;
    let ch = here.ch;
    // This dispatch's step (from 1).
    let step = params.info.z;
    let adds = adds_to_sums(step);
    // In the order the steps came: the sums identical to adding every step in its own dispatch.
    var total = vec4f(0.0);
    if (adds) { total = sum_in[at(v, ch, index)]; }
    for (var s = 0u; s < SOURCES; s++) {
        if ((sources_of(v) & (1u << s)) == 0u) { continue; }
        // The step before, which the dispatch before did not add (steps from 1 only: the
        // seed added what it keeps).
        if (adds && step % 2u == 0u && step - 1u <= params.steps[s]) {
            total += scratch_load(at(s, ch, index)) * scratch_watts();
        }
        if (step > params.steps[s]) { continue; }
        // The sums take the step as the next one reads it.
        total += scratch_store(at(s, ch, index), gather_from(s, ch, here.cell)) * scratch_watts();
    }
    if (adds) { sum_out[at(v, ch, index)] = total; }
}
