//! Point clouds for imperfect shadow maps (Knecht §2.9): points distributed uniformly over the
//! surface area of the real (or the virtual) objects, created at load time. Point `i` belongs
//! to VPL `i / points_per_vpl`, so every VPL's ISM is drawn from its own random subset.
//! They are also the candidate VPL positions of the multiple-bounce source (§2.8).

use crate::random::Pcg32;
use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};
use mrshade_core::flags::Realness;
use mrshade_scene::Scene;

/// Mirrors `struct Point` in shaders/lib/ism.wgsl. Object-space, so points follow their
/// instance when it moves.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct GpuPoint {
    /// Object-space position.
    pub position: [f32; 3],
    /// Index of the instance it lies on.
    pub instance: u32,
    /// Object-space unit normal.
    pub normal: [f32; 3],
    /// Material index.
    pub material: u32,
}

/// Where a point lies on a skinned or morphing instance, so that it can follow the
/// deformed surface: its triangle's corners (indices into the primitive's vertices) and the
/// barycentric weights of corners 1 and 2. Mirrors `struct Anchor` in follow.wgsl once the
/// corners are made global (`IsmResources`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct PointAnchor {
    /// Index of the point in its cloud.
    pub point: u32,
    /// The triangle's corners.
    pub corners: [u32; 3],
    /// Barycentric weights of corners 1 and 2.
    pub weights: [f32; 2],
    /// Index of the instance (made the primitive's first vertex when uploaded).
    pub instance: u32,
    _pad: u32,
}

/// The points of one kind of surface.
pub struct PointCloud {
    /// `count` points (empty when no surface of this kind exists).
    pub points: Vec<GpuPoint>,
    /// Anchors of the points on deformable instances.
    pub anchors: Vec<PointAnchor>,
    /// World-space surface area they sample, m².
    pub area: f32,
}

impl PointCloud {
    /// `count` points uniformly distributed over the world-space area of the instances of
    /// `realness` (skinned and morphing ones in their rest pose, with anchors to follow them), in blocks of `points_per_block` (one block per VPL), from a fixed seed
    /// (the same scene gives the same points).
    pub fn new(scene: &Scene, realness: Realness, count: usize, points_per_block: usize) -> Self {
        // Deformable instances are sampled where the rest pose puts their vertices.
        let posed = scene.has_deformations().then(|| scene.posed(&scene.rest_pose()));
        let (source, scene) = (scene, posed.as_ref().unwrap_or(scene));
        // Every triangle of every instance of this kind, with its world-space area.
        let mut triangles: Vec<(usize, usize, f32)> = Vec::new();
        for (i, inst) in scene.instances.iter().enumerate().filter(|(_, i)| i.realness == realness) {
            let p = &scene.primitives[inst.primitive];
            for t in 0..p.indices.len() / 3 {
                let [a, b, c] = [0, 1, 2]
                    .map(|k| inst.world_from_object.transform_point3(p.positions[p.indices[3 * t + k] as usize]));
                triangles.push((i, t, 0.5 * (b - a).cross(c - a).length()));
            }
        }
        let area: f32 = triangles.iter().map(|t| t.2).sum();
        if triangles.is_empty() || area <= 0.0 {
            return Self { points: Vec::new(), anchors: Vec::new(), area: 0.0 };
        }
        let mut cdf = Vec::with_capacity(triangles.len());
        let mut sum = 0.0f64;
        for t in &triangles {
            sum += t.2 as f64;
            cdf.push(sum);
        }
        let mut rng = Pcg32::new(0x6d72_7368_6164_6521 ^ realness as u64);
        // Each VPL's block of points is a stratified sample of the surfaces: stratified along
        // the area CDF (so triangles get points ∝ area), and laid out as a rank-1 lattice
        // (golden-ratio second coordinate) inside each triangle, so that splats of about the
        // point spacing tile the surfaces without holes. Every block has its own random shift.
        const GOLDEN: f64 = 0.618_033_988_749_894_9;
        let block = points_per_block.clamp(1, count.max(1));
        let mut points = Vec::with_capacity(count);
        let mut anchors = Vec::new();
        while points.len() < count {
            let (shift_u, shift_v) = (rng.next_f64(), rng.next_f64());
            for j in 0..block.min(count - points.len()) {
                let pick = (j as f64 + shift_u) / block as f64 * sum;
                let k = cdf.partition_point(|&c| c < pick).min(triangles.len() - 1);
                let (instance, t, tri_area) = triangles[k];
                let before = if k == 0 { 0.0 } else { cdf[k - 1] };
                let u = ((pick - before) / tri_area.max(1e-30) as f64).clamp(0.0, 1.0);
                let v = (j as f64 * GOLDEN + shift_v).fract();
                let inst = &scene.instances[instance];
                let prim = &scene.primitives[inst.primitive];
                let idx = [0, 1, 2].map(|q| prim.indices[3 * t + q] as usize);
                // Area-preserving square → triangle warp.
                let su = u.sqrt() as f32;
                let w = Vec2::new(su * (1.0 - v as f32), su * v as f32);
                let lerp = |a: Vec3, b: Vec3, c: Vec3| a * (1.0 - w.x - w.y) + b * w.x + c * w.y;
                let pos = lerp(prim.positions[idx[0]], prim.positions[idx[1]], prim.positions[idx[2]]);
                let nrm = lerp(prim.normals[idx[0]], prim.normals[idx[1]], prim.normals[idx[2]]).normalize_or(Vec3::Y);
                if source.primitives[source.instances[instance].primitive].is_deformable() {
                    anchors.push(PointAnchor {
                        point: points.len() as u32,
                        corners: idx.map(|i| i as u32),
                        weights: w.into(),
                        instance: instance as u32,
                        _pad: 0,
                    });
                }
                points.push(GpuPoint {
                    position: pos.into(),
                    instance: instance as u32,
                    normal: nrm.into(),
                    material: prim.material as u32,
                });
            }
        }
        Self { points, anchors, area }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;
    use mrshade_scene::{Instance, Primitive};

    /// A unit quad in the XZ plane at the origin, as a real instance.
    pub(super) fn unit_quad() -> Scene {
        let quad = Primitive {
            name: "quad".into(),
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, 1.0), Vec3::Z],
            normals: vec![Vec3::Y; 4],
            uvs: vec![Vec2::ZERO; 4],
            indices: vec![0, 2, 1, 0, 3, 2],
            material: 0,
            ..Default::default()
        };
        let mut s = Scene { primitives: vec![quad], ..Default::default() };
        s.instances.push(Instance {
            node_name: "real".into(),
            primitive: 0,
            world_from_object: Mat4::IDENTITY,
            realness: Realness::Real,
            skin: None,
            morph_weights: Vec::new(),
        });
        s
    }

    fn scene() -> Scene {
        // Two unit quads in the XZ plane: a real one at the origin, a virtual one 3× larger.
        let mut s = unit_quad();
        s.instances.push(Instance {
            node_name: "virtual".into(),
            primitive: 0,
            world_from_object: Mat4::from_scale(Vec3::splat(3.0_f32.sqrt())),
            realness: Realness::Virtual,
            skin: None,
            morph_weights: Vec::new(),
        });
        s
    }

    #[test]
    fn points_cover_the_surfaces_of_their_kind_uniformly() {
        let s = scene();
        let real = PointCloud::new(&s, Realness::Real, 4000, 1000);
        assert!((real.area - 1.0).abs() < 1e-5);
        assert!(real.points.iter().all(|p| p.instance == 0 && p.position[1] == 0.0 && p.normal == [0.0, 1.0, 0.0]));
        // Uniform: each quarter of the quad holds about a quarter of the points.
        let q = real.points.iter().filter(|p| p.position[0] < 0.5 && p.position[2] < 0.5).count();
        assert!((q as f32 / 4000.0 - 0.25).abs() < 0.03, "{q}");
        let virt = PointCloud::new(&s, Realness::Virtual, 100, 100);
        assert!((virt.area - 3.0).abs() < 1e-4);
        assert!(virt.points.iter().all(|p| p.instance == 1));
    }

    #[test]
    fn a_kind_without_surfaces_has_no_points_and_runs_are_reproducible() {
        let mut s = scene();
        s.instances.truncate(1);
        assert!(PointCloud::new(&s, Realness::Virtual, 100, 10).points.is_empty());
        assert_eq!(
            PointCloud::new(&s, Realness::Real, 50, 10).points,
            PointCloud::new(&s, Realness::Real, 50, 10).points
        );
    }
}

#[cfg(test)]
mod stratification {
    use super::*;

    #[test]
    fn every_block_covers_a_quad_evenly() {
        let s = super::tests::unit_quad();
        let cloud = PointCloud::new(&s, Realness::Real, 256 * 3, 256);
        // Each block of 256 points puts 16 ± 6 points into each of the 16 cells of a 4×4 grid
        // (independent random points would vary far more, down to a few).
        for block in cloud.points.chunks(256) {
            let mut cells = [0u32; 16];
            for p in block {
                let cx = ((p.position[0] * 4.0) as usize).min(3);
                let cz = ((p.position[2] * 4.0) as usize).min(3);
                cells[cz * 4 + cx] += 1;
            }
            assert!(cells.iter().all(|&c| (10..=22).contains(&c)), "{cells:?}");
        }
    }
}
