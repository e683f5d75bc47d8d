// The cones' light of each pixel from the trace texels around it (gather.wgsl, texel.wgsl):
// their irradiance, glossy radiance and probe visibility, weighted by how far the texel's
// pixel lies and how alike its depth and normal are (geometry_weight: nothing leaks across an
// edge), then the pixel's own material (pixel_light.wgsl), so that a texture keeps every
// texel of its detail. A pixel that no texel around it is like (its likest one's
// geometry_weight below `dvct.retrace_likeness`: a silhouette, a crease, the rim of an object
// where it meets the desk) is listed for a trace of its own (gather.wgsl cs_retrace), which
// overwrites the blend written here.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: VolumeParams;
@group(0) @binding(2) var gbuffer_depth_motion: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_albedo_metallic: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_normal_roughness: texture_2d<f32>;
@group(0) @binding(5) var gbuffer_specular: texture_2d<f32>;
@group(0) @binding(6) var gbuffer_flags: texture_2d<u32>;
@group(0) @binding(7) var<storage, read> materials: array<Material>;

@group(1) @binding(0) var traced_rv: texture_2d<f32>;
@group(1) @binding(1) var traced_r: texture_2d<f32>;
@group(1) @binding(2) var traced_env_rv: texture_2d<f32>;
@group(1) @binding(3) var traced_env_r: texture_2d<f32>;
@group(1) @binding(4) var traced_env_weight: texture_2d<f32>;
@group(1) @binding(5) var traced_glossy_rv: texture_2d<f32>;
@group(1) @binding(6) var traced_glossy_r: texture_2d<f32>;

// Group 2: the method's IndirectLight (shaders/lib/indirect_out.wgsl).

@group(3) @binding(0) var env_radiance: texture_2d<f32>;
@group(3) @binding(1) var env_irradiance: texture_2d<f32>;
@group(3) @binding(2) var env_dfg_table: texture_2d<f32>;
@group(3) @binding(3) var env_sampler: sampler;

// The pixels to trace again (gather.wgsl RetraceList): the indirect dispatch's workgroups
// (64 pixels each; y and z are 1 from the header each frame starts with, pixels.rs
// RetraceList) and how many were listed, then their pixels (x | y << 16). `retrace.x`: the
// list's capacity (0: none listed); `retrace.y`: the likeness below which a pixel is listed.
struct RetraceListOut {
    groups: atomic<u32>,
    groups_y: u32,
    groups_z: u32,
    count: atomic<u32>,
    pixels: array<u32>,
}

@group(2) @binding(5) var<storage, read_write> retrace_list: RetraceListOut;
@group(2) @binding(6) var<uniform> retrace: vec4f;

// Lists `pixel` for a trace of its own, if the list has room.
fn list_for_retrace(pixel: vec2i) {
    let i = atomicAdd(&retrace_list.count, 1u);
    if (i >= u32(retrace.x)) { return; }
    retrace_list.pixels[i] = u32(pixel.x) | (u32(pixel.y) << 16u);
    atomicMax(&retrace_list.groups, i / 64u + 1u);
}

fn add_texel(sum: ptr<function, Traced>, t: vec2i, w: f32) {
    (*sum).e_rv += w * textureLoad(traced_rv, t, 0).rgb;
    (*sum).e_r += w * textureLoad(traced_r, t, 0).rgb;
    (*sum).env_rv += w * textureLoad(traced_env_rv, t, 0).rgb;
    (*sum).env_r += w * textureLoad(traced_env_r, t, 0).rgb;
    (*sum).env += w * textureLoad(traced_env_weight, t, 0).rgb;
    (*sum).glossy_rv += w * textureLoad(traced_glossy_rv, t, 0).rgb;
    (*sum).glossy_r += w * textureLoad(traced_glossy_r, t, 0).rgb;
}

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id.xy >= frame.size.xy)) { return; }
    let pixel = vec2i(id.xy);
    let flags = textureLoad(gbuffer_flags, pixel, 0).r;
    if (!is_covered(flags)) {
        store_no_indirect(pixel);
        return;
    }
    let depth = textureLoad(gbuffer_depth_motion, pixel, 0).x;
    let n = textureLoad(gbuffer_normal_roughness, pixel, 0).xyz;
    let scale = trace_scale();
    let centre = pixel / scale;
    // The texels within one either side, by a tent one and a half blocks wide around the pixel.
    let reach = select(1, 0, scale == 1);
    let radius = 1.5 * f32(scale);
    var sum = Traced(vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0), vec3f(0.0));
    var total = 0.0;
    var likest = 0.0;
    for (var dy = -reach; dy <= reach; dy++) {
        for (var dx = -reach; dx <= reach; dx++) {
            let t = centre + vec2i(dx, dy);
            if (any(t < vec2i(0)) || any(t >= trace_size())) { continue; }
            let q = representative(t);
            if (q.x < 0) { continue; }
            let spatial = max(0.0, 1.0 - length(vec2f(q - pixel)) / radius);
            let depth_q = textureLoad(gbuffer_depth_motion, q, 0).x;
            let n_q = textureLoad(gbuffer_normal_roughness, q, 0).xyz;
            let own = all(q == pixel);
            let alike = select(geometry_weight(depth, n, depth_q, n_q), 1.0, own);
            likest = max(likest, alike);
            let w = select(spatial * alike, 1.0, own);
            if (w <= 0.0) { continue; }
            add_texel(&sum, t, w);
            total += w;
        }
    }
    if (likest < retrace.y) { list_for_retrace(pixel); }
    if (total <= 0.0) {
        // No texel like it around (a sliver of surface between edges): its own block's.
        add_texel(&sum, centre, 1.0);
        total = 1.0;
    }
    let inv = 1.0 / total;
    let t = Traced(sum.e_rv * inv, sum.e_r * inv, sum.env_rv * inv, sum.env_r * inv, sum.env * inv, sum.glossy_rv * inv, sum.glossy_r * inv);
    store_pixel_light(pixel, flags, t);
}
