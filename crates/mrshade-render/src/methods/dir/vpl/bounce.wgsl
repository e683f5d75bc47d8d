// The multiple-bounce light source (Knecht §2.8): the ISM point clouds are the candidate VPL
// positions; every point is assigned to one bounce slot (by a hash).
// - importance (DIR v2, default): a candidate is valid when it lies within the cone of
//   half-angle `bounce_cone_deg` around the slot's direction ω_o (a tube of that angular size
//   for parallel sources); the nearest valid candidate wins (atomicMax on inverted distance | id),
//   standing in for the ray's first hit. No shadow test, as in the thesis. Where the first hit
//   is virtual and the path is real, the ray in the real-only world goes on to the nearest
//   real candidate: that point gets a VPL3 (ir), which lights L_r only, as the VPL3s of the
//   primary lights do (§2.5). A slot holds one VPL, so it keeps one of the two, each with
//   probability ½ and twice the power (the first-hit VPL without it would leave L_r missing
//   the real bounce the photo shows, and real surfaces too bright around virtual objects).
// - fitness (DIR v1): the candidate receiving the most light from the source VPL (glossy
//   bounce with the previous frame's ISM visibility) wins (atomicMax on fitness | id).
// cs_candidates evaluates the candidates, cs_finalize turns each winner into a VPL, and each
// slot of the environment-bounce source into a VPL at a drawn surface point.

@group(0) @binding(0) var<uniform> params: VplParams;
@group(0) @binding(1) var<storage, read> ranges: array<vec4u>;
@group(0) @binding(2) var<storage, read> sources: array<Source>;
@group(0) @binding(3) var<storage, read> instances: array<Instance>;
@group(0) @binding(4) var<storage, read> materials: array<Material>;
@group(0) @binding(5) var<storage, read> points_real: array<Point>;
@group(0) @binding(6) var<storage, read> points_virtual: array<Point>;
@group(0) @binding(7) var<storage, read> previous: array<Vpl>;
@group(0) @binding(8) var<storage, read> bounce_slots: array<BounceSlot>;
// [slot]: the winning candidate (key << 32 | point); [slots + slot]: the nearest real one.
@group(0) @binding(9) var<storage, read_write> best: array<atomic<u64>>;
@group(0) @binding(10) var<storage, read_write> vpls: array<Vpl>;
@group(0) @binding(11) var<uniform> ism: IsmParams;
@group(0) @binding(12) var<storage, read> ism_real: array<u32>;
@group(0) @binding(13) var<storage, read> ism_virtual: array<u32>;
// World bounding spheres of the virtual instances.
@group(0) @binding(14) var<storage, read> virtual_spheres: array<vec4f>;
// [0]: the number of real points near virtual content.
@group(0) @binding(15) var<storage, read_write> near: array<atomic<u32>>;

// A real point is "near" virtual content within this many bounding radii of a sphere's centre.
const NEAR_RADII: f32 = 2.0;

fn bounce_range() -> vec4u {
    for (var s = 0u; s < params.counts.z; s++) {
        if (sources[s].info.x == SOURCE_BOUNCE) { return ranges[s]; }
    }
    return vec4u(0u);
}

struct WorldPoint {
    position: vec3f,
    normal: vec3f,
    material: u32,
    real: bool,
}

fn world_point(global: u32) -> WorldPoint {
    var p: Point;
    var w: WorldPoint;
    w.real = global < params.modes.z;
    if (w.real) { p = points_real[global]; } else { p = points_virtual[global - params.modes.z]; }
    let inst = instances[p.instance];
    w.position = (inst.world_from_object * vec4f(p.position, 1.0)).xyz;
    w.normal = normalize((inst.normal_from_object * vec4f(p.normal, 0.0)).xyz);
    w.material = p.material;
    return w;
}

// Previous-frame visibility (V_r, V_v) between VPL `index` (of the previous buffer) and `p`
// with normal `n` (the atlases still hold the previous frame's ISMs).
fn previous_visibility(index: u32, v: Vpl, p: vec3f, n: vec3f) -> vec2f {
    var visible = vec2f(1.0);
    for (var a = 0u; a < 2u; a++) {
        let virtual_atlas = a == 1u;
        let first = ism_project(v, p, ism, virtual_atlas);
        let extent = ism_texel_extent(v, first.depth, ism, virtual_atlas);
        let splat = select(ism.splat.x, ism.splat.y, virtual_atlas) * ism.splat.w;
        let c = ism_project(v, p + n * max(extent, splat), ism, virtual_atlas);
        if (!c.valid) { continue; }
        let i = ism_texel_index(index, c.uv, ism);
        let stored = select(ism_real[i], ism_virtual[i], virtual_atlas);
        let scale = select(c.depth, ism_sphere(ism, virtual_atlas).w, vpl_kind(v) == VPL_DIRECTIONAL);
        visible[a] = select(0.0, 1.0, ism_decode(stored) >= c.depth - scale * ism.splat.z - extent);
    }
    return visible;
}

// Irradiance (E_rv, E_r, luminance-free rgb) from the previous frame's environment VPLs at a
// surface point, shadowed by their ISMs, on both sides of the surface.
struct Irradiance {
    rv: vec3f,
    r: vec3f,
    back_rv: vec3f,
    back_r: vec3f,
}

// Threads per bounce slot in cs_finalize: the environment VPLs of a slot's irradiance sum and
// the tries of its near-point sampler are shared among them (one thread looping over every
// VPL was a chain of dependent ISM reads, 0.2 ms at 256 VPLs on an H100).
const LANES: u32 = 64u;
var<workgroup> partial: array<array<vec3f, LANES>, 4>;
var<workgroup> shared_word: u32;
var<workgroup> first_found: atomic<u32>;

fn add_irradiance(v: Vpl, index: u32, p: vec3f, n: vec3f, e: ptr<function, array<vec3f, 2>>) {
    let c = dot(n, -v.position.xyz);
    if (c <= 0.0) { return; }
    let vis = previous_visibility(index, v, p, n);
    (*e)[0] += v.power.rgb * c * min(vis.x, vis.y);
    (*e)[1] += v.power.rgb * c * vis.x;
}

// Every thread of the workgroup calls this and gets the sum.
fn environment_irradiance(p: vec3f, n: vec3f, lane: u32) -> Irradiance {
    var front = array<vec3f, 2>(vec3f(0.0), vec3f(0.0));
    var back = array<vec3f, 2>(vec3f(0.0), vec3f(0.0));
    for (var i = lane; i < params.counts.x; i += LANES) {
        let v = previous[i];
        if (vpl_kind(v) != VPL_DIRECTIONAL) { continue; }
        add_irradiance(v, i, p, n, &front);
        add_irradiance(v, i, p, -n, &back);
    }
    partial[0][lane] = front[0];
    partial[1][lane] = front[1];
    partial[2][lane] = back[0];
    partial[3][lane] = back[1];
    workgroupBarrier();
    for (var stride = LANES / 2u; stride > 0u; stride /= 2u) {
        if (lane < stride) {
            for (var k = 0u; k < 4u; k++) { partial[k][lane] += partial[k][lane + stride]; }
        }
        workgroupBarrier();
    }
    return Irradiance(partial[0][0], partial[1][0], partial[2][0], partial[3][0]);
}

@compute @workgroup_size(64)
fn cs_candidates(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let global = gid.x + gid.y * groups.x * 64u;
    if (global >= params.modes.z + params.modes.w) { return; }
    let range = bounce_range();
    if (range.y == 0u) { return; }
    // A hash, not `global % slots`: a block's points are ordered along the area CDF, so a
    // stride would give each slot a few thin stripes of the scene. New every frame.
    let slot = range.x + hash_u32(global ^ (params.counts.y * 0x9e3779b9u)) % range.y;
    let b = bounce_slots[slot];
    if (b.origin.w != SLOT_RAY) { return; }
    let p = world_point(global);
    // An `ir` path only continues on real geometry (§2.8, see the extraction's note 7).
    if ((b.info.x & VPL_IR) != 0u && !p.real) { return; }
    let to = p.position - b.origin.xyz;
    let dist = length(to);
    if (dist <= 1e-6) { return; }
    if (params.modes.y == 2u) {
        // DIR v1: the candidate with the largest received light.
        let v = previous[b.info.y];
        var received: f32;
        if (vpl_kind(v) == VPL_DIRECTIONAL) {
            received = luminance(v.power.rgb) * max(dot(p.normal * sign(dot(p.normal, -v.position.xyz)), -v.position.xyz), 0.0);
        } else {
            let l = to / dist;
            let cos_p = abs(dot(p.normal, l));
            // Clamped as the gather clamps: the point next to the source in a corner would
            // otherwise win every slot.
            received = luminance(vpl_intensity(v, l)) * cos_p / max(dist * dist, params.bounce.w * params.bounce.w);
        }
        let vis = previous_visibility(b.info.y, v, p.position, p.normal);
        let fitness = received * luminance(materials[p.material].base_color.rgb) * min(vis.x, vis.y);
        if (fitness <= 0.0) { return; }
        atomicMax(&best[slot], (u64(bitcast<u32>(fitness)) << 32u) | u64(global));
        return;
    }
    if (dot(to / dist, b.direction.xyz) < params.bounce.x) { return; }
    // Nearest first: the key grows as the distance shrinks.
    let key = (u64(0xffffffffu - bitcast<u32>(dist)) << 32u) | u64(global);
    atomicMax(&best[slot], key);
    if (p.real) { atomicMax(&best[params.counts.x + slot], key); }
}

// One workgroup per slot.
@compute @workgroup_size(LANES)
fn cs_finalize(@builtin(workgroup_id) group: vec3u, @builtin(local_invocation_index) lane: u32) {
    let slot = group.x;
    if (slot >= params.counts.x) { return; }
    let b = bounce_slots[slot];
    if (b.origin.w == SLOT_POINT) {
        let v = environment_bounce(slot, b, lane);
        if (lane == 0u) { vpls[slot] = v; }
        return;
    }
    if (lane != 0u) { return; }
    var packed = atomicLoad(&best[slot]);
    if (b.origin.w != SLOT_RAY || packed == u64(0u)) { return; }
    var p = world_point(u32(packed & u64(0xffffffffu)));
    var split = 1.0;
    var real_only = false;
    let behind = atomicLoad(&best[params.counts.x + slot]);
    if (params.modes.y == 1u && !p.real && (b.info.x & VPL_PATH_REAL) != 0u && behind != u64(0u)) {
        split = 2.0;
        if (hash_u32(slot ^ (params.counts.y * 0x85ebca6bu)) % 2u == 1u) {
            real_only = true;
            packed = behind;
            p = world_point(u32(packed & u64(0xffffffffu)));
        }
    }
    let m = materials[p.material];
    let incoming = normalize(b.origin.xyz - p.position);
    var v: Vpl;
    // Area this VPL stands for: 1 / (slots × density of the ray's hit point per area).
    let d2 = max(dot(p.position - b.origin.xyz, p.position - b.origin.xyz), 1e-8);
    let cos_hit = max(abs(dot(p.normal, incoming)), 0.05);
    v.position = vec4f(p.position, d2 / (cos_hit * max(b.direction.w, 1e-8)));
    let n = select(-p.normal, p.normal, dot(p.normal, incoming) >= 0.0);
    v.normal = vec4f(n, m.params.y);
    var power = b.carry.rgb * split;
    if (params.modes.y == 2u) {
        // DIR v1 has no sampling density: the winner stands for its share of the surfaces.
        // Its power is the slot's share of what the source reflects (the carry, as for a
        // traced ray), so the bounce conserves energy wherever the fitness puts it. (The
        // irradiance at the winner times that area was the *most* light any candidate got,
        // spread over all surfaces: it grew ×300 per frame and blacked the image.)
        v.position.w = (params.bounce.y + params.bounce.z) / f32(bounce_range().y);
    }
    v.power = vec4f(power, m.params.x);
    v.albedo = vec4f(vpl_base_color(m, m.base_color.rgb, m.params.x), m.dielectric.a);
    v.incoming = vec4f(incoming, (m.dielectric.r + m.dielectric.g + m.dielectric.b) / 3.0);
    // x̄ = x̄_source · r(p); ir is inherited (Eq. 5.9–5.10).
    var flags = (b.info.x & VPL_IR) | VPL_BOUNCED;
    if (real_only) { flags |= VPL_IR; }
    if (p.real) {
        flags |= VPL_REAL | (b.info.x & VPL_PATH_REAL);
    }
    let bounce_source = source_of_slot(slot, params.counts.z);
    v.info = vec4u(flags, bounce_source, VPL_SURFACE, previous[b.info.y].info.w + 1u);
    vpls[slot] = v;
}

fn is_near_virtual(p: vec3f) -> bool {
    for (var i = 0u; i < params.strata.x; i++) {
        let s = virtual_spheres[i];
        if (distance(p, s.xyz) < NEAR_RADII * s.w) { return true; }
    }
    return false;
}

// Counts the real points near virtual content (a sum: the same every run).
@compute @workgroup_size(64)
fn cs_near(@builtin(global_invocation_id) gid: vec3u, @builtin(num_workgroups) groups: vec3u) {
    let global = gid.x + gid.y * groups.x * 64u;
    if (global >= params.modes.z) { return; }
    if (is_near_virtual(world_point(global).position)) {
        atomicAdd(&near[0], 1u);
    }
}

// Tries of the rejection sampler of near points.
const NEAR_TRIES: u32 = 128u;

// The real point of try `t`.
fn near_try(seed: u32, t: u32, real_points: u32) -> u32 {
    return hash_u32(seed + t * 0x9e3779b9u) % real_points;
}

struct SurfaceSample {
    // The point; `area` is 0 where none was found.
    point: u32,
    // The surface area (m²) the sample stands for per expected sample: 1 / density.
    area: f32,
}

// Draws the surface point of an environment bounce from three strategies: uniformly over the
// virtual surfaces, uniformly over the real ones, and uniformly over the real points near
// virtual content, where the light that differential rendering adds or removes bounces
// between the two (a virtual object and the desk it stands on). Spending a third of the
// samples on each keeps VPLs dense where they matter without starving the rest; the real
// strategies are combined as one mixture (balance heuristic), so every real point is drawn
// with the same density whichever strategy chose it.
fn draw_surface_point(u: vec2f, lane: u32) -> SurfaceSample {
    let real_points = params.modes.z;
    let virtual_points = params.modes.w;
    if (lane == 0u) { shared_word = atomicLoad(&near[0]); }
    let near_count = workgroupUniformLoad(&shared_word);
    let has_virtual = params.bounce.z > 0.0 && virtual_points > 0u;
    let has_real = params.bounce.y > 0.0 && real_points > 0u;
    var w = vec3f(select(0.0, 1.0, has_virtual), select(0.0, 1.0, has_real), select(0.0, 1.0, has_real && near_count > 0u));
    w /= max(w.x + w.y + w.z, 1e-8);
    var out: SurfaceSample;
    if (u.x < w.x) {
        out.point = real_points + min(u32(u.y * f32(virtual_points)), virtual_points - 1u);
        out.area = params.bounce.z / w.x;
        return out;
    }
    // The near strategy draws real points until one is near (deterministic hashes of `u`, the
    // threads trying in parallel, the first success in try order winning); given success the
    // point is uniform over the near ones, and the strategy's weight is scaled by its success
    // probability 1 − (1 − f)^tries.
    let f = f32(near_count) / f32(real_points);
    let success = 1.0 - pow(1.0 - f, f32(NEAR_TRIES));
    out.point = min(u32(u.y * f32(real_points)), real_points - 1u);
    if (u.x >= w.x + w.y) {
        if (lane == 0u) { atomicStore(&first_found, NEAR_TRIES); }
        workgroupBarrier();
        let seed = bitcast<u32>(u.y) ^ 0x9e3779b9u;
        for (var t = lane; t < NEAR_TRIES; t += LANES) {
            if (is_near_virtual(world_point(near_try(seed, t, real_points)).position)) {
                atomicMin(&first_found, t);
                break;
            }
        }
        workgroupBarrier();
        if (lane == 0u) { shared_word = atomicLoad(&first_found); }
        let first = workgroupUniformLoad(&shared_word);
        if (first >= NEAR_TRIES) { return out; }
        out.point = near_try(seed, first, real_points);
    }
    // Mixture probability of this point per real sample.
    var p = w.y / f32(real_points);
    if (near_count > 0u && is_near_virtual(world_point(out.point).position)) { p += w.z * success / f32(near_count); }
    out.area = params.bounce.y / (f32(real_points) * p);
    return out;
}

// A VPL at a surface point drawn by area, lit by the probe (through last frame's environment
// VPLs). Real light on a real point that virtual content shadows goes into the co-located
// VPL3 (`power_ir`), so that L_r keeps it and L_rv does not.
fn environment_bounce(slot: u32, b: BounceSlot, lane: u32) -> Vpl {
    let sample = draw_surface_point(b.direction.xy, lane);
    if (sample.area <= 0.0) { return empty_vpl(); }
    let p = world_point(sample.point);
    let m = materials[p.material];
    // The probe's light off a mirror, a glass or a smooth metal is a caustic: the specular
    // stage's photons carry it, sharp and undiminished where the object touches the desk.
    // As a VPL it was spread over a roughened lobe around the normal (VPL_MIN_ROUGHNESS) and
    // clamped at d_min: the desk under desk-mirror's sphere and around its torus stayed 6/255
    // too dark within 10 pixels of them.
    if (params.strata.y == 1u && is_traced(m)) { return empty_vpl(); }
    let carry = b.carry.rgb * sample.area;
    // A single-sided surface is lit on its front; a double-sided one on its brighter side.
    var n = p.normal;
    let both = environment_irradiance(p.position, p.normal, lane);
    var e = Irradiance(both.rv, both.r, vec3f(0.0), vec3f(0.0));
    if (is_double_sided(m) && luminance(both.back_rv) > luminance(both.rv)) {
        n = -p.normal;
        e = Irradiance(both.back_rv, both.back_r, vec3f(0.0), vec3f(0.0));
    }
    var v: Vpl;
    if (all(e.r == vec3f(0.0))) { return v; }
    // carry: the area this VPL stands for.
    v.position = vec4f(p.position, carry.x);
    v.normal = vec4f(n, m.params.y);
    v.power = vec4f(e.rv * carry, m.params.x);
    v.albedo = vec4f(vpl_base_color(m, m.base_color.rgb, m.params.x), m.dielectric.a);
    v.incoming = vec4f(n, (m.dielectric.r + m.dielectric.g + m.dielectric.b) / 3.0);
    var flags = 0u;
    if (p.real) {
        flags = VPL_REAL | VPL_PATH_REAL;
        v.power_ir = vec4f(max(e.r - e.rv, vec3f(0.0)) * carry, 0.0);
    }
    v.info = vec4u(flags, source_of_slot(slot, params.counts.z), VPL_SURFACE, 1u);
    return v;
}
