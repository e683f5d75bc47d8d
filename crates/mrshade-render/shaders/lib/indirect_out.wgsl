// A method's IndirectLight targets as its per-pixel pass writes them (group 2, in the order
// of `IndirectLight::storage_entries` in src/methods/indirect_light.rs): indirect L_rv and
// L_r, and the probe's visibility sums Σw_c·V_rv, Σw_c·V_r, Σw_c.

@group(2) @binding(0) var out_rv: texture_storage_2d<rgba16float, write>;
@group(2) @binding(1) var out_r: texture_storage_2d<rgba16float, write>;
@group(2) @binding(2) var out_env_rv: texture_storage_2d<rgba16float, write>;
@group(2) @binding(3) var out_env_r: texture_storage_2d<rgba16float, write>;
@group(2) @binding(4) var out_env_weight: texture_storage_2d<rgba16float, write>;

fn store_indirect(pixel: vec2i, rv: vec3f, r: vec3f, env_rv: vec3f, env_r: vec3f, env_weight: vec3f) {
    textureStore(out_rv, pixel, vec4f(rv, 1.0));
    textureStore(out_r, pixel, vec4f(r, 1.0));
    textureStore(out_env_rv, pixel, vec4f(env_rv, 1.0));
    textureStore(out_env_r, pixel, vec4f(env_r, 1.0));
    textureStore(out_env_weight, pixel, vec4f(env_weight, 1.0));
}

// Where no surface covers the pixel: nothing (alpha 0 too).
fn store_no_indirect(pixel: vec2i) {
    textureStore(out_rv, pixel, vec4f(0.0));
    textureStore(out_r, pixel, vec4f(0.0));
    textureStore(out_env_rv, pixel, vec4f(0.0));
    textureStore(out_env_r, pixel, vec4f(0.0));
    textureStore(out_env_weight, pixel, vec4f(0.0));
}
