// Empties both levels of the caustic buffer (caustics/mod.rs, `CausticBuffer::clear`): a
// render pass's clear of these four targets cost 0.14 ms at 1080p on the H200, this dispatch
// runs beside the photon tracing. One thread per fine texel; the coarse level's texels are
// the first 1/COARSE_LEVEL_FACTOR² of them.

@group(0) @binding(0) var fine_rv: texture_storage_2d<rgba16float, write>;
@group(0) @binding(1) var fine_r: texture_storage_2d<rgba16float, write>;
@group(0) @binding(2) var coarse_rv: texture_storage_2d<rgba16float, write>;
@group(0) @binding(3) var coarse_r: texture_storage_2d<rgba16float, write>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (all(id.xy < textureDimensions(fine_rv))) {
        textureStore(fine_rv, id.xy, vec4f(0.0));
        textureStore(fine_r, id.xy, vec4f(0.0));
    }
    if (all(id.xy < textureDimensions(coarse_rv))) {
        textureStore(coarse_rv, id.xy, vec4f(0.0));
        textureStore(coarse_r, id.xy, vec4f(0.0));
    }
}
