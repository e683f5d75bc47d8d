// The photo's light in V_ρ (`dlpv.photo_bounce`; Franke §2.11: "in practice Σ T_μ^i L_e is the
// camera image"): the real surfaces the camera sees light the virtual objects with the
// radiance the photo shows of them, every bounce of the real scene in it, where the maps'
// VPLs hold one (the virtual faces of cornell took 0.87–0.96 of the answer's light from
// them). `photo_tiles`: one workgroup per tile of `gather_info.w`² pixels (internal size, a
// fortieth of its height: 27 pixels at 1080 lines, 3 at 120), its real pixels summed into
// one VPL: flux π·L·A per pixel (a Lambertian surface of radiance L, A
// the pixel's footprint on it), flux-weighted position and normal. The maps' VPLs leave out
// the texels the camera sees (`seen_by_camera`, used by `aggregate`), so that no surface
// lights twice. A surface the camera does not see (behind a virtual object, off screen)
// keeps its maps' light.

@group(1) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(1) var gbuffer_depth_motion: texture_2d<f32>;
@group(1) @binding(2) var gbuffer_normal_roughness: texture_2d<f32>;
@group(1) @binding(3) var gbuffer_flags: texture_2d<u32>;
@group(1) @binding(4) var photo_texture: texture_2d<f32>;

// Whether the camera sees the real surface at `p` (normal `n`) in its pixel: the pixel is a
// real surface with a like normal whose tangent plane passes within `tolerance` of `p`.
fn seen_by_camera(p: vec3f, n: vec3f, tolerance: f32) -> bool {
    let at = pixel_from_world(frame, p);
    if (at.z <= 0.0) { return false; }
    let q = vec2i(floor(at.xy));
    if (any(q < vec2i(0)) || any(q >= vec2i(frame.size.xy))) { return false; }
    let flags = textureLoad(gbuffer_flags, q, 0).r;
    if (!is_covered(flags) || !is_real(flags)) { return false; }
    let seen = world_from_pixel(frame, vec2f(q) + 0.5, textureLoad(gbuffer_depth_motion, q, 0).x);
    let n_seen = textureLoad(gbuffer_normal_roughness, q, 0).xyz;
    return dot(n_seen, n) > 0.7 && abs(dot(seen - p, n_seen)) < tolerance;
}

// A real pixel's share of its tile's VPL.
fn pixel_sum(q: vec2i) -> Sum {
    let zero = Sum(vec4f(0.0), vec4f(0.0), vec4f(0.0));
    if (any(q >= vec2i(frame.size.xy))) { return zero; }
    let flags = textureLoad(gbuffer_flags, q, 0).r;
    if (!is_covered(flags) || !is_real(flags)) { return zero; }
    let depth = textureLoad(gbuffer_depth_motion, q, 0).x;
    let centre = vec2f(q) + 0.5;
    let p = world_from_pixel(frame, centre, depth);
    let n = textureLoad(gbuffer_normal_roughness, q, 0).xyz;
    // The footprint across the view (neighbours at the same depth), over the cosine to the
    // camera (at most 5×: grazing pixels' footprints are long and their light uncertain).
    let across = length(cross(world_from_pixel(frame, centre + vec2f(1.0, 0.0), depth) - p,
                              world_from_pixel(frame, centre + vec2f(0.0, 1.0), depth) - p));
    let to_camera = normalize(frame.camera_position.xyz - p);
    let area = across / max(abs(dot(n, to_camera)), 0.2);
    let radiance = textureLoad(photo_texture, q / i32(frame.counts.z), 0).rgb / frame.exposure_env.x;
    let flux = PI * radiance * area;
    let w = dot(flux, vec3f(0.2126, 0.7152, 0.0722)) + 1e-20;
    return Sum(vec4f(flux, area), vec4f(p * w, w), vec4f(n * w, 0.0));
}

@compute @workgroup_size(8, 8)
fn photo_tiles(@builtin(workgroup_id) tile: vec3u, @builtin(local_invocation_id) local: vec3u,
               @builtin(local_invocation_index) thread: u32) {
    let side = gather_info.w;
    var sum = Sum(vec4f(0.0), vec4f(0.0), vec4f(0.0));
    for (var y = local.y; y < side; y += 8u) {
        for (var x = local.x; x < side; x += 8u) {
            sum = plus(sum, pixel_sum(vec2i(tile.xy * side + vec2u(x, y))));
        }
    }
    append_workgroup_sum(thread, sum, VPL_RHO | VPL_MU);
}

