// The surface a voxel holds (surface.wgsl's point) with its diffuse albedo: the base color
// texture prefiltered over about a voxel. The including pass declares textures_srgb,
// textures_linear and texture_sampler.

struct VoxelSurface {
    position: vec3f,
    normal: vec3f,
    // Diffuse albedo ρ (the part of the base color that is not metal or transmitted).
    albedo: vec3f,
    // Whether the material is double-sided (glTF `doubleSided`).
    double_sided: bool,
}

// The side of a real voxel's surface that sends out its light and gathers the room's: a
// single-sided surface's front (glTF culls its back: the inside of a closed object, a box's
// face that looks away from the virtual content is still the face the room sees), a
// double-sided one's side facing the virtual content (the volume's centre), as `dir`'s VPLs
// take a double-sided surface's brighter side. Every real surface was turned towards the
// centre before: the faces of desk-spot-virtual's real box and book that look away from the
// sphere shone into the box, and the desk in front of them took none of the light its virtual
// lamp sends off them (tests/dvct_cones.rs, 0.4 of the path tracer's).
fn sending_side(s: VoxelSurface) -> vec3f {
    if (!s.double_sided) { return s.normal; }
    return select(-s.normal, s.normal, dot(s.normal, toward_centre(s.position)) >= 0.0);
}

fn voxel_surface(triangle: u32, centre: vec3f) -> VoxelSurface {
    let d = load_triangle(triangle);
    let inst = instances[d.instance];
    let at = voxel_point(d, inst, centre);
    let w = at.weights;
    var s: VoxelSurface;
    s.position = at.position;
    s.normal = at.normal;
    let uv = d.uv[0] * w.x + d.uv[1] * w.y + d.uv[2] * w.z;
    // Texture footprint of a voxel: the triangle's texture extent per metre times a voxel.
    let uv_per_metre = (length(d.uv[1] - d.uv[0]) + length(d.uv[2] - d.uv[0])) / max(at.edges.x + at.edges.y, 1e-9);
    let footprint = vec2f(uv_per_metre * voxel_side(), 0.0);
    let m = materials[inst.info.x];
    s.double_sided = is_double_sided(m);
    let bits = m.texture_info.y;
    let base = m.base_color * sample_slot(true, m.texture_layers.x, bits, 0u, uv, footprint, footprint.yx, vec4f(1.0));
    let mr = sample_slot(false, m.texture_layers.y, bits, 1u, uv, footprint, footprint.yx, vec4f(1.0));
    let metallic = clamp(m.params.x * mr.b, 0.0, 1.0);
    s.albedo = vpl_base_color(m, base.rgb, metallic) * (1.0 - metallic);
    return s;
}
