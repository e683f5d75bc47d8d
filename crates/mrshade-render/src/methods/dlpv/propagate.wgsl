// Propagation (Franke §2.12.2 step 2, Kaplanyan & Dachsbacher 2010), as a gather: every cell
// collects, from each of its six neighbours, the flux through the five faces of its own that
// the shared face does not hide: flux = ΔΩ·I_neighbour(direction of the face's centre), ΔΩ
// the face's solid angle from the neighbour's centre (0.4007 for the far face, 0.4234 for a
// side face; the 30 sum to 4π, so an isotropic cell passes on all its flux), re-emitted
// from the face as a point light ⟨n_face, ω⟩₊·flux/π. V_ρ clamps negative flux (a regular
// LPV); the delta volume keeps it (antiradiance). Each step's result is added to the
// accumulated volume. Every source moves in the same dispatch, one dispatch per step (the
// per-dispatch cost, not the cells, bounds a 32³ volume). `seed` turns the fixed-point
// injection into the first step; only the
// direct change keeps the injected cells themselves in the result (the shadow lies on the
// surface it was injected at). Bounce light is read from the first propagation on, so a VPL
// does not light the cell it lies in, its own surface (self-illumination, spec §2.12.9).

@group(0) @binding(0) var<uniform> params: DlpvParams;
@group(0) @binding(1) var<storage, read> injected: array<i32>;
// Every source's volume, source-major, then channel, then cell.
@group(0) @binding(2) var<storage, read> source: array<vec4f>;
@group(0) @binding(3) var<storage, read_write> destination: array<vec4f>;
// The sums so far of V_ρ, V_Δ, V_μ (volume-major), and where the sums with this dispatch's
// results go (two buffers: one read-write buffer added to by consecutive dispatches raced on
// the H200, see mod.rs).
@group(0) @binding(4) var<storage, read> sum_in: array<vec4f>;
@group(0) @binding(5) var<storage, read_write> sum_out: array<vec4f>;

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

fn cell_of(id: u32) -> vec3i {
    let res = params.info.x;
    return vec3i(vec3u(id % res, (id / res) % res, id / (res * res)));
}

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

// The light of source `s`, channel `ch`, that the neighbours send into `cell` in one step.
// Each neighbour's intensity toward a face centre is Y0·c0 + Y1·⟨(c3, c1, c2), ω⟩; with
// ω = flow (the far face) or 0.894·flow + 0.447·face (a side face) it needs no normalising:
// 30 faces of dot products of axes, not 30 normalised directions and SH evaluations (the
// step took 39 µs at 32³ on an H200, its arithmetic rather than its memory).
fn gather_from(s: u32, ch: u32, cell: vec3i) -> vec4f {
    let clamp_negative = s == SOURCE_RHO || s == SOURCE_MU;
    // (Σ flux, Σ flux·face) over the faces, then the lobe's constants.
    var sum = vec4f(0.0);
    for (var i = 0u; i < 3u; i++) {
        let axis = AXES[i];
        let across_a = AXES[(i + 1u) % 3u];
        let across_b = AXES[(i + 2u) % 3u];
        for (var k = 0u; k < 2u; k++) {
            // Light flowing along `flow` from the neighbour behind.
            let flow = select(axis, -axis, k == 1u);
            let from_cell = cell - vec3i(flow);
            if (!cell_inside(from_cell)) { continue; }
            let c = source[at(s, ch, cell_index(from_cell))];
            let band1 = SH_Y1 * vec3f(c.w, c.y, c.z);
            let base = SH_Y0 * c.x;
            let along = dot(band1, flow);
            add_face(FAR_FACE_SOLID_ANGLE * (base + along), flow, clamp_negative, &sum);
            let side = base + SIDE_ALONG * along;
            let a = SIDE_ACROSS * dot(band1, across_a);
            let b = SIDE_ACROSS * dot(band1, across_b);
            add_face(SIDE_FACE_SOLID_ANGLE * (side + a), across_a, clamp_negative, &sum);
            add_face(SIDE_FACE_SOLID_ANGLE * (side - a), -across_a, clamp_negative, &sum);
            add_face(SIDE_FACE_SOLID_ANGLE * (side + b), across_b, clamp_negative, &sum);
            add_face(SIDE_FACE_SOLID_ANGLE * (side - b), -across_b, clamp_negative, &sum);
        }
    }
    // SH order (Y0, y, z, x).
    return vec4f(SH_Y0 * sum.x, LOBE_BAND1 * vec3f(sum.z, sum.w, sum.y));
}

// The injected coefficients of source `s`, channel `ch`, in `cell`.
fn injected_at(s: u32, ch: u32, cell: u32) -> vec4f {
    let word = at(s, ch, cell) * 4u;
    let q = vec4i(injected[word], injected[word + 1u], injected[word + 2u], injected[word + 3u]);
    return vec4f(q) / params.scale.x;
}

// One invocation per cell (x) and accumulated volume × channel (y: 3·v + ch): a cell's work
// spread over nine invocations, so a 32³ volume is more than one wave of the GPU.
@compute @workgroup_size(64)
fn seed(@builtin(global_invocation_id) id: vec3u) {
    let cell = id.x;
    if (cell >= cells() || id.y >= 3u * VOLUMES) { return; }
    let v = id.y / 3u;
    let ch = id.y % 3u;
    var added = vec4f(0.0);
    for (var s = 0u; s < SOURCES; s++) {
        if ((sources_of(v) & (1u << s)) == 0u) { continue; }
        var c = injected_at(s, ch, cell);
        // V_ρ's slot holds what differs from V_μ (inject.wgsl).
        if (s == SOURCE_RHO) { c += injected_at(SOURCE_MU, ch, cell); }
        destination[at(s, ch, cell)] = c;
        if (s == SOURCE_DIRECT) { added += c; }
    }
    sum_out[at(v, ch, cell)] = sum_in[at(v, ch, cell)] + added;
}

@compute @workgroup_size(64)
fn propagate(@builtin(global_invocation_id) id: vec3u) {
    let index = id.x;
    if (index >= cells() || id.y >= 3u * VOLUMES) { return; }
    let v = id.y / 3u;
    let ch = id.y % 3u;
    let cell = cell_of(index);
    // This dispatch's step (from 1).
    let step = params.info.z;
    var added = vec4f(0.0);
    for (var s = 0u; s < SOURCES; s++) {
        if ((sources_of(v) & (1u << s)) == 0u || step > params.steps[s]) { continue; }
        let gathered = gather_from(s, ch, cell);
        destination[at(s, ch, index)] = gathered;
        added += gathered;
    }
    sum_out[at(v, ch, index)] = sum_in[at(v, ch, index)] + added;
}
