// Split injection (Franke §2.13.2 step 2), per voxel rather than per RSM texel: the first
// bounce of both solutions is the voxel's diffuse radiance ρ/π·E under the punctual lights,
// shadowed as the frame's direct light is (Knecht Eq. 5.1–5.2: min(V_r, V_v) for L_rv,
// r(pl)·V_r for L_r), plus, with a single bounce, the probe's unshadowed irradiance (with two,
// the second bounce's cones shadow it). The real+virtual volume holds the
// virtual surface where a voxel has one, else the real one; the real-only volume only real
// surfaces. Their difference is the thesis's V_Δ = V_ρ − V_μ, exactly (§2.13.2: "identical to
// the differential"), with no RSM texels racing for a voxel. Premultiplied: rgb·α, α = 1.
// Real voxels the camera sees then take the photo's light (photo.wgsl), and each voxel's
// normal is kept for the mipmaps (mips.wgsl `facing`).

@group(1) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(1) var<uniform> shadow_params: ShadowParams;
@group(1) @binding(2) var<storage, read> lights: array<Light>;
@group(1) @binding(3) var<storage, read> shadow_clip_from_world: array<mat4x4f>;
@group(1) @binding(4) var<storage, read> shadow_texels: array<vec2u>;

@group(2) @binding(0) var env_radiance: texture_2d<f32>;
@group(2) @binding(1) var env_irradiance: texture_2d<f32>;
@group(2) @binding(2) var env_dfg_table: texture_2d<f32>;
@group(2) @binding(3) var env_sampler: sampler;
@group(2) @binding(4) var textures_srgb: texture_2d_array<f32>;
@group(2) @binding(5) var textures_linear: texture_2d_array<f32>;
@group(2) @binding(6) var texture_sampler: sampler;

@group(3) @binding(0) var out_rv: texture_storage_3d<rgba16float, write>;
@group(3) @binding(1) var out_r: texture_storage_3d<rgba16float, write>;
// The side of each solution's surface that sends out its light (mips.wgsl reads it).
@group(3) @binding(2) var normal_rv: texture_storage_3d<rgba8snorm, write>;
@group(3) @binding(3) var normal_r: texture_storage_3d<rgba8snorm, write>;

struct Radiance {
    rv: vec3f,
    r: vec3f,
}

fn first_bounce(s: VoxelSurface) -> Radiance {
    var e = Radiance(vec3f(0.0), vec3f(0.0));
    for (var i = 0u; i < frame.counts.x; i++) {
        let light = lights[i];
        let incident = light_incident(light, s.position);
        // Two-sided: with no viewer to pick the side, the lit side is the light's (a wall
        // whose normal faces out of a room is lit inside; a closed object's inner side is
        // shadowed by its outer one).
        let n = select(-s.normal, s.normal, dot(s.normal, incident.l) >= 0.0);
        let e_o = incident.radiance * dot(n, incident.l);
        if (all(e_o == vec3f(0.0))) { continue; }
        let v_r = shadow_visibility(light, light.info.y, s.position, n);
        let v_v = shadow_visibility(light, light.info.w, s.position, n);
        e.rv += e_o * min(v_r, v_v);
        e.r += e_o * light.direction_real.w * v_r;
    }
    let single = (params.info.w & VOLUME_SINGLE_BOUNCE) != 0u;
    let probe = select(vec3f(0.0), env_irradiance_at(frame, s.normal), single);
    return Radiance(s.albedo / PI * (e.rv + probe), s.albedo / PI * (e.r + probe));
}

@compute @workgroup_size(4, 4, 4)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id >= vec3u(params.info.x))) { return; }
    let index = voxel_index(id);
    let centre = voxel_centre(id);
    var rv = vec4f(0.0);
    var r = vec4f(0.0);
    var n_r = vec3f(0.0);
    let real = voxels[index * 2u];
    let virt = voxels[index * 2u + 1u];
    if (real != 0u) {
        let s = voxel_surface(voxel_triangle(real), centre);
        // The side of the real surface that sends out its light, as the second bounce gathers
        // on it (bounce.wgsl).
        n_r = sending_side(s);
        let lit = first_bounce(s);
        rv = vec4f(lit.rv, 1.0);
        r = vec4f(lit.r, 1.0);
        // Real voxels the camera sees take the photo's light (with `dvct.photo_voxels`), also
        // when a second bounce follows: the virtual surfaces' cones there gather the room as
        // bright as the camera sees it, not its first bounce alone (a cornell wall's direct
        // light is a fraction of what the photo shows: the blocks' faces took 80–90 % of the
        // answer's light). The photo pass puts the photo in again after that bounce.
        let seen = with_photo(rv, r, s.position, s.normal);
        rv = seen[0];
        r = seen[1];
    }
    var n_rv = n_r;
    if (virt != 0u) {
        let s = voxel_surface(voxel_triangle(virt), centre);
        rv = vec4f(first_bounce(s).rv, 1.0);
        n_rv = s.normal;
    }
    textureStore(out_rv, id, rv);
    textureStore(out_r, id, r);
    textureStore(normal_rv, id, vec4f(n_rv, 0.0));
    textureStore(normal_r, id, vec4f(n_r, 0.0));
}
