// Soft shadows of the probe's lights through their virtual-only maps, for real surfaces
// (methods/probe_maps.rs). Needs shaders/lib/probe_maps.wgsl before it, and one more binding
// in its group: probe_heights_near (array<f32>: per map texel, the highest surface within the
// blocker search's reach, methods/probe_maps_near.wgsl).

// The probe's light at a real surface point, over every light: Σ E_k·⟨n, l_k⟩₊·V_r (the real
// scene's own shadow, which a model of the photo needs: the walls of a room hold much of a
// probe's light back) and Σ E_k·⟨n, l_k⟩₊; of the lights up to `sharp_below` (weighted as in
// probe_map_visibility; none with 0), the light the virtual content alone takes,
// Σ w·V_r·(1 − V_v), V_v soft by each light's angular radius with `soft`
// (probe_map_soft_occlusion: hard shadows of broad lights darkened a desk far from the object
// that hides a little of them), else hard.
// The virtual-only map is read only for those lights.
struct ProbeMapRealLight {
    visible_r: vec3f,
    blocked: vec3f,
    all_weight: vec3f,
}

fn probe_map_real_light(p: vec3f, n: vec3f, sharp_below: f32, soft: bool) -> ProbeMapRealLight {
    var out = ProbeMapRealLight(vec3f(0.0), vec3f(0.0), vec3f(0.0));
    for (var i = 0u; i < probe_info.x; i++) {
        let lit = probe_map_irradiance(i, n);
        out.all_weight += lit.e;
        if (all(lit.e == vec3f(0.0))) { continue; }
        let k = probe_map_light(lit, p, n, sharp_below);
        if (probe_map_blocked(probe_map_texel(k.maps.x, k.st), k.height, k.bias)) { continue; }
        out.visible_r += k.e;
        if (sharp_below <= 0.0 || all(k.w == vec3f(0.0))) { continue; }
        if (!soft) {
            if (probe_map_blocked(probe_map_texel(k.maps.y, k.st), k.height, k.bias)) { out.blocked += k.w; }
            continue;
        }
        let tan_radius = tan(bitcast<f32>(k.maps.z));
        out.blocked += k.w * probe_map_soft_occlusion(k.maps.y, k.st, k.height, k.bias, tan_radius, length(lit.lookup.s.xyz));
    }
    return out;
}

// probe_map_visibility with soft shadows (`sharp_below` = 0: every light), for virtual
// surfaces: each light's real-only and virtual-only shadows soft by its angular radius
// (probe_map_soft_occlusion), V_rv = V_r·(1 − occlusion by the virtual maps). Each light
// stands for a patch of the probe, and hard, the patches a wall lets through drew their edges
// across cornell's blocks as stripes. `covered` as there.
fn probe_map_soft_visibility(p: vec3f, n: vec3f) -> ProbeMapVisibility {
    var out = ProbeMapVisibility(vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0), true);
    for (var i = 0u; i < probe_info.x; i++) {
        let lit = probe_map_irradiance(i, n);
        out.all_weight += lit.e;
        if (all(lit.e == vec3f(0.0))) { continue; }
        let k = probe_map_light(lit, p, n, 0.0);
        let tan_radius = tan(bitcast<f32>(k.maps.z));
        let per_metre = length(lit.lookup.s.xyz);
        let v_r = 1.0 - probe_map_soft_occlusion(k.maps.x, k.st, k.height, k.bias, tan_radius, per_metre);
        let v_v = 1.0 - probe_map_soft_occlusion(k.maps.y, k.st, k.height, k.bias, tan_radius, per_metre);
        out.visible_r += k.w * v_r;
        out.visible_rv += k.w * v_r * v_v;
        out.weight += k.w;
        out.covered = out.covered && probe_map_texel(k.maps.x, k.st) >= 0;
    }
    return out;
}

// Taps of the soft test below: a golden-angle spiral of PROBE_SOFT_TAPS points in the unit disk.
const PROBE_SOFT_TAPS: u32 = 12u;

fn probe_soft_tap(j: u32) -> vec2f {
    let r = sqrt((f32(j) + 0.5) / f32(PROBE_SOFT_TAPS));
    let a = f32(j) * 2.39996323;
    return r * vec2f(cos(a), sin(a));
}

// The share of a light of angular radius θ (`tan_radius` = tan θ) that the surfaces of map
// `layer` hide from a point at texel `st` and `height`: percentage-closer soft shadows
// (Fernando 2005) for a distant disk — the blockers found around the point give their mean
// height d above it, and the directions within θ of the light's pass the blockers' layer
// within d·tan θ of the point, the radius over which the taps are tested. A light narrower
// than half a texel there is tested at the point alone. `per_metre`: the maps' texels per metre.
fn probe_map_soft_occlusion(layer: u32, st: vec2f, height: f32, bias: f32, tan_radius: f32, per_metre: f32) -> f32 {
    let centre = probe_map_texel(layer, st);
    // Outside the maps nothing virtual stands toward the light; where nothing near the point
    // stands above it (most of a frame's pixels), no blocker is there to search for.
    if (centre < 0 || probe_heights_near[centre] - height <= bias) { return 0.0; }
    // probe_info.z: the search's widest radius (texels; ProbeMaps::soft_search_texels).
    let search = min(f32(probe_info.z), tan_radius * f32(probe_info.y));
    if (search < 0.5) { return select(0.0, 1.0, probe_map_blocked(centre, height, bias)); }
    var sum = 0.0;
    var count = 0.0;
    for (var j = 0u; j <= PROBE_SOFT_TAPS; j++) {
        // Tap PROBE_SOFT_TAPS is the point itself.
        var t = centre;
        if (j < PROBE_SOFT_TAPS) { t = probe_map_texel(layer, st + search * probe_soft_tap(j)); }
        if (t < 0) { continue; }
        let d = probe_heights[t] - height;
        if (d > bias) {
            sum += d;
            count += 1.0;
        }
    }
    if (count == 0.0) { return 0.0; }
    let radius = (sum / count) * tan_radius * per_metre;
    if (radius < 0.5) { return select(0.0, 1.0, probe_map_blocked(centre, height, bias)); }
    var blocked = 0u;
    for (var j = 0u; j < PROBE_SOFT_TAPS; j++) {
        if (probe_map_blocked(probe_map_texel(layer, st + radius * probe_soft_tap(j)), height, bias)) { blocked++; }
    }
    return f32(blocked) / f32(PROBE_SOFT_TAPS);
}
