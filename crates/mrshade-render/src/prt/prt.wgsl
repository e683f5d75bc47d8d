// PRT irradiance per pixel (Franke §2.4, Eq. 2.33–2.40: ∫ L_i T ≈ Σ l_c t_c): where the
// camera sees a triangle of an instance with baked transfer, its vertices' transfer vectors
// are interpolated at the pixel's barycentrics and dotted with the probe's SH coefficients
// in that instance's object frame (probe_sh's workgroup for it). rgb: irradiance with
// self-shadowing; a: 1 where PRT applies, 0 elsewhere (direct lighting falls back to SH).

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> visibility: array<vec2u>;
@group(0) @binding(2) var<storage, read> instances: array<Instance>;
@group(0) @binding(3) var<storage, read> vertices: array<f32>;
@group(0) @binding(4) var<storage, read> indices: array<u32>;
@group(0) @binding(5) var<storage, read> triangles: array<vec4u>;
// COEFFICIENTS per vertex of the scene's vertex buffer (zero where nothing was baked).
@group(0) @binding(6) var<storage, read> transfer: array<f32>;
// Per instance: its frame in `coefficients` (1, 2, …) or 0 without PRT.
@group(0) @binding(7) var<storage, read> instance_frame: array<u32>;
@group(0) @binding(8) var<storage, read> coefficients: array<vec4f>;
@group(0) @binding(9) var out_irradiance: texture_storage_2d<rgba16float, write>;

// SH coefficients per vertex and per frame of `coefficients`, 9 or 16, set when the pipeline
// is made (as probe_sh.wgsl's).
override COEFFICIENTS: u32 = 9u;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id.xy >= frame.size.xy)) { return; }
    let pixel = vec2i(id.xy);
    let triangle = visibility_triangle(visibility[id.y * frame.size.x + id.x]);
    if (triangle == 0u || frame.counts.y == 0u) {
        textureStore(out_irradiance, pixel, vec4f(0.0));
        return;
    }
    let origin = frame.camera_position.xyz;
    let dir = normalize(world_from_pixel(frame, vec2f(id.xy) + 0.5, 0.5) - origin);
    let h = intersect(triangle - 1u, origin, dir);
    let slot = instance_frame[h.instance];
    if (slot == 0u) {
        textureStore(out_irradiance, pixel, vec4f(0.0));
        return;
    }
    let tri = triangles[triangle - 1u];
    let w = vec3f(1.0 - h.bary.x - h.bary.y, h.bary.x, h.bary.y);
    var e = vec3f(0.0);
    let n = COEFFICIENTS;
    for (var corner = 0u; corner < 3u; corner++) {
        let v = (indices[tri.y + corner] + tri.z) * n;
        for (var i = 0u; i < n; i++) {
            e += coefficients[slot * n + i].rgb * (w[corner] * transfer[v + i]);
        }
    }
    textureStore(out_irradiance, pixel, vec4f(max(e, vec3f(0.0)) * frame.exposure_env.y, 1.0));
}
