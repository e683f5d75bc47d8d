// The landed photons in world space (reflections spec §2.17.4: caustics are seen in
// reflections and refractions too), for the surfaces that reflected and refracted rays reach
// but the camera does not see, where the screen-space caustic buffer has no texel. Level L's
// cells are GRID_CELL_FACTOR · splat_min · 2^L wide, and a photon joins the smallest level
// whose cells are at least as wide as its quad (2√2 h, diagonal included), so a point's
// photons lie in the 2×2×2 cells of each level nearest to it: a *block*, named by its lowest
// cell. The photon pass lists each landed photon in the eight blocks that hold its cell, in
// contiguous ranges (a counting sort: cs_size counts per block, cs_grid_ranges hands out the
// ranges, cs_grid_scatter fills them), so that a lookup reads one block per level and walks
// one range whose reads do not wait on each other (a linked list per cell, walked over eight
// cells a level, made the resolve 0.68 ms of a 4.1 ms frame at 1080p).
//
// The grid's buffer: GRID_HEADER words (the levels that hold photons as bits, splat_min and
// the depth epsilon as bits, the box the photons' quads span as order keys, the entries
// handed out), then each block head's count, then its range's end (its start until the
// scatter). Blocks of different keys may share a head: readers check each photon's own cell.
// The entries are indices of the punctual lights' photon G-buffer, where the photons' copies
// (`GridPhoton`) live.

struct GridPhoton {
    // where it landed; w: its quad half-size (m)
    position: vec4f,
    // the receiver's normal (facing the photon); w: 0 a photon of L_rv, 1 of L_r
    normal: vec4f,
    // power, W (rgb); w: unused
    power: vec4f,
}

const GRID_HEADER: u32 = 12u;
const GRID_LEVELS_WORD: u32 = 0u;
const GRID_SPLAT_MIN_WORD: u32 = 1u;
const GRID_EPSILON_WORD: u32 = 2u;
// The box's lower corner (x, y, z; order keys complemented) and upper corner (order keys).
const GRID_BOX_MIN_WORD: u32 = 4u;
const GRID_BOX_MAX_WORD: u32 = 8u;
// Entries handed out to the blocks' ranges so far (cs_grid_ranges).
const GRID_TOTAL_WORD: u32 = 11u;
// Cell width at level 0 over splat_min: 2√2, a quad's diagonal at the smallest half-size.
const GRID_CELL_FACTOR: f32 = 2.8284271;
// Levels at most (their cells span splat_min to 2^15 times it).
const GRID_LEVELS: u32 = 16u;

fn grid_level(half_size: f32, splat_min: f32) -> u32 {
    let level = ceil(log2(max(half_size / splat_min, 1.0)) - 1e-4);
    return min(u32(max(level, 0.0)), GRID_LEVELS - 1u);
}

fn grid_cell_size(level: u32, splat_min: f32) -> f32 {
    return GRID_CELL_FACTOR * splat_min * f32(1u << level);
}

// Block heads of a grid buffer of `words` words (a count and a range end each).
fn grid_heads(words: u32) -> u32 {
    return (words - GRID_HEADER) / 2u;
}

// The head (0 … heads − 1) of the block `block` of level `level`.
fn grid_head(level: u32, block: vec3i, heads: u32) -> u32 {
    let c = bitcast<vec3u>(block);
    return hash_u32(hash_u32(hash_u32(c.x ^ (level * 0x9e3779b9u)) ^ c.y) ^ c.z) % heads;
}

// Where head `head`'s count and range end lie in the grid's buffer.
fn grid_count_word(head: u32) -> u32 {
    return GRID_HEADER + head;
}

fn grid_end_word(head: u32, heads: u32) -> u32 {
    return GRID_HEADER + heads + head;
}

// The heads of the eight blocks of level `level` that hold cell `cell`, each once (a head
// that two of them share: GRID_NO_HEAD the second time).
const GRID_NO_HEAD: u32 = 0xffffffffu;

fn grid_block_heads(cell: vec3i, level: u32, heads: u32) -> array<u32, 8> {
    var out: array<u32, 8>;
    for (var k = 0u; k < 8u; k++) {
        let head = grid_head(level, cell - vec3i(vec3u(k & 1u, (k >> 1u) & 1u, k >> 2u)), heads);
        var seen = false;
        for (var j = 0u; j < k; j++) { seen = seen || out[j] == head; }
        out[k] = select(head, GRID_NO_HEAD, seen);
    }
    return out;
}

// The block of level `level` a lookup at `x` reads: the 2×2×2 cells nearest to it.
fn grid_block(x: vec3f, level: u32, splat_min: f32) -> vec3i {
    return vec3i(floor(x / grid_cell_size(level, splat_min) - 0.5));
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

// The cell of level `level` that holds point `x`.
fn grid_cell(x: vec3f, level: u32, splat_min: f32) -> vec3i {
    return vec3i(floor(x / grid_cell_size(level, splat_min)));
}

// The irradiance (rgb) that photon `p`'s quad gives point `x` with normal `n`, and 1 in a
// where the quad covers it (the splat's photon count); zero where the point lies off the
// quad, farther than `tolerance` off its plane, or facing another way (splat.wgsl's test).
fn grid_photon_irradiance(p: GridPhoton, x: vec3f, n: vec3f, tolerance: f32) -> vec4f {
    let d = x - p.position.xyz;
    if (abs(dot(d, p.normal.xyz)) > tolerance || dot(n, p.normal.xyz) < 0.5) { return vec4f(0.0); }
    let h = p.position.w;
    let tb = tangent_frame(p.normal.xyz);
    let local = vec2f(dot(d, tb[0]), dot(d, tb[1])) / h;
    if (any(abs(local) >= vec2f(1.0))) { return vec4f(0.0); }
    return vec4f(quad_irradiance(p.power.rgb, local, h), 1.0);
}
