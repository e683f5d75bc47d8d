// The probe's directional lights and their real-only and virtual-only maps
// (methods/probe_maps.rs), for shadowing the probe's light at a surface point. The including
// shader binds, in one group: probe_lights (array<Light>), probe_clip_from_world
// (array<mat4x4f>), probe_heights (array<f32>: the maps' heights toward their lights,
// rsm_height), probe_pairs (array<vec4u>: real-only layer,
// virtual-only layer, light, the light's angular radius as f32 bits) and probe_info (vec4u:
// lights, map side, shadow resolution). Needs shaders/lib/lights.wgsl and
// shaders/lib/probe_light.wgsl before it.

// Where `p` falls in the map of `layer`: its texel, or -1 outside the map.
fn probe_map_texel(layer: u32, p: vec3f) -> i32 {
    let res = probe_info.y;
    let clip = probe_clip_from_world[layer] * vec4f(p, 1.0);
    let ndc = clip.xy / clip.w;
    if (any(abs(ndc) >= vec2f(1.0))) { return -1; }
    let st = min(vec2u(vec2f(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * f32(res)), vec2u(res - 1u));
    return i32((layer * res + st.y) * res + st.x);
}

// Whether the map texel `texel` holds a surface nearer to the light than a point of
// rsm_height `height`, beyond `bias` (a texel that sees nothing holds NO_RSM_HEIGHT: never).
fn probe_map_blocked(texel: i32, height: f32, bias: f32) -> bool {
    if (texel < 0) { return false; }
    return probe_heights[texel] - height > bias;
}

// Half a texel of the map (its side is the light's texel size × resolution): how far a point
// is lifted off its surface and again along the light before the maps are read. Two texels
// lifted a point out of an object's contact shadow by a centimetre: the probe lit the desk
// under the bunny's rim and the rim from it (dvct's region FLIP on desk-bunny 0.0845 → 0.0756
// at half a texel, every diffuse scene lower, dlpv's too; a quarter of a texel lets the desk
// shadow itself).
fn probe_map_bias(light: Light) -> f32 {
    return 0.5 * light.cone.z * f32(probe_info.z) / f32(probe_info.y);
}

// Probe light `i` seen from `p` (normal `n`): its pair of maps, its irradiance E·⟨n, l⟩₊ and
// that weighted by its sharpness (probe_light_sharpness), the point lifted by the maps' bias
// where they are read, and that point's height toward the light (rsm_height, as the maps'
// texels hold theirs).
struct ProbeMapLight {
    pair: vec4u,
    e: vec3f,
    w: vec3f,
    q: vec3f,
    height: f32,
    bias: f32,
}

fn probe_map_light(i: u32, p: vec3f, n: vec3f, sharp_below: f32) -> ProbeMapLight {
    let pair = probe_pairs[i];
    let light = probe_lights[pair.z];
    let l = -light.direction_real.xyz;
    let e = light.intensity.rgb * max(dot(n, l), 0.0);
    let bias = probe_map_bias(light);
    let q = p + n * bias;
    return ProbeMapLight(pair, e, e * probe_light_sharpness(pair.w, sharp_below), q, rsm_height(light, q), bias);
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
        let k = probe_map_light(i, p, n, sharp_below);
        out.all_weight += k.e;
        if (all(k.w == vec3f(0.0))) { continue; }
        let real = probe_map_texel(k.pair.x, k.q);
        let v_r = select(1.0, 0.0, probe_map_blocked(real, k.height, k.bias));
        let v_v = select(1.0, 0.0, probe_map_blocked(probe_map_texel(k.pair.y, k.q), k.height, k.bias));
        out.visible_r += k.w * v_r;
        out.visible_rv += k.w * v_r * v_v;
        out.weight += k.w;
        out.covered = out.covered && real >= 0;
    }
    return out;
}

// The probe's light at a real surface point, over every light: Σ E_k·⟨n, l_k⟩₊·V_r (the real
// scene's own shadow, which a model of the photo needs: the walls of a room hold much of a
// probe's light back) and Σ E_k·⟨n, l_k⟩₊; of the lights up to `sharp_below` (weighted as in
// probe_map_visibility; none with 0), the light the virtual content alone takes,
// Σ w·V_r·(1 − V_v). The virtual-only map is read only for those lights.
struct ProbeMapRealLight {
    visible_r: vec3f,
    blocked: vec3f,
    all_weight: vec3f,
}

fn probe_map_real_light(p: vec3f, n: vec3f, sharp_below: f32) -> ProbeMapRealLight {
    var out = ProbeMapRealLight(vec3f(0.0), vec3f(0.0), vec3f(0.0));
    for (var i = 0u; i < probe_info.x; i++) {
        let k = probe_map_light(i, p, n, sharp_below);
        out.all_weight += k.e;
        if (all(k.e == vec3f(0.0))) { continue; }
        if (probe_map_blocked(probe_map_texel(k.pair.x, k.q), k.height, k.bias)) { continue; }
        out.visible_r += k.e;
        if (sharp_below <= 0.0 || all(k.w == vec3f(0.0))) { continue; }
        if (probe_map_blocked(probe_map_texel(k.pair.y, k.q), k.height, k.bias)) { out.blocked += k.w; }
    }
    return out;
}
