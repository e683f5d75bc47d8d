// The volumes of delta light propagation (Franke §2.12): a cube of `res`³ cells around the
// virtual content, each holding four SH coefficients of radiant intensity per color channel
// (three vec4f per cell, channel-major). Mirrors `DlpvParams` in mod.rs.

struct DlpvParams {
    // xyz: world position of the lower corner; w: cell side h (m)
    origin: vec4f,
    // cells per side, cells in all, this dispatch's source (0: V_ρ, 1: indirect change,
    // 2: direct change, 3: V_μ), 1 if propagation clamps negative flux (V_ρ, V_μ)
    info: vec4u,
    // fixed-point units per watt of injected intensity coefficients, unused…
    scale: vec4f,
}

const SOURCE_RHO: u32 = 0u;
const SOURCE_INDIRECT: u32 = 1u;
const SOURCE_DIRECT: u32 = 2u;
const SOURCE_MU: u32 = 3u;

fn cells() -> u32 { return params.info.y; }
fn cell_side() -> f32 { return params.origin.w; }
fn cell_index(c: vec3i) -> u32 {
    let res = i32(params.info.x);
    return u32((c.z * res + c.y) * res + c.x);
}
fn cell_inside(c: vec3i) -> bool {
    return all(c >= vec3i(0)) && all(c < vec3i(i32(params.info.x)));
}
// Continuous cell coordinates of world point `p` (cell centres at integers + 0.5).
fn cell_coords(p: vec3f) -> vec3f { return (p - params.origin.xyz) / cell_side(); }
