// The landed photons in world space (reflections spec §2.17.4: caustics are seen in
// reflections and refractions too), for the surfaces that reflected and refracted rays reach
// but the camera does not see, where the screen-space caustic buffer has no texel. A photon
// joins the level whose quads are at most GRID_LEVEL_STEP (√2) times its own (level L holds
// half-sizes up to splat_min · √2^L), and is listed in every cell of that level that the box
// around its quad (its footprint, with half a quad of slack off the plane) touches; level
// L's cells are as wide as its largest quads. A lookup then reads one cell per level: the
// photons listed there are those whose footprint reaches it, some four times those whose
// quad covers the point. The lists are contiguous ranges (a counting sort: cs_size counts
// per cell, cs_grid_ranges hands out the ranges, cs_grid_scatter fills them), whose reads do
// not wait on each other. (Linked lists per cell of 2√2 times the largest half-size, walked
// over the 2×2×2 cells nearest to the point on every level of powers of two, read eight to
// thirty times the covering photons: the resolve took 0.68 ms of a 4.05 ms frame at 1080p.)
//
// The grid's buffer: GRID_HEADER words (the levels that hold photons as bits, splat_min and
// the depth epsilon as bits, the box the photons' footprints span as order keys, the entries
// handed out), then each head's count, then its range's end (its start until the scatter).
// Cells of different keys may share a head (a photon is listed once per head): readers check
// each photon's level, and its quad decides the rest. The entries are indices of the punctual
// lights' photon G-buffer, where the photons' copies (`GridPhoton`) live.

struct GridPhoton {
    // where it landed; w: its quad half-size (m)
    position: vec4f,
    // the receiver's normal (facing the photon); w: which world's light it carries
    // (GRID_OF_RV, GRID_OF_R, GRID_OF_BOTH)
    normal: vec4f,
    // power, W (rgb); w: unused
    power: vec4f,
}

// GridPhoton.normal.w: a photon of L_rv, of L_r, or one of L_rv whose L_r twin (the same
// light and texel) landed the same, listed once for both worlds. A lookup that reads a subset
// of a crowded cell then adds the same photons to both worlds where no virtual part changed
// their paths (no virtual content: the photo, to the bit), and twins are listed once.
const GRID_OF_RV: f32 = 0.0;
const GRID_OF_R: f32 = 1.0;
const GRID_OF_BOTH: f32 = 2.0;
// GridCells packed for a photon that is not listed (its twin carries it).
const GRID_NOT_LISTED: vec4i = vec4i(0, 0, 0, -1);

const GRID_HEADER: u32 = 12u;
const GRID_LEVELS_WORD: u32 = 0u;
const GRID_SPLAT_MIN_WORD: u32 = 1u;
const GRID_EPSILON_WORD: u32 = 2u;
// (Word 3 is unused.)
// The box's lower corner (x, y, z; order keys complemented) and upper corner (order keys).
const GRID_BOX_MIN_WORD: u32 = 4u;
const GRID_BOX_MAX_WORD: u32 = 8u;
// Entries handed out to the cells' ranges so far (cs_grid_ranges).
const GRID_TOTAL_WORD: u32 = 11u;
// Ratio of the largest half-sizes of consecutive levels.
const GRID_LEVEL_STEP: f32 = 1.4142136;
// Levels at most (their largest half-sizes span splat_min to √2^31 times it).
const GRID_LEVELS: u32 = 32u;
// Most cells a footprint is listed in along an axis: it spans at most 3 of its level's
// largest half-sizes (2 in the plane, the slack off it), its cells are two of them wide.
const GRID_CELLS_PER_AXIS: i32 = 3;

fn grid_level(half_size: f32, splat_min: f32) -> u32 {
    let level = ceil(2.0 * log2(max(half_size / splat_min, 1.0)) - 1e-4);
    return min(u32(max(level, 0.0)), GRID_LEVELS - 1u);
}

// Cell width of level `level`: its largest quads' (2 · splat_min · √2^L).
fn grid_cell_size(level: u32, splat_min: f32) -> f32 {
    return 2.0 * splat_min * pow(GRID_LEVEL_STEP, f32(level));
}

// Heads of a grid buffer of `words` words (a count and a range end each).
fn grid_heads(words: u32) -> u32 {
    return (words - GRID_HEADER) / 2u;
}

// The head (0 … heads − 1) of the cell `cell` of level `level`.
fn grid_head(level: u32, cell: vec3i, heads: u32) -> u32 {
    let c = bitcast<vec3u>(cell);
    return hash_u32(hash_u32(hash_u32(c.x ^ (level * 0x9e3779b9u)) ^ c.y) ^ c.z) % heads;
}

// Where head `head`'s count and range end lie in the grid's buffer.
fn grid_count_word(head: u32) -> u32 {
    return GRID_HEADER + head;
}

fn grid_end_word(head: u32, heads: u32) -> u32 {
    return GRID_HEADER + heads + head;
}

// The cell of level `level` that holds point `x`.
fn grid_cell(x: vec3f, level: u32, splat_min: f32) -> vec3i {
    return vec3i(floor(x / grid_cell_size(level, splat_min)));
}

// Half-extent along the axes of the footprint of a quad of half-size `h` on a surface of
// normal `n`: the quad's box (its tangent frame's, as the splat and the lookup place it) and
// half a quad off the plane, for a lookup's point that the trace put beside where the
// photon's march did.
fn grid_reach(n: vec3f, h: f32) -> vec3f {
    let tb = tangent_frame(n);
    return h * (abs(tb[0]) + abs(tb[1]) + GRID_PLANE_SLACK * abs(n));
}

// How far off a photon's plane, in its quad's half-sizes, a lookup finds it (the footprint's
// slack; the splat's depth tolerance, a fraction of the camera distance, is far wider than a
// small quad's cells).
const GRID_PLANE_SLACK: f32 = 0.5;

// The cells of a photon's footprint (at `p`, half-extent `reach`, level `level`): the lowest
// and the count along each axis (at most GRID_CELLS_PER_AXIS).
struct GridCells {
    lo: vec3i,
    count: vec3i,
}

fn grid_cells(p: vec3f, reach: vec3f, level: u32, splat_min: f32) -> GridCells {
    let lo = grid_cell(p - reach, level, splat_min);
    let hi = grid_cell(p + reach, level, splat_min);
    return GridCells(lo, min(hi - lo + 1, vec3i(GRID_CELLS_PER_AXIS)));
}

// `c` and the photon's level in a vec4i (cs_size writes it, cs_grid_scatter reads it, so that
// the two passes list a photon in the same cells whatever their float arithmetic rounds).
fn grid_cells_pack(c: GridCells, level: u32) -> vec4i {
    let counts = vec3u(c.count - 1);
    return vec4i(c.lo, bitcast<i32>(level | (counts.x << 8u) | (counts.y << 10u) | (counts.z << 12u)));
}

fn grid_cells_unpack(v: vec4i) -> GridCells {
    let w = bitcast<u32>(v.w);
    return GridCells(v.xyz, vec3i(vec3u((w >> 8u) & 3u, (w >> 10u) & 3u, (w >> 12u) & 3u)) + 1);
}

fn grid_cells_level(v: vec4i) -> u32 {
    return bitcast<u32>(v.w) & 0xffu;
}

// The `k`-th cell of `c` (x fastest).
fn grid_cells_at(c: GridCells, k: i32) -> vec3i {
    return c.lo + vec3i(k % c.count.x, (k / c.count.x) % c.count.y, k / (c.count.x * c.count.y));
}

// The head of the `k`-th cell of `c` if no earlier cell of `c` has it (a photon is listed
// once per head), else GRID_NO_HEAD.
const GRID_NO_HEAD: u32 = 0xffffffffu;

fn grid_listed_head(c: GridCells, k: i32, level: u32, heads: u32) -> u32 {
    let head = grid_head(level, grid_cells_at(c, k), heads);
    for (var j = 0; j < k; j++) {
        if (grid_head(level, grid_cells_at(c, j), heads) == head) { return GRID_NO_HEAD; }
    }
    return head;
}

// A u32 that orders as the float `f` does (negative floats' bits complemented, positive
// ones' sign bit set), and back.
fn order_key(f: f32) -> u32 {
    let b = bitcast<u32>(f);
    return select(b | 0x80000000u, ~b, (b & 0x80000000u) != 0u);
}

fn from_order_key(k: u32) -> f32 {
    return bitcast<f32>(select(~k, k & 0x7fffffffu, (k & 0x80000000u) != 0u));
}

// The irradiance (rgb) that photon `p`'s quad gives point `x` with normal `n`, and 1 in a
// where the quad covers it (the splat's photon count); zero where the point lies off the
// quad, farther than `tolerance` off its plane, or facing another way (splat.wgsl's test).
fn grid_photon_irradiance(p: GridPhoton, x: vec3f, n: vec3f, tolerance: f32) -> vec4f {
    let d = x - p.position.xyz;
    let h = p.position.w;
    // No farther than the footprint reaches, so that cell boundaries do not decide.
    if (abs(dot(d, p.normal.xyz)) > min(tolerance, GRID_PLANE_SLACK * h) || dot(n, p.normal.xyz) < 0.5) {
        return vec4f(0.0);
    }
    let tb = tangent_frame(p.normal.xyz);
    let local = vec2f(dot(d, tb[0]), dot(d, tb[1])) / h;
    if (any(abs(local) >= vec2f(1.0))) { return vec4f(0.0); }
    return vec4f(quad_irradiance(p.power.rgb, local, h), 1.0);
}
