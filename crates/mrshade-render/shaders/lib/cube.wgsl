// Cube maps (point lights' shadow maps, the specular stage's cubes): six faces in the order
// +X, −X, +Y, −Y, +Z, −Z, as `scene_gpu::cube_faces` builds them.

// Which of the six cube faces sees direction `d`.
fn cube_face(d: vec3f) -> u32 {
    let a = abs(d);
    if (a.x >= a.y && a.x >= a.z) { return select(1u, 0u, d.x > 0.0); }
    if (a.y >= a.z) { return select(3u, 2u, d.y > 0.0); }
    return select(5u, 4u, d.z > 0.0);
}
