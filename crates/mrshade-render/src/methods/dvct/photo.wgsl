// The photo's light in the real voxels (Franke §2.11: "in practice Σ T_μ^i L_e is the camera
// image", (T_μ² + T_μ)·L_e ≈ B): a real voxel whose surface the camera sees takes its radiance
// from the photo, with the virtual content's change to it (L_rv − L_r, as the composite adds it
// to the photo) on top. The photo holds the light of every bounce in the real scene, where the
// voxels' own two bounces hold about 70 % of a cornell wall's (its light goes back and forth
// between the box's walls many times); the cones of the virtual objects and of the real pixels
// around them then see the walls and the desk as bright as the camera does. Voxels the camera
// does not see (behind a real or a virtual surface, outside the frustum, the far side of a
// wall) keep their computed light. Bound in group 2 with the probe; applied by the light pass
// to the first bounce and, with two, by the photo pass after the second (photo_pass.wgsl;
// settings `dvct.photo_voxels`, VolumeParams.info.w). A new photo or camera alone runs the
// photo pass: the second bounce keeps the photo's light of the frame it last ran in (it runs
// again when the scene's light or content changes) — one bounce's lag, at no cost per frame.

@group(2) @binding(8) var gbuffer_depth_motion: texture_2d<f32>;
@group(2) @binding(9) var gbuffer_normal_roughness: texture_2d<f32>;
@group(2) @binding(10) var gbuffer_flags: texture_2d<u32>;
@group(2) @binding(11) var photo_texture: texture_2d<f32>;

// The radiance the photo shows of the real surface at `p` with normal `n` (either side), in w
// whether it shows it: the camera's pixel there is a real surface whose normal is alike and
// whose tangent plane passes within a voxel and a half of `p`.
fn photo_radiance(p: vec3f, n: vec3f) -> vec4f {
    let at = pixel_from_world(frame, p);
    if (at.z <= 0.0) { return vec4f(0.0); }
    let q = vec2i(floor(at.xy));
    if (any(q < vec2i(0)) || any(q >= vec2i(frame.size.xy))) { return vec4f(0.0); }
    let flags = textureLoad(gbuffer_flags, q, 0).r;
    if (!is_covered(flags) || !is_real(flags)) { return vec4f(0.0); }
    let seen = world_from_pixel(frame, vec2f(q) + 0.5, textureLoad(gbuffer_depth_motion, q, 0).x);
    let n_seen = textureLoad(gbuffer_normal_roughness, q, 0).xyz;
    if (abs(dot(n_seen, n)) < 0.7 || abs(dot(seen - p, n_seen)) > 1.5 * voxel_side()) {
        return vec4f(0.0);
    }
    let photo = textureLoad(photo_texture, q / i32(frame.counts.z), 0).rgb;
    return vec4f(photo / frame.exposure_env.x, 1.0);
}

// A real voxel's light (premultiplied, both solutions) with the photo's in place of its own
// real-only light where the camera sees its surface at `p` (normal `n`); `rv` keeps the
// virtual content's change.
fn with_photo(rv: vec4f, r: vec4f, p: vec3f, n: vec3f) -> array<vec4f, 2> {
    if ((params.info.w & VOLUME_PHOTO) == 0u) { return array(rv, r); }
    let b = photo_radiance(p, n);
    if (b.w == 0.0) { return array(rv, r); }
    // With no change (no virtual content), exactly the photo's: b + rv − r rounds, in
    // whatever order the compiler sums it.
    let changed = select(max(b.rgb + (rv.rgb - r.rgb), vec3f(0.0)), b.rgb, rv.rgb == r.rgb);
    return array(vec4f(changed, 1.0), vec4f(b.rgb, 1.0));
}
