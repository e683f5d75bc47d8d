//! All primitives in one vertex and one index buffer, a flat triangle table for the compute
//! rasteriser, and per-instance transforms (current and previous frame, for motion vectors).

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec4, Vec3, Vec4};
use mrshade_core::flags::{Realness, SURFACE_REAL};
use mrshade_core::math::{bounding_box, box_corners};
use mrshade_scene::Scene;
use wgpu::util::DeviceExt;

/// Interleaved vertex of every mesh (8 floats; the shaders read it as `array<f32>`).
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

/// Mirrors `struct Instance` in shaders/lib/instance.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuInstance {
    /// Object → world.
    pub world_from_object: Mat4,
    /// Inverse transpose of `world_from_object` (for normals).
    pub normal_from_object: Mat4,
    /// Object → world in the previous frame (for motion vectors).
    pub previous_world_from_object: Mat4,
    /// Material index, surface flag bits (`SURFACE_REAL`), first triangle, triangle count.
    pub info: UVec4,
}

/// Buffers of the scene's geometry.
pub struct Geometry {
    /// All vertices.
    pub vertices: wgpu::Buffer,
    /// All indices (u32).
    pub indices: wgpu::Buffer,
    /// Per triangle: instance, first index, base vertex, unused.
    pub triangles: wgpu::Buffer,
    /// Number of triangles over all instances.
    pub triangle_count: u32,
    /// `GpuInstance` per instance.
    pub instances: wgpu::Buffer,
    /// Realness of every instance.
    pub realness: Vec<Realness>,
    /// First vertex and vertex count of every instance's primitive.
    vertex_ranges: Vec<(usize, usize)>,
    /// First vertex of every primitive in `vertices`.
    pub base_vertex: Vec<u32>,
    static_info: Vec<(UVec4, Mat4)>,
    /// Object-space bounding box of every instance: min, max.
    object_boxes: Vec<(Vec3, Vec3)>,
    current: Vec<Mat4>,
    previous: Vec<Mat4>,
    /// Which kinds of instance differed from `previous` (or deformed) at the last `begin_frame`.
    moved: Moved,
    /// Which kinds of instance a deformation changed since the last `begin_frame`.
    deform_pending: Moved,
    /// Whether one changed before the last `begin_frame` (this frame deforms).
    deformed: bool,
}

impl Geometry {
    /// Uploads the scene's geometry.
    pub fn new(device: &wgpu::Device, scene: &Scene) -> Self {
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        let mut ranges = Vec::new();
        for p in &scene.primitives {
            ranges.push((indices.len() as u32, p.indices.len() as u32, vertices.len() as u32));
            indices.extend_from_slice(&p.indices);
            for i in 0..p.positions.len() {
                vertices.push(Vertex {
                    position: p.positions[i].into(),
                    normal: p.normals[i].into(),
                    uv: p.uvs[i].into(),
                });
            }
        }
        let mut triangles: Vec<UVec4> = Vec::new();
        let mut static_info = Vec::new();
        for (id, inst) in scene.instances.iter().enumerate() {
            let prim = &scene.primitives[inst.primitive];
            let (first_index, index_count, base_vertex) = ranges[inst.primitive];
            let real = if inst.realness == Realness::Real { SURFACE_REAL } else { 0 };
            let first_triangle = triangles.len() as u32;
            for t in 0..index_count / 3 {
                triangles.push(UVec4::new(id as u32, first_index + 3 * t, base_vertex, 0));
            }
            let info = UVec4::new(prim.material as u32, real, first_triangle, index_count / 3);
            static_info.push((info, inst.world_from_object));
        }
        let triangle_count = triangles.len() as u32;
        // Buffers may not be empty; a scene without geometry still renders its probe.
        if vertices.is_empty() {
            vertices.push(Vertex::zeroed());
            indices.push(0);
        }
        if triangles.is_empty() {
            triangles.push(UVec4::ZERO);
        }
        let init = |label: &str, contents: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let current: Vec<Mat4> = static_info.iter().map(|s| s.1).collect();
        let mut geometry = Self {
            // Copied out by `Renderer::read_instance_vertices` (tests of the deformation pass).
            vertices: init("scene/vertices", bytemuck::cast_slice(&vertices), storage | wgpu::BufferUsages::COPY_SRC),
            indices: init("scene/indices", bytemuck::cast_slice(&indices), storage),
            triangles: init("scene/triangles", bytemuck::cast_slice(&triangles), storage),
            triangle_count,
            instances: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("scene/instances"),
                size: (static_info.len().max(1) * std::mem::size_of::<GpuInstance>()) as u64,
                usage: storage | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            realness: scene.instances.iter().map(|i| i.realness).collect(),
            base_vertex: ranges.iter().map(|r| r.2).collect(),
            vertex_ranges: scene
                .instances
                .iter()
                .map(|i| (ranges[i.primitive].2 as usize, scene.primitives[i.primitive].positions.len()))
                .collect(),
            object_boxes: scene
                .instances
                .iter()
                .map(|i| bounding_box(&scene.primitives[i.primitive].positions))
                .collect(),
            previous: current.clone(),
            current,
            moved: Moved::NONE,
            deform_pending: Moved::NONE,
            deformed: false,
            static_info,
        };
        geometry.previous = geometry.current.clone();
        geometry
    }

    /// Moves instance `index` (takes effect at the next frame).
    pub fn set_transform(&mut self, index: usize, world_from_object: Mat4) {
        self.current[index] = world_from_object;
    }

    /// First vertex and vertex count of instance `index`'s primitive in `vertices`.
    pub fn vertex_range(&self, index: usize) -> (usize, usize) {
        self.vertex_ranges[index]
    }

    /// Instance `index` was deformed: its vertices (in its object space) now span
    /// `object_box` (takes effect at the next frame, which counts as moved).
    pub fn set_deformed_box(&mut self, index: usize, object_box: (Vec3, Vec3)) {
        self.object_boxes[index] = object_box;
        self.deform_pending.add(self.realness[index]);
    }

    /// World-space bounding spheres (centre, radius) of the virtual instances, as they will
    /// be rendered.
    pub fn virtual_spheres(&self) -> Vec<Vec4> {
        self.virtual_boxes()
            .map(|((lo, hi), m)| {
                let scale =
                    m.x_axis.truncate().length().max(m.y_axis.truncate().length()).max(m.z_axis.truncate().length());
                m.transform_point3((lo + hi) * 0.5).extend((hi - lo).length() * 0.5 * scale)
            })
            .collect()
    }

    /// World-space box around all virtual instances as they will be rendered (None without
    /// virtual instances).
    pub fn virtual_box(&self) -> Option<(Vec3, Vec3)> {
        self.virtual_boxes().map(|(b, m)| world_box(b, m)).reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
    }

    /// Object box and current transform of every virtual instance.
    fn virtual_boxes(&self) -> impl Iterator<Item = ((Vec3, Vec3), &Mat4)> + '_ {
        self.object_boxes
            .iter()
            .zip(&self.current)
            .zip(&self.realness)
            .filter(|(_, realness)| **realness == Realness::Virtual)
            .map(|((b, m), _)| (*b, m))
    }

    /// Number of instances.
    pub fn instance_count(&self) -> usize {
        self.current.len()
    }

    /// Material index, first triangle and triangle count of instance `index`.
    pub fn instance_triangles(&self, index: usize) -> (u32, u32, u32) {
        let info = self.static_info[index].0;
        (info.x, info.z, info.w)
    }

    /// World-space box of instance `index` as it will be rendered: min, max.
    pub fn world_box(&self, index: usize) -> (Vec3, Vec3) {
        world_box(self.object_boxes[index], &self.current[index])
    }

    /// The transform instance `index` will be rendered with.
    pub fn transform(&self, index: usize) -> Mat4 {
        self.current[index]
    }

    /// Uploads this frame's transforms (with last frame's as "previous") and remembers them.
    pub fn begin_frame(&mut self, queue: &wgpu::Queue) {
        let gpu: Vec<GpuInstance> = self
            .static_info
            .iter()
            .zip(self.current.iter().zip(&self.previous))
            .map(|(&(info, _), (&now, &before))| GpuInstance {
                world_from_object: now,
                normal_from_object: mrshade_core::math::normal_from_object(now),
                previous_world_from_object: before,
                info,
            })
            .collect();
        if !gpu.is_empty() {
            queue.write_buffer(&self.instances, 0, bytemuck::cast_slice(&gpu));
        }
        let mut moved = std::mem::take(&mut self.deform_pending);
        self.deformed = moved.any();
        for ((now, before), &realness) in self.current.iter().zip(&self.previous).zip(&self.realness) {
            if now != before {
                moved.add(realness);
            }
        }
        self.moved = moved;
        self.previous.clone_from(&self.current);
    }

    /// Whether this frame deforms vertices (a skinned or morphing instance changed pose).
    pub fn deformed(&self) -> bool {
        self.deformed
    }

    /// Whether an instance moved between the last two frames.
    pub fn moved(&self) -> bool {
        self.moved.any()
    }

    /// Which kinds of instance moved (or deformed) between the last two frames: views that
    /// see only real casters stay as they were when only virtual instances moved.
    pub fn moved_casters(&self) -> Moved {
        self.moved
    }
}

/// Which kinds of caster (real, virtual) moved or deformed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Moved {
    real: bool,
    inserted: bool,
}

impl Moved {
    /// Nothing moved.
    pub const NONE: Self = Self { real: false, inserted: false };
    /// Everything counts as moved (a light or a view's projection changed).
    pub const ALL: Self = Self { real: true, inserted: true };

    /// Instances of `realness` moved too.
    pub fn add(&mut self, realness: Realness) {
        match realness {
            Realness::Real => self.real = true,
            Realness::Virtual => self.inserted = true,
        }
    }

    /// Whether instances of `realness` moved.
    pub fn of(self, realness: Realness) -> bool {
        match realness {
            Realness::Real => self.real,
            Realness::Virtual => self.inserted,
        }
    }

    /// Whether anything moved.
    pub fn any(self) -> bool {
        self.real || self.inserted
    }

    /// What moved in either.
    pub fn union(self, other: Self) -> Self {
        Self { real: self.real || other.real, inserted: self.inserted || other.inserted }
    }
}

/// The world box around object box `(lo, hi)` moved by `m`.
fn world_box(object_box: (Vec3, Vec3), m: &Mat4) -> (Vec3, Vec3) {
    box_corners(object_box).iter().fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(a, b), &c| {
        let p = m.transform_point3(c);
        (a.min(p), b.max(p))
    })
}
