// A pair of a light's maps, real-only and virtual-only (inject.wgsl, vpl_aggregate.wgsl):
// whether the virtual map's texel `virt` hides the real map's `real` from `light` — a virtual
// surface is hit and lies nearer the light than any real one (shaders/lib/lights.wgsl
// `rsm_height`: higher is nearer). Their nearer hit is R_ρ's texel, the real one R_μ's.
fn virtual_nearer(light: Light, real: RsmTexel, virt: RsmTexel) -> bool {
    let real_hit = real.position.w > 0.5;
    return virt.position.w > 0.5
        && (!real_hit || rsm_height(light, virt.position.xyz) > rsm_height(light, real.position.xyz));
}
