// `gather` of the volumes gathered from VPLs (vpl.wgsl): V_ρ over the cells of the
// virtual content's box and one cell around it (the only ones virtual pixels read), with the
// bounce light gathered V_μ and V_Δ's indirect change over every cell (real pixels read any),
// each VPL adding to the volumes it lights (VPL_*): a workgroup per 4³ cells and chunk of the
// VPLs, which it reads 64 at a time into workgroup memory, each invocation one cell's sum over
// the chunk (`gather`); then each cell's chunks summed (`gather_sum`). One invocation per cell
// over all VPLs ran a few waves on the whole GPU, each waiting on its reads: 7 ms for
// cornell's 6 500 cells and 12 000 VPLs on an H100. A VPL's patch
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
// The maps' and the photo's VPLs, the virtual surfaces' cells' (from `rho_first.w` on).
@group(0) @binding(4) var<storage, read> vpl_count: array<u32, 2>;
// Per chunk, per cell gathered: its sums over the chunk, `RHO_VECTORS` of V_ρ (`RhoSums`),
// then three of V_Δ and three of V_μ (a channel each; `BounceSums`).
@group(0) @binding(5) var<storage, read_write> partials: array<vec4f>;
// The injection (inject.wgsl), for V_Δ's direct change.
@group(0) @binding(6) var<storage, read> injected: array<i32>;
// Per block of 4³ cells, 1 where a pixel reads one of them (`mark_cells`).
@group(0) @binding(7) var<storage, read> blocks_read: array<u32>;
// V_ρ's band 2 per cell (volume.wgsl `rho_band2`), which `gather_sum` writes with V_ρ.
@group(0) @binding(8) var<storage, read_write> rho_band2: array<vec4f>;
// Per cell the plane of the virtual surfaces in it that most texels face and their albedo
// (vpl_aggregate.wgsl `cell_vpls`), with `virtual_bounce`.
@group(0) @binding(9) var<storage, read> planes: array<vec4f>;

// Per part of V_ρ's blocks, its visibility map (visibility_maps.wgsl), with
// `virtual_bounce`.
@group(0) @binding(10) var<storage, read> visibility: array<u32>;

// Whether the path from `a` (a VPL) to `x` (a cell's centre, in cell coordinates) crosses a
// virtual surface (visibility.wgsl `first_crossing`). The first and the last cell and a half
// are left out: a VPL on a virtual surface leaves its own plane, and the cells the merge reads
// beside a face lie partly behind it.
fn blocked(a: vec3f, x: vec3f) -> bool {
    let ca = cell_coords(a);
    let d = x - ca;
    let len = length(d);
    if (len < 3.0) { return false; }
    return first_crossing(ca, d / len, 1.5, len - 1.5, true) < 1e29;
}

// The same from part `part`'s centre to `a`, read from the part's map where it has one (the
// distance to the first crossing toward the texel of `a`'s direction; the march where it has
// none). At 1080p on the H100 (moving) the gather took 0.35 ms on cornell with the maps,
// 0.94 with a march per VPL and part; cornell's region FLIP (lavapipe) 0.1310 against 0.1282.
// Marching the paths shorter than 8 / 16 cells took it to 0.1304 / 0.1293 at 0.12 / 0.33 ms
// more; the open share of the four texels around the direction, 0.1306 (docs/benchmarks.md,
// 2026-12-06).
fn part_blocked(part: vec3u, a: vec3f) -> bool {
    let centre = part_centre(part);
    let m = part_map(part);
    if (m == 0xffffffffu) { return blocked(a, centre); }
    let d = cell_coords(a) - centre;
    let len = length(d);
    if (len < 3.0) { return false; }
    let texel = min(vec2u(octahedral_uv(d / len) * f32(MAP_SIDE)), vec2u(MAP_SIDE - 1u));
    let i = texel.y * MAP_SIDE + texel.x;
    let q = (visibility[m * MAP_WORDS + i / 2u] >> (16u * (i & 1u))) & 0xffffu;
    return q != NO_CROSSING && f32(q) / MAP_UNITS <= len - 1.5;
}

const TILE: u32 = 64u;
var<workgroup> tile: array<GatherVpl, 64>;
var<workgroup> shared_count: u32;
// Per VPL of the tile, one bit per part of the workgroup's 4³ cells (`VISIBILITY_PARTS`): the
// virtual content blocks its path to the part's centre (`bounce_visible`).
var<workgroup> tile_blocked: array<u32, 64>;

// The workgroup's 4³ cells are tested for the visibility of a VPL in parts of 2³ cells, at
// their centres (visibility.wgsl): in V_ρ's cells (`dlpv.virtual_bounce`; from the parts'
// maps), or in every cell (`dlpv.bounce_visibility`; by a march outside V_ρ's blocks). At
// 1080p on an H100 (moving, docs/benchmarks.md, 2026-12-06), marching, the gather over every
// cell took 2.2–2.9 ms more tested per cell (64 paths per VPL), 0.5–0.9 ms per part of 2³
// (8), 0.08–0.16 ms once per workgroup; cornell's region FLIP (lavapipe) 0.1348 / 0.1362 /
// 0.1384. Once per workgroup in V_ρ's cells, where the cells a face's pixels read lie within
// a part of it, left the light of the far side of a block on its faces (cornell 0.1655
// against 0.1320).
const VISIBILITY_PARTS: u32 = 8u;

// Whether a VPL of `lights` at `vpl` (a virtual surface's cell: `VPL_CELL`) lights V_ρ at
// cell centre `x`: a cell's light lights no cell within a cell and a half of its own plane,
// which are those its own surface's pixels read (its light along its face went into the
// face itself, brightening cornell's blocks by 8 of 255).
fn lights_rho_cell(vpl: GatherVpl, lights: u32, x: vec3f) -> bool {
    if ((lights & VPL_CELL) == 0u) { return true; }
    return abs(dot(vpl.normal.xyz, x - vpl.position.xyz)) >= 1.5 * cell_side();
}

// One cell's sums of V_ρ per channel: bands 0–1, band 2's coefficients 4–7, and coefficient
// 8 of the three channels. Nine coefficients: with four, light from behind a face subtracted a
// third of itself from the face and light along it added a third (the clamped cosine of bands
// 0–1, 1/3 + 2/3·cos θ of its peak), and cornell's virtual faces took the colours of the walls
// beside them (docs/benchmarks.md, 2026-12-06). Fields, not an array: an array indexed in a
// loop went to local memory, and the gather ran 8–12 times slower (the same, 2026-12-06).
struct RhoSums {
    r: vec4f, g: vec4f, b: vec4f,
    r2: vec4f, g2: vec4f, b2: vec4f, rgb8: vec4f,
}

// One cell's sums of V_Δ and V_μ per channel, four coefficients.
struct BounceSums {
    delta_r: vec4f, delta_g: vec4f, delta_b: vec4f,
    mu_r: vec4f, mu_g: vec4f, mu_b: vec4f,
}

// Vectors of V_ρ in a cell's partial sums (`RhoSums`); V_Δ's and V_μ's three each follow.
const RHO_VECTORS: u32 = 7u;

// The irradiance one VPL gives at `x`, a cell centre, and the way its light goes there
// (`e` zero behind the VPL).
struct VplAtCell {
    e: vec3f,
    way: vec3f,
}

fn vpl_at_cell(vpl: GatherVpl, x: vec3f) -> VplAtCell {
    let d = x - vpl.position.xyz;
    let dist2 = max(dot(d, d), 1e-12);
    let way = d * inverseSqrt(dist2);
    let cos_v = max(dot(vpl.normal.xyz, way), 0.0);
    return VplAtCell(vpl.flux.rgb * (cos_v / (PI * (dist2 + vpl.position.w / PI))), way);
}

// One VPL's light at a cell (`at`, `lights`: its VPL_* bits) added to V_ρ as SH coefficients
// per channel, E·Y(ω) (the same VPL in every invocation of the workgroup: the tests are
// uniform).
fn rho_light(at: VplAtCell, lights: u32, c: ptr<function, RhoSums>) {
    if ((lights & (VPL_RHO | VPL_RHO_HIDDEN)) == 0u) { return; }
    let e = select(at.e, -at.e, (lights & VPL_RHO_HIDDEN) != 0u);
    let y = sh4(at.way);
    (*c).r += e.r * y;
    (*c).g += e.g * y;
    (*c).b += e.b * y;
    let y2 = sh9_band2(at.way);
    (*c).r2 += e.r * y2;
    (*c).g2 += e.g * y2;
    (*c).b2 += e.b * y2;
    (*c).rgb8 += vec4f(e * sh9_y8(at.way), 0.0);
}

// The same for V_Δ and V_μ.
fn bounce_light(at: VplAtCell, lights: u32, c: ptr<function, BounceSums>) {
    let y = sh4(at.way);
    if ((lights & (VPL_DELTA | VPL_DELTA_HIDDEN)) != 0u) {
        let signed = select(at.e, -at.e, (lights & VPL_DELTA_HIDDEN) != 0u);
        (*c).delta_r += signed.r * y;
        (*c).delta_g += signed.g * y;
        (*c).delta_b += signed.b * y;
    }
    if ((lights & VPL_MU) != 0u) {
        (*c).mu_r += at.e.r * y;
        (*c).mu_g += at.e.g * y;
        (*c).mu_b += at.e.b * y;
    }
}

// Vectors per cell in `partials`: V_ρ's, or V_ρ's, V_Δ's and V_μ's.
fn partial_vectors() -> u32 { return select(RHO_VECTORS + 6u, RHO_VECTORS, bounce_propagated()); }

// Whether block `block` of 4³ cells (of the gathered box) holds a cell the merge reads: with
// the bounce light gathered the box is the whole volume and `mark_cells` (mark_cells.wgsl) has
// flagged the blocks.
fn block_read(block: vec3u, blocks: vec3u) -> bool { return (block_bits(block, blocks) & BLOCK_READ) != 0u; }

// Whether block `block` holds or borders a virtual surface's cell (`BLOCK_NEAR_VIRTUAL`, with
// `dlpv.virtual_bounce`, when the gathered box is the whole volume).
fn block_near_virtual(block: vec3u, blocks: vec3u) -> bool {
    return virtual_bounce() && (block_bits(block, blocks) & BLOCK_NEAR_VIRTUAL) != 0u;
}

fn cells_gathered() -> u32 { return gather_info.size.x * gather_info.size.y * gather_info.size.z; }

// The first VPL and one past the last of chunk `chunk` of `count`.
fn chunk_range(chunk: u32, count: u32) -> vec2u {
    let chunks = gather_info.chunks_first.x;
    let per_chunk = (count + chunks - 1u) / chunks;
    let begin = chunk * per_chunk;
    return vec2u(begin, min(begin + per_chunk, count));
}

// One workgroup per 4³ cells of the gathered box and chunk: V_μ's and V_Δ's sums with the
// bounce light gathered, V_ρ's in the blocks that hold its cells (GatherInfo `rho_first`,
// `rho_end`: those virtual pixels read; a workgroup's test, uniform). Summing V_ρ's nine
// coefficients in every cell the bounce light needs took the gather from 0.15–0.19 to
// 0.26–0.34 ms at 1080p on the H100, and V_ρ's cells in a pass of their own (a few blocks,
// too few workgroups to fill the GPU) 0.21–0.32 ms (docs/benchmarks.md, 2026-12-06). A block no
// pixel reads gathers no VPL (its count through workgroup memory, so that the loop's barriers
// stay in uniform control flow: an early return crashed lavapipe).
@compute @workgroup_size(64)
fn gather(@builtin(workgroup_id) group: vec3u, @builtin(local_invocation_index) t: u32) {
    let size = gather_info.size.xyz;
    let blocks = (size + 3u) / 4u;
    let block = vec3u(group.x % blocks.x, (group.x / blocks.x) % blocks.y, group.x / (blocks.x * blocks.y));
    let id = block * 4u + vec3u(t % 4u, (t / 4u) % 4u, t / 16u);
    let first_cell = gather_info.chunks_first.yzw + block * 4u;
    let x = params.origin.xyz + (vec3f(id + gather_info.chunks_first.yzw) + 0.5) * cell_side();
    let bounce = !bounce_propagated();
    let local = vec3u(t % 4u, (t / 4u) % 4u, t / 16u) / PART_CELLS;
    let parts = 4u / PART_CELLS;
    let my_part = (local.z * parts + local.y) * parts + local.x;
    let rho = !rho_propagated() && all(first_cell < gather_info.rho_end.xyz)
        && all(first_cell + 4u > gather_info.rho_first.xyz);
    // The bounce light where a pixel reads it; V_ρ where a pixel reads it or, with the virtual
    // surfaces' bounce, beside any virtual surface: the faces the camera does not see pass on
    // their light too (cornell's cube lights the tall block's foot with its side). In all of
    // V_ρ's box, the empty cells between the surfaces cost as much.
    let read = !bounce || block_read(block, blocks);
    // The cells' VPLs light V_ρ, and V_Δ where the paths are tested (`tested`): blocks of
    // neither leave them out.
    let maps = vpl_count[0];
    let all_vpls = select(maps, maps + vpl_count[1], rho || bounce_visible());
    if (t == 0u) { shared_count = select(0u, all_vpls, read || (rho && block_near_virtual(block, blocks))); }
    let count = workgroupUniformLoad(&shared_count);
    if (count == 0u) { return; }
    // The paths are tested in V_ρ's cells with the virtual surfaces' bounce (also where no
    // pixel reads them: the faces the camera does not see pass on their light), in every cell
    // with the bounce's visibility (uniform: the workgroup's).
    let tested = bounce && virtual_bounce() && (rho || bounce_visible());
    let range = chunk_range(group.y, count);
    var r: RhoSums;
    var c: BounceSums;
    for (var first = range.x; first < range.y; first += TILE) {
        let i = first + t;
        if (i < range.y) { tile[t] = vpls[select(gather_info.rho_first.w + i - maps, i, i < maps)]; }
        workgroupBarrier();
        // Invocation t tests VPL t of the tile against the parts' centres (the test is
        // uniform: the barrier stays in uniform control flow, and off it costs nothing).
        if (tested) {
            if (first + t < range.y) {
                let source = tile[t].position.xyz;
                var bits = 0u;
                for (var k = 0u; k < VISIBILITY_PARTS; k++) {
                    let part = vec3u(k % parts, (k / parts) % parts, k / (parts * parts));
                    if (part_blocked(first_cell / PART_CELLS + part, source)) { bits |= 1u << k; }
                }
                tile_blocked[t] = bits;
            }
            workgroupBarrier();
        }
        let n = min(TILE, range.y - first);
        for (var i = 0u; i < n; i++) {
            let vpl = tile[i];
            let at = vpl_at_cell(vpl, x);
            let lights = u32(vpl.normal.w);
            let blocked_here = tested && ((tile_blocked[i] >> my_part) & 1u) != 0u;
            // A path the virtual content blocks carries nothing into V_ρ (with the virtual
            // surfaces' own light added, every path open let the light of a block's far side
            // through it onto its faces).
            if (rho && !blocked_here && lights_rho_cell(vpl, lights, x)) { rho_light(at, lights, &r); }
            if (bounce && read) {
                // A path the virtual content blocks: in L_rv none of the VPL's light arrives,
                // so V_Δ takes what V_μ gets (a real VPL) and adds nothing (a virtual one, or
                // one whose change is already that, the photo's VPL taking it all).
                // A virtual surface's cell lights V_Δ only where the paths are tested: the light
                // it passes on without the light it blocks made the real surfaces beside it
                // too bright (cornell-va's green wall beside the tall block, ×1.05 of the answer).
                var seen = select(lights, 0u, !tested && (lights & VPL_CELL) != 0u);
                if (blocked_here) {
                    seen = select(0u, VPL_MU | VPL_DELTA_HIDDEN, (lights & VPL_MU) != 0u);
                }
                bounce_light(at, seen, &c);
            }
        }
        workgroupBarrier();
    }
    if (any(id >= size)) { return; }
    let at = (group.y * cells_gathered() + (id.z * size.y + id.y) * size.x + id.x) * partial_vectors();
    if (rho) {
        partials[at] = r.r;
        partials[at + 1u] = r.g;
        partials[at + 2u] = r.b;
        partials[at + 3u] = r.r2;
        partials[at + 4u] = r.g2;
        partials[at + 5u] = r.b2;
        partials[at + 6u] = r.rgb8;
    }
    if (!bounce || !read) { return; }
    partials[at + 7u] = c.delta_r;
    partials[at + 8u] = c.delta_g;
    partials[at + 9u] = c.delta_b;
    partials[at + 10u] = c.mu_r;
    partials[at + 11u] = c.mu_g;
    partials[at + 12u] = c.mu_b;
}

@compute @workgroup_size(4, 4, 4)
fn gather_sum(@builtin(global_invocation_id) id: vec3u) {
    let size = gather_info.size.xyz;
    if (any(id >= size)) { return; }
    let in_volume = id + gather_info.chunks_first.yzw;
    // V_ρ's cells, and with the bounce light only the cells the pixels read (of either; all
    // of V_ρ's beside a virtual surface with the virtual surfaces' bounce, as `gather`).
    let read = bounce_propagated() || block_read(id / 4u, (size + 3u) / 4u);
    let rho = (read || block_near_virtual(id / 4u, (size + 3u) / 4u)) && all(in_volume >= gather_info.rho_first.xyz)
        && all(in_volume < gather_info.rho_end.xyz);
    let bounce = read && !bounce_propagated();
    if (!rho && !bounce) { return; }
    let h = cell_side();
    let cell = cell_index(vec3i(in_volume));
    let in_box = (id.z * size.y + id.y) * size.x + id.x;
    let k = partial_vectors();
    for (var j = 0u; j < k; j++) {
        if (j < RHO_VECTORS && (rho_propagated() || !rho)) { continue; }
        if (j >= RHO_VECTORS && !bounce) { continue; }
        var c = vec4f(0.0);
        for (var chunk = 0u; chunk < gather_info.chunks_first.x; chunk++) {
            c += partials[(chunk * cells_gathered() + in_box) * k + j];
        }
        c *= h * h;
        if (j >= 3u && j < RHO_VECTORS) {
            rho_band2[cell * 4u + j - 3u] = c;
            continue;
        }
        // Volume v (V_ρ, V_Δ, V_μ as the accumulated volumes), channel ch.
        let v = select(1u + (j - RHO_VECTORS) / 3u, 0u, j < 3u);
        let ch = select((j - RHO_VECTORS) % 3u, j, j < 3u);
        if (v == 1u) {
            let word = ((SOURCE_DIRECT * 3u + ch) * cells() + cell) * 4u;
            let q = vec4i(injected[word], injected[word + 1u], injected[word + 2u], injected[word + 3u]);
            c += vec4f(q) / params.scale.x;
        }
        volumes[(v * 3u + ch) * cells() + cell] = c;
    }
}
