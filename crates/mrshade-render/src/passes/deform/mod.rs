//! Deformation pass: skinned and morphing instances (glTF 2.0 §3.7.3, §3.7.2.2) deformed on
//! the GPU into the scene's vertex buffer, first in the frame, so that every pass that reads
//! geometry (shadow maps, G-buffer, RSMs, the ISMs' point clouds drawn from it) sees the
//! deformed surface. It runs only when a deformation changed (a still deforms once).
//!
//! Inputs: the rest vertices, joints and weights, and morph displacements of every deformed
//! instance (uploaded once), this frame's joint matrices and morph weights
//! ([`mrshade_scene::Deformation`] per instance). Output: `scene/vertices`.

use crate::scene_gpu::Vertex;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec4, Vec3, Vec4};
use mrshade_core::math::bounding_box;
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, bind, wgsl};
use mrshade_scene::{Deformation, Primitive, Scene, deform_vertices};
use wgpu::util::DeviceExt;

/// The pass's WGSL.
pub const SHADER: &str = wgsl!("deform.wgsl");

/// Mirrors `struct Range` in deform.wgsl: one deformed instance.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuRange {
    /// First vertex of the range in the pass's own per-vertex buffers.
    pub first: u32,
    /// Its vertex count.
    pub count: u32,
    /// Its first vertex in the scene's vertex buffer.
    pub destination: u32,
    /// First joint matrix, or `u32::MAX` when not skinned.
    pub joint_base: u32,
    /// First morph weight.
    pub weight_base: u32,
    /// Morph targets.
    pub target_count: u32,
    /// First displacement (position and normal pairs).
    pub delta_base: u32,
    _pad: u32,
}

const NOT_SKINNED: u32 = u32::MAX;

/// What one deformed instance needs per frame: where its joint matrices and weights go.
struct Slot {
    instance: usize,
    /// Its primitive, for its bounds once deformed.
    primitive: Primitive,
    joint_base: usize,
    joint_count: usize,
    weight_base: usize,
    weight_count: usize,
}

/// The pass, present only when the scene has deformed instances.
pub struct DeformPass {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    joints: wgpu::Buffer,
    weights: wgpu::Buffer,
    slots: Vec<Slot>,
    vertex_count: u32,
    /// The last deformation uploaded per deformed instance (to skip unchanged frames).
    current: Vec<Deformation>,
    pending: bool,
}

impl DeformPass {
    /// GPU timing label.
    pub const LABEL: &'static str = "deform";

    /// Uploads the rest data of `scene`'s deformed instances and binds `vertices` (the
    /// scene's vertex buffer, in which instance `i`'s primitive starts at
    /// `base_vertex[primitive]`); `None` when nothing deforms.
    pub fn new(ctx: &GpuContext, scene: &Scene, base_vertex: &[u32], vertices: &wgpu::Buffer) -> Option<Self> {
        let mut rest: Vec<Vertex> = Vec::new();
        let mut skins: Vec<[UVec4; 2]> = Vec::new();
        let mut range_of: Vec<u32> = Vec::new();
        let mut ranges: Vec<GpuRange> = Vec::new();
        let mut deltas: Vec<Vec4> = Vec::new();
        let mut slots = Vec::new();
        let (mut joint_total, mut weight_total) = (0, 0);
        for (i, instance) in scene.instances.iter().enumerate() {
            let p = &scene.primitives[instance.primitive];
            if !p.is_deformable() {
                continue;
            }
            let joint_count = instance.skin.and_then(|s| scene.skins.get(s)).map_or(0, |s| s.joints.len());
            let skinned = joint_count > 0 && !p.skin.is_empty();
            ranges.push(GpuRange {
                first: rest.len() as u32,
                count: p.positions.len() as u32,
                destination: base_vertex[instance.primitive],
                joint_base: if skinned { joint_total as u32 } else { NOT_SKINNED },
                weight_base: weight_total as u32,
                target_count: p.targets.len() as u32,
                delta_base: deltas.len() as u32,
                _pad: 0,
            });
            for v in 0..p.positions.len() {
                rest.push(Vertex { position: p.positions[v].into(), normal: p.normals[v].into(), uv: p.uvs[v].into() });
                let s = p.skin.get(v).copied().unwrap_or_default();
                let joints = UVec4::from(s.joints.map(u32::from));
                skins.push([joints, bytemuck::cast(Vec4::from(s.weights))]);
                range_of.push(ranges.len() as u32 - 1);
            }
            for target in &p.targets {
                for v in 0..p.positions.len() {
                    deltas.push(target.positions.get(v).copied().unwrap_or_default().extend(0.0));
                    deltas.push(target.normals.get(v).copied().unwrap_or_default().extend(0.0));
                }
            }
            let joint_count = if skinned { joint_count } else { 0 };
            slots.push(Slot {
                instance: i,
                primitive: p.clone(),
                joint_base: joint_total,
                joint_count,
                weight_base: weight_total,
                weight_count: p.targets.len(),
            });
            joint_total += joint_count;
            weight_total += p.targets.len();
        }
        if slots.is_empty() {
            return None;
        }
        let device = &ctx.device;
        let storage = |label: &str, contents: &[u8]| {
            // Buffers may not be empty.
            let contents = if contents.is_empty() { &[0u8; 16][..] } else { contents };
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            })
        };
        let rest_buffer = storage("deform/rest", bytemuck::cast_slice(&rest));
        let skins_buffer = storage("deform/skins", bytemuck::cast_slice(&skins));
        let range_buffer = storage("deform/range_of", bytemuck::cast_slice(&range_of));
        let ranges_buffer = storage("deform/ranges", bytemuck::cast_slice(&ranges));
        let deltas_buffer = storage("deform/deltas", bytemuck::cast_slice(&deltas));
        let joints = storage("deform/joints", bytemuck::cast_slice(&vec![Mat4::IDENTITY; joint_total.max(1)]));
        let weights = storage("deform/weights", bytemuck::cast_slice(&vec![0f32; weight_total.max(4)]));
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("deform/params"),
            contents: bytemuck::cast_slice(&[rest.len() as u32, 0, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let cs = wgpu::ShaderStages::COMPUTE;
        let mut entries: Vec<_> = (0..7).map(|b| bind::storage(b, cs)).collect();
        entries.push(bind::storage_rw(7, cs));
        entries.push(bind::uniform(8, cs));
        let layout = bind::layout(device, "deform/layout", &entries);
        let buffers =
            [&rest_buffer, &skins_buffer, &range_buffer, &ranges_buffer, &deltas_buffer, &joints, &weights, vertices];
        let mut resources: Vec<_> = buffers.iter().map(|b| b.as_entire_binding()).collect();
        resources.push(params.as_entire_binding());
        let group = bind::group(device, "deform/group", &layout, &resources);
        let pipeline = mrshade_gpu::shader::compute_pipeline(device, "deform", SHADER, &[&layout]);
        Some(Self {
            pipeline,
            group,
            joints,
            weights,
            slots,
            vertex_count: rest.len() as u32,
            current: Vec::new(),
            pending: true,
        })
    }

    /// Takes this frame's deformations (one per scene instance; the pass runs this frame if
    /// any changed) and returns the object-space box of every instance whose deformation
    /// changed (the pose's, `Deformation::bounds`: shadow maps and VPL sampling fit to them).
    pub fn update(&mut self, queue: &wgpu::Queue, deformations: &[Deformation]) -> Vec<(usize, (Vec3, Vec3))> {
        let wanted: Vec<Deformation> =
            self.slots.iter().map(|s| deformations.get(s.instance).cloned().unwrap_or_default()).collect();
        let mut changed = Vec::new();
        for (k, (slot, d)) in self.slots.iter().zip(&wanted).enumerate() {
            if self.current.get(k) == Some(d) {
                continue;
            }
            // The pose computed the box; a deformation built by hand has none yet.
            let object_box = d.bounds.unwrap_or_else(|| bounding_box(&deform_vertices(&slot.primitive, d).0));
            changed.push((slot.instance, object_box));
            if slot.joint_count > 0 && d.joint_matrices.len() == slot.joint_count {
                let offset = (slot.joint_base * std::mem::size_of::<Mat4>()) as u64;
                queue.write_buffer(&self.joints, offset, bytemuck::cast_slice(&d.joint_matrices));
            }
            if slot.weight_count > 0 && d.morph_weights.len() == slot.weight_count {
                let offset = (slot.weight_base * 4) as u64;
                queue.write_buffer(&self.weights, offset, bytemuck::cast_slice(&d.morph_weights));
            }
        }
        if !changed.is_empty() {
            self.current = wanted;
            self.pending = true;
        }
        changed
    }

    /// Deforms the vertices if a deformation changed since the last frame.
    pub fn record(&mut self, rec: &mut Recorder) {
        if !std::mem::take(&mut self.pending) {
            return;
        }
        rec.compute(Self::LABEL, |pass| {
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.group, &[]);
            mrshade_gpu::shader::dispatch_linear(pass, self.vertex_count, 64);
        });
    }
}
