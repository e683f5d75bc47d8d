// A placed primitive (mirrors `GpuInstance` in src/scene_gpu/geometry.rs; checked by a test).
struct Instance {
    world_from_object: mat4x4f,
    normal_from_object: mat4x4f,
    previous_world_from_object: mat4x4f,
    // material, surface flag bits, first triangle, triangle count
    info: vec4u,
}
