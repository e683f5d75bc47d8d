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

// +x, −x, +y, −y, +z, −z.
fn axis(i: u32) -> vec3i {
    var v = vec3i(0);
    v[i / 2u] = select(1, -1, (i & 1u) == 1u);
    return v;
}

fn cell_of(id: u32) -> vec3i {
    let res = params.info.x;
    return vec3i(vec3u(id % res, (id / res) % res, id / (res * res)));
}

fn at(source_or_volume: u32, ch: u32, cell: u32) -> u32 {
    return (source_or_volume * 3u + ch) * cells() + cell;
}

// The light of source `s`, channel `ch`, that the neighbours send into `cell` in one step.
fn gather_from(s: u32, ch: u32, cell: vec3i) -> vec4f {
    let clamp_negative = s == SOURCE_RHO || s == SOURCE_MU;
    var gathered = vec4f(0.0);
    for (var a = 0u; a < 6u; a++) {
        // Light flowing along `flow` from the neighbour behind.
        let flow = axis(a);
        let from_cell = cell - flow;
        if (!cell_inside(from_cell)) { continue; }
        let sender = source[at(s, ch, cell_index(from_cell))];
        for (var f = 0u; f < 6u; f++) {
            let face = axis(f);
            if (all(face == -flow)) { continue; }
            let is_far = all(face == flow);
            let to_face = normalize(vec3f(flow) + select(0.5 * vec3f(face), vec3f(0.0), is_far));
            let solid_angle = select(SIDE_FACE_SOLID_ANGLE, FAR_FACE_SOLID_ANGLE, is_far);
            var flux = solid_angle * dot(sender, sh4(to_face));
            if (clamp_negative) { flux = max(flux, 0.0); }
            gathered += flux * sh4_clamped_cosine(vec3f(face)) / PI;
        }
    }
    return gathered;
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
        let word = at(s, ch, cell) * 4u;
        let c = vec4f(f32(injected[word]), f32(injected[word + 1u]), f32(injected[word + 2u]), f32(injected[word + 3u])) / params.scale.x;
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
