// One texel of a reflective shadow map (src/methods/rsm): the surface a light layer's texel
// sees and the power it receives. Written by the RSM resolve, read by `dir`'s VPL placement
// and `dlpv`'s injection and merge.

struct RsmTexel {
    // xyz: world position; w: 1 where a surface was hit, 0 elsewhere
    position: vec4f,
    // xyz: unit normal on the side facing the light; w: roughness
    normal: vec4f,
    // rgb: base color; w: metallic
    albedo: vec4f,
    // rgb: power Φ reaching this texel's patch (W); w: importance (luminance of reflected power)
    power: vec4f,
    // dielectric F0 (mean), dielectric F90, 1 if the surface is real, surface area seen
    // through the texel (m²)
    material: vec4f,
}
