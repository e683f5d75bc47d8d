// The volumes gathered from VPLs instead of propagated: V_ρ (`dlpv.virtual_light`), the
// virtual objects' light from the real scene, and V_μ with V_Δ's indirect change
// (`dlpv.bounce_light`), the real surfaces' bounce light and its change. The propagation walks
// rather than flies (docs/benchmarks.md, 2026-12-04: a lit wall reaches a surface 8 cells away
// with 5 % of its irradiance after 32 steps and piles up near itself; 2026-12-06: a floor lit
// itself through its own cells), so that the virtual objects took 200× too little light from
// far walls and too much beside a lit floor; a sum over VPLs has the inverse-square falloff at
// every distance.
//
// `aggregate`: one workgroup per block of `gather_info.w`² texels of a pair of maps, its texels
// summed into VPLs by what they light (reflected flux, flux-weighted position and normal, the
// patch's area; vpl_aggregate.wgsl); `photo_tiles` the same of the photo's light of the real
// surfaces the camera sees (vpl_photo.wgsl); `mark_cells` the blocks of cells the pixels read
// (mark_cells.wgsl). `gather`: one invocation per cell, the radiance of every VPL arriving at
// the cell's centre projected onto the cell's SH (the SH of a direction, Σ E·Y(ω)), scaled to
// the volume's intensity convention (× h², read by the merge as ⟨c, clamped cosine(−n)⟩ / h²).

struct GatherVpl {
    // xyz: position; w: area of the patch (m²)
    position: vec4f,
    // xyz: unit normal; w: the volumes it lights (VPL_* bits, as a float)
    normal: vec4f,
    // rgb: reflected flux (W); w: unused
    flux: vec4f,
}

// Mirrors `GatherInfo` in vpl_gather.rs: which cells are gathered.
struct GatherInfo {
    // x: chunks of the VPLs; yzw: the first cell gathered
    chunks_first: vec4u,
    // xyz: cells gathered along each axis (which volumes are gathered: volume.wgsl
    // `rho_propagated`, `bounce_propagated`); w: parts with visibility maps at most along each
    // axis (visibility.wgsl)
    size: vec4u,
    // xyz: the first cell of V_ρ's, those virtual pixels read; w: the index of the first of the
    // virtual surfaces' cells' VPLs (`cell_vpls`, after room for all the maps' and the photo's)
    rho_first: vec4u,
    // xyz: one past its last cell; w: unused
    rho_end: vec4u,
}

// What a VPL lights: V_ρ, V_μ, V_Δ positively (a virtual surface's light, a virtual lamp's
// on a real one) or negatively (a real surface's that a virtual one hides from the light).
// V_ρ has bands 0–2 (vpl_gather.wgsl `RhoSums`).
const VPL_RHO: u32 = 1u;
const VPL_MU: u32 = 2u;
const VPL_DELTA: u32 = 4u;
const VPL_DELTA_HIDDEN: u32 = 8u;
// Taken from V_ρ: a real surface the camera sees (its photo's light is in V_ρ, vpl_photo.wgsl)
// that a virtual surface hides from the light — the virtual objects' shadow on it.
const VPL_RHO_HIDDEN: u32 = 16u;
// A virtual surface's cell passing on the light it takes (vpl_aggregate.wgsl `cell_vpls`): it
// lights no cell of V_ρ beside its own plane (vpl_gather.wgsl `lights_rho_cell`).
const VPL_CELL: u32 = 32u;
