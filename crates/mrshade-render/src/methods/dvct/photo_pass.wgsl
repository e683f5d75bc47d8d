// The photo's light in the real voxels (photo.wgsl) as a pass of its own after the second
// bounce: each voxel's light as the bounce left it (`raw_*`), with the photo's in place of a
// seen real surface's own, into the volumes the pixels' cones read. A new photo or camera
// (footage, a stream) runs this pass and the mipmaps again, not the bounce.

@group(1) @binding(0) var raw_rv: texture_3d<f32>;
@group(1) @binding(1) var raw_r: texture_3d<f32>;

// Group 2: the frame, the G-buffer and the photo (photo.wgsl); the probe's and the material
// textures' bindings 0–6 are not read here (the voxel's point is enough, not its albedo).
@group(2) @binding(7) var<uniform> frame: Frame;

@group(3) @binding(0) var out_rv: texture_storage_3d<rgba16float, write>;
@group(3) @binding(1) var out_r: texture_storage_3d<rgba16float, write>;

@compute @workgroup_size(4, 4, 4)
fn cs_main(@builtin(global_invocation_id) id: vec3u) {
    if (any(id >= vec3u(params.info.x))) { return; }
    let index = voxel_index(id);
    var rv = textureLoad(raw_rv, id, 0);
    var r = textureLoad(raw_r, id, 0);
    let real = voxels[index * 2u];
    if (real != 0u) {
        let d = load_triangle(voxel_triangle(real));
        let at = voxel_point(d, instances[d.instance], voxel_centre(id));
        let seen = with_photo(rv, r, at.position, at.normal);
        r = seen[1];
        // A voxel that holds a virtual surface shows it in the real+virtual volume.
        if (voxels[index * 2u + 1u] == 0u) { rv = seen[0]; }
    }
    textureStore(out_rv, id, rv);
    textureStore(out_r, id, r);
}
