// Photon G-buffers (reflections spec §2.17.1, Table T6.3) for every punctual light type (the
// documents had spots only). Each light shoots one photon per texel of a square map aimed at
// the bounding sphere of the traced objects: perspective for point and spot lights,
// orthographic for directional ones. Where a photon meets a traced object's surface, lit past
// the shadow maps, it splits into a reflected and a refracted photon (Schlick Fresnel from
// the IOR; the refracted one followed through the object's inside with total internal
// reflection and Beer–Lambert, as the camera's rays are), and both fly on through the
// impostors, across further specular surfaces up to `max_bounces`, to the diffuse surface
// they land on.
//
// Routing (§2.17.5, Eq. P12–P14): the L_rv photons fly through the whole world, their power
// shadowed by every caster; L_r photons exist only for a real light on a real object, fly
// through the real-only world and are shadowed by real casters only. A real caustic that a
// virtual object blocks (in either segment) stays in L_r and leaves L_rv, so that the
// difference takes it off the photo: the paper's Fig. 7a fails this (spec §5.1, L6).

struct CausticParams {
    // photon resolution, source count, sources (0 the punctual lights, 1 probe directions),
    // caustic buffer divisor
    info: vec4u,
    // bounding sphere of the traced instances: centre, radius
    casters: vec4f,
    // splat half-size min, max of the fine level, max of the coarse level (metres), depth
    // epsilon
    splat: vec4f,
}

// Photon slots of the group: sources × kinds × resolution².
fn photon_slots() -> u32 {
    return caustics.info.x * caustics.info.x * caustics.info.y * PHOTON_KINDS;
}

// One indirect draw per caustic level (wgpu's DrawIndirectArgs; the CPU resets it to
// (0, 1, 0, 0) every frame): cs_size lists the landed photons of each level and counts six
// vertices for each, so that the splat's vertex stage runs only for photons that landed.
struct SplatDraw {
    vertex_count: atomic<u32>,
    instance_count: u32,
    first_vertex: u32,
    first_instance: u32,
}

fn photon_index(light: u32, kind: u32, texel: vec2u) -> u32 {
    let res = caustics.info.x;
    return ((light * PHOTON_KINDS + kind) * res + texel.y) * res + texel.x;
}
