// The second bounce (beyond Franke §2.13.9, whose single bounce leaves "the unlit side
// completely black"): every occupied voxel gathers the first bounce through the nine diffuse
// cones of its surface and adds ρ/π·E to its first-bounce radiance, into the volumes the
// pixels' cones then read. The probe's light reaches a voxel here, shadowed by the same
// cones (the first bounce left it out: unshadowed, it lit the inside of a closed box). Real
// voxels the camera sees then take the photo's light in a pass of its own (photo_pass.wgsl).

// Group 1: the volumes (cones.wgsl).

@group(2) @binding(0) var env_radiance: texture_2d<f32>;
@group(2) @binding(1) var env_irradiance: texture_2d<f32>;
@group(2) @binding(2) var env_dfg_table: texture_2d<f32>;
@group(2) @binding(3) var env_sampler: sampler;
@group(2) @binding(4) var textures_srgb: texture_2d_array<f32>;
@group(2) @binding(5) var textures_linear: texture_2d_array<f32>;
@group(2) @binding(6) var texture_sampler: sampler;
@group(2) @binding(7) var<uniform> frame: Frame;

@group(3) @binding(0) var out_rv: texture_storage_3d<rgba16float, write>;
@group(3) @binding(1) var out_r: texture_storage_3d<rgba16float, write>;

@compute @workgroup_size(4, 4, 4)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id >= vec3u(params.info.x))) { return; }
    let index = voxel_index(id);
    let centre = voxel_centre(id);
    let first_rv = textureLoad(volume_rv, id, 0);
    var rv = first_rv;
    var r = textureLoad(volume_r, id, 0);
    let real = voxels[index * 2u];
    let virt = voxels[index * 2u + 1u];
    if (real != 0u) {
        var s = voxel_surface(voxel_triangle(real), centre);
        // On the side that sends out its light (voxel_surface.wgsl).
        s.normal = sending_side(s);
        // Turning the voxels' cones by voxel changed nothing (their mipmaps blend them anyway).
        let e = gather_diffuse(s.position, s.normal, bounce_spacing(), 0.0);
        rv += vec4f(s.albedo / PI * (e.rv + e.env_rv), 0.0);
        r += vec4f(s.albedo / PI * (e.r + e.env_r), 0.0);
    }
    if (virt != 0u) {
        let s = voxel_surface(voxel_triangle(virt), centre);
        let e = gather_diffuse(s.position, s.normal, bounce_spacing(), 0.0);
        rv = vec4f(first_rv.rgb + s.albedo / PI * (e.rv + e.env_rv), 1.0);
    }
    textureStore(out_rv, id, rv);
    textureStore(out_r, id, r);
}
