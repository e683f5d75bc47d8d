// VPL creation (Knecht §2.8, §2.2). One thread per VPL slot:
// - punctual lights: a texel of the light's RSMs, importance-sampled by hierarchical warping.
//   Real lights choose between their real-only and virtual-only RSM with probability ∝ the
//   pixels each covers (a Halton number decides) and compensate the flux. A real texel that a
//   virtual surface hides from a real light becomes a VPL3 (ir = 1): it cancels the real
//   colour bleeding the photo shows but the virtual object now blocks.
// - the environment: a probe direction, importance-sampled on the probe's luminance pyramid;
//   the VPL is parallel light (real, used for the probe's direct light and its shadows).
// - the environment-bounce source (the probe's light reflected once) and the multiple-bounce
//   source (source VPL of the previous frame chosen ∝ flux, direction ω_o) prepare their
//   slots; bounce.wgsl places their VPLs.
// - the punctual lights' caustics (reflections spec §2.18): a photon of the last frame, where
//   it landed on a diffuse surface after the lights' mirrors and glass.

@group(0) @binding(0) var<uniform> params: VplParams;
@group(0) @binding(1) var<storage, read> sources: array<Source>;
@group(0) @binding(2) var<storage, read> ranges: array<vec4u>;
@group(0) @binding(3) var<storage, read> lights: array<Light>;
@group(0) @binding(4) var<storage, read> rsm: array<RsmTexel>;
@group(0) @binding(5) var<storage, read> rsm_pyramid: array<vec2f>;
@group(0) @binding(6) var<storage, read> probe_importance: array<f32>;
@group(0) @binding(7) var<storage, read> probe_offsets: array<u32>;
@group(0) @binding(8) var<storage, read> probe_radiance: array<vec4f>;
@group(0) @binding(9) var<storage, read> previous: array<Vpl>;
@group(0) @binding(10) var<storage, read_write> vpls: array<Vpl>;
@group(0) @binding(11) var<storage, read_write> bounce_slots: array<BounceSlot>;
// Inclusive prefix sum of the previous frame's surface-VPL flux (allocate.wgsl).
@group(0) @binding(12) var<storage, read> flux_cdf: array<f32>;
// The punctual lights' photons (the specular stage's caustics, last frame) and what their
// receivers are.
@group(0) @binding(13) var<storage, read> photons: array<Photon>;
// The landed photons' indices per caustic level (level × slots + i), and how many landed
// (six vertices each: the splat draws' vertex counts, x of each vec4).
@group(0) @binding(14) var<storage, read> photon_list: array<u32>;
@group(0) @binding(15) var<storage, read> landed: array<vec4u, 2>;
@group(0) @binding(16) var<storage, read> triangles: array<vec4u>;
@group(0) @binding(17) var<storage, read> instances: array<Instance>;
@group(0) @binding(18) var<storage, read> materials: array<Material>;

fn rsm_level_offset(level: u32) -> u32 {
    var offset = 0u;
    var side = params.rsm.x;
    for (var l = 0u; l < level; l++) {
        offset += side * side;
        side /= 2u;
    }
    return offset;
}

fn rsm_node(layer: u32, level: u32, x: u32, y: u32) -> vec2f {
    let side = params.rsm.x >> level;
    return rsm_pyramid[layer * params.rsm.z + rsm_level_offset(level) + y * side + x];
}

// One step of hierarchical warping: picks the child of a 2×2 block (importances w = top left,
// top right, bottom left, bottom right) ∝ importance, column first, and rescales `u` to [0, 1)
// within it.
fn warp_quad(u: ptr<function, vec2f>, w: vec4f) -> vec2u {
    let left = w.x + w.z;
    let total = max(left + w.y + w.w, 1e-30);
    var col = 0u;
    if ((*u).x * total < left) {
        (*u).x = min((*u).x * total / max(left, 1e-30), 0.99999);
    } else {
        (*u).x = min(((*u).x * total - left) / max(w.y + w.w, 1e-30), 0.99999);
        col = 1u;
    }
    let top = select(w.y, w.x, col == 0u);
    let bottom = select(w.w, w.z, col == 0u);
    var row = 0u;
    if ((*u).y * (top + bottom) < top) {
        (*u).y = min((*u).y * (top + bottom) / max(top, 1e-30), 0.99999);
    } else {
        (*u).y = min(((*u).y * (top + bottom) - top) / max(bottom, 1e-30), 0.99999);
        row = 1u;
    }
    return vec2u(col, row);
}

// Hierarchical warping of `u` down one layer's pyramid; returns the texel (x, y).
fn warp_rsm(layer: u32, u_in: vec2f) -> vec2u {
    var u = u_in;
    var p = vec2u(0u);
    for (var level = params.rsm.y - 1u; level > 0u; level--) {
        let q = p * 2u;
        p = q + warp_quad(&u, vec4f(
            rsm_node(layer, level - 1u, q.x, q.y).x,
            rsm_node(layer, level - 1u, q.x + 1u, q.y).x,
            rsm_node(layer, level - 1u, q.x, q.y + 1u).x,
            rsm_node(layer, level - 1u, q.x + 1u, q.y + 1u).x,
        ));
    }
    return p;
}

fn light_vpl(slot: u32, source: u32, light_index: u32, seq: u32, count: u32) -> Vpl {
    let light = lights[light_index];
    let res = params.rsm.x;
    let top = params.rsm.y - 1u;
    let per_set = light.info.z;
    let first = array<u32, 2>(light.info.y, light.info.w);
    // Coverage and importance of each set (real-only, virtual-only).
    var coverage = array<f32, 2>(0.0, 0.0);
    var importance = array<f32, 2>(0.0, 0.0);
    for (var s = 0u; s < 2u; s++) {
        for (var f = 0u; f < per_set; f++) {
            let node = rsm_node(first[s] + f, top, 0u, 0u);
            importance[s] += node.x;
            coverage[s] += node.y;
        }
    }
    let covered = coverage[0] + coverage[1];
    if (covered <= 0.0) { return empty_vpl(); }
    // The split of the thesis: ∝ covered pixels, chosen by a Halton number.
    let p_real = coverage[0] / covered;
    let chosen_set = select(1u, 0u, halton(5u, seq) < p_real);
    let p_set = select(1.0 - p_real, p_real, chosen_set == 0u);
    if (importance[chosen_set] <= 0.0) { return empty_vpl(); }
    // Face ∝ importance, then texel ∝ importance inside it.
    var face = 0u;
    var acc = 0.0;
    let pick = halton(7u, seq) * importance[chosen_set];
    for (var f = 0u; f < per_set; f++) {
        acc += rsm_node(first[chosen_set] + f, top, 0u, 0u).x;
        face = f;
        if (pick < acc) { break; }
    }
    let layer = first[chosen_set] + face;
    let t = warp_rsm(layer, vec2f(halton2(seq), halton(3u, seq)));
    let texel = rsm[(layer * res + t.y) * res + t.x];
    if (texel.position.w == 0.0 || texel.power.w <= 0.0) { return empty_vpl(); }
    let probability = p_set * texel.power.w / importance[chosen_set];

    // Is the texel hidden from the light by a surface of the other chosen_set?
    let other = rsm[((first[1u - chosen_set] + face) * res + t.y) * res + t.x];
    var occluded = false;
    if (other.position.w > 0.0) {
        var d_this: f32;
        var d_other: f32;
        if (light.info.x == LIGHT_DIRECTIONAL) {
            d_this = dot(texel.position.xyz, light.direction_real.xyz);
            d_other = dot(other.position.xyz, light.direction_real.xyz);
        } else {
            d_this = distance(texel.position.xyz, light.position.xyz);
            d_other = distance(other.position.xyz, light.position.xyz);
        }
        occluded = d_other < d_this * 0.999;
    }
    let light_real = light.direction_real.w > 0.5;
    var flags = 0u;
    if (chosen_set == 0u) {
        flags = VPL_REAL;
        if (occluded) {
            // Real light blocked by a virtual surface: a VPL3, else unlit.
            if (!light_real) { return empty_vpl(); }
            flags |= VPL_IR;
        }
        if (light_real) { flags |= VPL_PATH_REAL; }
    } else if (occluded) {
        return empty_vpl();
    }
    var v: Vpl;
    // The surface area this VPL stands for: its texel's, divided by the expected number of
    // VPLs the texel receives.
    v.position = vec4f(texel.position.xyz, texel.material.w / (probability * f32(count)));
    v.normal = texel.normal;
    v.power = vec4f(texel.power.rgb / (probability * f32(count)), texel.albedo.w);
    v.albedo = vec4f(texel.albedo.rgb, texel.material.y);
    var incoming = -light.direction_real.xyz;
    if (light.info.x != LIGHT_DIRECTIONAL) { incoming = normalize(light.position.xyz - texel.position.xyz); }
    v.incoming = vec4f(incoming, texel.material.x);
    v.info = vec4u(flags, source, VPL_SURFACE, 1u);
    return v;
}

// A caustic VPL (reflections spec §2.18: "the VPLs are placed where caustics appear"; the
// thesis "places it on the final hit position of the photon"): one of the punctual lights'
// photons that landed in the last frame (their count lags a frame, as the thesis's photon
// count does), uniformly; it reflects the photon's power with its receiver's material. Each
// photon is one path whichever its branch (reflected or refracted), so the paper's Halton
// choice between the two and its doubled intensity are not needed. Routing (§2.17.5): an
// L_rv photon whose L_r twin landed alike took an all-real path (x̄, both buffers); otherwise
// it adds to L_rv only; an L_r photon whose L_rv twin did not land alike is real light that
// virtual content blocks, a VPL3 (ir: L_r only); a matched L_r photon is its twin's.
fn caustic_vpl(source: u32, seq: u32, count: u32) -> Vpl {
    let slots = params.strata.z;
    let per_kind = params.strata.w;
    let fine = landed[0].x / 6u;
    let total = fine + landed[1].x / 6u;
    if (total == 0u) { return empty_vpl(); }
    let j = min(u32(halton2(seq) * f32(total)), total - 1u);
    let index = photon_list[select(slots + j - fine, j, j < fine)];
    let p = photons[index];
    if (p.position.w == 0.0) { return empty_vpl(); }
    let kind = (index / per_kind) % PHOTON_KINDS;
    let twin = photons[index + ((kind + 2u) % PHOTON_KINDS) * per_kind - kind * per_kind];
    let alike = twin.position.w != 0.0 && all(twin.position.xyz == p.position.xyz) && all(twin.power.rgb == p.power.rgb);
    var flags = 0u;
    if (kind < 2u) {
        flags = select(0u, VPL_PATH_REAL, alike);
    } else {
        if (alike) { return empty_vpl(); }
        flags = VPL_IR | VPL_PATH_REAL;
    }
    let instance = triangles[bitcast<u32>(p.power.w) - 1u].x;
    let inst = instances[instance];
    if ((inst.info.y & SURFACE_REAL) != 0u) { flags |= VPL_REAL; }
    let m = materials[inst.info.x];
    let metallic = clamp(m.params.x, 0.0, 1.0);
    // Each landed photon is picked with probability 1 / total.
    let scale = f32(total) / f32(count);
    let half = max(p.normal.w, 1e-4);
    var v: Vpl;
    v.position = vec4f(p.position.xyz, 4.0 * half * half * scale);
    v.normal = vec4f(p.normal.xyz, clamp(m.params.y, 0.0, 1.0));
    v.power = vec4f(p.power.rgb * scale, metallic);
    // The receiver's material factors (its textures are not read here).
    v.albedo = vec4f(vpl_base_color(m, m.base_color.rgb, metallic), m.dielectric.a);
    // The photon's last direction is not kept: its glossy lobe is centred on the normal.
    v.incoming = vec4f(p.normal.xyz, (m.dielectric.r + m.dielectric.g + m.dielectric.b) / 3.0);
    v.info = vec4u(flags, source, VPL_SURFACE, 2u);
    return v;
}

fn probe_node(level: u32, x: u32, y: u32) -> f32 {
    let w = params.probe.x >> level;
    return probe_importance[probe_offsets[level] + y * w + x];
}

fn environment_vpl(source: u32, seq: u32, count: u32) -> Vpl {
    if (params.probe.w == 0u) { return empty_vpl(); }
    var u = vec2f(halton2(seq), halton(3u, seq));
    let levels = params.probe.z;
    // Top level: two cells side by side.
    let l = probe_node(levels - 1u, 0u, 0u);
    let r = probe_node(levels - 1u, 1u, 0u);
    var p = vec2u(0u);
    if (u.x * (l + r) < l) { u.x = min(u.x * (l + r) / max(l, 1e-30), 0.99999); } else { u.x = min((u.x * (l + r) - l) / max(r, 1e-30), 0.99999); p.x = 1u; }
    for (var level = levels - 1u; level > 0u; level--) {
        let q = p * 2u;
        p = q + warp_quad(&u, vec4f(
            probe_node(level - 1u, q.x, q.y),
            probe_node(level - 1u, q.x + 1u, q.y),
            probe_node(level - 1u, q.x, q.y + 1u),
            probe_node(level - 1u, q.x + 1u, q.y + 1u),
        ));
    }
    let w = params.probe.x;
    let h = params.probe.y;
    let importance = probe_node(0u, p.x, p.y);
    if (importance <= 0.0) { return empty_vpl(); }
    let pdf_texel = importance / params.probe_scale.y;
    let uv = vec2f((f32(p.x) + u.x) / f32(w), (f32(p.y) + u.y) / f32(h));
    let phi = uv.x * 2.0 * PI;
    let theta = uv.y * PI;
    let probe_dir = vec3f(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
    let world_dir = normalize((params.world_from_probe * vec4f(probe_dir, 0.0)).xyz);
    let theta0 = PI * f32(p.y) / f32(h);
    let theta1 = PI * f32(p.y + 1u) / f32(h);
    let solid_angle = (2.0 * PI / f32(w)) * (cos(theta0) - cos(theta1));
    let radiance = probe_radiance[p.y * w + p.x].rgb * params.probe_scale.x;
    var v: Vpl;
    // Light arrives from `world_dir` and travels along −world_dir.
    v.position = vec4f(-world_dir, 0.0);
    // The solid angle this VPL stands for (its normal is unused): what a virtual mirror
    // hides of the sky (vpl_light.wgsl).
    v.normal = vec4f(solid_angle / (pdf_texel * f32(count)), 0.0, 0.0, 0.0);
    v.power = vec4f(radiance * solid_angle / (pdf_texel * f32(count)), 0.0);
    v.info = vec4u(VPL_REAL | VPL_PATH_REAL, source, VPL_DIRECTIONAL, 0u);
    return v;
}

// The environment-bounce source: the probe's light reflected once. Its VPLs lie at surface
// points (bounce.wgsl draws them from the point clouds and gives them the probe light that
// reaches them through the environment VPLs); here the slot only gets its random numbers and
// its share: per unit of area and irradiance, 1 / slots.
fn setup_environment_bounce(seq: u32, count: u32) -> BounceSlot {
    var b: BounceSlot;
    if (params.bounce.y + params.bounce.z <= 0.0) { return b; }
    b.origin = vec4f(0.0, 0.0, 0.0, SLOT_POINT);
    b.direction = vec4f(halton2(seq), halton(3u, seq), 0.0, 0.0);
    b.carry = vec4f(vec3f(1.0 / f32(count)), 1.0);
    b.info = vec4u(VPL_REAL | VPL_PATH_REAL, 0u, VPL_DIRECTIONAL, 0u);
    return b;
}

// The multiple-bounce source: picks a previous-frame surface VPL ∝ flux and a direction for
// it (§2.8). (The probe's directional VPLs bounce through the environment-bounce source.)
fn setup_bounce(slot: u32, seq: u32, count: u32) -> BounceSlot {
    var b: BounceSlot;
    let n = params.counts.x;
    let radius = params.scene.w;
    let total = flux_cdf[n - 1u];
    if (total <= 0.0) { return b; }
    // The first VPL whose cumulative flux exceeds the pick (it has flux > 0).
    let pick = halton(5u, seq) * total;
    var lo = 0u;
    var hi = n - 1u;
    while (lo < hi) {
        let mid = (lo + hi) / 2u;
        if (flux_cdf[mid] > pick) { hi = mid; } else { lo = mid + 1u; }
    }
    let chosen = lo;
    let v = previous[chosen];
    let selection = surface_flux(v, radius) / total;
    if (selection <= 0.0) { return b; }
    let u = vec2f(halton2(seq), halton(3u, seq));
    let s = vpl_surface(v);
    let n_src = s.normal;
    // Diffuse or specular lobe, by their share of the reflected light.
    let diffuse = luminance(s.base_color * (1.0 - s.metallic));
    let specular = luminance(surface_f0(s)) + 1e-4;
    let p_diffuse = diffuse / (diffuse + specular);
    let alpha = max(s.roughness * s.roughness, 0.02);
    let k = max(2.0 / (alpha * alpha) - 2.0, 1.0);
    let mirror = reflect(-s.view, n_src);
    var dir: vec3f;
    if (halton(7u, seq) < p_diffuse) {
        dir = to_world(cosine_hemisphere(u), n_src);
    } else {
        dir = to_world(phong_lobe(u, k), mirror);
    }
    let cos_n = dot(dir, n_src);
    if (cos_n <= 0.0) { return b; }
    let pdf = p_diffuse * cos_n / PI + (1.0 - p_diffuse) * (k + 1.0) / (2.0 * PI) * pow(max(dot(dir, mirror), 0.0), k);
    let carry = vpl_intensity(v, dir) / max(pdf, 1e-8);
    b.origin = vec4f(v.position.xyz, SLOT_RAY);
    // The solid-angle density of the ray over all slots (for the area of its VPL).
    b.direction = vec4f(dir, pdf * selection * f32(count));
    b.carry = vec4f(carry / (selection * f32(count)), selection);
    b.info = vec4u(v.info.x, chosen, vpl_kind(v), 0u);
    return b;
}

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) gid: vec3u) {
    let slot = gid.x;
    if (slot >= params.counts.x) { return; }
    let source = source_of_slot(slot, params.counts.z);
    var v = empty_vpl();
    var bounce: BounceSlot;
    if (source < params.counts.z) {
        let range = ranges[source];
        let j = slot - range.x;
        // Pixels shade with the VPLs of one subset (slot mod I²). Each subset of a source
        // takes a contiguous run of the source's Halton points, so that every subset is a
        // well-spread sample on its own; frames continue the sequence.
        let subsets = params.rsm.w;
        let per_subset = (range.y + subsets - 1u) / subsets;
        let subset = slot % subsets;
        let rank = (j + range.x % subsets) / subsets;
        let seq = params.counts.y * range.y + subset * per_subset + rank;
        let kind = sources[source].info.x;
        if (kind == SOURCE_LIGHT) {
            v = light_vpl(slot, source, sources[source].info.y, seq, range.y);
        } else if (kind == SOURCE_ENVIRONMENT) {
            v = environment_vpl(source, seq, range.y);
        } else if (kind == SOURCE_ENVIRONMENT_BOUNCE) {
            bounce = setup_environment_bounce(seq, range.y);
        } else if (kind == SOURCE_CAUSTICS) {
            v = caustic_vpl(source, seq, range.y);
        } else {
            bounce = setup_bounce(slot, seq, range.y);
        }
    }
    vpls[slot] = v;
    bounce_slots[slot] = bounce;
}
