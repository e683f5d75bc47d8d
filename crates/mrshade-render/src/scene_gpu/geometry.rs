//! All primitives in one vertex and one index buffer; one draw per instance.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec4};
use mrshade_core::flags::{Realness, SURFACE_REAL};
use mrshade_scene::Scene;
use wgpu::util::DeviceExt;

/// Interleaved vertex of every mesh.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Vertex {
    /// Object-space position.
    pub position: [f32; 3],
    /// Object-space unit normal.
    pub normal: [f32; 3],
    /// `TEXCOORD_0`.
    pub uv: [f32; 2],
}

impl Vertex {
    /// The vertex buffer layout of `shaders` (locations 0, 1, 2).
    pub const LAYOUT: wgpu::VertexBufferLayout<'static> = wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2],
    };
}

/// Mirrors `struct Instance` in gbuffer.wgsl / shadow.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuInstance {
    /// Object → world.
    pub world_from_object: Mat4,
    /// Inverse transpose of `world_from_object` (for normals).
    pub normal_from_object: Mat4,
    /// Material index, surface flag bits (`SURFACE_REAL`), unused, unused.
    pub info: UVec4,
}

/// One indexed draw: an instance of a primitive.
#[derive(Clone, Debug)]
pub struct Draw {
    /// First index in the shared index buffer.
    pub first_index: u32,
    /// Number of indices.
    pub index_count: u32,
    /// Added to every index.
    pub base_vertex: i32,
    /// Index into the instance buffer (passed as the draw's instance index).
    pub instance: u32,
    /// Material index.
    pub material: usize,
    /// Real or virtual: decides which shadow maps it casts into.
    pub realness: Realness,
}

/// Vertex, index and instance buffers plus the draw list (sorted by material).
pub struct Geometry {
    /// All vertices.
    pub vertices: wgpu::Buffer,
    /// All indices (u32).
    pub indices: wgpu::Buffer,
    /// `GpuInstance` per draw.
    pub instances: wgpu::Buffer,
    /// Draws, sorted by material.
    pub draws: Vec<Draw>,
}

impl Geometry {
    /// Uploads the scene's geometry.
    pub fn new(device: &wgpu::Device, scene: &Scene) -> Self {
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        let mut ranges = Vec::new();
        for p in &scene.primitives {
            ranges.push((indices.len() as u32, p.indices.len() as u32, vertices.len() as i32));
            indices.extend_from_slice(&p.indices);
            for i in 0..p.positions.len() {
                vertices.push(Vertex {
                    position: p.positions[i].into(),
                    normal: p.normals[i].into(),
                    uv: p.uvs[i].into(),
                });
            }
        }
        let mut instances = Vec::new();
        let mut draws = Vec::new();
        for inst in &scene.instances {
            let prim = &scene.primitives[inst.primitive];
            let (first_index, index_count, base_vertex) = ranges[inst.primitive];
            let real = if inst.realness == Realness::Real { SURFACE_REAL } else { 0 };
            draws.push(Draw {
                first_index,
                index_count,
                base_vertex,
                instance: instances.len() as u32,
                material: prim.material,
                realness: inst.realness,
            });
            instances.push(GpuInstance {
                world_from_object: inst.world_from_object,
                normal_from_object: inst.world_from_object.inverse().transpose(),
                info: UVec4::new(prim.material as u32, real, 0, 0),
            });
        }
        draws.sort_by_key(|d| d.material);
        // Buffers may not be empty; a scene without geometry still renders its probe.
        if vertices.is_empty() {
            vertices.push(Vertex::zeroed());
            indices.push(0);
        }
        if instances.is_empty() {
            instances.push(GpuInstance::zeroed());
        }
        let init = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        Self {
            vertices: init("scene/vertices", bytemuck::cast_slice(&vertices), wgpu::BufferUsages::VERTEX),
            indices: init("scene/indices", bytemuck::cast_slice(&indices), wgpu::BufferUsages::INDEX),
            instances: init("scene/instances", bytemuck::cast_slice(&instances), wgpu::BufferUsages::STORAGE),
            draws,
        }
    }

    /// Records `draws` (vertex and index buffers bound here).
    pub fn draw<'a>(&self, pass: &mut wgpu::RenderPass<'_>, draws: impl Iterator<Item = &'a Draw>) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        for d in draws {
            pass.draw_indexed(d.first_index..d.first_index + d.index_count, d.base_vertex, d.instance..d.instance + 1);
        }
    }
}
