// Shadow maps: depth of real-only or virtual-only casters seen from a light (one layer per
// pass). Knecht §2.7: separate real and virtual maps avoid double shadowing.

@group(0) @binding(0) var<uniform> layer_clip_from_world: mat4x4f;
@group(0) @binding(1) var<storage, read> instances: array<Instance>;

@vertex
fn vs_main(@location(0) position: vec3f, @builtin(instance_index) instance: u32) -> @builtin(position) vec4f {
    return layer_clip_from_world * instances[instance].world_from_object * vec4f(position, 1.0);
}
