// G-buffer resolve (Knecht §2.12): turns the camera's visibility buffer (triangle per pixel,
// from the compute rasteriser) into surface attributes. Each pixel's ray is intersected with
// its triangle; ray differentials of the neighbouring pixels give texture footprints.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
@group(0) @binding(2) var<storage, read> vertices: array<f32>;
@group(0) @binding(3) var<storage, read> indices: array<u32>;
@group(0) @binding(4) var<storage, read> triangles: array<vec4u>;
@group(0) @binding(5) var<storage, read> materials: array<Material>;
@group(0) @binding(6) var<storage, read> visibility: array<vec2u>;

@group(1) @binding(0) var textures_srgb: texture_2d_array<f32>;
@group(1) @binding(1) var textures_linear: texture_2d_array<f32>;
@group(1) @binding(2) var texture_sampler: sampler;

// reversed depth, previous-frame pixel offset (x, y), previous-frame reversed depth
@group(2) @binding(0) var out_depth_motion: texture_storage_2d<rgba32float, write>;
@group(2) @binding(1) var out_albedo_metallic: texture_storage_2d<rgba16float, write>;
@group(2) @binding(2) var out_normal_roughness: texture_storage_2d<rgba16float, write>;
@group(2) @binding(3) var out_specular: texture_storage_2d<rgba8unorm, write>;
@group(2) @binding(4) var out_emission_occlusion: texture_storage_2d<rgba16float, write>;
@group(2) @binding(5) var out_flags: texture_storage_2d<r32uint, write>;

fn pixel_ray(pixel: vec2f) -> vec3f {
    return normalize(world_from_pixel(frame, pixel, 0.5) - frame.camera_position.xyz);
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id.xy >= frame.size.xy)) { return; }
    let pixel = vec2i(id.xy);
    let texel = visibility[id.y * frame.size.x + id.x];
    let triangle = visibility_triangle(texel);
    if (triangle == 0u) {
        textureStore(out_depth_motion, pixel, vec4f(0.0));
        textureStore(out_flags, pixel, vec4u(0u));
        return;
    }
    let origin = frame.camera_position.xyz;
    let centre = vec2f(id.xy) + 0.5;
    let h = intersect(triangle - 1u, origin, pixel_ray(centre));
    let inst = instances[h.instance];
    let m = materials[inst.info.x];

    // Texture footprint from the rays through the next pixels, on the triangle's plane.
    let hx = intersect(triangle - 1u, origin, pixel_ray(centre + vec2f(1.0, 0.0)));
    let hy = intersect(triangle - 1u, origin, pixel_ray(centre + vec2f(0.0, 1.0)));
    let duv_dx = hx.uv - h.uv;
    let duv_dy = hy.uv - h.uv;
    let bits = m.texture_info.y;
    let base_sample = sample_slot(true, m.texture_layers.x, bits, 0u, h.uv, duv_dx, duv_dy, vec4f(1.0));
    let mr_sample = sample_slot(false, m.texture_layers.y, bits, 1u, h.uv, duv_dx, duv_dy, vec4f(1.0));
    let normal_sample = sample_slot(false, m.texture_layers.z, bits, 2u, h.uv, duv_dx, duv_dy, vec4f(0.5, 0.5, 1.0, 1.0));
    let occlusion_sample = sample_slot(false, m.texture_layers.w, bits, 3u, h.uv, duv_dx, duv_dy, vec4f(1.0));
    let emissive_sample = sample_slot(true, m.texture_info.x, bits, 4u, h.uv, duv_dx, duv_dy, vec4f(1.0));

    let to_camera = origin - h.position;
    var n = facing_normal(h, to_camera);
    if (m.texture_layers.z != NO_TEXTURE) {
        // Tangent frame of the triangle from its positions and texture coordinates.
        let dp1 = hx.position - h.position;
        let dp2 = hy.position - h.position;
        let det = duv_dx.x * duv_dy.y - duv_dx.y * duv_dy.x;
        if (abs(det) > 1e-20) {
            let t = normalize((dp1 * duv_dy.y - dp2 * duv_dx.y) / det);
            // glTF's v axis runs down the image.
            let b = -normalize((dp2 * duv_dx.x - dp1 * duv_dy.x) / det);
            let tn = normalize((normal_sample.xyz * 2.0 - 1.0) * vec3f(m.params.z, m.params.z, 1.0));
            let tt = normalize(t - n * dot(n, t));
            n = normalize(tt * tn.x + cross(n, tt) * sign(dot(cross(n, tt), b)) * tn.y + n * tn.z);
        }
    }
    let base = m.base_color * base_sample;
    let metallic = clamp(m.params.x * mr_sample.b, 0.0, 1.0);
    let roughness = clamp(m.params.y * mr_sample.g, 0.0, 1.0);
    let occlusion = 1.0 + m.params.w * (occlusion_sample.r - 1.0);

    // Where this surface point was in the previous frame (object and camera motion).
    let previous_world = inst.previous_world_from_object * vec4f(h.object_position, 1.0);
    let previous_clip = frame.previous_clip_from_world * previous_world;
    let previous_ndc = previous_clip.xyz / previous_clip.w;
    let size = vec2f(frame.size.xy);
    let previous_pixel = vec2f((previous_ndc.x * 0.5 + 0.5) * size.x, (0.5 - previous_ndc.y * 0.5) * size.y);
    let depth = visibility_depth(texel);

    textureStore(out_depth_motion, pixel, vec4f(depth, previous_pixel - centre, previous_ndc.z));
    textureStore(out_albedo_metallic, pixel, vec4f(base.rgb, metallic));
    textureStore(out_normal_roughness, pixel, vec4f(n, roughness));
    textureStore(out_specular, pixel, m.dielectric);
    textureStore(out_emission_occlusion, pixel, vec4f(m.emissive.rgb * emissive_sample.rgb, occlusion));
    textureStore(out_flags, pixel, vec4u(SURFACE_COVERED | inst.info.y | (inst.info.x << SURFACE_MATERIAL_SHIFT), 0u, 0u, 0u));
}
