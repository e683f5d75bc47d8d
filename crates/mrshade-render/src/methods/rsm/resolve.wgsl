// Reflective shadow maps (Knecht §2.8, Dachsbacher & Stamminger 2005): for every texel of a
// light's view, the surface it sees with the power it receives and an importance factor
// (the reflected power) for placing VPLs. One map per shadow layer of every light, at a
// lower resolution: real-only and virtual-only sets, one layer or six cube faces each.

struct RsmParams {
    // resolution, layer count, 1 if traced surfaces take no VPLs (their light flies on as
    // photons and lands as caustic VPLs, reflections spec §2.18), unused
    size: vec4u,
    // shadow-map resolution / RSM resolution (scales the lights' texel extents), unused…
    scale: vec4f,
}

@group(0) @binding(0) var<uniform> params: RsmParams;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;
@group(0) @binding(2) var<storage, read> vertices: array<f32>;
@group(0) @binding(3) var<storage, read> indices: array<u32>;
@group(0) @binding(4) var<storage, read> triangles: array<vec4u>;
@group(0) @binding(5) var<storage, read> materials: array<Material>;
@group(0) @binding(6) var<storage, read> lights: array<Light>;
@group(0) @binding(7) var<storage, read> layer_world_from_clip: array<mat4x4f>;
// Light index of every layer.
@group(0) @binding(8) var<storage, read> layer_light: array<u32>;
@group(0) @binding(9) var<storage, read> visibility: array<vec2u>;
@group(0) @binding(10) var<storage, read_write> rsm: array<RsmTexel>;
// Per texel, the surface's height toward the light (rsm_height), NO_RSM_HEIGHT where none.
@group(0) @binding(11) var<storage, read_write> heights: array<f32>;

@group(1) @binding(0) var textures_srgb: texture_2d_array<f32>;
@group(1) @binding(1) var textures_linear: texture_2d_array<f32>;
@group(1) @binding(2) var texture_sampler: sampler;

struct LightRay {
    origin: vec3f,
    dir: vec3f,
}

// The ray of texel centre `st` (in texels) of `layer`.
fn light_ray(layer: u32, light: Light, st: vec2f) -> LightRay {
    let res = f32(params.size.x);
    let ndc = vec2f(st.x / res * 2.0 - 1.0, 1.0 - st.y / res * 2.0);
    let world_from_clip = layer_world_from_clip[layer];
    var r: LightRay;
    if (light.info.x == LIGHT_DIRECTIONAL) {
        let h = world_from_clip * vec4f(ndc, 1.0, 1.0);
        r.origin = h.xyz / h.w;
        r.dir = light.direction_real.xyz;
    } else {
        let h = world_from_clip * vec4f(ndc, 0.5, 1.0);
        r.origin = light.position.xyz;
        r.dir = normalize(h.xyz / h.w - r.origin);
    }
    return r;
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    let res = params.size.x;
    let layer = id.z;
    if (id.x >= res || id.y >= res || layer >= params.size.y) { return; }
    let index = (layer * res + id.y) * res + id.x;
    let texel = visibility[index];
    let triangle = visibility_triangle(texel);
    var out: RsmTexel;
    if (triangle == 0u) {
        rsm[index] = out;
        heights[index] = NO_RSM_HEIGHT;
        return;
    }
    let light = lights[layer_light[layer]];
    let st = vec2f(id.xy) + 0.5;
    let ray = light_ray(layer, light, st);
    let h = intersect(triangle - 1u, ray.origin, ray.dir);
    let ray_x = light_ray(layer, light, st + vec2f(1.0, 0.0));
    let ray_y = light_ray(layer, light, st + vec2f(0.0, 1.0));
    let hx = intersect(triangle - 1u, ray_x.origin, ray_x.dir);
    let hy = intersect(triangle - 1u, ray_y.origin, ray_y.dir);
    let inst = instances[h.instance];
    let m = materials[inst.info.x];
    let bits = m.texture_info.y;
    let base = m.base_color * sample_slot(true, m.texture_layers.x, bits, 0u, h.uv, hx.uv - h.uv, hy.uv - h.uv, vec4f(1.0));
    let mr = sample_slot(false, m.texture_layers.y, bits, 1u, h.uv, hx.uv - h.uv, hy.uv - h.uv, vec4f(1.0));
    let n = facing_normal(h, -ray.dir);

    // Power through this texel: intensity × solid angle (perspective), irradiance × area
    // (orthographic). The lights' texel extents are those of the shadow maps.
    let extent = light.cone.z * params.scale.x;
    var power: vec3f;
    if (light.info.x == LIGHT_DIRECTIONAL) {
        power = light.intensity.rgb * extent * extent;
    } else {
        let incident = light_incident(light, h.position);
        let axis_ray = light_ray(layer, light, vec2f(f32(res) * 0.5));
        let c = max(dot(ray.dir, axis_ray.dir), 0.0);
        let solid_angle = extent * extent * c * c * c;
        // light_incident divides by d²; intensity × solid angle is the power.
        let d2 = dot(h.position - light.position.xyz, h.position - light.position.xyz);
        power = incident.radiance * d2 * solid_angle;
    }
    let metallic = clamp(m.params.x * mr.b, 0.0, 1.0);
    let albedo = vpl_base_color(m, base.rgb, metallic);
    let reflectance = albedo * (1.0 - metallic) + mix(m.dielectric.rgb, albedo, metallic);
    out.position = vec4f(h.position, 1.0);
    out.normal = vec4f(n, clamp(m.params.y * mr.g, 0.0, 1.0));
    out.albedo = vec4f(albedo, metallic);
    // A mirror or a glass under caustic VPLs: no VPL here ("placing VPLs directly on their
    // surface is not a good idea", [P §4.2.2]); its photons carry the light on.
    let importance = select(luminance(power * reflectance), 0.0, params.size.z == 1u && is_traced(m));
    out.power = vec4f(power, importance);
    out.material = vec4f((m.dielectric.r + m.dielectric.g + m.dielectric.b) / 3.0, m.dielectric.a, select(0.0, 1.0, (inst.info.y & SURFACE_REAL) != 0u), length(cross(hx.position - h.position, hy.position - h.position)));
    rsm[index] = out;
    heights[index] = rsm_height(light, h.position);
}
