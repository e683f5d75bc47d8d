// Near-field bounce in screen space. The VPL sum clamps its geometry term at d_min, so light
// between surfaces closer than that (a virtual object and the desk it stands on, the inside
// of a torus) is mostly lost; VPLs are too sparse there anyway. As SSDO complements ISMs
// (Ritschel et al. 2009), the missing part
//   ∫_{d < d_min} L(q) · f_r · cos θ_p · cos θ_q · (1/d² − 1/d_min²) dA_q
// is gathered from the pixels around p: each is a patch of the surface the camera sees, with
// the previous frame's radiance as its outgoing light (diffuse approximation). The part of
// it that is indirect light, reflected more than once, is gathered farther (next function):
// here only the rest. Both buffers from the same samples:
// L_rv from every neighbour, L_r from real neighbours onto real receivers only (Eq. 5.7's
// path rule; the real surface a virtual neighbour hides is unknown and adds nothing).
// Neighbours the specular stage traces send what they reflect of p's surroundings (metals)
// or nothing (glass; see below).
// Expects the indirect module's bindings (frame, G-buffer, previous_l_rv/_r,
// previous_indirect_rv/_r).

struct NearField {
    rv: vec3f,
    r: vec3f,
}

// Pixels per metre at unit distance from the camera, measured around world point `p`.
fn pixels_per_metre(p: vec3f, pixel: vec2f) -> f32 {
    let view = normalize(p - frame.camera_position.xyz);
    let side = normalize(cross(view, select(vec3f(0.0, 1.0, 0.0), vec3f(1.0, 0.0, 0.0), abs(view.y) > 0.9)));
    let moved = pixel_from_world(frame, p + side * 0.01).xy;
    return length(moved - pixel) / 0.01 * distance(p, frame.camera_position.xyz);
}

// A neighbour pixel q as a patch of surface that lights p.
struct Patch {
    valid: bool,
    flags: u32,
    // Unit direction p → q, squared distance, cosine at q.
    l: vec3f,
    d2: f32,
    cos_q: f32,
    n_q: vec3f,
    // World area of the pixel.
    area: f32,
}

// Pixel `q` seen from surface `s`, within `radius` metres; `scale` is pixels per metre at
// unit distance.
fn patch_at(q: vec2i, pixel: vec2i, s: Surface, radius: f32, scale: f32) -> Patch {
    var out: Patch;
    if (any(q < vec2i(0)) || any(q >= vec2i(frame.size.xy)) || all(q == pixel)) { return out; }
    out.flags = textureLoad(gbuffer_flags, q, 0).r;
    if (!is_covered(out.flags)) { return out; }
    let x_q = world_from_pixel(frame, vec2f(q) + 0.5, textureLoad(gbuffer_depth_motion, q, 0).x);
    let to = x_q - s.position;
    out.d2 = dot(to, to);
    if (out.d2 >= radius * radius || out.d2 <= 0.0) { return out; }
    out.l = to * inverseSqrt(out.d2);
    out.n_q = normalize(textureLoad(gbuffer_normal_roughness, q, 0).xyz);
    out.cos_q = -dot(out.n_q, out.l);
    if (out.cos_q <= 0.0 || dot(s.normal, out.l) <= 0.0) { return out; }
    // Its footprint at its distance, spread by its obliquity.
    let t_q = distance(x_q, frame.camera_position.xyz);
    let view_cos = max(abs(dot(out.n_q, normalize(frame.camera_position.xyz - x_q))), 0.2);
    out.area = (t_q / scale) * (t_q / scale) / view_cos;
    out.valid = true;
    return out;
}

// 1/d² of a disc of the patch's area (bounded), minus what the VPLs clamped at `clamp` gave.
fn near_kernel(c: Patch, clamp: f32) -> f32 {
    return max(1.0 / (c.d2 + c.area / PI) - 1.0 / (clamp * clamp), 0.0);
}

// `scale`: pixels per metre at unit distance around the receiver (pixels_per_metre).
fn near_field(pixel: vec2i, s: Surface, traced: bool, r_p: f32, d_min: f32, scale: f32, samples: u32, frame_index: u32) -> NearField {
    var out: NearField;
    if (samples == 0u || d_min <= 0.0) { return out; }
    let centre = vec2f(pixel) + 0.5;
    let radius_px = d_min * scale / distance(s.position, frame.camera_position.xyz);
    if (radius_px < 1.0) { return out; }
    // Each sample stands for this many pixels of the disc.
    let pixels_per_sample = PI * radius_px * radius_px / f32(samples);
    let seed = hash_u32(u32(pixel.x) * 1973u + u32(pixel.y) * 9277u + frame_index * 26699u);
    for (var k = 0u; k < samples; k++) {
        let u = hash_uniform2(seed + k * 2u);
        let offset = sqrt(u.x) * radius_px * vec2f(cos(2.0 * PI * u.y), sin(2.0 * PI * u.y));
        let q = vec2i(floor(centre + offset));
        let c = patch_at(q, pixel, s, d_min, scale);
        if (!c.valid) { continue; }
        // A mirror's or a glass's radiance toward the camera is the scene it reflects or lets
        // through, nothing like what it sends to p: such a neighbour glowed like a lamp onto
        // the desk a glass object stands on. What a traced metal sends to p is what it
        // reflects: from below p's horizon, p's own surroundings (a desk under a mirror ball
        // sees the desk in it; their radiance taken as p's own of the previous frame), else
        // the sky, which the probe's photons carry. A glass's light reaches p as a caustic.
        var radiance_rv: vec3f;
        var radiance_r = vec3f(0.0);
        if (is_traced(materials[material_of(c.flags)])) {
            let albedo_metallic = textureLoad(gbuffer_albedo_metallic, q, 0);
            let source = reflect(c.l, c.n_q);
            if (albedo_metallic.a < 0.5 || dot(source, s.normal) >= 0.0) { continue; }
            let reflectance = schlick(albedo_metallic.rgb, 1.0, c.cos_q);
            radiance_rv = reflectance * textureLoad(previous_l_rv, pixel, 0).rgb;
            if (is_real(c.flags)) { radiance_r = reflectance * textureLoad(previous_l_r, pixel, 0).rgb; }
        } else {
            // Light reflected once: the rest is near_field_bounced's.
            radiance_rv = max(textureLoad(previous_l_rv, q, 0).rgb - textureLoad(previous_indirect_rv, q, 0).rgb, vec3f(0.0));
            if (is_real(c.flags)) {
                radiance_r = max(textureLoad(previous_l_r, q, 0).rgb - textureLoad(previous_indirect_r, q, 0).rgb, vec3f(0.0));
            }
        }
        let transfer = receiver_brdf_cos(s, c.l, traced) * c.cos_q * c.area * pixels_per_sample * near_kernel(c, d_min);
        out.rv += transfer * radiance_rv;
        out.r += transfer * radiance_r * r_p;
    }
    return out;
}

struct Bounced {
    light: NearField,
    // The distance at which the multiple-bounce VPLs the screen covers are clamped at p, and
    // the radius in pixels of the disc gathered.
    d_bounce: f32,
    radius_px: f32,
}

// Pixels the multiple-bounce near field reaches at most (its cost and the screen's reach).
const BOUNCED_MAX_PIXELS: f32 = 128.0;

// Whether the multiple-bounce near field gathers the surface at `x`: the camera sees it (the
// G-buffer's surface at its pixel lies within a few pixels' size of it) within the disc
// around the receiver's pixel. Multiple-bounce VPLs elsewhere (the desk hidden under an
// object) keep their light within the disc's reach.
fn screen_covers(x: vec3f, how: VplShading) -> bool {
    let at = pixel_from_world(frame, x);
    if (at.z <= 0.0 || distance(at.xy, how.pixel) > how.screen_radius) { return false; }
    let q = vec2i(floor(at.xy));
    if (any(q < vec2i(0)) || any(q >= vec2i(frame.size.xy))) { return false; }
    if (!is_covered(textureLoad(gbuffer_flags, q, 0).r)) { return false; }
    let seen = world_from_pixel(frame, vec2f(q) + 0.5, textureLoad(gbuffer_depth_motion, q, 0).x);
    // The receiver's pixel size stands for x's (they lie within the disc of each other).
    let metres_per_pixel = distance(x, frame.camera_position.xyz) / how.scale;
    return distance(seen, x) <= SCREEN_COVER_PIXELS * metres_per_pixel;
}

// How far (in pixels' size) the camera's surface may lie from a VPL that it still covers.
const SCREEN_COVER_PIXELS: f32 = 4.0;

// The multiple-bounce near field: light reflected more than once between surfaces close to
// each other (the inside corner between a block and the floor it stands on, where the floor
// lit by the block lights the block again). The multiple-bounce VPLs are too sparse to resolve
// it and lose it to their clamp (a block's lower faces were 12/255 too dark near the floor
// of the Cornell box, as dark as two bounces). Within `radius` of p (up to what the screen
// holds), their kernel is clamped at that radius and the rest,
//   ∫_{d < radius} L_indirect(q) · f_r · cos θ_p · cos θ_q · (1/d² − 1/radius²) dA_q,
// is gathered from the pixels around p with the previous frame's indirect light as their
// outgoing light: every further bounce among them, over frames. Samples are drawn uniformly
// in distance (density ∝ 1/r, matching the kernel's 1/d²). Real and virtual routing as above.
fn near_field_bounced(pixel: vec2i, s: Surface, traced: bool, r_p: f32, d_min: f32, scale: f32, radius: f32, samples: u32, frame_index: u32) -> Bounced {
    var out = Bounced(NearField(vec3f(0.0), vec3f(0.0)), d_min, 0.0);
    if (samples == 0u || radius <= d_min) { return out; }
    let centre = vec2f(pixel) + 0.5;
    let metres_per_pixel = distance(s.position, frame.camera_position.xyz) / scale;
    let radius_px = min(radius / metres_per_pixel, BOUNCED_MAX_PIXELS);
    out.d_bounce = max(radius_px * metres_per_pixel, d_min);
    if (radius_px < 2.0) { out.d_bounce = d_min; return out; }
    out.radius_px = radius_px;
    let seed = hash_u32(u32(pixel.x) * 7919u + u32(pixel.y) * 6007u + frame_index * 15485863u);
    for (var k = 0u; k < samples; k++) {
        let u = hash_uniform2(seed + k * 2u);
        let r = u.x * radius_px;
        let q = vec2i(floor(centre + r * vec2f(cos(2.0 * PI * u.y), sin(2.0 * PI * u.y))));
        let c = patch_at(q, pixel, s, out.d_bounce, scale);
        // Mirrors and glass send what they reflect or let through, not their indirect light.
        if (!c.valid || is_traced(materials[material_of(c.flags)])) { continue; }
        let radiance_rv = textureLoad(previous_indirect_rv, q, 0).rgb;
        var radiance_r = vec3f(0.0);
        if (is_real(c.flags)) { radiance_r = textureLoad(previous_indirect_r, q, 0).rgb; }
        // Pixels this sample stands for: 1 / its density 1 / (2π r R) per pixel, over the count.
        let pixels_per_sample = 2.0 * PI * max(r, 0.5) * radius_px / f32(samples);
        let transfer = receiver_brdf_cos(s, c.l, traced) * c.cos_q * c.area * pixels_per_sample * near_kernel(c, out.d_bounce);
        out.light.rv += transfer * radiance_rv;
        out.light.r += transfer * radiance_r * r_p;
    }
    return out;
}
