// The landed photons in world space (reflections spec §2.17.4: caustics are seen in
// reflections and refractions too), for the surfaces that reflected and refracted rays reach
// but the camera does not see, where the screen-space caustic buffer has no texel. The photon
// pass's cs_size copies every landed photon, with the quad half-size h it sized, into a list
// per cell of a hashed grid: level L's cells are GRID_CELL_FACTOR · splat_min · 2^L wide, and
// a photon joins the smallest level whose cells are at least as wide as its quad (2√2 h,
// diagonal included). A point's photons then lie in the 2×2×2 cells of each level nearest to
// it, and the resolve sums their quads' tent kernels there, the same irradiance the splat
// writes into the caustic buffer (caustics/splat.wgsl).
//
// The grid's buffer: GRID_HEADER words (the levels that hold photons as bits, splat_min and
// the depth epsilon as bits, the box the photons' quads span as order keys), then each
// cell's list head: its last photon + 1 (0: empty). Photon i of the punctual lights' photon
// G-buffer is listed at i, and stores the next one of its cell's list (`GridPhoton.power.w`).

struct GridPhoton {
    // where it landed; w: its quad half-size (m)
    position: vec4f,
    // the receiver's normal (facing the photon); w: 0 a photon of L_rv, 1 of L_r
    normal: vec4f,
    // power, W (rgb); w: the next photon of its cell + 1, as bits (0: the list ends)
    power: vec4f,
}

const GRID_HEADER: u32 = 12u;
const GRID_LEVELS_WORD: u32 = 0u;
const GRID_SPLAT_MIN_WORD: u32 = 1u;
const GRID_EPSILON_WORD: u32 = 2u;
// The box's lower corner (x, y, z; order keys complemented) and upper corner (order keys).
const GRID_BOX_MIN_WORD: u32 = 4u;
const GRID_BOX_MAX_WORD: u32 = 8u;
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

// The list head's index in the grid's buffer of the cell `cell` of level `level`, for a
// buffer of `words` words. Cells of different keys may share a head: readers check each
// photon's own cell.
fn grid_head(level: u32, cell: vec3i, words: u32) -> u32 {
    let c = bitcast<vec3u>(cell);
    let h = hash_u32(hash_u32(hash_u32(c.x ^ (level * 0x9e3779b9u)) ^ c.y) ^ c.z);
    return GRID_HEADER + h % (words - GRID_HEADER);
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
