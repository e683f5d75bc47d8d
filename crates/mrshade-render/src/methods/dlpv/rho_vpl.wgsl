// V_ρ gathered from VPLs (`dlpv.virtual_light = "gathered"`): the virtual objects' light from
// the real scene, summed over the lights' VPLs at every cell instead of propagated. The
// propagation walks rather than flies (docs/benchmarks.md, 2026-12-04: a lit wall reaches a
// surface 8 cells away with 5 % of its irradiance after 32 steps and piles up near itself),
// so that the virtual objects took 200× too little light from far walls and too much beside
// a lit floor; a sum over VPLs has the inverse-square falloff at every distance.
//
// `aggregate`: one workgroup per block of `gather_info.w`² texels of a pair of maps: R_ρ's real
// texels (those no virtual surface hides, as V_ρ's injection) summed into one VPL (reflected
// flux, flux-weighted position and normal, the patch's area); `photo_tiles` the same of the
// photo's light of the real surfaces the camera sees (rho_photo.wgsl). `gather`: one invocation per
// cell, the radiance of every VPL arriving at the cell's centre projected onto the cell's SH
// (the SH of a direction, Σ E·Y(ω)), scaled to the volume's intensity convention (× h², read
// by the merge as ⟨c, clamped cosine(−n)⟩ / h²).

struct GatherVpl {
    // xyz: position; w: area of the patch (m²)
    position: vec4f,
    // xyz: unit normal; w: unused
    normal: vec4f,
    // rgb: reflected flux (W); w: unused
    flux: vec4f,
}

// Mirrors `GatherInfo` in rho.rs: which cells are gathered.
struct RhoGatherInfo {
    // x: chunks of the VPLs; yzw: the first cell gathered
    chunks_first: vec4u,
    // xyz: cells gathered along each axis
    size: vec4u,
}
