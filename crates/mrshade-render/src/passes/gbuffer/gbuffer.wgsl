// G-buffer: real and virtual surfaces seen from the camera (Knecht §2.12). Stores what the
// shading passes need per pixel; the real/virtual flag and material index go into `flags`
// (the thesis encodes the flag in the depth sign; a separate word keeps depth hardware-tested).

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
@group(0) @binding(2) var<storage, read> materials: array<Material>;

@group(1) @binding(0) var base_color_texture: texture_2d<f32>;
@group(1) @binding(1) var metallic_roughness_texture: texture_2d<f32>;
@group(1) @binding(2) var normal_texture: texture_2d<f32>;
@group(1) @binding(3) var occlusion_texture: texture_2d<f32>;
@group(1) @binding(4) var emissive_texture: texture_2d<f32>;
@group(1) @binding(5) var base_color_sampler: sampler;
@group(1) @binding(6) var metallic_roughness_sampler: sampler;
@group(1) @binding(7) var normal_sampler: sampler;
@group(1) @binding(8) var occlusion_sampler: sampler;
@group(1) @binding(9) var emissive_sampler: sampler;

struct VertexOut {
    @builtin(position) clip: vec4f,
    @location(0) world: vec3f,
    @location(1) normal: vec3f,
    @location(2) uv: vec2f,
    @location(3) @interpolate(flat) instance: u32,
}

@vertex
fn vs_main(
    @location(0) position: vec3f,
    @location(1) normal: vec3f,
    @location(2) uv: vec2f,
    @builtin(instance_index) instance: u32,
) -> VertexOut {
    let inst = instances[instance];
    let world = inst.world_from_object * vec4f(position, 1.0);
    var out: VertexOut;
    out.clip = frame.clip_from_world * world;
    out.world = world.xyz;
    out.normal = (inst.normal_from_object * vec4f(normal, 0.0)).xyz;
    out.uv = uv;
    out.instance = instance;
    return out;
}

struct GBufferOut {
    @location(0) albedo_metallic: vec4f,
    @location(1) normal_roughness: vec4f,
    @location(2) specular: vec4f,
    @location(3) emission_occlusion: vec4f,
    @location(4) flags: u32,
}

// Normal mapping without stored tangents: the cotangent frame from screen derivatives
// (Schüler 2013). glTF's v axis points down the image, hence the sign of `b`.
fn perturbed_normal(n: vec3f, dp_dx: vec3f, dp_dy: vec3f, duv_dx: vec2f, duv_dy: vec2f, tangent_normal: vec3f) -> vec3f {
    let dp2perp = cross(dp_dy, n);
    let dp1perp = cross(n, dp_dx);
    let t = dp2perp * duv_dx.x + dp1perp * duv_dy.x;
    let b = -(dp2perp * duv_dx.y + dp1perp * duv_dy.y);
    let scale = inverseSqrt(max(max(dot(t, t), dot(b, b)), 1e-20));
    return normalize(mat3x3f(t * scale, b * scale, n) * tangent_normal);
}

@fragment
fn fs_main(in: VertexOut) -> GBufferOut {
    // Derivatives first, in uniform control flow.
    let dp_dx = dpdx(in.world);
    let dp_dy = dpdy(in.world);
    let duv_dx = dpdx(in.uv);
    let duv_dy = dpdy(in.uv);
    let base_sample = textureSample(base_color_texture, base_color_sampler, in.uv);
    let mr_sample = textureSample(metallic_roughness_texture, metallic_roughness_sampler, in.uv);
    let normal_sample = textureSample(normal_texture, normal_sampler, in.uv).xyz;
    let occlusion_sample = textureSample(occlusion_texture, occlusion_sampler, in.uv).r;
    let emissive_sample = textureSample(emissive_texture, emissive_sampler, in.uv).rgb;

    let inst = instances[in.instance];
    let m = materials[inst.info.x];
    let base = m.base_color * base_sample;
    if (m.attenuation_cutoff.w >= 0.0 && base.a < m.attenuation_cutoff.w) {
        discard;
    }
    // Both sides of a surface are lit, and triangle winding is not trusted (meshes in the
    // wild mix it): the vertex normal is flipped only when it points to the other side of
    // the surface than the camera, judged by the screen-space geometric normal.
    var geometric = cross(dp_dx, dp_dy);
    if (dot(geometric, frame.camera_position.xyz - in.world) < 0.0) { geometric = -geometric; }
    var n = normalize(in.normal);
    if (dot(n, geometric) < 0.0) { n = -n; }
    if ((m.texture_flags.x & 1u) != 0u) {
        let tn = (normal_sample * 2.0 - 1.0) * vec3f(m.params.z, m.params.z, 1.0);
        n = perturbed_normal(n, dp_dx, dp_dy, duv_dx, duv_dy, normalize(tn));
    }
    let metallic = clamp(m.params.x * mr_sample.b, 0.0, 1.0);
    let roughness = clamp(m.params.y * mr_sample.g, 0.0, 1.0);
    let occlusion = 1.0 + m.params.w * (occlusion_sample - 1.0);

    var out: GBufferOut;
    out.albedo_metallic = vec4f(base.rgb, metallic);
    out.normal_roughness = vec4f(n, roughness);
    out.specular = m.dielectric;
    out.emission_occlusion = vec4f(m.emissive.rgb * emissive_sample, occlusion);
    out.flags = SURFACE_COVERED | inst.info.y | (inst.info.x << SURFACE_MATERIAL_SHIFT);
    return out;
}
