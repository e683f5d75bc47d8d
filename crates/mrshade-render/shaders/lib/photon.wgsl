// A landed photon of the caustics (reflections spec §2.17.1), as the specular stage's photon
// pass writes it and `dir`'s caustic VPLs (§2.18) read it.
struct Photon {
    // where it landed; w: 1 if it did
    position: vec4f,
    // the receiver's normal (facing the photon); w: the quad half-size of its splat (m)
    normal: vec4f,
    // power, W (rgb); w: the receiver's triangle + 1, as bits (bitcast<u32>)
    power: vec4f,
}

// Per light and texel: the reflected and the refracted photon of L_rv, then those of L_r.
const PHOTON_KINDS: u32 = 4u;

// The irradiance that a photon of `power` spread over its quad of half-size `half_size` gives
// the point at `local` (in half-sizes from its centre, inside the quad): a tent that
// integrates to one over the quad (the splat's and the world-space grid's kernel alike).
fn quad_irradiance(power: vec3f, local: vec2f, half_size: f32) -> vec3f {
    return power * quad_tent(local) / (half_size * half_size);
}

// The tent kernel at `local` (the quad's corners at ±1): 1 at the centre, 0 at the edges.
fn quad_tent(local: vec2f) -> f32 {
    return (1.0 - abs(local.x)) * (1.0 - abs(local.y));
}
