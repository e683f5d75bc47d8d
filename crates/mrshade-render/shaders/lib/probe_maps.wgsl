// The probe's directional lights and their real-only and virtual-only maps
// (methods/probe_maps.rs), for shadowing the probe's light at a surface point. The including
// shader binds, in one group: probe_lookups (uniform array<ProbeLookup, PROBE_LIGHTS_MAX>),
// probe_heights (array<f32>: the maps' heights toward their lights, rsm_height) and
// probe_info (vec4u: lights, map side, the soft test's search reach in texels,
// probe_maps_soft.wgsl). Needs shaders/lib/lights.wgsl and shaders/lib/probe_light.wgsl
// before it.

// The most lights a probe is split into (`PROBE_LIGHTS_MAX` of mrshade-core's settings, the
// most `probe_lights` takes): `probe_lookups` is a uniform array of as many. Uniform, not
// storage: every invocation reads the same light at once, which a uniform buffer serves as
// one broadcast.
const PROBE_LIGHTS_MAX: u32 = 64u;

// One light as a shadow test of its maps reads it (ProbeLookup in probe_maps.rs): every
// pixel tests every light, so its words are few and made for the test.
struct ProbeLookup {
    // Continuous texel column and row of world point p in the light's maps: ⟨s, (p, 1)⟩,
    // ⟨t, (p, 1)⟩ (the maps are orthographic).
    s: vec4f,
    t: vec4f,
    // xyz: unit direction toward the light; w: the maps' bias, half a texel (m). Half a texel
    // is how far a point is lifted off its surface before the maps are read. Two texels lifted
    // a point out of an object's contact shadow by a centimetre: the probe lit the desk under
    // the bunny's rim and the rim from it (dvct's region FLIP on desk-bunny 0.0845 → 0.0756 at
    // half a texel, every diffuse scene lower, dlpv's too; a quarter of a texel lets the desk
    // shadow itself).
    toward_bias: vec4f,
    // rgb: intensity × colour
    intensity: vec4f,
    // real-only layer, virtual-only layer, angular radius (f32 bits), 0
    maps: vec4u,
}

// The texel of map `layer` that lifted point `q` falls in (`st`: its continuous texel
// coordinates), or -1 outside the map.
fn probe_map_texel(layer: u32, st: vec2f) -> i32 {
    let res = probe_info.y;
    if (any(st <= vec2f(0.0)) || any(st >= vec2f(f32(res)))) { return -1; }
    let texel = min(vec2u(st), vec2u(res - 1u));
    return i32((layer * res + texel.y) * res + texel.x);
}

// Whether the map texel `texel` holds a surface nearer to the light than a point of
// rsm_height `height`, beyond `bias` (a texel that sees nothing holds NO_RSM_HEIGHT: never).
fn probe_map_blocked(texel: i32, height: f32, bias: f32) -> bool {
    if (texel < 0) { return false; }
    return probe_heights[texel] - height > bias;
}

// Probe light `i` seen from `p` (normal `n`): its maps, its irradiance E·⟨n, l⟩₊ and that
// weighted by its sharpness (probe_light_sharpness), where the point lifted by the maps' bias
// falls in them, that point's height toward the light (rsm_height, as the maps' texels hold
// theirs) and the bias. `e` first (probe_map_irradiance): about half the lights lie below a
// surface, and their maps need not be read.
struct ProbeMapLight {
    maps: vec4u,
    e: vec3f,
    w: vec3f,
    st: vec2f,
    height: f32,
    bias: f32,
}

// Light `i` and its irradiance E·⟨n, l⟩₊ at a surface of normal `n`.
struct ProbeMapIrradiance {
    lookup: ProbeLookup,
    e: vec3f,
}

fn probe_map_irradiance(i: u32, n: vec3f) -> ProbeMapIrradiance {
    let lookup = probe_lookups[i];
    return ProbeMapIrradiance(lookup, lookup.intensity.rgb * max(dot(n, lookup.toward_bias.xyz), 0.0));
}

// The rest of probe_map_light for a light that reaches the point.
fn probe_map_light(k: ProbeMapIrradiance, p: vec3f, n: vec3f, sharp_below: f32) -> ProbeMapLight {
    let bias = k.lookup.toward_bias.w;
    let q = vec4f(p + n * bias, 1.0);
    let st = vec2f(dot(k.lookup.s, q), dot(k.lookup.t, q));
    // rsm_height of a directional light: the position along the direction toward it.
    let height = dot(q.xyz, k.lookup.toward_bias.xyz);
    let w = k.e * probe_light_sharpness(k.lookup.maps.z, sharp_below);
    return ProbeMapLight(k.lookup.maps, k.e, w, st, height, bias);
}

// Σw·V of both solutions and Σw, w = E_k·⟨n, l_k⟩₊·s_k per channel, over the probe's lights:
// V_r = 0 where a real surface lies toward the light, V_rv also where a virtual one does.
// s_k = 1 with `sharp_below` = 0; else how sharp a shadow light k casts, 1 up to an angular
// radius of `sharp_below`, 0 from twice that. `all_weight`: Σ E_k·⟨n, l_k⟩₊. `covered`:
// whether every light that reaches the point has it inside its maps.
struct ProbeMapVisibility {
    visible_rv: vec3f,
    visible_r: vec3f,
    weight: vec3f,
    all_weight: vec3f,
    covered: bool,
}

fn probe_map_visibility(p: vec3f, n: vec3f, sharp_below: f32) -> ProbeMapVisibility {
    var out = ProbeMapVisibility(vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0), true);
    for (var i = 0u; i < probe_info.x; i++) {
        let lit = probe_map_irradiance(i, n);
        out.all_weight += lit.e;
        if (all(lit.e == vec3f(0.0))) { continue; }
        let k = probe_map_light(lit, p, n, sharp_below);
        if (all(k.w == vec3f(0.0))) { continue; }
        let real = probe_map_texel(k.maps.x, k.st);
        let v_r = select(1.0, 0.0, probe_map_blocked(real, k.height, k.bias));
        let v_v = select(1.0, 0.0, probe_map_blocked(probe_map_texel(k.maps.y, k.st), k.height, k.bias));
        out.visible_r += k.w * v_r;
        out.visible_rv += k.w * v_r * v_v;
        out.weight += k.w;
        out.covered = out.covered && real >= 0;
    }
    return out;
}
