// The cones' light at one pixel, before any material: the diffuse cones' irradiance of both
// solutions, the probe's visibility sums and the glossy cone's radiance (gather.wgsl traces
// it once per trace texel, resolve.wgsl blends the texels around each pixel, and the pixels
// that no texel around them is like trace their own, gather.wgsl cs_retrace).
struct Traced {
    e_rv: vec3f,
    e_r: vec3f,
    env_rv: vec3f,
    env_r: vec3f,
    env: vec3f,
    glossy_rv: vec3f,
    glossy_r: vec3f,
}

// The pixel's own material applied to its light, into the method's IndirectLight (group 2):
// L = ρ_d/π·E + F_spec·L_glossy (the glossy term not on mirror-like and transmissive
// materials, which the specular stage draws), L_r only on real pixels.
fn store_pixel_light(pixel: vec2i, flags: u32, t: Traced) {
    var s = pixel_surface(pixel);
    let m = materials[material_of(flags)];
    s.transmission = m.transmission.x;
    let specular_albedo = env_specular_albedo(s);
    let diffuse = env_diffuse_weight(s, specular_albedo) * s.base_color / PI;
    let glossy = select(specular_albedo, vec3f(0.0), is_traced(m));
    let l_rv = diffuse * t.e_rv + glossy * t.glossy_rv;
    let l_r = diffuse * t.e_r + glossy * t.glossy_r;
    store_indirect(pixel, l_rv, l_r * r_of(flags), t.env_rv, t.env_r, t.env);
}
