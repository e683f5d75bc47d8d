// Per-frame constants shared by every pass. Mirrors `FrameUniforms` in src/uniforms.rs
// (layout checked by a test).

const PI: f32 = 3.14159265358979;

struct Frame {
    clip_from_world: mat4x4f,
    world_from_clip: mat4x4f,
    // The camera of the previous frame (for reprojection).
    previous_clip_from_world: mat4x4f,
    // Rotation of the probe (`[environment] rotation_deg`), in the upper 3×3.
    probe_from_world: mat4x4f,
    camera_position: vec4f,
    // Internal (shading) width and height, output width and height.
    size: vec4u,
    // Light count, 1 if a probe is present, supersampling factor, radiance mip count.
    counts: vec4u,
    // Exposure, probe intensity, camera near plane, frame index.
    exposure_env: vec4f,
}

// World position of the pixel with centre `pixel` (internal resolution) at reversed depth `depth`.
fn world_from_pixel(frame: Frame, pixel: vec2f, depth: f32) -> vec3f {
    let size = vec2f(frame.size.xy);
    let ndc = vec2f(pixel.x / size.x * 2.0 - 1.0, 1.0 - pixel.y / size.y * 2.0);
    let h = frame.world_from_clip * vec4f(ndc, depth, 1.0);
    return h.xyz / h.w;
}

// Pixel coordinates (internal resolution; centres at +0.5) of world point `x` in xy, its clip
// w in z (≤ 0: behind the camera, xy meaningless): the inverse of world_from_pixel.
fn pixel_from_world(frame: Frame, x: vec3f) -> vec3f {
    let clip = frame.clip_from_world * vec4f(x, 1.0);
    let ndc = clip.xy / clip.w;
    return vec3f(vec2f(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * vec2f(frame.size.xy), clip.w);
}

// Rec.709 luminance of linear RGB.
fn luminance(c: vec3f) -> f32 {
    return dot(c, vec3f(0.2126, 0.7152, 0.0722));
}
