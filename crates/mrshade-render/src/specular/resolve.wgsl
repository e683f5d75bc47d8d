// Resolve of the reflection and refraction G-buffers (reflections spec §2.5–§2.9): the light
// that each traced pixel's branches bring, as camera values, composed by differential
// rendering per branch. A branch ending on a real surface that the photo shows (inside the
// frustum and not behind a real surface in the real-only depth, §2.8) takes the photo's
// pixel there, the back-projection of §2.9, plus α'·(L'_rv − L'_r) of that surface: the
// photo's own detail, with the virtual objects' shadows and light added. Where the photo
// does not show it, the branch is rendered, `L'_rv`; a ray that leaves the scene sees the
// probe (`L_env`, counted real). The surface's `L'_rv`, `L'_r` are the screen's buffers where
// the camera sees that very surface (so the method's indirect light is in them), and are
// otherwise shaded here with every punctual light and the probe, routed by the flags of the
// light → surface part of the path only (§2.5: r(ls) ∧ r(p_hit)).
//
// Virtual pixels receive Σ w·C of their branches; real pixels (a real mirror or glass) the
// difference Σ w·(C − C_r) against the same rays traced through the real-only world, which
// is exactly zero when nothing virtual is seen or shadows what is seen.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: SpecularParams;
@group(0) @binding(2) var<uniform> composite_params: CompositeParams;
@group(0) @binding(3) var<uniform> shadow_params: ShadowParams;
@group(0) @binding(4) var gbuffer_flags: texture_2d<u32>;
@group(0) @binding(5) var l_rv_texture: texture_2d<f32>;
@group(0) @binding(6) var l_r_texture: texture_2d<f32>;
@group(0) @binding(7) var photo_texture: texture_2d<f32>;
@group(0) @binding(8) var reflection_hit: texture_2d<f32>;
@group(0) @binding(9) var reflection_dir: texture_2d<f32>;
@group(0) @binding(10) var reflection_weight: texture_2d<f32>;
@group(0) @binding(11) var refraction_hit: texture_2d<f32>;
@group(0) @binding(12) var refraction_dir: texture_2d<f32>;
@group(0) @binding(13) var refraction_weight: texture_2d<f32>;
@group(0) @binding(14) var reflection_real_hit: texture_2d<f32>;
@group(0) @binding(15) var refraction_real_hit: texture_2d<f32>;
@group(0) @binding(16) var gbuffer_albedo_metallic: texture_2d<f32>;
// The caustic buffer (caustics/splat.wgsl): irradiance of the L_rv and of the L_r photons.
@group(0) @binding(17) var caustics_rv: texture_2d<f32>;
@group(0) @binding(18) var caustics_r: texture_2d<f32>;
// The method's light at any point (methods::PointLight): its VPLs and their ISMs.
@group(0) @binding(19) var<uniform> ism: IsmParams;
// The caustic buffer's coarse level (photons farther apart than splat_max).
@group(0) @binding(20) var caustics_coarse_rv: texture_2d<f32>;
@group(0) @binding(21) var caustics_coarse_r: texture_2d<f32>;
// The landed photons in world space (shaders/lib/photon_grid.wgsl), for the surfaces the
// camera does not see.
@group(0) @binding(22) var<storage, read> grid: array<u32>;
@group(0) @binding(23) var<storage, read> grid_photons: array<GridPhoton>;
@group(0) @binding(24) var<storage, read> grid_entries: array<u32>;

@group(1) @binding(0) var<storage, read> instances: array<Instance>;
@group(1) @binding(1) var<storage, read> vertices: array<f32>;
@group(1) @binding(2) var<storage, read> indices: array<u32>;
@group(1) @binding(3) var<storage, read> triangles: array<vec4u>;
@group(1) @binding(4) var<storage, read> materials: array<Material>;
@group(1) @binding(5) var<storage, read> impostors: array<Impostor>;
@group(1) @binding(6) var<storage, read> owners: array<Owner>;
@group(1) @binding(7) var<storage, read> impostor_texels: array<vec2u>;
@group(1) @binding(8) var<storage, read> camera_visibility: array<vec2u>;
@group(1) @binding(9) var<storage, read> real_visibility: array<vec2u>;
@group(1) @binding(10) var<storage, read> lights: array<Light>;
@group(1) @binding(11) var<storage, read> shadow_clip_from_world: array<mat4x4f>;
@group(1) @binding(12) var<storage, read> shadow_texels: array<vec2u>;
@group(1) @binding(13) var<storage, read> interiors: array<Interior>;
@group(1) @binding(14) var<storage, read> bvh_nodes: array<BvhNode>;
@group(1) @binding(15) var<storage, read> bvh_triangles: array<u32>;
@group(1) @binding(16) var<storage, read> bvh_corners: array<vec4f>;
@group(1) @binding(17) var<storage, read> vpls: array<Vpl>;
@group(1) @binding(18) var<storage, read> ism_real: array<u32>;
@group(1) @binding(19) var<storage, read> ism_virtual: array<u32>;

@group(2) @binding(0) var env_radiance: texture_2d<f32>;
@group(2) @binding(1) var env_irradiance: texture_2d<f32>;
@group(2) @binding(2) var env_dfg_table: texture_2d<f32>;
@group(2) @binding(3) var env_sampler: sampler;
@group(2) @binding(4) var textures_srgb: texture_2d_array<f32>;
@group(2) @binding(5) var textures_linear: texture_2d_array<f32>;
@group(2) @binding(6) var texture_sampler: sampler;

// The first of the VPLs this pixel's hit surfaces are shaded with (every `stride`-th from it,
// params.more.y): the subset rotates over the pixels and frames like the method's interleaving.
var<private> hit_vpl_first: u32;

// rgb: camera values to add (virtual pixels) or the difference to add (real pixels)
@group(3) @binding(0) var out_specular: texture_storage_2d<rgba16float, write>;

// What one branch brings, in camera values: rendered, and (if the photo shows its surface)
// back-projected.
struct BranchLight {
    rendered: vec3f,
    photo_based: vec3f,
    in_photo: bool,
    // The real-only world's value with the same choice (for real pixels).
    real: vec3f,
}

// The surface of `triangle` where the ray along `dir` meets it, shaded with every punctual
// light, the method's light at any point (its VPLs) and the unshadowed probe (`L'_rv`,
// `L'_r`).
// Surfaces reached off screen have no screen-space near field (vpl_light.wgsl).
fn screen_covers(x: vec3f, how: VplShading) -> bool { return false; }

fn shade_hit(triangle: u32, position: vec3f, dir: vec3f) -> Radiance {
    let h = intersect(triangle - 1u, position - dir * 1e-3, dir);
    let inst = instances[h.instance];
    let m = materials[inst.info.x];
    let bits = m.texture_info.y;
    let zero = vec2f(0.0);
    let base = m.base_color * sample_slot(true, m.texture_layers.x, bits, 0u, h.uv, zero, zero, vec4f(1.0));
    let mr = sample_slot(false, m.texture_layers.y, bits, 1u, h.uv, zero, zero, vec4f(1.0));
    var s: Surface;
    s.position = h.position;
    s.normal = facing_normal(h, -dir);
    s.view = -dir;
    s.base_color = base.rgb;
    s.metallic = clamp(m.params.x * mr.b, 0.0, 1.0);
    s.roughness = clamp(m.params.y * mr.g, 0.0, 1.0);
    s.dielectric_f0 = m.dielectric.rgb;
    s.dielectric_f90 = m.dielectric.a;
    s.transmission = m.transmission.x;
    s.emission = m.emissive.rgb;
    s.occlusion = 1.0;
    let r_p = select(0.0, 1.0, (inst.info.y & SURFACE_REAL) != 0u);
    var light = punctual_radiance(s, r_p);
    // The method's VPLs, every `stride`-th (scaled by it): their indirect light. Not the
    // visibility ratios of the environment VPLs: shadowing the probe here made both specular
    // scenes worse (desk-glass region FLIP 0.145 → 0.158, desk-mirror 0.109 → 0.111): these
    // surfaces receive none of the probe's photons (the caustic buffer is the screen's, the
    // grid below holds the punctual lights'), so the light the glass and the mirror send
    // onto the desk went missing, and the shadows of the virtual
    // boxes beside desk-mirror's sphere turned black in its reflection.
    let how = VplShading(params.tolerances.z, params.tolerances.z, vec2f(0.0), 0.0, 1.0, false, false);
    let stride = params.more.y;
    let vpl = vpl_light(s, is_traced(m), r_p, hit_vpl_first, stride, params.more.x, how);
    let probe = env_shading(frame, s, vec3f(0.0)) + s.emission;
    // The caustics of the punctual lights on it (§2.17.4): from the photons' world-space
    // grid, as the camera does not see this surface (the caustic buffer is the screen's).
    // Not the probe's photons: the unshadowed probe above already holds the sky that a glass
    // lets through onto it (with them, desk-glass's region FLIP went 0.111 → 0.134 for `dir`
    // at 32 frames on lavapipe: the desk under the glass bunny, seen through it, twice lit).
    let caustic = grid_caustics(s.position, s.normal);
    let diffuse = caustic_brdf(s.base_color, s.metallic, s.transmission);
    light.rv += probe + vpl.rv * f32(stride) + diffuse * caustic.rv;
    light.r += probe * r_p + vpl.r * f32(stride) + diffuse * caustic.r * r_p;
    return light;
}

// Most entries one lookup reads in a cell: a cell crowded with more (a caustic's focus, its
// quads clamped to splat_min, holds hundreds) is read at a stratified subset, every
// stride-th entry from a random start, each weighted by the stride (an unbiased estimate of
// the sum that the frames average; with `concentration = "thesis"`, whose k_c is a nonlinear
// function of the count, nearly so), so that a lookup's cost does not follow the photon
// count. Twins that landed alike are one entry for both worlds (GRID_OF_BOTH), so that
// without virtual parts on their paths both worlds read the same photons. (A subset chosen
// per entry by a hash of its photon pair read every index of the cell: resolve 0.29 → 0.39 ms
// at 1080p on an H100.)
const GRID_CELL_VISITS: u32 = 32u;

// The caustic irradiance at `x` (normal `n`) of the L_rv and of the L_r photons, from the
// photons' world-space grid: the quads listed in the cell of `x` on every level that holds
// photons (photons of another level that share the cell's head are skipped).
fn grid_caustics(x: vec3f, n: vec3f) -> Radiance {
    var rv = vec4f(0.0);
    var r = vec4f(0.0);
    let levels = grid[GRID_LEVELS_WORD];
    if (levels == 0u) { return Radiance(vec3f(0.0), vec3f(0.0)); }
    let tolerance = bitcast<f32>(grid[GRID_EPSILON_WORD]) * distance(x, frame.camera_position.xyz);
    // Most reflected and refracted rays end far from every caustic.
    let lo = vec3f(
        from_order_key(~grid[GRID_BOX_MIN_WORD]),
        from_order_key(~grid[GRID_BOX_MIN_WORD + 1u]),
        from_order_key(~grid[GRID_BOX_MIN_WORD + 2u]),
    );
    let hi = vec3f(
        from_order_key(grid[GRID_BOX_MAX_WORD]),
        from_order_key(grid[GRID_BOX_MAX_WORD + 1u]),
        from_order_key(grid[GRID_BOX_MAX_WORD + 2u]),
    );
    if (any(x < lo) || any(x > hi)) { return Radiance(vec3f(0.0), vec3f(0.0)); }
    let splat_min = bitcast<f32>(grid[GRID_SPLAT_MIN_WORD]);
    let heads = grid_heads(arrayLength(&grid));
    let entries = arrayLength(&grid_entries);
    let seed = hash_u32(bitcast<u32>(x.x) ^ hash_u32(bitcast<u32>(x.y) ^ hash_u32(bitcast<u32>(x.z) ^ u32(frame.exposure_env.w))));
    for (var level = 0u; level < GRID_LEVELS; level++) {
        if ((levels & (1u << level)) == 0u) { continue; }
        let head = grid_head(level, grid_cell(x, level, splat_min), heads);
        let end = min(grid[grid_end_word(head, heads)], entries);
        let count = min(grid[grid_count_word(head)], end);
        let stride = max((count + GRID_CELL_VISITS - 1u) / GRID_CELL_VISITS, 1u);
        let weight = f32(stride);
        for (var i = end - count + hash_u32(seed ^ level) % stride; i < end; i += stride) {
            let p = grid_photons[grid_entries[i]];
            if (grid_level(p.position.w, splat_min) != level) { continue; }
            let e = weight * grid_photon_irradiance(p, x, n, tolerance);
            if (p.normal.w != GRID_OF_R) { rv += e; }
            if (p.normal.w != GRID_OF_RV) { r += e; }
        }
    }
    return Radiance(caustic_irradiance(rv), caustic_irradiance(r));
}

// Internal pixel of world point `x` (−1 when outside the frustum).
fn project(x: vec3f) -> vec2i {
    let at = pixel_from_world(frame, x);
    if (at.z <= 0.0) { return vec2i(-1); }
    let q = vec2i(floor(at.xy));
    if (any(q < vec2i(0)) || any(q >= vec2i(frame.size.xy))) { return vec2i(-1); }
    return q;
}

// Whether the visibility texel `texel` at pixel `q` shows the point `x` (same instance, depth
// within the back-projection epsilon).
fn shows(texel: vec2u, q: vec2i, x: vec3f, instance: u32) -> bool {
    if (texel.x == 0u || triangles[texel.x - 1u].x != instance) { return false; }
    let seen = world_from_pixel(frame, vec2f(q) + 0.5, visibility_depth(texel));
    let eye = frame.camera_position.xyz;
    return distance(seen, x) <= params.tolerances.x * distance(eye, x);
}

fn branch_light(hit: vec4f, dir: vec4f) -> BranchLight {
    let exposure = frame.exposure_env.x;
    var out: BranchLight;
    out.in_photo = false;
    if (hit.w == 0.0) {
        // Left the scene: the probe (L_env), real in both worlds.
        out.rendered = exposure * env_radiance_at(frame, dir.xyz, dir.w);
        out.photo_based = out.rendered;
        out.real = out.rendered;
        return out;
    }
    let triangle = u32(hit.w);
    let x = hit.xyz;
    let instance = triangles[triangle - 1u].x;
    let real_hit = instance_is_real(instance);
    let traced_hit = is_traced(materials[instances[instance].info.x]);
    let q = project(x);
    var on_screen = false;
    var photo = vec3f(0.0);
    if (q.x >= 0) {
        let index = u32(q.y) * frame.size.x + u32(q.x);
        on_screen = !traced_hit && shows(camera_visibility[index], q, x, instance);
        out.in_photo = real_hit && shows(real_visibility[index], q, x, instance);
        photo = textureLoad(photo_texture, q / i32(frame.counts.z), 0).rgb;
    }
    var light: Radiance;
    if (on_screen) {
        // The camera sees this very surface: the screen's light, and the caustics on it
        // (§2.17.4: caustics are seen in reflections and refractions too). A surface the
        // camera does not see has no caustic buffer texel: its caustics are missing.
        let caustic = caustic_radiance(q, textureLoad(gbuffer_flags, q, 0).r);
        light = Radiance(
            textureLoad(l_rv_texture, q, 0).rgb + caustic.rv,
            textureLoad(l_r_texture, q, 0).rgb + caustic.r,
        );
    } else {
        light = shade_hit(triangle, x, dir.xyz);
    }
    out.rendered = exposure * light.rv;
    out.real = exposure * light.r;
    if (out.in_photo) {
        let a = alpha_of(composite_params, photo, exposure * light.r);
        out.photo_based = photo + a * exposure * (light.rv - light.r);
        out.real = photo;
    }
    return out;
}

// A branch's value in the real-only world (for real pixels): the rv branch's own when the
// real-only ray ends in the same place, else that of where it ends.
fn real_world(rv: BranchLight, rv_hit: vec4f, real_hit: vec4f, dir: vec4f) -> vec3f {
    if (all(real_hit == rv_hit)) { return rv.real; }
    return branch_light(real_hit, dir).real;
}

// One branch of a pixel: its light, and (for real pixels) its real-only world's value. A
// branch of weight alpha 0 was not traced: its targets hold stale values and are not read.
struct Branch {
    light: BranchLight,
    real: vec3f,
}

fn traced_branch(
    pixel: vec2i,
    weight: vec4f,
    hits: texture_2d<f32>,
    dirs: texture_2d<f32>,
    real_hits: texture_2d<f32>,
    real_pixel: bool,
) -> Branch {
    var out: Branch;
    out.light = BranchLight(vec3f(0.0), vec3f(0.0), false, vec3f(0.0));
    out.real = vec3f(0.0);
    if (weight.a == 0.0) { return out; }
    let hit = textureLoad(hits, pixel, 0);
    let dir = textureLoad(dirs, pixel, 0);
    out.light = branch_light(hit, dir);
    if (real_pixel) {
        out.real = real_world(out.light, hit, textureLoad(real_hits, pixel, 0), dir);
    }
    return out;
}

// Irradiance of one half of the caustic buffer's texel `c`: as splatted (energy), or the
// thesis's mean photon irradiance times k_c (Eq. T6.2).
fn caustic_irradiance(c: vec4f) -> vec3f {
    if (params.info.y == 0u) { return c.rgb; }
    if (c.a < 0.5) { return vec3f(0.0); }
    let b = params.tolerances.y;
    let n_max = f32(params.info.z);
    let k_c = (pow(b, min(c.a, n_max)) - 1.0) / (pow(b, n_max) - 1.0);
    return c.rgb / c.a * k_c;
}

// A caustic-buffer level `t` (1/`divisor` of the frame along each axis) at full-size
// `pixel`, bilinearly.
fn caustic_texel(t: texture_2d<f32>, pixel: vec2i, divisor: u32) -> vec4f {
    let st = (vec2f(pixel) + 0.5) / f32(divisor) - 0.5;
    let base = vec2i(floor(st));
    let f = fract(st);
    let last = vec2i(textureDimensions(t)) - 1;
    let a = textureLoad(t, clamp(base, vec2i(0), last), 0);
    let b = textureLoad(t, clamp(base + vec2i(1, 0), vec2i(0), last), 0);
    let c = textureLoad(t, clamp(base + vec2i(0, 1), vec2i(0), last), 0);
    let d = textureLoad(t, clamp(base + vec2i(1, 1), vec2i(0), last), 0);
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

// One differential half's caustic irradiance at full-size `pixel`: its fine and its coarse
// level summed.
fn caustic_levels(fine: texture_2d<f32>, coarse: texture_2d<f32>, pixel: vec2i) -> vec3f {
    let divisor = params.info.w;
    return caustic_irradiance(caustic_texel(fine, pixel, divisor))
        + caustic_irradiance(caustic_texel(coarse, pixel, divisor * COARSE_LEVEL_FACTOR));
}

// The diffuse BRDF through which a surface of `base` colour, `metallic` and `transmission`
// turns caustic irradiance into radiance.
fn caustic_brdf(base: vec3f, metallic: f32, transmission: f32) -> vec3f {
    return base * (1.0 - metallic) * (1.0 - transmission) / PI;
}

// The caustics on the diffuse surface at `pixel` (spec §2.17.4–§2.17.5, Eq. T5.4–T5.6): the
// caustic buffer's irradiance through the surface's diffuse BRDF, of the L_rv photons and, on
// a real surface, of the L_r photons (radiance, before exposure).
fn caustic_radiance(pixel: vec2i, flags: u32) -> Radiance {
    if (!is_covered(flags)) { return Radiance(vec3f(0.0), vec3f(0.0)); }
    let am = textureLoad(gbuffer_albedo_metallic, pixel, 0);
    let m = materials[material_of(flags)];
    let diffuse = caustic_brdf(am.rgb, am.a, m.transmission.x);
    let e_rv = caustic_levels(caustics_rv, caustics_coarse_rv, pixel);
    var e_r = vec3f(0.0);
    if (is_real(flags)) { e_r = caustic_levels(caustics_r, caustics_coarse_r, pixel); }
    return Radiance(diffuse * e_rv, diffuse * e_r);
}

// The caustics the camera sees at `pixel`, in camera values: all of the L_rv photons' on a
// virtual pixel, on a real one their difference from the L_r photons' (the photo already
// shows the real caustics); in a, minus the luminance of the L_r photons' light (the
// composite's α compares the photo with all the real light it shows).
fn caustic_light(pixel: vec2i, flags: u32) -> vec4f {
    let c = caustic_radiance(pixel, flags);
    let exposure = frame.exposure_env.x;
    return vec4f(exposure * (c.rv - c.r), -luminance(exposure * c.r));
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) local: u32) {
    lane = local;
    if (any(id.xy >= frame.size.xy)) { return; }
    let pixel = vec2i(id.xy);
    let w_reflection = textureLoad(reflection_weight, pixel, 0);
    let w_refraction = textureLoad(refraction_weight, pixel, 0);
    let flags = textureLoad(gbuffer_flags, pixel, 0).r;
    if (w_reflection.a == 0.0 && w_refraction.a == 0.0) {
        textureStore(out_specular, pixel, caustic_light(pixel, flags));
        return;
    }
    let real_pixel = is_real(flags);
    let stride = params.more.y;
    hit_vpl_first = (id.x + id.y + 7u * u32(frame.exposure_env.w)) % stride;
    let reflection = traced_branch(pixel, w_reflection, reflection_hit, reflection_dir, reflection_real_hit, real_pixel);
    let refraction = traced_branch(pixel, w_refraction, refraction_hit, refraction_dir, refraction_real_hit, real_pixel);
    // Which background each branch uses (§2.8): policy B keeps each back-projection that
    // works; policy A renders both as soon as one of them fails.
    var use_photo_reflection = reflection.light.in_photo;
    var use_photo_refraction = refraction.light.in_photo;
    let both_exist = w_reflection.a > 0.0 && w_refraction.a > 0.0 && any(w_refraction.rgb > vec3f(0.0));
    if (params.info.x == 1u && both_exist && (use_photo_reflection != use_photo_refraction)) {
        use_photo_reflection = false;
        use_photo_refraction = false;
    }
    let c_reflection = select(reflection.light.rendered, reflection.light.photo_based, use_photo_reflection);
    let c_refraction = select(refraction.light.rendered, refraction.light.photo_based, use_photo_refraction);
    var total = w_reflection.rgb * c_reflection + w_refraction.rgb * c_refraction;
    if (real_pixel) {
        // A real mirror or glass: only what the virtual content changes (the photo already
        // shows the real reflection), against the same rays through the real-only world.
        total -= w_reflection.rgb * reflection.real + w_refraction.rgb * refraction.real;
    }
    textureStore(out_specular, pixel, vec4f(total, 1.0));
}
