// `gather` of V_ρ gathered from VPLs (rho_vpl.wgsl), over the cells of the virtual content's
// box and one cell around it (the only ones virtual pixels read): a workgroup per 4³ cells
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
@group(0) @binding(1) var<storage, read> rho_vpls: array<GatherVpl>;
// The accumulated V_ρ, V_Δ, V_μ; `gather_sum` writes V_ρ.
@group(0) @binding(2) var<storage, read_write> volumes: array<vec4f>;
@group(0) @binding(3) var<uniform> gather_info: RhoGatherInfo;
@group(0) @binding(4) var<storage, read> vpl_count: u32;
// Per chunk, per cell gathered, per channel: its sum over the chunk.
@group(0) @binding(5) var<storage, read_write> partials: array<vec4f>;

const TILE: u32 = 64u;
var<workgroup> tile: array<GatherVpl, 64>;
var<workgroup> shared_count: u32;

// The light of one VPL at `x`, a cell centre, added as SH coefficients per channel: E·Y(ω).
fn vpl_light(vpl: GatherVpl, x: vec3f, c: ptr<function, array<vec4f, 3>>) {
    let n = vpl.normal.xyz;
    let d = x - vpl.position.xyz;
    let dist2 = max(dot(d, d), 1e-12);
    let to_cell = d * inverseSqrt(dist2);
    let cos_v = dot(n, to_cell);
    if (cos_v <= 0.0) { return; }
    let e = vpl.flux.rgb * (cos_v / (PI * (dist2 + vpl.position.w / PI)));
    let y = sh4(to_cell);
    (*c)[0] += e.r * y;
    (*c)[1] += e.g * y;
    (*c)[2] += e.b * y;
}

fn cells_gathered() -> u32 { return gather_info.size.x * gather_info.size.y * gather_info.size.z; }

@compute @workgroup_size(64)
fn gather(@builtin(workgroup_id) group: vec3u, @builtin(local_invocation_index) t: u32) {
    let size = gather_info.size.xyz;
    let blocks = (size + 3u) / 4u;
    let block = vec3u(group.x % blocks.x, (group.x / blocks.x) % blocks.y, group.x / (blocks.x * blocks.y));
    let id = block * 4u + vec3u(t % 4u, (t / 4u) % 4u, t / 16u);
    let x = params.origin.xyz + (vec3f(id + gather_info.chunks_first.yzw) + 0.5) * cell_side();
    if (t == 0u) { shared_count = vpl_count; }
    let count = workgroupUniformLoad(&shared_count);
    let chunks = gather_info.chunks_first.x;
    let per_chunk = (count + chunks - 1u) / chunks;
    let begin = group.y * per_chunk;
    let end = min(begin + per_chunk, count);
    var c = array<vec4f, 3>(vec4f(0.0), vec4f(0.0), vec4f(0.0));
    for (var first = begin; first < end; first += TILE) {
        if (first + t < end) { tile[t] = rho_vpls[first + t]; }
        workgroupBarrier();
        let n = min(TILE, end - first);
        for (var i = 0u; i < n; i++) {
            vpl_light(tile[i], x, &c);
        }
        workgroupBarrier();
    }
    if (any(id >= size)) { return; }
    let at = (group.y * cells_gathered() + (id.z * size.y + id.y) * size.x + id.x) * 3u;
    partials[at] = c[0];
    partials[at + 1u] = c[1];
    partials[at + 2u] = c[2];
}

@compute @workgroup_size(4, 4, 4)
fn gather_sum(@builtin(global_invocation_id) id: vec3u) {
    let size = gather_info.size.xyz;
    if (any(id >= size)) { return; }
    let h = cell_side();
    let cell = cell_index(vec3i(id + gather_info.chunks_first.yzw));
    let in_box = (id.z * size.y + id.y) * size.x + id.x;
    for (var ch = 0u; ch < 3u; ch++) {
        var c = vec4f(0.0);
        for (var k = 0u; k < gather_info.chunks_first.x; k++) {
            c += partials[(k * cells_gathered() + in_box) * 3u + ch];
        }
        volumes[ch * cells() + cell] = c * (h * h);
    }
}
