// Ray intersection through depth-refined impostors (reflections spec §2.16.3) or cube maps
// (§2.14, §2.15), shared by the trace pass (camera rays), the resolve pass (the real-only
// world's rays) and the photons. Each specular instance owns a range of slices: every other
// instance seen from its centre through an orthographic camera (or the six faces of a cube),
// as visibility textures of the compute rasteriser (reversed depth, triangle + 1). A ray is
// clipped to an impostor's box, marched in `linear_steps`, and the first under/overshoot
// pair is bisected `binary_steps` times; the triangle in the texel found is then intersected
// exactly (the documents interpolate stored attributes instead), and a hit whose triangle
// plane lies far from the marched depth is a depth discontinuity, not a surface, and the
// march goes on. Bindings are declared by the including pass:
// params, impostors, owners, impostor_texels, instances, vertices, indices, triangles, materials.

struct SpecularParams {
    // impostor resolution, linear steps, binary steps, max bounces
    steps: vec4u,
    // refraction policy (0 keep refraction, 1 rendered), caustic concentration (0 energy,
    // 1 thesis), k_c n_max, caustic buffer divisor
    info: vec4u,
    // back-projection epsilon (fraction of the camera distance), k_c base, the VPLs' d_min
    // (m), unused
    tolerances: vec4f,
    // the method's VPL slots (0: none), the stride of the VPL subset a hit surface is shaded
    // with, 1 if internal reflections are sampled (0: dropped), intersection (INTERSECTION_*)
    more: vec4u,
}

// `specular.intersection`: how a ray finds its surface in the slices of a pair.
const INTERSECTION_IMPOSTOR: u32 = 0u;
const INTERSECTION_CUBE: u32 = 1u;
const INTERSECTION_LAYERED_CUBE: u32 = 2u;

// One slice: an impostor, or one face of a pair's cube (six in a row, in cube_face's order).
struct Impostor {
    clip_from_world: mat4x4f,
    // instance drawn, first texel of its slice, side in texels, unused
    info: vec4u,
    // cube faces: the traced instance's centre; w: the faces' near plane
    eye: vec4f,
    // the drawn instance's world box
    seen_min: vec4f,
    seen_max: vec4f,
}

// Per instance: first impostor and impostor count of its set (0 if not traced), first texel of
// its farthest-surface view (NO_VIEW if none), 1 if refraction is traced through its BVH;
// its planar views (spec §2.13): the slice of the whole world's and of the real-only
// world's mirrored camera (NO_VIEW if none), unused…
struct Owner {
    info: vec4u,
    planar: vec4u,
}

const NO_VIEW: u32 = 0xffffffffu;

// A traced ray's end: a triangle (+1; 0 = it left the scene) at `position`, or a direction.
struct RayEnd {
    triangle: u32,
    position: vec3f,
    dir: vec3f,
    t: f32,
    weight: vec3f,
    // Roughness of the probe lookup when the ray leaves the scene (0: along `dir` itself).
    roughness: f32,
}

fn impostor_texel(imp: Impostor, c: vec3f) -> vec2u {
    let res = imp.info.z;
    let uv = vec2f(c.x * 0.5 + 0.5, 0.5 - c.y * 0.5);
    let xy = min(vec2u(max(uv, vec2f(0.0)) * f32(res)), vec2u(res - 1u));
    return impostor_texels[imp.info.y + xy.y * res + xy.x];
}

// Signed depth of impostor-space point `c` behind the stored surface (> 0: behind, i.e.
// farther from the impostor camera; reversed depth stores nearer surfaces as larger).
fn behind(texel: vec2u, c: vec3f) -> f32 {
    return bitcast<f32>(texel.y) - c.z;
}

// What a pair's slices show at a point of the ray: the texel, and how far behind its surface
// the point lies (> 0: behind, in the slice's reversed depth).
struct SliceSample {
    texel: vec2u,
    behind: f32,
}

// The ray in one pair's slices: for an impostor, origin and direction in its clip space
// (orthographic: the point at t is co + cd·t); for a cube, in world space.
struct SliceRay {
    first: u32,
    co: vec3f,
    cd: vec3f,
}

// What the cube of slices `first`…`first + 5` shows toward world point `x`.
fn cube_sample(first: u32, x: vec3f) -> SliceSample {
    let face = impostors[first + cube_face(x - impostors[first].eye.xyz)];
    let clip = face.clip_from_world * vec4f(x, 1.0);
    let ndc = clip.xyz / clip.w;
    let texel = impostor_texel(face, ndc);
    return SliceSample(texel, behind(texel, ndc));
}

fn slice_sample(ray: SliceRay, t: f32) -> SliceSample {
    if (params.more.w == INTERSECTION_IMPOSTOR) {
        let c = ray.co + ray.cd * t;
        let texel = impostor_texel(impostors[ray.first], c);
        return SliceSample(texel, behind(texel, c));
    }
    return cube_sample(ray.first, ray.co + ray.cd * t);
}

// The nearest surface of the pair whose slices start at `first` on the ray before `t_max`:
// (triangle + 1, t), or triangle 0. Impostors (§2.16.3) clip the ray to the impostor's box
// (x, y ∈ [−1, 1], reversed depth ∈ [0, 1]); layered cubes (§2.15) to the drawn instance's
// world box. The span is marched in `linear_steps` for the first under/overshoot pair,
// bisected `binary_steps` times (empty texels count as the near side), and the texel's
// triangle intersected exactly; a triangle far from the marched depth is a depth
// discontinuity, not a surface, and the march goes on.
fn march_slices(first: u32, origin: vec3f, dir: vec3f, t_max: f32) -> vec2f {
    let imp = impostors[first];
    var ray = SliceRay(first, origin, dir);
    var span: vec2f;
    if (params.more.w == INTERSECTION_IMPOSTOR) {
        ray.co = (imp.clip_from_world * vec4f(origin, 1.0)).xyz;
        ray.cd = (imp.clip_from_world * vec4f(dir, 0.0)).xyz;
        span = box_span(ray.co, ray.cd, vec3f(-1.0, -1.0, 0.0), vec3f(1.0), t_max);
    } else {
        let pad = 1e-3 * max(distance(imp.seen_min.xyz, imp.seen_max.xyz), 1e-3);
        span = box_span(origin, dir, imp.seen_min.xyz - pad, imp.seen_max.xyz + pad, t_max);
    }
    if (span.x >= span.y) { return vec2f(0.0); }
    let steps = params.steps.y;
    let step = (span.y - span.x) / f32(steps);
    var prev_t = span.x;
    var prev_s = 0.0;
    var prev_valid = false;
    // One sample ahead: the next sample's read is issued before this one is tested (each step
    // of the march otherwise waited on its own read).
    var c = slice_sample(ray, span.x);
    for (var i = 0u; i <= steps; i++) {
        let t = span.x + step * f32(i);
        let here = c;
        c = slice_sample(ray, span.x + step * f32(i + 1u));
        if (here.texel.x == 0u) {
            prev_valid = false;
            prev_t = t;
            continue;
        }
        if (prev_valid && (here.behind >= 0.0) != (prev_s >= 0.0)) {
            var a = prev_t;
            var b = t;
            var triangle = here.texel.x;
            for (var j = 0u; j < params.steps.z; j++) {
                let mid = 0.5 * (a + b);
                let m = slice_sample(ray, mid);
                let sm = select(prev_s, m.behind, m.texel.x != 0u);
                if ((sm >= 0.0) == (here.behind >= 0.0)) {
                    b = mid;
                    if (m.texel.x != 0u) { triangle = m.texel.x; }
                } else {
                    a = mid;
                }
            }
            let h = intersect(triangle - 1u, origin, dir);
            if (h.t > 0.0 && abs(h.t - b) <= 2.0 * step + 1e-4 + cube_texel_depth(imp, origin + dir * b)) {
                return vec2f(f32(triangle), h.t);
            }
        }
        prev_valid = true;
        prev_s = here.behind;
        prev_t = t;
    }
    return vec2f(0.0);
}

// Side of a cube face at unit distance: 2·tan(46°), its field of view being 90° plus
// scene_gpu::FOV_MARGIN (tests/shaders.rs checks it).
const CUBE_FACE_SIDE: f32 = 2.0711;

// How far a cube's texel may put a surface off the ray at `x` (four texels' width there): a
// thin object's span is marched in tiny steps, finer than the texels. Impostors store the
// depth of flat objects exactly: 0.
fn cube_texel_depth(imp: Impostor, x: vec3f) -> f32 {
    if (params.more.w == INTERSECTION_IMPOSTOR) { return 0.0; }
    return 4.0 * CUBE_FACE_SIDE / f32(imp.info.z) * distance(x, imp.eye.xyz);
}

// Standard cubic environment mapping (spec §2.14): the surface the cube of slices `first`…
// shows in the ray's direction, wherever the ray starts ("only accurate at its center"), met
// by the ray on its plane: (triangle + 1, t), or triangle 0.
fn lookup_cube(first: u32, origin: vec3f, dir: vec3f, t_max: f32) -> vec2f {
    let texel = cube_sample(first, impostors[first].eye.xyz + dir).texel;
    if (texel.x == 0u) { return vec2f(0.0); }
    let h = intersect(texel.x - 1u, origin, dir);
    if (h.t <= 0.0 || h.t >= t_max) { return vec2f(0.0); }
    return vec2f(f32(texel.x), h.t);
}

// Planar reflection (spec §2.13): the surface that the mirrored camera of planar view `slice`
// sees through the point `origin` of its plane, met by the ray (`dir`, the camera ray's mirror
// image: the view's ray through that pixel): (triangle + 1, t), or triangle 0 where the view
// shows nothing (the ray leaves the scene).
fn lookup_planar(slice: u32, origin: vec3f, dir: vec3f) -> vec2f {
    let view = impostors[slice];
    let clip = view.clip_from_world * vec4f(origin, 1.0);
    if (clip.w <= 0.0) { return vec2f(0.0); }
    let size = view.info.zw;
    let uv = vec2f(clip.x / clip.w * 0.5 + 0.5, 0.5 - clip.y / clip.w * 0.5);
    let xy = vec2i(floor(uv * vec2f(size)));
    if (any(xy < vec2i(0)) || any(xy >= vec2i(size))) { return vec2f(0.0); }
    let texel = impostor_texels[view.info.y + u32(xy.y) * size.x + u32(xy.x)];
    if (texel.x == 0u) { return vec2f(0.0); }
    let h = intersect(texel.x - 1u, origin, dir);
    if (h.t <= 0.0) { return vec2f(0.0); }
    return vec2f(f32(texel.x), h.t);
}

// The nearest surface of the pair whose slices start at `k`, by `specular.intersection`.
fn intersect_pair(k: u32, origin: vec3f, dir: vec3f, t_max: f32) -> vec2f {
    if (params.more.w == INTERSECTION_CUBE) { return lookup_cube(k, origin, dir, t_max); }
    return march_slices(k, origin, dir, t_max);
}

fn instance_is_real(instance: u32) -> bool {
    return (instances[instance].info.y & SURFACE_REAL) != 0u;
}

// Schlick's Fresnel of a dielectric of index `ior` (spec §2.1, f⊥ from the IOR with k = 0).
fn fresnel_ior(ior: f32, cos_i: f32) -> f32 {
    let f0 = (ior - 1.0) * (ior - 1.0) / ((ior + 1.0) * (ior + 1.0));
    return schlick(vec3f(f0), 1.0, cos_i).x;
}

// Follows a ray from a surface of instance `owner` through the impostors of its set, on
// through specular surfaces up to `max_bounces` (spec §2.3: accumulated Fresnel and
// transmittance; the path flag FlagPathRV is not kept, as routing reads only the flags of
// the light → hit-surface part, §2.5; a refractive second-order hit is bent at its first
// boundary only, spec §2.16.3). `real_only` sees only real instances (the `L_r` world);
// `first_sees_self` tests the first segment against the object itself too; `planar`, a planar
// view (or NO_VIEW), finds the first segment's surface instead of the slices.
fn trace_ray(origin: vec3f, dir: vec3f, owner: u32, real_only: bool, first_sees_self: bool, planar: u32) -> RayEnd {
    var end = RayEnd(0u, origin, dir, 0.0, vec3f(1.0), 0.0);
    var o = origin;
    var d = dir;
    var range = owners[owner].info;
    var current = owner;
    for (var bounce = 0u; bounce <= params.steps.w; bounce++) {
        var best = vec2f(0.0, 3.0e38);
        if (bounce == 0u && planar != NO_VIEW) {
            // A plane cannot see itself: no self test either.
            let hit = lookup_planar(planar, o, d);
            if (hit.x > 0.0) { best = hit; }
            range.y = 0u;
        }
        let per_pair = select(6u, 1u, params.more.w == INTERSECTION_IMPOSTOR);
        for (var k = range.x; k < range.x + range.y; k += per_pair) {
            if (real_only && !instance_is_real(impostors[k].info.x)) { continue; }
            let hit = intersect_pair(k, o, d, best.y);
            if (hit.x > 0.0 && hit.y < best.y) { best = hit; }
        }
        // The object itself (its BVH, when rigid): the self-reflections impostors miss
        // (spec §2.16, limitation of [T §7]), e.g. a torus's inner side seeing its other side.
        let sees_self = bounce > 0u || first_sees_self;
        if (sees_self && interiors[current].info.y == 1u && !(real_only && !instance_is_real(current))) {
            let own = trace_interior(current, o, d, 1e-5 * max(1.0, length(o)));
            if (own.x > 0.0 && own.y < best.y) { best = own; }
        }
        if (best.x == 0.0) {
            end.triangle = 0u;
            end.dir = d;
            return end;
        }
        let triangle = u32(best.x);
        let h = intersect(triangle - 1u, o, d);
        end.triangle = triangle;
        end.position = h.position;
        end.dir = d;
        end.t = best.y;
        let m = materials[instances[h.instance].info.x];
        if (!is_traced(m) || bounce == params.steps.w) { return end; }
        // A specular surface in the way: continue along its mirror or refracted direction.
        let n = facing_normal(h, -d);
        let cos_i = max(dot(n, -d), 0.0);
        let transmission = m.transmission.x * (1.0 - m.params.x);
        var next = reflect(d, n);
        if (transmission > 0.0) {
            let f = fresnel_ior(max(m.transmission.y, 1.0), cos_i);
            let t = refract(d, n, 1.0 / max(m.transmission.y, 1.0));
            if (any(t != vec3f(0.0))) {
                next = t;
                end.weight *= transmission * (1.0 - f) * m.base_color.rgb;
            } else {
                end.weight *= f;
            }
        } else {
            let f0 = material_f0(m);
            end.weight *= schlick(f0, 1.0, cos_i);
        }
        o = h.position;
        d = normalize(next);
        range = owners[h.instance].info;
        current = h.instance;
    }
    return end;
}

// Where the refracted view ray leaves the object and in which direction (traced, or by Wyman's
// two interfaces, spec §2.12), with the distance travelled inside.
struct Exit {
    position: vec3f,
    dir: vec3f,
    thickness: f32,
    // The share that leaves through the exit interface: 1 − F there, or 1 where the choice
    // between leaving and reflecting inside was sampled with probability F.
    leave: f32,
}

// A GGX microfacet normal around `n` for roughness `roughness` (the normal itself when
// smooth), drawn from the normals visible from direction `v` (away from the surface: toward
// the eye, or back toward a photon's source) by the random bits of `seed` (Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals"). Reflected about it, `v` follows the
// BRDF's lobe up to F·G1(l) (which varies little), off-specular peak and grazing stretch
// included; sampling D(h)·cos θ_h instead, weighted by the lobe's mean albedo, bent a rough
// metal's highlights toward the mirror direction and widened them at grazing angles.
fn microfacet_normal(n: vec3f, v: vec3f, roughness: f32, seed: u32) -> vec3f {
    let alpha = roughness * roughness;
    if (alpha < 1e-3) { return n; }
    let u = vec2f(f32(seed & 0xffffu) / 65536.0, f32(seed >> 16u) / 65536.0);
    let tb = tangent_frame(n);
    let v_local = vec3f(dot(v, tb[0]), dot(v, tb[1]), max(dot(v, n), 1e-4));
    // The view direction in the hemisphere configuration (the lobe stretched to α = 1).
    let vh = normalize(vec3f(alpha * v_local.x, alpha * v_local.y, v_local.z));
    let len2 = dot(vh.xy, vh.xy);
    let t1 = select(vec3f(1.0, 0.0, 0.0), vec3f(-vh.y, vh.x, 0.0) * inverseSqrt(len2), len2 > 1e-12);
    let t2 = cross(vh, t1);
    // A point of the unit disc, its lower half squeezed to the part of the projected
    // hemisphere that `v` sees.
    let r = sqrt(u.x);
    let phi = 2.0 * PI * u.y;
    let d1 = r * cos(phi);
    let s = 0.5 * (1.0 + vh.z);
    let d2 = (1.0 - s) * sqrt(max(1.0 - d1 * d1, 0.0)) + s * r * sin(phi);
    let nh = d1 * t1 + d2 * t2 + sqrt(max(1.0 - d1 * d1 - d2 * d2, 0.0)) * vh;
    let m = normalize(vec3f(alpha * nh.x, alpha * nh.y, max(nh.z, 1e-6)));
    return normalize(tb[0] * m.x + tb[1] * m.y + n * m.z);
}

// Internal events a traced refraction follows before it gives up and leaves by the tangent.
const MAX_INTERNAL: u32 = 8u;

// The refracted view ray followed exactly through the instance's inside: at each internal
// hit it leaves, or is reflected on inside: always when totally reflected, else with
// probability F when internal reflections are sampled (params.more.z; the choices are drawn
// from `key`, the pixel's or photon's index, and the frame), F being Schlick's from the
// outside angle (the larger one, for light leaving the denser medium). Dropped, the leaving
// ray is weighted by 1 − F and the share F is lost.
fn traced_exit(owner: u32, p1: vec3f, view_dir: vec3f, n1: vec3f, ior: f32, key: u32) -> Exit {
    let eps = 1e-5 * max(1.0, length(p1));
    let seed = hash_u32(key) ^ hash_u32(u32(frame.exposure_env.w) + 0x9e3779b9u);
    let sampled = params.more.z == 1u;
    var d = normalize(refract(view_dir, n1, 1.0 / ior));
    var o = p1;
    var exit = Exit(p1, d, 0.0, 1.0);
    for (var k = 0u; k < MAX_INTERNAL; k++) {
        let hit = trace_interior(owner, o, d, eps);
        if (hit.x == 0.0) { break; }
        let h = intersect(u32(hit.x) - 1u, o, d);
        exit.thickness += hit.y;
        o = h.position;
        let n_out = facing_normal(h, d);
        let out = refract(d, -n_out, ior);
        if (any(out != vec3f(0.0))) {
            let leaving = normalize(out);
            let f = fresnel_ior(ior, clamp(dot(leaving, n_out), 0.0, 1.0));
            let u = f32(hash_u32(seed ^ hash_u32(k + 1u))) * 2.3283064365386963e-10;
            if (!sampled || u >= f) {
                exit.position = o;
                exit.dir = leaving;
                exit.leave = select(1.0 - f, 1.0, sampled);
                return exit;
            }
        }
        d = reflect(d, -n_out);
    }
    // Still inside: leave along the last direction, as Wyman's total-reflection fallback.
    exit.position = o;
    exit.dir = d;
    return exit;
}

// What the inside and the exit let through of a refracted ray (base color `base`): the exit's
// Fresnel and Beer–Lambert over the distance travelled (KHR_materials_volume).
fn exit_transmittance(m: Material, base: vec3f, exit: Exit, ior: f32) -> vec3f {
    let absorption = select(
        vec3f(0.0),
        -log(max(m.attenuation_cutoff.rgb, vec3f(1e-4))) / m.transmission.w,
        m.transmission.w < 1e29,
    );
    return exit.leave * base * exp(-absorption * exit.thickness);
}

// Exact interiors of rigid transmissive instances (see interior.rs): a BVH per instance in
// object space. Bindings declared by the including pass: interiors, bvh_nodes, bvh_triangles
// (global triangle ids in leaf order) and bvh_corners (their object-space corners, 3 per).
struct BvhNode {
    min: vec3f,
    // Triangles of a leaf; 0 for an inner node (children at `first`, `first + 1`).
    count: u32,
    max: vec3f,
    first: u32,
}

struct Interior {
    object_from_world: mat4x4f,
    // root node (NO_VIEW: none), 1 if the object can see itself (not convex), unused…
    info: vec4u,
}

// Entry distance of the ray into box [lo, hi] before `t_max`, or −1.
fn box_entry(o: vec3f, inv_d: vec3f, lo: vec3f, hi: vec3f, t_max: f32) -> f32 {
    let span = slab_span(o, inv_d, lo, hi, t_max);
    return select(-1.0, span.x, span.x <= span.y);
}

// Distance along object-space ray (o, d) to BVH triangle `k` (its object-space corners,
// stored in leaf order; Möller–Trumbore), or −1 where it misses.
fn object_triangle_t(k: u32, o: vec3f, d: vec3f) -> f32 {
    let p0 = bvh_corners[3u * k].xyz;
    let e1 = bvh_corners[3u * k + 1u].xyz - p0;
    let e2 = bvh_corners[3u * k + 2u].xyz - p0;
    let pv = cross(d, e2);
    let det = dot(e1, pv);
    if (abs(det) < 1e-20) { return -1.0; }
    let inv = 1.0 / det;
    let tv = o - p0;
    let u = dot(tv, pv) * inv;
    let qv = cross(tv, e1);
    let v = dot(d, qv) * inv;
    if (u < 0.0 || v < 0.0 || u + v > 1.0) { return -1.0; }
    return dot(e2, qv) * inv;
}

// Traversal stacks in workgroup memory, one per invocation of the 8×8 workgroups (a dynamically
// indexed private array would live in slow local memory). `lane` is set by the entry point.
const STACK: u32 = 24u;
var<workgroup> stacks: array<array<u32, STACK>, 64>;
var<private> lane: u32;

// The nearest triangle of `instance` on the world ray past `t_min`: (triangle + 1, t). The
// nearer child is visited first, so that farther boxes are culled by the hit found.
fn trace_interior(instance: u32, origin: vec3f, dir: vec3f, t_min: f32) -> vec2f {
    let it = interiors[instance];
    var best = vec2f(0.0, 3.0e38);
    if (it.info.x == NO_VIEW) { return best; }
    // The object-space ray keeps the world ray's parameter t (the map is affine).
    let o = (it.object_from_world * vec4f(origin, 1.0)).xyz;
    let d = (it.object_from_world * vec4f(dir, 0.0)).xyz;
    let inv_d = 1.0 / select(d, vec3f(1e-30), abs(d) < vec3f(1e-30));
    var top = 1u;
    stacks[lane][0] = it.info.x;
    while (top > 0u) {
        top -= 1u;
        let node = bvh_nodes[stacks[lane][top]];
        if (node.count == 0u) {
            let a = bvh_nodes[node.first];
            let b = bvh_nodes[node.first + 1u];
            let ta = box_entry(o, inv_d, a.min, a.max, best.y);
            let tb = box_entry(o, inv_d, b.min, b.max, best.y);
            // Push the farther child first; a missed child (−1) is not pushed.
            let a_first = ta >= 0.0 && (tb < 0.0 || ta <= tb);
            let near = select(node.first + 1u, node.first, a_first);
            let far = select(node.first, node.first + 1u, a_first);
            let t_near = select(tb, ta, a_first);
            let t_far = select(ta, tb, a_first);
            if (t_far >= 0.0 && top < STACK) { stacks[lane][top] = far; top += 1u; }
            if (t_near >= 0.0 && top < STACK) { stacks[lane][top] = near; top += 1u; }
            continue;
        }
        for (var k = node.first; k < node.first + node.count; k++) {
            let t = object_triangle_t(k, o, d);
            if (t > t_min && t < best.y) { best = vec2f(f32(bvh_triangles[k] + 1u), t); }
        }
    }
    return best;
}
