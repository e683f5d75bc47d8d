// Near-field bounce in screen space. The VPL sum clamps its geometry term at d_min, so light
// between surfaces closer than that (a virtual object and the desk it stands on, the inside
// of a torus) is mostly lost; VPLs are too sparse there anyway. As SSDO complements ISMs
// (Ritschel et al. 2009), the missing part
//   ∫_{d < d_min} L(q) · f_r · cos θ_p · cos θ_q · (1/d² − 1/d_min²) dA_q
// is gathered from the pixels around p: each is a patch of the surface the camera sees, with
// the previous frame's radiance as its outgoing light (diffuse approximation; over frames
// this also carries further near-field bounces). Both buffers from the same samples:
// L_rv from every neighbour, L_r from real neighbours onto real receivers only (Eq. 5.7's
// path rule; the real surface a virtual neighbour hides is unknown and adds nothing).
// Neighbours the specular stage traces send what they reflect of p's surroundings (metals)
// or nothing (glass; see below).
// Expects the indirect module's bindings (frame, G-buffer, previous_l_rv/_r).

struct NearField {
    rv: vec3f,
    r: vec3f,
}

// Pixels per metre at unit distance from the camera, measured around world point `p`.
fn pixels_per_metre(p: vec3f, pixel: vec2f) -> f32 {
    let view = normalize(p - frame.camera_position.xyz);
    let side = normalize(cross(view, select(vec3f(0.0, 1.0, 0.0), vec3f(1.0, 0.0, 0.0), abs(view.y) > 0.9)));
    let h = frame.clip_from_world * vec4f(p + side * 0.01, 1.0);
    let ndc = h.xy / h.w;
    let size = vec2f(frame.size.xy);
    let moved = vec2f((ndc.x * 0.5 + 0.5) * size.x, (0.5 - ndc.y * 0.5) * size.y);
    return length(moved - pixel) / 0.01 * distance(p, frame.camera_position.xyz);
}

fn near_field(pixel: vec2i, s: Surface, traced: bool, r_p: f32, d_min: f32, samples: u32, frame_index: u32) -> NearField {
    var out: NearField;
    if (samples == 0u || d_min <= 0.0) { return out; }
    let centre = vec2f(pixel) + 0.5;
    let scale = pixels_per_metre(s.position, centre);
    let radius_px = d_min * scale / distance(s.position, frame.camera_position.xyz);
    if (radius_px < 1.0) { return out; }
    let size = vec2i(frame.size.xy);
    // Each sample stands for this many pixels of the disc.
    let pixels_per_sample = PI * radius_px * radius_px / f32(samples);
    let inv_d_min2 = 1.0 / (d_min * d_min);
    let seed = hash_u32(u32(pixel.x) * 1973u + u32(pixel.y) * 9277u + frame_index * 26699u);
    for (var k = 0u; k < samples; k++) {
        let u = vec2f(f32(hash_u32(seed + k * 2u)), f32(hash_u32(seed + k * 2u + 1u))) * 2.3283064365386963e-10;
        let offset = sqrt(u.x) * radius_px * vec2f(cos(2.0 * PI * u.y), sin(2.0 * PI * u.y));
        let q = vec2i(floor(centre + offset));
        if (any(q < vec2i(0)) || any(q >= size) || all(q == pixel)) { continue; }
        let flags = textureLoad(gbuffer_flags, q, 0).r;
        if (!is_covered(flags)) { continue; }
        let x_q = world_from_pixel(frame, vec2f(q) + 0.5, textureLoad(gbuffer_depth_motion, q, 0).x);
        let to = x_q - s.position;
        let d2 = dot(to, to);
        if (d2 >= d_min * d_min || d2 <= 0.0) { continue; }
        let l = to * inverseSqrt(d2);
        let n_q = normalize(textureLoad(gbuffer_normal_roughness, q, 0).xyz);
        let cos_q = -dot(n_q, l);
        if (cos_q <= 0.0 || dot(s.normal, l) <= 0.0) { continue; }
        // A mirror's or a glass's radiance toward the camera is the scene it reflects or lets
        // through, nothing like what it sends to p: such a neighbour glowed like a lamp onto
        // the desk a glass object stands on. What a traced metal sends to p is what it
        // reflects: from below p's horizon, p's own surroundings (a desk under a mirror ball
        // sees the desk in it; their radiance taken as p's own of the previous frame), else
        // the sky, which the probe's photons carry. A glass's light reaches p as a caustic.
        var radiance_rv: vec3f;
        var radiance_r = vec3f(0.0);
        if (is_traced(materials[material_of(flags)])) {
            let albedo_metallic = textureLoad(gbuffer_albedo_metallic, q, 0);
            let source = reflect(l, n_q);
            if (albedo_metallic.a < 0.5 || dot(source, s.normal) >= 0.0) { continue; }
            let reflectance = schlick(albedo_metallic.rgb, 1.0, cos_q);
            radiance_rv = reflectance * textureLoad(previous_l_rv, pixel, 0).rgb;
            if (is_real(flags)) { radiance_r = reflectance * textureLoad(previous_l_r, pixel, 0).rgb; }
        } else {
            radiance_rv = textureLoad(previous_l_rv, q, 0).rgb;
            if (is_real(flags)) { radiance_r = textureLoad(previous_l_r, q, 0).rgb; }
        }
        // World area of pixel q: its footprint at its distance, spread by its obliquity.
        let t_q = distance(x_q, frame.camera_position.xyz);
        let view_cos = max(abs(dot(n_q, normalize(frame.camera_position.xyz - x_q))), 0.2);
        let pixel_area = (t_q / scale) * (t_q / scale) / view_cos;
        // 1/d² of a disc of the pixel's area (bounded), minus what the clamped VPLs gave.
        let kernel = max(1.0 / (d2 + pixel_area / PI) - inv_d_min2, 0.0);
        let transfer = receiver_brdf_cos(s, l, traced) * cos_q * pixel_area * pixels_per_sample * kernel;
        out.rv += transfer * radiance_rv;
        out.r += transfer * radiance_r * r_p;
    }
    return out;
}
