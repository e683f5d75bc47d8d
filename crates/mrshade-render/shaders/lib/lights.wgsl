// KHR_lights_punctual with the data contract's radiometric units: radiant intensity
// intensity × color, inverse-square falloff, glTF spot falloff t².
// Mirrors `GpuLight` in src/scene_gpu/lights.rs.

const LIGHT_POINT: u32 = 0u;
const LIGHT_SPOT: u32 = 1u;
const LIGHT_DIRECTIONAL: u32 = 2u;

struct Light {
    // xyz: position (world); w: unused
    position: vec4f,
    // xyz: unit direction the light shines along; w: r(pl), 1 real / 0 virtual
    direction_real: vec4f,
    // rgb: intensity × color
    intensity: vec4f,
    // cos(outer), 1 / (cos(inner) − cos(outer)), shadow texel size at unit distance, unused
    cone: vec4f,
    // kind, first shadow layer of the real-only set, layers per set (1 or 6), first layer of the virtual-only set
    info: vec4u,
}

struct Incident {
    // Unit direction from the surface toward the light.
    l: vec3f,
    // Irradiance on a surface facing the light (before the cosine).
    radiance: vec3f,
    distance: f32,
}

fn light_incident(light: Light, p: vec3f) -> Incident {
    var out: Incident;
    if (light.info.x == LIGHT_DIRECTIONAL) {
        out.l = -light.direction_real.xyz;
        out.radiance = light.intensity.rgb;
        out.distance = 1e30;
        return out;
    }
    let to_light = light.position.xyz - p;
    let d2 = max(dot(to_light, to_light), 1e-8);
    out.distance = sqrt(d2);
    out.l = to_light / out.distance;
    var falloff = 1.0 / d2;
    if (light.info.x == LIGHT_SPOT) {
        let cos_angle = dot(-out.l, light.direction_real.xyz);
        let t = clamp((cos_angle - light.cone.x) * light.cone.y, 0.0, 1.0);
        falloff *= t * t;
    }
    out.radiance = light.intensity.rgb * falloff;
    return out;
}

// How far toward `light` the point `p` lies: its height along the direction toward a
// directional light, minus its distance from any other. A surface nearer the light is higher.
// The RSM resolve writes each texel's (RsmPass::heights) for shadow tests, NO_RSM_HEIGHT where
// the texel sees nothing.
fn rsm_height(light: Light, p: vec3f) -> f32 {
    if (light.info.x == LIGHT_DIRECTIONAL) { return -dot(p, light.direction_real.xyz); }
    return -distance(p, light.position.xyz);
}
const NO_RSM_HEIGHT: f32 = -3.0e38;
