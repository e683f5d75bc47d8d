@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: SpecularParams;
@group(0) @binding(2) var<uniform> caustics: CausticParams;
@group(0) @binding(3) var<uniform> shadow_params: ShadowParams;

@group(1) @binding(0) var<storage, read> instances: array<Instance>;
@group(1) @binding(1) var<storage, read> vertices: array<f32>;
@group(1) @binding(2) var<storage, read> indices: array<u32>;
@group(1) @binding(3) var<storage, read> triangles: array<vec4u>;
@group(1) @binding(4) var<storage, read> materials: array<Material>;
@group(1) @binding(5) var<storage, read> impostors: array<Impostor>;
@group(1) @binding(6) var<storage, read> owners: array<Owner>;
@group(1) @binding(7) var<storage, read> impostor_texels: array<vec2u>;
@group(1) @binding(8) var<storage, read> lights: array<Light>;
@group(1) @binding(9) var<storage, read> shadow_clip_from_world: array<mat4x4f>;
@group(1) @binding(10) var<storage, read> shadow_texels: array<vec2u>;
@group(1) @binding(11) var<storage, read> interiors: array<Interior>;
@group(1) @binding(12) var<storage, read> bvh_nodes: array<BvhNode>;
@group(1) @binding(13) var<storage, read> bvh_triangles: array<u32>;
@group(1) @binding(14) var<storage, read> bvh_corners: array<vec4f>;

@group(2) @binding(0) var<storage, read_write> photons: array<Photon>;
// The landed photons of each caustic level (level × photon_slots() + i), and their draws.
@group(2) @binding(1) var<storage, read_write> splat_list: array<u32>;
@group(2) @binding(2) var<storage, read_write> splat_draws: array<SplatDraw, 2>;
// The world-space grid of the landed photons (shaders/lib/photon_grid.wgsl): header, heads'
// counts and range ends; the photons it lists; its cells' ranges of photon indices.
@group(2) @binding(3) var<storage, read_write> grid: array<atomic<u32>>;
@group(2) @binding(4) var<storage, read_write> grid_photons: array<GridPhoton>;
@group(2) @binding(5) var<storage, read_write> grid_entries: array<u32>;
// Per photon slot: the cells cs_size counted the photon in (grid_cells_pack).
@group(2) @binding(6) var<storage, read_write> grid_photon_cells: array<vec4i>;

@group(3) @binding(0) var env_radiance: texture_2d<f32>;
@group(3) @binding(1) var env_irradiance: texture_2d<f32>;
@group(3) @binding(2) var env_dfg_table: texture_2d<f32>;
@group(3) @binding(3) var env_sampler: sampler;

// Probe direction `k` of this frame's `count` as a directional light (beyond the documents,
// whose caustics are of spot lights): a spherical Fibonacci set over the upper hemisphere
// (light from below comes through the floor), rotated and shifted every frame so that stills
// and the temporal smoothing see the whole sky; each direction carries the probe's radiance
// prefiltered over about the 2π/count sr it stands for, times that solid angle.
fn probe_light(k: u32, count: u32) -> Light {
    let frame_index = u32(frame.exposure_env.w);
    let jitter = hash_uniform2(frame_index * 2u + 1u);
    let y = 1.0 - (f32(k) + jitter.x) / f32(count);
    let phi = 2.0 * PI * fract(f32(k) * 0.6180339887 + jitter.y);
    let r = sqrt(max(1.0 - y * y, 0.0));
    let toward = vec3f(r * cos(phi), y, r * sin(phi));
    let solid_angle = 2.0 * PI / f32(count);
    // GGX roughness whose lobe spans about that solid angle (α² ≈ Ω / π, clamped).
    let roughness = clamp(sqrt(sqrt(solid_angle / PI)), 0.05, 1.0);
    var l: Light;
    l.direction_real = vec4f(-toward, 1.0);
    l.intensity = vec4f(env_radiance_at(frame, toward, roughness) * solid_angle, 0.0);
    l.info = vec4u(LIGHT_DIRECTIONAL, 0u, 1u, 0u);
    return l;
}

// A photon as it leaves the light: its ray and the solid angle (perspective maps) or area
// (orthographic) its texel stands for.
struct Emitted {
    origin: vec3f,
    dir: vec3f,
    measure: f32,
}

fn emit(light: Light, texel: vec2u) -> Emitted {
    var out: Emitted;
    let res = f32(caustics.info.x);
    let uv = (vec2f(texel) + 0.5) / res * 2.0 - 1.0;
    let centre = caustics.casters.xyz;
    let radius = caustics.casters.w;
    if (light.info.x == LIGHT_DIRECTIONAL) {
        let axis = light.direction_real.xyz;
        let tb = tangent_frame(axis);
        out.origin = centre - axis * (2.0 * radius) + (tb[0] * uv.x + tb[1] * uv.y) * radius;
        out.dir = axis;
        out.measure = (2.0 * radius / res) * (2.0 * radius / res);
        return out;
    }
    let to = centre - light.position.xyz;
    let d = length(to);
    let axis = to / max(d, 1e-12);
    // Half-angle of the map: the sphere's silhouette (a wide 84° when the light is inside it).
    let s = min(radius / max(d, 1e-12), 0.995);
    let t = s / sqrt(1.0 - s * s);
    let tb = tangent_frame(axis);
    let ray = axis + (tb[0] * uv.x + tb[1] * uv.y) * t;
    out.origin = light.position.xyz;
    out.dir = normalize(ray);
    // Solid angle of a texel of side e on the plane at unit distance: e² cos³θ.
    let e = 2.0 * t / res;
    let c = dot(out.dir, axis);
    out.measure = e * e * c * c * c;
    return out;
}

// The first traced object on the ray: (triangle + 1, t), or triangle 0.
fn first_caster(origin: vec3f, dir: vec3f) -> vec2f {
    var best = vec2f(0.0, 3.0e38);
    for (var k = 0u; k < arrayLength(&interiors); k++) {
        let hit = trace_interior(k, origin, dir, 0.0);
        if (hit.x > 0.0 && hit.y < best.y) { best = hit; }
    }
    return best;
}

// Where a photon leaving `origin` along `dir` from `owner` lands, in the whole world or the
// real-only one, with `power` times the path's Fresnel and transmittance.
fn land(origin: vec3f, dir: vec3f, owner: u32, real_only: bool, first_sees_self: bool, power: vec3f) -> Photon {
    var out: Photon;
    if (all(power <= vec3f(0.0))) { return out; }
    let end = trace_ray(origin, dir, owner, real_only, first_sees_self, NO_VIEW);
    if (end.triangle == 0u) { return out; }
    let h = intersect(end.triangle - 1u, end.position - end.dir, end.dir);
    // A specular surface at the last bounce receives no caustic: it has no diffuse part.
    if (is_traced(materials[instances[h.instance].info.x])) { return out; }
    out.position = vec4f(end.position, 1.0);
    out.normal = vec4f(facing_normal(h, -end.dir), 0.0);
    out.power = vec4f(power * end.weight, bitcast<f32>(end.triangle));
    return out;
}

// One photon of one kind per invocation (z = source · PHOTON_KINDS + kind): 0 reflected and
// 1 refracted through the whole world (L_rv), 2 and 3 the same through the real-only world
// (L_r, only for paths whose light and caster are real). The four kinds of a texel draw the
// same random choices (their keys are the kind-0 and kind-1 indices), so that a path without
// virtual parts lands alike in both worlds.
@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) local: u32) {
    lane = local;
    let res = caustics.info.x;
    let source = id.z / PHOTON_KINDS;
    let kind = id.z % PHOTON_KINDS;
    if (any(id.xy >= vec2u(res)) || source >= caustics.info.y) { return; }
    let slot = photon_index(source, kind, id.xy);
    photons[slot] = Photon(vec4f(0.0), vec4f(0.0), vec4f(0.0));
    let from_probe = caustics.info.z == 1u;
    var light: Light;
    if (from_probe) { light = probe_light(source, caustics.info.y); } else { light = lights[source]; }
    let e = emit(light, id.xy);
    let first = first_caster(e.origin, e.dir);
    if (first.x == 0.0) { return; }
    let h = intersect(u32(first.x) - 1u, e.origin, e.dir);
    let real_world = kind >= 2u;
    if (real_world && !(light.direction_real.w > 0.5 && instance_is_real(h.instance))) { return; }
    let m = materials[instances[h.instance].info.x];
    let n = facing_normal(h, -e.dir);
    let incident = light_incident(light, h.position);
    // Power through the texel: intensity × solid angle (light_incident divides by d²), or
    // irradiance × area.
    var power = incident.radiance * e.measure;
    if (light.info.x != LIGHT_DIRECTIONAL) { power *= incident.distance * incident.distance; }
    // The punctual lights' shadow maps (the real-only world sees only real casters); the
    // probe's light reaches its casters unoccluded.
    var visible = 1.0;
    if (!from_probe) {
        visible = shadow_visibility(light, light.info.y, h.position, n);
        if (!real_world) { visible = min(visible, shadow_visibility(light, light.info.w, h.position, n)); }
    }
    let cos_i = max(dot(n, -e.dir), 0.0);
    let metallic = m.params.x;
    if ((kind & 1u) == 0u) {
        let f0 = material_f0(m);
        let reflectance = schlick(f0, mix(m.dielectric.a, 1.0, metallic), cos_i);
        // A glossy caster reflects each photon into its GGX lobe: one microfacet per photon
        // and frame, as the camera's rays (stills and temporal smoothing average them): a
        // rough metal's caustic of a lamp is a glow, not a mirror's sharp image.
        let roughness = clamp(m.params.y, 0.0, 1.0);
        let lobe_seed = hash_u32(photon_index(source, 0u, id.xy) * 2654435761u ^ u32(frame.exposure_env.w) * 83492791u);
        var reflected = reflect(e.dir, microfacet_normal(n, -e.dir, roughness, lobe_seed));
        if (dot(reflected, n) <= 0.0) { reflected = reflect(e.dir, n); }
        let concave = interiors[h.instance].info.y == 1u;
        // The probe's light reflected by a traced surface lands as photons too; `dir`'s
        // environment-bounce VPLs leave traced surfaces out (bounce.wgsl), so it is counted
        // once.
        photons[slot] = land(h.position, reflected, h.instance, real_world, concave, power * reflectance * visible);
        return;
    }
    let transmission = m.transmission.x * (1.0 - metallic);
    if (transmission <= 0.0) { return; }
    let ior = max(m.transmission.y, 1.0);
    let exit = traced_exit(h.instance, h.position, e.dir, n, ior, photon_index(source, 1u, id.xy));
    let through = power * transmission * (1.0 - fresnel_ior(ior, cos_i)) * exit_transmittance(m, m.base_color.rgb, exit, ior);
    photons[slot] = land(exit.position, exit.dir, h.instance, real_world, true, through * visible);
}

// World distance to the photon's landed neighbour `dx`, `dy` texels away (0 if none).
fn neighbour_distance(index: u32, texel: vec2u, p: vec3f, dx: i32, dy: i32) -> f32 {
    let res = i32(caustics.info.x);
    let q = vec2i(texel) + vec2i(dx, dy);
    if (any(q < vec2i(0)) || any(q >= vec2i(res))) { return 0.0; }
    let other = photons[u32(i32(index) + dy * res + dx)];
    if (other.position.w == 0.0) { return 0.0; }
    return distance(other.position.xyz, p);
}

// The smaller of two neighbour distances that exist (0: none).
fn nearer(a: f32, b: f32) -> f32 {
    if (a == 0.0) { return b; }
    if (b == 0.0) { return a; }
    return min(a, b);
}

// What a workgroup's photons add to the grid's header: the levels they use (bits), and the
// box their footprints span (order keys: the lower corner's complemented, so that both corners
// grow by atomicMax from the cleared 0).
var<workgroup> group_levels: atomic<u32>;
var<workgroup> group_box: array<atomic<u32>, 6>;

// Counts the landed photon `index` (its half-size sized) in the cells of the world-space
// grid that its footprint touches, and copies it there, as a photon of `world` (GRID_OF_RV,
// GRID_OF_R); cs_grid_scatter lists it once the cells' ranges are known.
fn grid_count(index: u32, world: f32) {
    let photon = photons[index];
    let splat_min = caustics.splat.x;
    let p = photon.position.xyz;
    let h = photon.normal.w;
    let level = grid_level(h, splat_min);
    atomicOr(&group_levels, 1u << level);
    let reach = grid_reach(photon.normal.xyz, h);
    for (var axis = 0u; axis < 3u; axis++) {
        atomicMax(&group_box[axis], ~order_key(p[axis] - reach[axis]));
        atomicMax(&group_box[3u + axis], order_key(p[axis] + reach[axis]));
    }
    let heads = grid_heads(arrayLength(&grid));
    let cells = grid_cells(p, reach, level, splat_min);
    for (var k = 0; k < cells.count.x * cells.count.y * cells.count.z; k++) {
        let head = grid_listed_head(cells, k, level, heads);
        if (head != GRID_NO_HEAD) { atomicAdd(&grid[grid_count_word(head)], 1u); }
    }
    grid_photons[index] = GridPhoton(vec4f(p, h), vec4f(photon.normal.xyz, world), vec4f(photon.power.rgb, 0.0));
    grid_photon_cells[index] = grid_cells_pack(cells, level);
}

// Puts the sized photon of `light`, `kind` and `texel` on the grid, once both worlds' photons
// of this texel and branch are known: an L_r photon that landed as its L_rv twin did (no
// virtual part on its path) is not listed, the twin carries it for both worlds.
fn grid_add(light: u32, kind: u32, texel: vec2u, landed: array<bool, 4>) {
    let index = photon_index(light, kind, texel);
    if (kind < 2u) {
        grid_count(index, GRID_OF_RV);
        return;
    }
    let twin = photon_index(light, kind - 2u, texel);
    let a = photons[index];
    let b = photons[twin];
    if (landed[kind - 2u] && all(a.position == b.position) && all(a.normal == b.normal) && all(a.power == b.power)) {
        grid_photons[twin].normal.w = GRID_OF_BOTH;
        grid_photon_cells[index] = GRID_NOT_LISTED;
    } else {
        grid_count(index, GRID_OF_R);
    }
}

// Adds the workgroup's levels and box to the grid's header, once per workgroup (local
// invocation `local`).
fn grid_header_update(local: u32) {
    let levels = atomicLoad(&group_levels);
    if (levels == 0u) { return; }
    if (local == 0u) { atomicOr(&grid[GRID_LEVELS_WORD], levels); }
    if (local < 6u) {
        let word = select(GRID_BOX_MAX_WORD + local - 3u, GRID_BOX_MIN_WORD + local, local < 3u);
        atomicMax(&grid[word], atomicLoad(&group_box[local]));
    }
}

// Each landed photon's quad half-size (spec §2.17.2, "computed from the world-position of the
// adjacent photons, similar as in the work of Wyman"), into normal.w, clamped to [splat_min,
// splat_far_max]: the photon spacing along each axis of the map is the nearer neighbour's
// distance, so that one neighbour across a discontinuity (another surface, the caster's
// silhouette) does not blow the quad up; the wider axis sizes the quad. Once per photon
// here, not per vertex of its quad. Then the photon joins its level's splat list: counted in
// workgroup memory first, so that a workgroup adds to each global count once.
var<workgroup> group_count: array<atomic<u32>, 2>;
var<workgroup> group_base: array<u32, 2>;

@compute @workgroup_size(8, 8)
fn cs_size(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) local: u32) {
    if (local < 2u) { atomicStore(&group_count[local], 0u); }
    if (local < 6u) { atomicStore(&group_box[local], 0u); }
    if (local == 0u) { atomicStore(&group_levels, 0u); }
    workgroupBarrier();
    let res = caustics.info.x;
    let inside = all(id.xy < vec2u(res)) && id.z < caustics.info.y;
    // Per kind: the photon's index, its level and its slot within the workgroup's share.
    var listed = array<vec3u, 4>(vec3u(0u), vec3u(0u), vec3u(0u), vec3u(0u));
    var landed = array<bool, 4>(false, false, false, false);
    for (var kind = 0u; kind < PHOTON_KINDS; kind++) {
        if (!inside) { break; }
        let index = photon_index(id.z, kind, id.xy);
        let photon = photons[index];
        if (photon.position.w == 0.0) { continue; }
        let p = photon.position.xyz;
        let spacing = max(
            nearer(neighbour_distance(index, id.xy, p, -1, 0), neighbour_distance(index, id.xy, p, 1, 0)),
            nearer(neighbour_distance(index, id.xy, p, 0, -1), neighbour_distance(index, id.xy, p, 0, 1)),
        );
        let size = clamp(spacing, caustics.splat.x, caustics.splat.z);
        photons[index].normal.w = size;
        let level = select(0u, 1u, size > caustics.splat.y);
        listed[kind] = vec3u(index, level, atomicAdd(&group_count[level], 1u));
        landed[kind] = true;
        // The probe's photons stay off the grid: surfaces off screen take the probe
        // unshadowed (resolve.wgsl, shade_hit), which holds the sky a glass lets through.
        if (caustics.info.z == 0u) { grid_add(id.z, kind, id.xy, landed); }
    }
    workgroupBarrier();
    grid_header_update(local);
    if (local < 2u) {
        let count = atomicLoad(&group_count[local]);
        group_base[local] = atomicAdd(&splat_draws[local].vertex_count, 6u * count) / 6u;
    }
    workgroupBarrier();
    for (var kind = 0u; kind < PHOTON_KINDS; kind++) {
        if (!landed[kind]) { continue; }
        let l = listed[kind];
        splat_list[l.y * photon_slots() + group_base[l.y] + l.z] = l.x;
    }
}

// Each head's range of the grid's entries (after cs_size counted them), one thread per head:
// the workgroup's heads take one share of the entries, handed out by a single atomic (the
// ranges' order does not matter). A range's start goes where its end will be.
var<workgroup> group_entries: atomic<u32>;
var<workgroup> group_start: u32;

@compute @workgroup_size(256)
fn cs_grid_ranges(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) local: u32) {
    if (local == 0u) { atomicStore(&group_entries, 0u); }
    workgroupBarrier();
    let heads = grid_heads(arrayLength(&grid));
    let head = id.x;
    var count = 0u;
    if (head < heads) { count = atomicLoad(&grid[grid_count_word(head)]); }
    var offset = 0u;
    if (count != 0u) { offset = atomicAdd(&group_entries, count); }
    workgroupBarrier();
    if (local == 0u) {
        let total = atomicLoad(&group_entries);
        if (total != 0u) { group_start = atomicAdd(&grid[GRID_TOTAL_WORD], total); }
    }
    workgroupBarrier();
    if (count != 0u) { atomicStore(&grid[grid_end_word(head, heads)], group_start + offset); }
}

// Lists each landed photon of the punctual lights in the ranges of the cells cs_size
// counted it in (their ends then lie past their last entries).
@compute @workgroup_size(8, 8)
fn cs_grid_scatter(@builtin(global_invocation_id) id: vec3u) {
    let res = caustics.info.x;
    if (any(id.xy >= vec2u(res)) || id.z >= caustics.info.y) { return; }
    let heads = grid_heads(arrayLength(&grid));
    for (var kind = 0u; kind < PHOTON_KINDS; kind++) {
        let index = photon_index(id.z, kind, id.xy);
        if (photons[index].position.w == 0.0) { continue; }
        let packed = grid_photon_cells[index];
        if (all(packed == GRID_NOT_LISTED)) { continue; }
        let level = grid_cells_level(packed);
        let cells = grid_cells_unpack(packed);
        for (var k = 0; k < cells.count.x * cells.count.y * cells.count.z; k++) {
            let head = grid_listed_head(cells, k, level, heads);
            if (head == GRID_NO_HEAD) { continue; }
            let slot = atomicAdd(&grid[grid_end_word(head, heads)], 1u);
            if (slot < arrayLength(&grid_entries)) { grid_entries[slot] = index; }
        }
    }
}

// Empties the grid for the next frame's photons once the resolve has read it (a dispatch
// beside the specular smoothing: a buffer fill between passes waits for all the work before
// it): its levels (word 0), box, entries handed out and the heads' counts, one thread per
// word; splat_min and the depth epsilon stay, and the range ends are written before they are
// read.
@compute @workgroup_size(256)
fn cs_grid_clear(@builtin(global_invocation_id) id: vec3u) {
    let word = id.x;
    if (word < GRID_HEADER + grid_heads(arrayLength(&grid)) && (word == GRID_LEVELS_WORD || word >= GRID_BOX_MIN_WORD)) {
        atomicStore(&grid[word], 0u);
    }
}
