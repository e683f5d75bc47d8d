// Bindings and helpers shared by the VPL passes (Knecht §2.7–§2.8).

struct VplParams {
    // VPL count, frame index, source count, light count
    counts: vec4u,
    // RSM resolution, RSM levels, RSM pyramid stride, interleave² (VPL subsets)
    rsm: vec4u,
    // probe pyramid finest width, height, level count, 1 if there is a probe
    probe: vec4u,
    // probe intensity, total importance, unused, unused
    probe_scale: vec4f,
    // scene bounding sphere: centre, radius
    scene: vec4f,
    // distribution (0 equal, 1 weighted, 2 flux), bounce method (0 off, 1 importance, 2 fitness),
    // real points, virtual points
    modes: vec4u,
    // cos(bounce cone), total real surface area, total virtual surface area, d_min (the VPL
    // distance clamp, m)
    bounce: vec4f,
    // virtual bounding spheres, 1 if the probe's light reflected by traced surfaces flies as
    // the specular stage's photons (RenderSettings::probe_caustics), the punctual lights'
    // photon slots (0: no caustic VPLs), photons per light and kind
    strata: vec4u,
    world_from_probe: mat4x4f,
}

struct Source {
    // kind (0 punctual light, 1 environment, 2 multiple bounce, 3 environment bounce, 4 the
    // punctual lights' caustics), light index, unused, unused
    info: vec4u,
    // weight for the weighted distribution, unused…
    weight: vec4f,
}

// State of one multiple-bounce slot between its passes.
struct BounceSlot {
    // xyz: ray origin; w: 0 inactive, 1 a ray (surface source), 2 a surface point lit by the
    // probe (environment source)
    origin: vec4f,
    // ray: xyz unit direction ω_o, w its density over all slots (per steradian);
    // surface point: xy the random numbers that pick the point
    direction: vec4f,
    // rgb: power carried by the ray, divided by selection probability and slot count;
    // w: selection probability of the source
    carry: vec4f,
    // source flags (x̄, ir), source VPL index in the previous buffer, source kind, point index
    info: vec4u,
}

const SLOT_RAY: f32 = 1.0;
const SLOT_POINT: f32 = 2.0;

const SOURCE_LIGHT: u32 = 0u;
const SOURCE_ENVIRONMENT: u32 = 1u;
const SOURCE_BOUNCE: u32 = 2u;
const SOURCE_ENVIRONMENT_BOUNCE: u32 = 3u;
const SOURCE_CAUSTICS: u32 = 4u;

// The power a VPL sends into the scene (selection weight of bounce sources and of the flux
// distribution).
fn vpl_flux(v: Vpl, scene_radius: f32) -> f32 {
    switch (vpl_kind(v)) {
        case 1u: { return luminance(v.power.rgb * v.albedo.rgb); }
        case 2u: { return luminance(v.power.rgb) * PI * scene_radius * scene_radius; }
        default: { return 0.0; }
    }
}

// Selection weight of a previous VPL as the multiple-bounce source's origin.
fn surface_flux(v: Vpl, radius: f32) -> f32 {
    return select(0.0, vpl_flux(v, radius), vpl_kind(v) == VPL_SURFACE);
}

// Slot range of every source: (start, count).
fn source_of_slot(slot: u32, source_count: u32) -> u32 {
    for (var s = 0u; s < source_count; s++) {
        let r = ranges[s];
        if (slot >= r.x && slot < r.x + r.y) { return s; }
    }
    return source_count;
}

fn empty_vpl() -> Vpl {
    var v: Vpl;
    v.info = vec4u(0u, 0u, VPL_EMPTY, 0u);
    return v;
}
