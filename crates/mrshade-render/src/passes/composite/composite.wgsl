// Differential composite (TVCG Eq. 1–2; Knecht §2.1). In linear camera values:
//   virtual pixels: exposure · L_rv
//   real pixels:    photo + α · exposure · (L_rv − L_r),
//                   α = (photo + ε) / (exposure · L_r + ε) per channel, clamped to [0, α_max]
//                   (α = 1 in the additive mode of Debevec).
// With supersampling, each output pixel averages its s×s shading samples: the real samples'
// differences are averaged and added to the photo, then blended with the mean virtual
// sample by virtual coverage. Where nothing virtual changes a pixel the photo passes through
// bit-exactly (difference 0 and coverage 0).

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> params: CompositeParams;
@group(0) @binding(2) var l_rv_texture: texture_2d<f32>;
@group(0) @binding(3) var l_r_texture: texture_2d<f32>;
@group(0) @binding(4) var flags_texture: texture_2d<u32>;
@group(0) @binding(5) var photo_texture: texture_2d<f32>;
// rgb: composite (linear camera value); a: virtual coverage
@group(0) @binding(6) var out_composite: texture_storage_2d<rgba32float, write>;
// rgb: mean α of the real samples
@group(0) @binding(7) var out_alpha: texture_storage_2d<rgba16float, write>;
// The specular stage's light, in camera values: on traced pixels (a = 1) the whole traced
// part on virtual pixels, its difference on real ones; on diffuse pixels (a ≤ 0) the
// caustics, their difference on real ones, and in −a the luminance of the real caustic.
@group(0) @binding(8) var specular_texture: texture_2d<f32>;

@compute @workgroup_size(8, 8)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id.xy >= frame.size.zw)) { return; }
    let pixel = vec2i(id.xy);
    let photo = textureLoad(photo_texture, pixel, 0).rgb;
    let exposure = frame.exposure_env.x;
    let s = i32(frame.counts.z);
    var real_delta = vec3f(0.0);
    var alpha_sum = vec3f(0.0);
    var real_count = 0.0;
    var virtual_sum = vec3f(0.0);
    var virtual_count = 0.0;
    for (var sy = 0; sy < s; sy++) {
        for (var sx = 0; sx < s; sx++) {
            let q = pixel * s + vec2i(sx, sy);
            let flags = textureLoad(flags_texture, q, 0).r;
            let l_rv = textureLoad(l_rv_texture, q, 0).rgb;
            let specular = textureLoad(specular_texture, q, 0);
            if (is_covered(flags) && !is_real(flags)) {
                virtual_sum += exposure * l_rv + specular.rgb;
                virtual_count += 1.0;
            } else {
                let l_r = textureLoad(l_r_texture, q, 0).rgb;
                // A caustic on a real diffuse surface is part of its differential light: α
                // scales it like the rest, so that it takes the photo's texture (the proxy's
                // flat albedo gave it none; desk-glass region FLIP 0.109 → 0.103), and α
                // compares the photo with all the real light, the real caustic's included
                // (else a real caustic that virtual content blocks is taken off the photo
                // times the photo's caustic over L_r's lack of it). A real mirror's or glass's
                // traced difference is not α's: its L_r holds no reflection.
                let traced = specular.a > 0.5;
                let caustic = select(specular.rgb, vec3f(0.0), traced);
                let exposed_l_r = exposure * l_r;
                let real_caustic = select(-specular.a, 0.0, traced);
                // The real caustic's color is unknown here: L_r's (gray on an unlit surface).
                let lum = luminance(exposed_l_r);
                let tint = select(vec3f(1.0), exposed_l_r / max(lum, 1e-6), lum > 1e-6);
                let real_light = exposed_l_r + real_caustic * tint;
                let a = alpha_of(params, photo, real_light);
                real_delta += a * (exposure * (l_rv - l_r) + caustic) + (specular.rgb - caustic);
                alpha_sum += a;
                real_count += 1.0;
            }
        }
    }
    let real_part = photo + real_delta / max(real_count, 1.0);
    var value = real_part;
    let coverage = virtual_count / f32(s * s);
    if (virtual_count > 0.0) {
        value = mix(real_part, virtual_sum / virtual_count, coverage);
    }
    textureStore(out_composite, pixel, vec4f(max(value, vec3f(0.0)), coverage));
    textureStore(out_alpha, pixel, vec4f(alpha_sum / max(real_count, 1.0), 1.0));
}
