// Reflection and refraction G-buffers (reflections spec §2.10–§2.12, Tables T6.1–T6.2): for
// every pixel of a traced (mirror-like or transmissive) material, the surface its reflected
// ray and its refracted ray reach, in camera screen space. The first hit is the G-buffer's
// own pixel (the depth-EQUAL pass of §2.11); glossy materials reflect about a GGX-sampled
// microfacet normal, one per pixel and frame (beyond the documents, which are mirror-only).
// Refraction follows Wyman's two interfaces (§2.12): the farthest surface of the object
// along the pixel's view ray gives the thickness d_v, p2 ≈ p1 + d_v·r_t is moved onto the
// back surface seen at p2's pixel, and the ray leaves with the reciprocal index; a missing
// back surface and total internal reflection take the documents' fallbacks. Beer–Lambert
// absorption (KHR_materials_volume) uses the distance between the interfaces.
//
// Per branch: hit position and triangle + 1 (0: the ray left the scene; xyz is then its
// direction), the ray's last direction with the roughness its probe lookup is prefiltered
// for in w, and the accumulated Fresnel · transmittance weight (rgb; 1 in w where traced).

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: SpecularParams;
@group(0) @binding(2) var gbuffer_depth_motion: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_albedo_metallic: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal_roughness: texture_2d<f32>;
@group(0) @binding(5) var gbuffer_specular: texture_2d<f32>;
@group(0) @binding(6) var gbuffer_emission_occlusion: texture_2d<f32>;
@group(0) @binding(7) var gbuffer_flags: texture_2d<u32>;
@group(0) @binding(8) var env_dfg_table: texture_2d<f32>;
@group(0) @binding(9) var env_sampler: sampler;

@group(1) @binding(0) var<storage, read> instances: array<Instance>;
@group(1) @binding(1) var<storage, read> vertices: array<f32>;
@group(1) @binding(2) var<storage, read> indices: array<u32>;
@group(1) @binding(3) var<storage, read> triangles: array<vec4u>;
@group(1) @binding(4) var<storage, read> materials: array<Material>;
@group(1) @binding(5) var<storage, read> impostors: array<Impostor>;
@group(1) @binding(6) var<storage, read> owners: array<Owner>;
@group(1) @binding(7) var<storage, read> impostor_texels: array<vec2u>;
// The camera's visibility (which triangle each pixel shows) and the farthest surfaces of the
// transmissive instances (at `owners[i].info.z`).
@group(1) @binding(8) var<storage, read> camera_visibility: array<vec2u>;
@group(1) @binding(9) var<storage, read> farthest_texels: array<vec2u>;
@group(1) @binding(10) var<storage, read> interiors: array<Interior>;
@group(1) @binding(11) var<storage, read> bvh_nodes: array<BvhNode>;
@group(1) @binding(12) var<storage, read> bvh_triangles: array<u32>;
@group(1) @binding(13) var<storage, read> bvh_corners: array<vec4f>;

@group(2) @binding(0) var out_reflection_hit: texture_storage_2d<rgba32float, write>;
@group(2) @binding(1) var out_reflection_dir: texture_storage_2d<rgba16float, write>;
@group(2) @binding(2) var out_reflection_weight: texture_storage_2d<rgba16float, write>;
@group(2) @binding(3) var out_refraction_hit: texture_storage_2d<rgba32float, write>;
@group(2) @binding(4) var out_refraction_dir: texture_storage_2d<rgba16float, write>;
@group(2) @binding(5) var out_refraction_weight: texture_storage_2d<rgba16float, write>;
// Real pixels only: the same rays through the real-only world (what the photo shows there).
@group(2) @binding(6) var out_reflection_real_hit: texture_storage_2d<rgba32float, write>;
@group(2) @binding(7) var out_refraction_real_hit: texture_storage_2d<rgba32float, write>;

fn hit_texel(end: RayEnd) -> vec4f {
    return select(vec4f(end.dir, 0.0), vec4f(end.position, f32(end.triangle)), end.triangle != 0u);
}

fn store_branch(pixel: vec2i, refraction: bool, end: RayEnd) {
    let hit = hit_texel(end);
    let dir = vec4f(end.dir, end.roughness);
    let weight = vec4f(end.weight, 1.0);
    if (refraction) {
        textureStore(out_refraction_hit, pixel, hit);
        textureStore(out_refraction_dir, pixel, dir);
        textureStore(out_refraction_weight, pixel, weight);
    } else {
        textureStore(out_reflection_hit, pixel, hit);
        textureStore(out_reflection_dir, pixel, dir);
        textureStore(out_reflection_weight, pixel, weight);
    }
}

// An untraced pixel: zero weights are all the resolve reads there (the other targets keep
// stale values, which saves most of this pass's memory traffic on untraced pixels).
fn store_nothing(pixel: vec2i) {
    textureStore(out_reflection_weight, pixel, vec4f(0.0));
    textureStore(out_refraction_weight, pixel, vec4f(0.0));
}


// A glossy ray that leaves the scene sees the probe along its own sampled direction, prefiltered
// over a lobe narrower than the surface's (roughness × specular.probe_lobe, params.tolerances.w):
// the samples of successive frames spread it over the surface's lobe, and the probe's sun is
// less of a firefly in any one of them. (The split sum's lookup along the mirror direction,
// prefiltered with n = v = r, put a rough metal's highlights where a mirror has them and
// widened them at grazing angles: desk-mirror's torus.)
fn glossy_miss(end: RayEnd, roughness: f32) -> RayEnd {
    var out = end;
    if (end.triangle == 0u && roughness * roughness >= 1e-3) {
        out.roughness = roughness * params.tolerances.w;
    }
    return out;
}

fn farthest_triangle(view_offset: u32, pixel: vec2i) -> u32 {
    return farthest_texels[view_offset + u32(pixel.y) * frame.size.x + u32(pixel.x)].x;
}

// Where the refracted view ray leaves the object by Wyman's two interfaces (spec §2.12).
fn refraction_exit(pixel: vec2i, p1: vec3f, view_dir: vec3f, n1: vec3f, ior: f32, view_offset: u32) -> Exit {
    let rt = normalize(refract(view_dir, n1, 1.0 / ior));
    var exit = Exit(p1, rt, 0.0, 1.0);
    if (view_offset == NO_VIEW) { return exit; }
    let back = farthest_triangle(view_offset, pixel);
    if (back == 0u) { return exit; }
    // d_v: front-to-farthest distance along this pixel's view ray (Eq. T6.1).
    let eye = frame.camera_position.xyz;
    let d_v = max(intersect(back - 1u, eye, view_dir).t - distance(eye, p1), 0.0);
    var p2 = p1 + rt * d_v;
    var n_out = vec3f(0.0);
    let at = pixel_from_world(frame, p2);
    let q = vec2i(floor(at.xy));
    if (at.z > 0.0 && all(q >= vec2i(0)) && all(q < vec2i(frame.size.xy))) {
        let back2 = farthest_triangle(view_offset, q);
        if (back2 != 0u) {
            // The back surface seen at p2's pixel, met by the refracted ray itself.
            let h = intersect(back2 - 1u, p1, rt);
            if (h.t > 0.0) { p2 = h.position; }
            n_out = facing_normal(h, rt);
        }
    }
    if (all(n_out == vec3f(0.0))) {
        // No back surface there: the projection of r_t onto the plane ⟂ the view direction.
        n_out = rt - dot(rt, view_dir) * view_dir;
        n_out = select(rt, normalize(n_out), dot(n_out, n_out) > 1e-8);
    }
    exit.position = p2;
    exit.thickness = distance(p1, p2);
    exit.leave = 1.0 - fresnel_ior(ior, clamp(dot(rt, n_out), 0.0, 1.0));
    let out = refract(rt, -n_out, ior);
    if (all(out == vec3f(0.0))) {
        // Total internal reflection, neglected as in the thesis: the tangent at p2.
        let tangent = rt - dot(rt, n_out) * n_out;
        exit.dir = select(rt, normalize(tangent), dot(tangent, tangent) > 1e-8);
        exit.leave = 1.0 - fresnel_ior(ior, 1.0);
    } else {
        exit.dir = normalize(out);
    }
    return exit;
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u, @builtin(local_invocation_index) local: u32) {
    lane = local;
    if (any(id.xy >= frame.size.xy)) { return; }
    let pixel = vec2i(id.xy);
    let flags = textureLoad(gbuffer_flags, pixel, 0).r;
    let m = materials[material_of(flags)];
    if (!is_covered(flags) || !is_traced(m)) {
        store_nothing(pixel);
        return;
    }
    let triangle = camera_visibility[id.y * frame.size.x + id.x].x;
    let owner = triangles[triangle - 1u].x;
    var s = pixel_surface(pixel);
    let p1 = s.position;
    let occlusion = textureLoad(gbuffer_emission_occlusion, pixel, 0).a;
    let view_dir = -s.view;
    let n = microfacet_normal(s.normal, s.view, s.roughness, hash_u32(id.x * 73856093u ^ id.y * 19349663u ^ u32(frame.exposure_env.w) * 83492791u));
    // Reflection (spec §2.11): r = 2(n·v)n − v, weighted by the split-sum albedo of the lobe.
    let ab = env_dfg(max(dot(s.normal, s.view), 1e-4), s.roughness);
    let specular_albedo = surface_f0(s) * ab.x + surface_f90(s) * ab.y;
    var reflected = reflect(view_dir, n);
    if (dot(reflected, s.normal) <= 0.0) { reflected = reflect(view_dir, s.normal); }
    let real_pixel = is_real(flags);
    // A dielectric reflects a few percent: its self-reflections are not worth a BVH traversal.
    let transmission = m.transmission.x * (1.0 - s.metallic);
    let sees_self = transmission <= 0.0;
    // A smooth reflection off a planar reflector is its mirrored camera's ray (spec §2.13).
    var planar = owners[owner].planar;
    let plane = impostors[min(planar.x, arrayLength(&impostors) - 1u)].eye.xyz;
    if (planar.x == NO_VIEW || any(n != s.normal) || abs(dot(s.normal, plane)) < 0.9999) {
        planar = vec4u(NO_VIEW);
    }
    var reflection = glossy_miss(trace_ray(p1, reflected, owner, false, sees_self, planar.x), s.roughness);
    reflection.weight *= specular_albedo * occlusion;
    store_branch(pixel, false, reflection);
    if (real_pixel) {
        let real_end = glossy_miss(trace_ray(p1, reflected, owner, true, sees_self, planar.y), s.roughness);
        textureStore(out_reflection_real_hit, pixel, hit_texel(real_end));
    }

    // Refraction: what the lobe does not reflect, times transmission (KHR_materials_transmission).
    if (transmission <= 0.0) {
        textureStore(out_refraction_weight, pixel, vec4f(0.0));
        return;
    }
    let ior = max(m.transmission.y, 1.0);
    var exit: Exit;
    if (interiors[owner].info.x != NO_VIEW && owners[owner].info.w == 1u) {
        exit = traced_exit(owner, p1, view_dir, n, ior, id.y * frame.size.x + id.x);
    } else {
        exit = refraction_exit(pixel, p1, view_dir, n, ior, owners[owner].info.z);
    }
    var refraction = trace_ray(exit.position, exit.dir, owner, false, true, NO_VIEW);
    if (real_pixel) {
        textureStore(out_refraction_real_hit, pixel, hit_texel(trace_ray(exit.position, exit.dir, owner, true, true, NO_VIEW)));
    }
    refraction.weight *= transmission * (vec3f(1.0) - specular_albedo) * exit_transmittance(m, s.base_color, exit, ior)
        * occlusion;
    store_branch(pixel, true, refraction);
}
