//! The own triangles of rigid traced instances: a BVH over each one's triangles in its object
//! space, built once on the CPU. Rays leaving an object test it for self-reflections (which
//! impostors cannot show), and refraction is traced exactly through the insides of
//! transmissive ones (`specular.refraction = "traced"`). Wyman's two interfaces (spec §2.12) see one exit and no total
//! internal reflection ("neglected" by the thesis); traced, a ray meets the real back
//! surface, reflects totally where it must and leaves after several internal bounces, as the
//! thesis's future work proposes (GPU ray tracing for concave objects, spec §5.2). Deforming
//! instances keep Wyman's approximation.

use crate::scene_gpu::Geometry;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec4};
use mrshade_scene::Scene;
use obvhs::{BvhBuildParams, bvh2::builder::build_bvh2_from_tris, triangle::Triangle};
use wgpu::util::DeviceExt;

/// Mirrors `BvhNode` in tracing.wgsl: an inner node (`count` 0; children at `first` and
/// `first + 1`) or a leaf (`count` triangles listed from `first`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuBvhNode {
    /// Box minimum (object space).
    pub min: [f32; 3],
    /// Triangle count of a leaf; 0 for an inner node.
    pub count: u32,
    /// Box maximum.
    pub max: [f32; 3],
    /// First child node, or first entry in the triangle list.
    pub first: u32,
}

/// Mirrors `Interior` in tracing.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuInterior {
    /// The instance's inverse transform (rays are traversed in object space).
    pub object_from_world: Mat4,
    /// Root node (`u32::MAX`: none), 1 if the object can see itself (it is not convex), unused…
    pub info: UVec4,
}

/// BVHs of the traced instances' insides, one table entry per instance.
pub struct Interiors {
    /// `GpuBvhNode`s of every BVH.
    pub nodes: wgpu::Buffer,
    /// Global triangle ids, in leaf order.
    pub triangles: wgpu::Buffer,
    /// Their object-space corners (3 `vec4` each), in the same order.
    pub corners: wgpu::Buffer,
    /// `GpuInterior` per instance.
    pub table: wgpu::Buffer,
    roots: Vec<u32>,
    /// Per instance: whether it can reflect itself (not convex).
    concave: Vec<bool>,
}

impl Interiors {
    /// BVHs for `instances` (the rigid ones among them).
    pub fn new(device: &wgpu::Device, scene: &Scene, geometry: &Geometry, instances: &[usize]) -> Self {
        let mut nodes: Vec<GpuBvhNode> = Vec::new();
        let mut triangle_list: Vec<u32> = Vec::new();
        let mut corners: Vec<[f32; 4]> = Vec::new();
        let mut roots = vec![u32::MAX; geometry.instance_count()];
        let mut concave = vec![false; geometry.instance_count()];
        for &i in instances {
            let instance = &scene.instances[i];
            let primitive = &scene.primitives[instance.primitive];
            if primitive.is_deformable() || primitive.indices.len() < 3 {
                continue;
            }
            let (_, first_triangle, _) = geometry.instance_triangles(i);
            concave[i] = !is_convex(&primitive.positions, &primitive.indices);
            let p = |k: u32| primitive.positions[k as usize].into();
            let tris: Vec<Triangle> =
                primitive.indices.chunks_exact(3).map(|t| Triangle { v0: p(t[0]), v1: p(t[1]), v2: p(t[2]) }).collect();
            let bvh = build_bvh2_from_tris(&tris, BvhBuildParams::medium_build(), &mut Default::default());
            let (node_base, list_base) = (nodes.len() as u32, triangle_list.len() as u32);
            roots[i] = node_base;
            for n in &bvh.nodes {
                let leaf = n.prim_count > 0;
                nodes.push(GpuBvhNode {
                    min: n.aabb.min.into(),
                    count: n.prim_count,
                    max: n.aabb.max.into(),
                    first: if leaf { list_base + n.first_index } else { node_base + n.first_index },
                });
            }
            triangle_list.extend(bvh.primitive_indices.iter().map(|&t| first_triangle + t));
            for &t in &bvh.primitive_indices {
                for &v in &primitive.indices[3 * t as usize..3 * t as usize + 3] {
                    corners.push(primitive.positions[v as usize].extend(0.0).to_array());
                }
            }
        }
        let buffer = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            })
        };
        if nodes.is_empty() {
            nodes.push(GpuBvhNode::zeroed());
            triangle_list.push(0);
        }
        if corners.is_empty() {
            corners.push([0.0; 4]);
        }
        let table = pad(interior_table(&roots, &concave, geometry));
        Self {
            nodes: buffer("specular/interior_nodes", bytemuck::cast_slice(&nodes)),
            triangles: buffer("specular/interior_triangles", bytemuck::cast_slice(&triangle_list)),
            corners: buffer("specular/interior_corners", bytemuck::cast_slice(&corners)),
            table: buffer("specular/interiors", bytemuck::cast_slice(&table)),
            roots,
            concave,
        }
    }

    /// Whether instance `i` has a BVH (it is traced and rigid).
    pub fn has(&self, i: usize) -> bool {
        self.roots[i] != u32::MAX
    }

    /// Whether any instance has a BVH.
    pub fn any(&self) -> bool {
        self.roots.iter().any(|&r| r != u32::MAX)
    }

    /// Uploads each instance's current inverse transform.
    pub fn update(&self, queue: &wgpu::Queue, geometry: &Geometry) {
        if self.any() {
            let table = interior_table(&self.roots, &self.concave, geometry);
            queue.write_buffer(&self.table, 0, bytemuck::cast_slice(&table));
        }
    }
}

/// One `GpuInterior` per instance, with its current inverse transform.
fn interior_table(roots: &[u32], concave: &[bool], geometry: &Geometry) -> Vec<GpuInterior> {
    roots
        .iter()
        .zip(concave)
        .enumerate()
        .map(|(i, (&root, &concave))| GpuInterior {
            object_from_world: geometry.transform(i).inverse(),
            info: UVec4::new(root, concave as u32, 0, 0),
        })
        .collect()
}

fn pad(mut table: Vec<GpuInterior>) -> Vec<GpuInterior> {
    if table.is_empty() {
        table.push(GpuInterior::zeroed());
    }
    table
}

/// Whether the mesh lies entirely on one side of each of its triangles' planes (a convex
/// object cannot see itself, so its rays skip the self test). Winding is not trusted.
fn is_convex(positions: &[glam::Vec3], indices: &[u32]) -> bool {
    // Every plane against every vertex: beyond 10⁸ tests (a few tenths of a second) the mesh
    // is taken as concave, which costs only the self test.
    if (indices.len() / 3) as u64 * positions.len() as u64 > 100_000_000 {
        return false;
    }
    let scale = positions.iter().fold(0f32, |m, p| m.max(p.abs().max_element())).max(1e-6);
    let eps = 1e-4 * scale;
    indices.chunks_exact(3).all(|t| {
        let [a, b, c] = [0, 1, 2].map(|k| positions[t[k] as usize]);
        let Some(n) = (b - a).cross(c - a).try_normalize() else { return true };
        let (mut front, mut back) = (false, false);
        positions.iter().all(|p| {
            let d = n.dot(*p - a);
            front |= d > eps;
            back |= d < -eps;
            !(front && back)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn a_box_is_convex_and_a_notched_mesh_is_not() {
        let cube: Vec<Vec3> =
            (0..8).map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, (i >> 2) as f32)).collect();
        let faces = [0, 1, 3, 0, 3, 2, 4, 5, 7, 4, 7, 6];
        assert!(is_convex(&cube, &faces));
        let mut notched = cube.clone();
        notched.push(Vec3::new(0.5, 0.5, 0.5));
        // A face through the inner point has cube corners on both sides.
        assert!(!is_convex(&notched, &[0, 1, 8]));
    }
}
