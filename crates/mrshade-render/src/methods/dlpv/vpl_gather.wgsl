// `gather` of the volumes gathered from VPLs (vpl.wgsl): V_ρ over the cells of the
// virtual content's box and one cell around it (the only ones virtual pixels read), with the
// bounce light gathered V_μ and V_Δ's indirect change over every cell (real pixels read any),
// each VPL adding to the volumes it lights (VPL_*): a workgroup per 4³ cells
// and chunk of the VPLs, which it reads 64 at a time into workgroup memory, each invocation
// one cell's sum over the chunk (`gather`); then each cell's chunks summed (`gather_sum`). One
// invocation per cell over all VPLs ran a few waves on the whole GPU, each waiting on its
// reads: 7 ms for cornell's 6 500 cells and 12 000 VPLs on an H100. A VPL's patch
// of area A, exitance M = Φ/A, lights the cell's centre x with the irradiance of a disk
// facing it, E = Φ/π·cos_v / (d² + A/π) (exact on the disk's axis, no pole as d → 0), cos_v
// its emission cosine toward the cell. (With the maps' VPLs alone, one bounce, the virtual
// faces of cornell took 0.80–0.87 of the answer's light, and a cosine seen from a cell behind
// the patch, lighter at grazing angles, scored better; with the photo's light, which holds
// every bounce, they take 0.94–0.99 and the plain cosine scores best: docs/benchmarks.md.)

@group(0) @binding(0) var<uniform> params: DlpvParams;
@group(0) @binding(1) var<storage, read> vpls: array<GatherVpl>;
// The accumulated V_ρ, V_Δ, V_μ; `gather_sum` writes those gathered (V_Δ: the injected
// direct change, which is not propagated, and the gathered indirect one).
@group(0) @binding(2) var<storage, read_write> volumes: array<vec4f>;
@group(0) @binding(3) var<uniform> gather_info: GatherInfo;
@group(0) @binding(4) var<storage, read> vpl_count: u32;
// Per chunk, per cell gathered, per volume gathered (V_ρ, then V_Δ and V_μ), per channel:
// its sum over the chunk.
@group(0) @binding(5) var<storage, read_write> partials: array<vec4f>;
// The injection (inject.wgsl), for V_Δ's direct change.
@group(0) @binding(6) var<storage, read> injected: array<i32>;
// Per block of 4³ cells, 1 where a pixel reads one of them (`mark_cells`).
@group(0) @binding(7) var<storage, read> blocks_read: array<u32>;

const TILE: u32 = 64u;
var<workgroup> tile: array<GatherVpl, 64>;
var<workgroup> shared_count: u32;

// One cell's sums: per volume (V_ρ, V_Δ, V_μ) and channel, four SH coefficients. Fields, not
// an array: an array indexed in a loop went to local memory, and the gather ran 8–12 times
// slower (docs/benchmarks.md, 2026-12-06).
struct CellSums {
    rho_r: vec4f, rho_g: vec4f, rho_b: vec4f,
    delta_r: vec4f, delta_g: vec4f, delta_b: vec4f,
    mu_r: vec4f, mu_g: vec4f, mu_b: vec4f,
}

// The light of one VPL at `x`, a cell centre, added as SH coefficients per channel, E·Y(ω),
// to each volume it lights (the same VPL in every invocation of the workgroup: the tests
// are uniform).
fn vpl_light(vpl: GatherVpl, x: vec3f, c: ptr<function, CellSums>) {
    let n = vpl.normal.xyz;
    let d = x - vpl.position.xyz;
    let dist2 = max(dot(d, d), 1e-12);
    let to_cell = d * inverseSqrt(dist2);
    let cos_v = dot(n, to_cell);
    if (cos_v <= 0.0) { return; }
    let e = vpl.flux.rgb * (cos_v / (PI * (dist2 + vpl.position.w / PI)));
    let y = sh4(to_cell);
    let lights = u32(vpl.normal.w);
    if ((lights & VPL_RHO) != 0u) {
        (*c).rho_r += e.r * y;
        (*c).rho_g += e.g * y;
        (*c).rho_b += e.b * y;
    }
    if ((lights & (VPL_DELTA | VPL_DELTA_HIDDEN)) != 0u) {
        let signed = select(e, -e, (lights & VPL_DELTA_HIDDEN) != 0u);
        (*c).delta_r += signed.r * y;
        (*c).delta_g += signed.g * y;
        (*c).delta_b += signed.b * y;
    }
    if ((lights & VPL_MU) != 0u) {
        (*c).mu_r += e.r * y;
        (*c).mu_g += e.g * y;
        (*c).mu_b += e.b * y;
    }
}

// Vectors per cell in `partials`: V_ρ's three channels, or V_ρ's, V_Δ's and V_μ's.
fn partial_vectors() -> u32 { return select(9u, 3u, bounce_propagated()); }

// Whether block `block` of 4³ cells (of the gathered box) holds a cell the merge reads: with
// the bounce light gathered the box is the whole volume and `mark_cells` (mark_cells.wgsl) has
// flagged the blocks; V_ρ alone gathers its box whole.
fn block_read(block: vec3u, blocks: vec3u) -> bool {
    if (bounce_propagated()) { return true; }
    return blocks_read[(block.z * blocks.y + block.y) * blocks.x + block.x] != 0u;
}

fn cells_gathered() -> u32 { return gather_info.size.x * gather_info.size.y * gather_info.size.z; }

@compute @workgroup_size(64)
fn gather(@builtin(workgroup_id) group: vec3u, @builtin(local_invocation_index) t: u32) {
    let size = gather_info.size.xyz;
    let blocks = (size + 3u) / 4u;
    let block = vec3u(group.x % blocks.x, (group.x / blocks.x) % blocks.y, group.x / (blocks.x * blocks.y));
    let id = block * 4u + vec3u(t % 4u, (t / 4u) % 4u, t / 16u);
    let x = params.origin.xyz + (vec3f(id + gather_info.chunks_first.yzw) + 0.5) * cell_side();
    // A block no pixel reads gathers no VPL (its count through workgroup memory, so that the
    // loop's barriers stay in uniform control flow: an early return crashed lavapipe).
    if (t == 0u) { shared_count = select(0u, vpl_count, block_read(block, blocks)); }
    let count = workgroupUniformLoad(&shared_count);
    if (count == 0u) { return; }
    let chunks = gather_info.chunks_first.x;
    let per_chunk = (count + chunks - 1u) / chunks;
    let begin = group.y * per_chunk;
    let end = min(begin + per_chunk, count);
    var c: CellSums;
    for (var first = begin; first < end; first += TILE) {
        if (first + t < end) { tile[t] = vpls[first + t]; }
        workgroupBarrier();
        let n = min(TILE, end - first);
        for (var i = 0u; i < n; i++) {
            vpl_light(tile[i], x, &c);
        }
        workgroupBarrier();
    }
    if (any(id >= size)) { return; }
    let at = (group.y * cells_gathered() + (id.z * size.y + id.y) * size.x + id.x) * partial_vectors();
    partials[at] = c.rho_r;
    partials[at + 1u] = c.rho_g;
    partials[at + 2u] = c.rho_b;
    if (bounce_propagated()) { return; }
    partials[at + 3u] = c.delta_r;
    partials[at + 4u] = c.delta_g;
    partials[at + 5u] = c.delta_b;
    partials[at + 6u] = c.mu_r;
    partials[at + 7u] = c.mu_g;
    partials[at + 8u] = c.mu_b;
}

@compute @workgroup_size(4, 4, 4)
fn gather_sum(@builtin(global_invocation_id) id: vec3u) {
    let size = gather_info.size.xyz;
    if (any(id >= size) || !block_read(id / 4u, (size + 3u) / 4u)) { return; }
    let h = cell_side();
    let cell = cell_index(vec3i(id + gather_info.chunks_first.yzw));
    let in_box = (id.z * size.y + id.y) * size.x + id.x;
    let k = partial_vectors();
    for (var j = 0u; j < k; j++) {
        // Volume v (V_ρ, V_Δ, V_μ as the accumulated volumes), channel ch.
        let v = j / 3u;
        let ch = j % 3u;
        if (v == 0u && rho_propagated()) { continue; }
        var c = vec4f(0.0);
        for (var chunk = 0u; chunk < gather_info.chunks_first.x; chunk++) {
            c += partials[(chunk * cells_gathered() + in_box) * k + j];
        }
        c *= h * h;
        if (v == 1u) {
            let word = ((SOURCE_DIRECT * 3u + ch) * cells() + cell) * 4u;
            let q = vec4i(injected[word], injected[word + 1u], injected[word + 2u], injected[word + 3u]);
            c += vec4f(q) / params.scale.x;
        }
        volumes[(v * 3u + ch) * cells() + cell] = c;
    }
}
