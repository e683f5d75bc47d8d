// The volumes of delta light propagation (Franke §2.12): a cube of `res`³ cells around the
// virtual content, each holding four SH coefficients of radiant intensity per color channel
// (three vec4f per cell, channel-major), and V_ρ gathered from VPLs its band 2 beside them,
// `rho_band2`: four vec4f per cell, coefficients 4–7 of red, green, blue, then coefficient 8
// of the three in rgb (vpl_gather.wgsl). Mirrors `DlpvParams` in mod.rs.

struct DlpvParams {
    // xyz: world position of the lower corner; w: cell side h (m)
    origin: vec4f,
    // cells per side, cells in all, this propagation dispatch's step (from 1; 0 for seeding
    // and injection), how VPLs are splatted (SPLAT_*)
    info: vec4u,
    // fixed-point units per watt of injected intensity coefficients, the angular radius (rad)
    // below which a probe light shadows real surfaces through its maps, unused…
    scale: vec4f,
    // propagation steps per source (SOURCE_*)
    steps: vec4u,
    // x: 1 when V_ρ is gathered from VPLs (vpl.wgsl): its source is neither injected nor
    // propagated, and the propagation writes the accumulated volumes from the second on;
    // y: 1 when the photo's light is in the gathered volumes (vpl_photo.wgsl); z: which of the
    // probe's shadows are soft (SOFT_REAL, SOFT_VIRTUAL); w: bit 0 when V_μ and V_Δ's
    // indirect change are gathered (`dlpv.bounce_light`): their sources are neither injected
    // nor propagated; bit 1 when the virtual content stands in the gathered bounce light's
    // paths in every cell (`dlpv.bounce_visibility`, vpl_gather.wgsl `blocked`); bit 2 when
    // the virtual surfaces pass on their light and stand in its way in V_ρ's cells
    // (`dlpv.virtual_bounce`, vpl_aggregate.wgsl `cell_vpls`)
    gathered: vec4u,
}

// `gathered.z`: the probe's shadows soft on real surfaces, on virtual ones.
const SOFT_REAL: u32 = 1u;
const SOFT_VIRTUAL: u32 = 2u;

fn rho_propagated() -> bool { return params.gathered.x == 0u; }
fn bounce_propagated() -> bool { return (params.gathered.w & 1u) == 0u; }
fn bounce_visible() -> bool { return (params.gathered.w & 2u) != 0u; }
fn virtual_bounce() -> bool { return (params.gathered.w & 4u) != 0u; }

// Bits of a block of 4³ cells in `blocks_read` (mark_cells.wgsl, vpl_aggregate.wgsl,
// vpl_gather.wgsl): a pixel reads one of its cells; a virtual surface's cell lies in it or
// beside it (`dlpv.virtual_bounce`: V_ρ is gathered there for the light the surface passes on).
const BLOCK_READ: u32 = 1u;
const BLOCK_NEAR_VIRTUAL: u32 = 2u;

// `info.w`: a VPL goes into the cell it lies in, or trilinearly into the eight around it.
const SPLAT_CELL: u32 = 0u;
const SPLAT_TRILINEAR: u32 = 1u;

// Sources of injection: V_ρ's VPLs, the indirect change, the direct change, V_μ's VPLs.
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
