// Propagation (Franke §2.12.2 step 2, Kaplanyan & Dachsbacher 2010), as a gather: every cell
// collects, from each of its six neighbours, the flux through the five faces of its own that
// the shared face does not hide: flux = ΔΩ·I_neighbour(direction of the face's centre), ΔΩ
// the face's solid angle from the neighbour's centre (0.4007 for the far face, 0.4234 for a
// side face; the 30 sum to 4π, so an isotropic cell passes on all its flux), re-emitted
// from the face as a point light ⟨n_face, ω⟩₊·flux/π. V_ρ clamps negative flux (a regular
// LPV); the delta volume keeps it (antiradiance). Each step's result is added to the
// accumulated volume. Every source moves in the same dispatch, two steps per dispatch (the
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

// The light that a cell's six neighbours send into it in one step, from their coefficients
// `c` (index 2·axis + k: the neighbour behind along +axis for k = 0, along −axis for k = 1;
// zero outside the volume). Each neighbour's intensity toward a face centre is
// Y0·c0 + Y1·⟨(c3, c1, c2), ω⟩; with ω = flow (the far face) or 0.894·flow + 0.447·face (a
// side face) it needs no normalising: 30 faces of dot products of axes, not 30 normalised
// directions and SH evaluations (the step took 39 µs at 32³ on an H200, its arithmetic
// rather than its memory).
fn gather_neighbours(c: array<vec4f, 6>, clamp_negative: bool) -> vec4f {
    // (Σ flux, Σ flux·face) over the faces, then the lobe's constants.
    var sum = vec4f(0.0);
    for (var i = 0u; i < 3u; i++) {
        let axis = AXES[i];
        let across_a = AXES[(i + 1u) % 3u];
        let across_b = AXES[(i + 2u) % 3u];
        for (var k = 0u; k < 2u; k++) {
            // Light flowing along `flow` from the neighbour behind.
            let flow = select(axis, -axis, k == 1u);
            let n = c[2u * i + k];
            let band1 = SH_Y1 * vec3f(n.w, n.y, n.z);
            let base = SH_Y0 * n.x;
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

// The neighbour behind `cell` along the flow of slot `slot` of gather_neighbours.
fn behind(cell: vec3i, slot: u32) -> vec3i {
    let axis = vec3i(AXES[slot / 2u]);
    return select(cell - axis, cell + axis, (slot & 1u) == 1u);
}

// Whether source `s` keeps negative light (the changes: antiradiance) or clamps it (V_ρ, V_μ:
// regular LPVs).
fn clamps_negative(s: u32) -> bool { return s == SOURCE_RHO || s == SOURCE_MU; }

// One step of source `s`, channel `ch`, into `cell`, from the previous step's volume.
fn gather_from(s: u32, ch: u32, cell: vec3i) -> vec4f {
    var c: array<vec4f, 6>;
    for (var slot = 0u; slot < 6u; slot++) {
        let from_cell = behind(cell, slot);
        if (cell_inside(from_cell)) { c[slot] = source[at(s, ch, cell_index(from_cell))]; }
    }
    return gather_neighbours(c, clamps_negative(s));
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

// Two steps per dispatch (the per-dispatch cost, not the cells, bounds a 32³ volume: 14 µs a
// step on an H200, most of it the launch and the barrier). A workgroup owns a tile of
// TILE³ cells of one accumulated volume × channel; it gathers the first step over the tile
// and a one-cell border into workgroup memory, then the second step of its tile from
// there: the same sums as two dispatches, in half of them. The dispatch's steps are
// `params.info.z` and the next; a source with fewer steps left takes one.
const TILE: u32 = 4u;
const BORDERED: u32 = TILE + 2u;
var<workgroup> first_step: array<vec4f, BORDERED * BORDERED * BORDERED>;

fn bordered_cell(tile: vec3u, k: u32) -> vec3i {
    let b = vec3u(k % BORDERED, (k / BORDERED) % BORDERED, k / (BORDERED * BORDERED));
    return vec3i(tile * TILE + b) - vec3i(1);
}

// Workgroups: (tiles, tiles, tiles · 3 · VOLUMES), tiles = ⌈res / TILE⌉ (propagate_workgroups
// in mod.rs).
@compute @workgroup_size(64)
fn propagate(@builtin(workgroup_id) group: vec3u, @builtin(local_invocation_index) local: u32) {
    let slice = group.z % (3u * VOLUMES);
    let v = slice / 3u;
    let ch = slice % 3u;
    let tile = vec3u(group.xy, group.z / (3u * VOLUMES));
    let mine = vec3u(local % TILE, (local / TILE) % TILE, local / (TILE * TILE));
    let cell = vec3i(tile * TILE + mine);
    // The cell's slot in the bordered tile.
    let slot = ((mine.z + 1u) * BORDERED + mine.y + 1u) * BORDERED + mine.x + 1u;
    let inside = cell_inside(cell);
    let step = params.info.z;
    var added = vec4f(0.0);
    for (var s = 0u; s < SOURCES; s++) {
        // Uniform over the workgroup: every invocation reaches the barriers.
        if ((sources_of(v) & (1u << s)) == 0u || step > params.steps[s]) { continue; }
        for (var k = local; k < BORDERED * BORDERED * BORDERED; k += 64u) {
            let c = bordered_cell(tile, k);
            first_step[k] = select(vec4f(0.0), gather_from(s, ch, c), cell_inside(c));
        }
        workgroupBarrier();
        var result = first_step[slot];
        added += result;
        if (step + 1u <= params.steps[s]) {
            var c: array<vec4f, 6>;
            for (var n = 0u; n < 6u; n++) {
                let b = behind(vec3i(mine) + vec3i(1), n);
                c[n] = first_step[(u32(b.z) * BORDERED + u32(b.y)) * BORDERED + u32(b.x)];
            }
            result = gather_neighbours(c, clamps_negative(s));
            added += result;
        }
        if (inside) { destination[at(s, ch, cell_index(cell))] = result; }
        workgroupBarrier();
    }
    if (inside) {
        let index = cell_index(cell);
        sum_out[at(v, ch, index)] = sum_in[at(v, ch, index)] + added;
    }
}
