// The light of the VPLs at one receiver, with the flag routing of Knecht §2.7 Eq. 5.6–5.8:
//   L_rv += L_o · (1 − ir) · min(V_r, V_v)          (5.6, 5.8)
//   L_r  += L_o · x̄ · r(p) · V_r                     (5.7, with the path flag of §2.8)
// (plus the light of each VPL's co-located VPL3, see vpl.wgsl). Directional (environment)
// VPLs are not added as light: their cosine-weighted visibilities per channel are summed
// (Σw_c·V_rv, Σw_c·V_r, Σw_c), from which the caller scales the probe's exact image-based
// light (env_visibility.wgsl). One function for the `dir` method's interleaved shading of
// the screen and for the specular stage's shading of the surfaces that reflections and
// refractions hit off screen.
// Needs vpl.wgsl, ism.wgsl, brdf.wgsl, gbuffer.wgsl and the bindings `vpls`, `ism`,
// `ism_real`, `ism_virtual`, `materials`, and a function
// `screen_covers(x: vec3f, how: VplShading) -> bool` (whether the screen-space near field
// gathers the surface at x; `false` where there is none).

struct VplLight {
    rv: vec3f,
    r: vec3f,
    env_rv: vec3f,
    env_r: vec3f,
    env_weight: vec3f,
    // What the receiver reflects per unit radiance of its surroundings that virtual mirrors
    // show it where they hide the sky (the caller multiplies by that radiance; L_rv only).
    mirrored: vec3f,
}

// Share of the sky directions that a virtual mirror hides whose reflection shows the
// receiver's surroundings (below its horizon) rather than more sky (which the probe's photons
// carry off the mirror). A convex mirror seen from beside it, as from the desk around a
// chrome ball or a gold torus, reflects about half of the rays down.
const MIRRORED_SURROUNDINGS: f32 = 0.5;

// How the VPLs light one receiver: their lower bound of the VPL–receiver distance (m), for
// once-reflected light and for the multiple-bounce VPLs' (VPL_BOUNCED) that lie on a surface
// the camera sees within `screen_radius` pixels of `pixel` (where the screen gathers what
// this wider clamp leaves out; `screen_covers`); whether the probe's light through
// transmissive casters is carried by photons (the specular stage's caustics) rather than let
// through by the shadow; whether the directional VPLs' visibility sums are wanted.
struct VplShading {
    d_min: f32,
    d_bounce: f32,
    pixel: vec2f,
    screen_radius: f32,
    // Pixels per metre at unit distance around the receiver.
    scale: f32,
    photons: bool,
    directional: bool,
}

// Visibility of VPL `index` at receiver `p` (normal `n`) past the casters of one atlas: 0 or
// 1, or the transmittance of a transmissive nearest caster; and the nearest caster's
// material + 1 where it blocks (0: none or unknown).
struct IsmLookup {
    visible: f32,
    caster: u32,
}

// Where a lookup reads its atlas, before it reads it: the texel (0 where the point falls
// outside the map: `valid` false) and the depth below which a stored caster blocks.
// Offsets and biases keep a surface from shadowing itself; they are needed only where the
// receiver's own surface is in the atlas (`own_atlas`: a real receiver in the real atlas, a
// virtual one in the virtual atlas). Elsewhere they would only grow the other atlas's
// shadows, most visibly where a virtual object touches the real surface it stands on.
struct IsmProbe {
    valid: bool,
    texel: u32,
    limit: f32,
}

fn ism_probe(index: u32, v: Vpl, p: vec3f, n: vec3f, virtual_atlas: bool, own_atlas: bool) -> IsmProbe {
    let first = ism_project(v, p, ism, virtual_atlas);
    let extent = ism_texel_extent(v, first.depth, ism, virtual_atlas);
    // Depth bias against the quantisation of the other atlas's depths: half a texel for
    // splatted maps; a tenth for the triangle-rasterised directional maps, whose texels hold
    // exact depths at their centres. (Half a texel there is 1–2 cm under a room-sized proxy:
    // the bottom of a virtual object standing on a real desk then saw the probe through the
    // desk and glowed; desk-bunny region FLIP 0.071 → 0.069.)
    var offset = 0.0;
    var limit_bias = select(0.5, 0.1, vpl_kind(v) == VPL_DIRECTIONAL) * extent;
    if (own_atlas) {
        if (vpl_kind(v) == VPL_DIRECTIONAL) {
            // Exact triangle maps: a texel-and-a-half of normal offset and half a texel of
            // depth bias suffice; a bias relative to the map's sphere would erase the
            // shadows of thin casters (a book on a desk) under a room-sized real proxy.
            offset = 1.5 * extent;
            limit_bias = 0.5 * extent;
        } else {
            // Lift the receiver off its own surface's splats: by a texel and by the splat size.
            let splat = select(ism.splat.x, ism.splat.y, virtual_atlas) * ism.splat.w;
            offset = max(extent, splat);
            limit_bias = first.depth * ism.splat.z + extent;
        }
    }
    let c = ism_project(v, p + n * offset, ism, virtual_atlas);
    if (!c.valid) { return IsmProbe(false, 0u, 0.0); }
    return IsmProbe(true, ism_texel_index(index, c.uv, ism), c.depth - limit_bias);
}

// The atlas word a probe reads.
fn ism_read(probe: IsmProbe, virtual_atlas: bool) -> u32 {
    if (virtual_atlas) { return ism_virtual[probe.texel]; }
    return ism_real[probe.texel];
}

// What a probe's atlas word `stored` says.
fn ism_result(probe: IsmProbe, stored: u32, v: Vpl, photons: bool) -> IsmLookup {
    if (!probe.valid || ism_decode(stored) >= probe.limit) { return IsmLookup(1.0, 0u); }
    if (!ism_caster_known(stored)) { return IsmLookup(0.0, 0u); }
    let caster = ism_caster_material(stored);
    // The probe's light through a transmissive caster: its photons carry it when they fly
    // (RenderSettings::probe_caustics), else the shadow lets it through.
    let carried = vpl_kind(v) == VPL_DIRECTIONAL && photons;
    return IsmLookup(select(caster_transmittance(materials[caster]), 0.0, carried), caster + 1u);
}

// Both atlases' lookups of VPL `index` at receiver `p` (normal `n`; `real`: a real receiver),
// their reads issued together: one after the other, each VPL of a pixel's loop waited on two
// reads in turn.
struct IsmPair {
    real: IsmLookup,
    virt: IsmLookup,
}

fn ism_pair(index: u32, v: Vpl, p: vec3f, n: vec3f, real: bool, photons: bool) -> IsmPair {
    let a = ism_probe(index, v, p, n, false, real);
    let b = ism_probe(index, v, p, n, true, !real);
    let stored_a = ism_read(a, false);
    let stored_b = ism_read(b, true);
    return IsmPair(ism_result(a, stored_a, v, photons), ism_result(b, stored_b, v, photons));
}

// f_r · cos θ_l of the receiver toward a VPL. On a surface the specular stage traces (a mirror,
// a glass, a smooth metal) the specular lobe is the stage's: its reflection of the surfaces
// these VPLs light. Here, a near-delta GGX lobe turned each VPL into a firefly that the
// interleaving spread into a block (desk-mirror's sphere), and counted that light twice.
fn receiver_brdf_cos(s: Surface, l: vec3f, traced: bool) -> vec3f {
    let lobes = brdf_lobes(s, l);
    return select(lobes.diffuse + lobes.specular, lobes.diffuse, traced);
}

// Whether receiver `s` reflects any light of surface VPLs, or of the surfaces around it
// (receiver_brdf_cos can be non-zero).
fn reflects_vpls(s: Surface, traced: bool) -> bool { return !traced || has_diffuse(s); }

// (V_r, V_v) of VPL `index` at receiver `p` with normal `n`, on a real or virtual surface.
fn ism_visibility(index: u32, v: Vpl, p: vec3f, n: vec3f, real: bool, photons: bool) -> vec2f {
    let pair = ism_pair(index, v, p, n, real, photons);
    return vec2f(pair.real.visible, pair.virt.visible);
}

// The squared clamp distance of VPL `v` at squared distance `d2`: the multiple-bounce VPLs
// that the screen-space near field covers stand for the light beyond its reach only.
fn vpl_clamp2(v: Vpl, d2: f32, d_min2: f32, d_bounce2: f32, how: VplShading) -> f32 {
    if ((v.info.x & VPL_BOUNCED) == 0u || d2 >= d_bounce2 || d_bounce2 <= d_min2) { return d_min2; }
    return select(d_min2, d_bounce2, screen_covers(v.position.xyz, how));
}

// The VPLs `first`, `first + step`, … below `count` at surface `s` (r(p) = `r_p`; `traced`:
// the specular stage reflects its specular lobe), unscaled.

fn vpl_light(s: Surface, traced: bool, r_p: f32, first: u32, step: u32, count: u32, how: VplShading) -> VplLight {
    var out = VplLight(vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0));
    let receiver_real = r_p > 0.0;
    let p = s.position;
    let d_min2 = how.d_min * how.d_min;
    let d_bounce2 = how.d_bounce * how.d_bounce;
    // A traced mirror or glass with no diffuse lobe reflects none of the surface VPLs' light
    // (receiver_brdf_cos is zero): their visibility lookups are skipped.
    let surface_vpls = reflects_vpls(s, traced);
    for (var i = first; i < count; i += step) {
        let v = vpls[i];
        let kind = vpl_kind(v);
        if (kind == VPL_SURFACE) {
            if (!surface_vpls) { continue; }
            let to = v.position.xyz - p;
            let d2 = max(dot(to, to), 1e-12);
            let l = to * inverseSqrt(d2);
            if (dot(s.normal, l) <= 0.0) { continue; }
            let emission = vpl_emission(v, -l);
            if (all(emission == vec3f(0.0))) { continue; }
            let transfer = receiver_brdf_cos(s, l, traced) * emission / max(d2, vpl_clamp2(v, d2, d_min2, d_bounce2, how));
            let l_o = transfer * v.power.rgb;
            let vis = ism_visibility(i, v, p, s.normal, receiver_real, how.photons);
            let route = vpl_routing(v.info.x, r_p, vis);
            out.rv += l_o * route.x;
            out.r += l_o * route.y + transfer * v.power_ir.rgb * route.z;
        } else if (kind == VPL_DIRECTIONAL && how.directional) {
            let cos_theta = dot(s.normal, -v.position.xyz);
            if (cos_theta <= 0.0) { continue; }
            let w = v.power.rgb * cos_theta;
            let pair = ism_pair(i, v, p, s.normal, receiver_real, how.photons);
            let v_r = pair.real.visible;
            let virtual_caster = pair.virt;
            out.env_rv += w * min(v_r, virtual_caster.visible);
            out.env_r += w * v_r;
            out.env_weight += w;
            // Where a virtual mirror (a traced metal) hides this direction of the sky that the
            // real world lets through, p sees in it, in part, its own surroundings mirrored:
            // the desk under a chrome ball or around a gold torus is lit by the desk (the
            // photons carry the sky it mirrors). Without it those were as dark as under a
            // black object (desk-mirror: 0.66 of the photo's light within 5 px of the torus,
            // 0.80 in the reference).
            if (virtual_caster.caster != 0u && v_r > 0.0) {
                let m = materials[virtual_caster.caster - 1u];
                if (is_traced(m) && m.transmission.x <= 0.0) {
                    let f0 = material_f0(m);
                    let l = -v.position.xyz;
                    out.mirrored += receiver_brdf_cos(s, l, traced) * f0 * (MIRRORED_SURROUNDINGS * v.normal.x * v_r * (1.0 - virtual_caster.visible));
                }
            }
        }
    }
    return out;
}
