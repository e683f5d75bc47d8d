//! The proxy scene as world-space triangles in one BVH (obvhs' compressed wide BVH), with the
//! two queries differential path tracing needs: the nearest hit in the world with or without
//! the virtual objects, and shadow-ray visibility in both worlds at once.
//!
//! Both worlds share one BVH. The real-only world skips virtual triangles during traversal,
//! so where a ray meets no virtual triangle both queries run the same arithmetic and return
//! the same bits: the exact invariant of differential rendering (no virtual content ⇒
//! `L_rv = L_r`) holds per path, not only on average.

use crate::texture::sample_alpha;
use glam::{Vec2, Vec3, Vec3A};
use mrshade_core::Differential;
use mrshade_core::flags::Realness;
use mrshade_scene::{AlphaMode, Scene};
use obvhs::{
    BvhBuildParams,
    aabb::Aabb,
    cwbvh::{CwBvh, builder::build_cwbvh},
    ray::{Ray, RayHit},
    triangle::Triangle as BvhTriangle,
};

/// One world-space triangle with what shading needs.
#[derive(Clone, Debug)]
pub struct Triangle {
    /// Corner positions.
    pub p: [Vec3; 3],
    /// Unit vertex normals (world space).
    pub n: [Vec3; 3],
    /// Texture coordinates.
    pub uv: [Vec2; 3],
    /// World-space directions of increasing u and of decreasing v (glTF's v runs down the
    /// image; a normal map's +y points up it), for normal maps; zero where the uvs are degenerate.
    pub tangents: [Vec3; 2],
    /// Index into `Scene::materials`.
    pub material: usize,
    /// Whether the triangle is part of the real proxy or inserted.
    pub realness: Realness,
}

/// A ray–scene intersection.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    /// Distance along the (unit) ray direction.
    pub t: f32,
    /// Index into [`Geometry::triangles`].
    pub triangle: usize,
    /// Barycentric weights of corners 1 and 2.
    pub bary: Vec2,
}

/// Which objects a query sees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum World {
    /// Real proxy and virtual objects: the world of `L_rv`.
    RealAndVirtual,
    /// Real proxy only: the world of `L_r`.
    RealOnly,
}

/// The scene's triangles and their BVH.
pub struct Geometry {
    /// All triangles, in BVH order is not assumed: `bvh.primitive_indices` maps.
    pub triangles: Vec<Triangle>,
    bvh: Option<CwBvh>,
    alpha_cutoff: Vec<Option<f32>>,
}

/// The box the BVH is built over for triangle `index`: its bounds grown by a tiny amount that
/// differs from triangle to triangle. PLOC (obvhs) merges only mutual nearest neighbours;
/// copies of one triangle at one place cost the same everywhere, which leaves one merge per
/// pass (20,000 coincident quads from a hostile glTF took a minute). Different paddings break
/// the ties. The boxes only grow, so traversal still finds every triangle it must test.
fn tie_breaking_box(t: &Triangle, index: usize) -> Aabb {
    let b = BvhTriangle { v0: t.p[0].into(), v1: t.p[1].into(), v2: t.p[2].into() }.aabb();
    let size = (b.max - b.min).max_element() + b.max.abs().max(b.min.abs()).max_element();
    let fraction = ((index as u32).wrapping_mul(0x9e37_79b1) >> 8) as f32 / (1u32 << 24) as f32;
    let pad = Vec3A::splat(size * 1e-5 * (0.5 + fraction));
    Aabb::new(b.min - pad, b.max + pad)
}

impl Geometry {
    /// Flattens every instance of `scene` into world space and builds the BVH.
    pub fn new(scene: &Scene) -> Geometry {
        let mut triangles = Vec::new();
        for inst in &scene.instances {
            let prim = &scene.primitives[inst.primitive];
            let normal_from_object = mrshade_core::math::normal_from_object(inst.world_from_object);
            // A mirroring transform flips the winding; normals stay as the file gives them.
            for tri in prim.indices.chunks_exact(3) {
                let idx = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
                let p = idx.map(|i| inst.world_from_object.transform_point3(prim.positions[i]));
                let n = idx.map(|i| normal_from_object.transform_vector3(prim.normals[i]).normalize_or_zero());
                let uv = idx.map(|i| prim.uvs[i]);
                let tangents = uv_tangents(p, uv);
                triangles.push(Triangle { p, n, uv, tangents, material: prim.material, realness: inst.realness });
            }
        }
        let alpha_cutoff = scene
            .materials
            .iter()
            .map(|m| match m.alpha_mode {
                AlphaMode::Mask(cutoff) => Some(cutoff),
                _ => None,
            })
            .collect();
        let bvh = (!triangles.is_empty()).then(|| {
            let boxes: Vec<Aabb> = triangles.iter().enumerate().map(|(i, t)| tie_breaking_box(t, i)).collect();
            build_cwbvh(&boxes, BvhBuildParams::medium_build(), &mut Default::default())
        });
        Geometry { triangles, bvh, alpha_cutoff }
    }

    /// The nearest hit of the ray `origin + t·dir`, `t ∈ (0, t_max)`, in `world`.
    pub fn intersect(&self, scene: &Scene, origin: Vec3, dir: Vec3, t_max: f32, world: World) -> Option<Hit> {
        let bvh = self.bvh.as_ref()?;
        let ray = Ray::new(Vec3A::from(origin), positive_zeros(dir), 0.0, t_max);
        let mut hit = RayHit::none();
        let mut bary = Vec2::ZERO;
        bvh.ray_traverse(ray, &mut hit, |ray, id| {
            let index = bvh.primitive_indices[id] as usize;
            match self.test(scene, index, ray, world) {
                Some((t, b)) if t < ray.tmax => {
                    bary = b;
                    t
                }
                _ => f32::INFINITY,
            }
        });
        (hit.t < t_max).then(|| Hit {
            t: hit.t,
            triangle: bvh.primitive_indices[hit.primitive_id as usize] as usize,
            bary,
        })
    }

    /// Whether the segment `origin + t·dir`, `t ∈ (0, t_max)`, is free of real triangles (`r`)
    /// and of any triangles (`rv`). Both answers come from one traversal: it stops at the first
    /// real blocker and otherwise remembers whether it passed a virtual one.
    pub fn visibility(&self, scene: &Scene, origin: Vec3, dir: Vec3, t_max: f32) -> Differential<bool> {
        let Some(bvh) = self.bvh.as_ref() else { return Differential { rv: true, r: true } };
        let ray = Ray::new(Vec3A::from(origin), positive_zeros(dir), 0.0, t_max);
        let mut virtual_blocker = false;
        let free_of_real = bvh.ray_traverse_miss(ray, |ray, id| {
            let index = bvh.primitive_indices[id] as usize;
            match self.test(scene, index, ray, World::RealAndVirtual) {
                Some((t, _)) if self.triangles[index].realness == Realness::Real => t,
                Some(_) => {
                    virtual_blocker = true;
                    f32::INFINITY
                }
                None => f32::INFINITY,
            }
        });
        Differential { rv: free_of_real && !virtual_blocker, r: free_of_real }
    }

    /// Ray–triangle test (Möller–Trumbore, both faces) with the world filter and alpha masks.
    fn test(&self, scene: &Scene, index: usize, ray: &Ray, world: World) -> Option<(f32, Vec2)> {
        let tri = &self.triangles[index];
        if world == World::RealOnly && tri.realness == Realness::Virtual {
            return None;
        }
        let (t, bary) = intersect_triangle(tri.p, Vec3::from(ray.origin), Vec3::from(ray.direction))?;
        if t <= ray.tmin || t >= ray.tmax {
            return None;
        }
        if let Some(cutoff) = self.alpha_cutoff[tri.material] {
            let uv = interpolate(tri.uv, bary);
            if sample_alpha(scene, &scene.materials[tri.material], uv) < cutoff {
                return None;
            }
        }
        Some((t, bary))
    }
}

/// `dir` with every −0.0 component made +0.0. obvhs 0.4 picks a ray's octant by `d < 0` but
/// inverts `d` by its sign bit, so a −0.0 component puts the ray in one octant with the slopes
/// of another and it misses everything: a sun straight down (a −90° rotation about x leaves
/// x = −0.0) shone through every roof.
fn positive_zeros(dir: Vec3) -> Vec3A {
    Vec3A::from(dir) + Vec3A::ZERO
}

/// Möller–Trumbore: distance and barycentrics (of corners 1, 2) of the hit, both faces.
pub fn intersect_triangle(p: [Vec3; 3], origin: Vec3, dir: Vec3) -> Option<(f32, Vec2)> {
    let e1 = p[1] - p[0];
    let e2 = p[2] - p[0];
    let q = dir.cross(e2);
    let det = e1.dot(q);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - p[0];
    let b1 = s.dot(q) * inv;
    if !(0.0..=1.0).contains(&b1) {
        return None;
    }
    let r = s.cross(e1);
    let b2 = dir.dot(r) * inv;
    if b2 < 0.0 || b1 + b2 > 1.0 {
        return None;
    }
    let t = e2.dot(r) * inv;
    (t > 0.0).then_some((t, Vec2::new(b1, b2)))
}

/// Barycentric interpolation of three corner values.
pub fn interpolate<T>(v: [T; 3], bary: Vec2) -> T
where
    T: std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T> + Copy,
{
    v[0] * (1.0 - bary.x - bary.y) + v[1] * bary.x + v[2] * bary.y
}

/// The world-space directions of increasing u and decreasing v over the triangle (zero if the
/// uvs are degenerate).
fn uv_tangents(p: [Vec3; 3], uv: [Vec2; 3]) -> [Vec3; 2] {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let det = d1.x * d2.y - d1.y * d2.x;
    if det.abs() < 1e-12 {
        return [Vec3::ZERO; 2];
    }
    let along_u = (e1 * d2.y - e2 * d1.y) / det;
    let along_v = (e2 * d1.x - e1 * d2.x) / det;
    [along_u.normalize_or_zero(), -along_v.normalize_or_zero()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_hit_has_the_right_distance_and_barycentrics() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let (t, b) = intersect_triangle(p, Vec3::new(0.25, 0.5, 2.0), Vec3::NEG_Z).unwrap();
        assert!((t - 2.0).abs() < 1e-6);
        assert!(b.abs_diff_eq(Vec2::new(0.25, 0.5), 1e-6));
        // From behind too: both faces are hit.
        assert!(intersect_triangle(p, Vec3::new(0.25, 0.25, -1.0), Vec3::Z).is_some());
        assert!(intersect_triangle(p, Vec3::new(0.75, 0.75, 1.0), Vec3::NEG_Z).is_none());
    }

    #[test]
    fn rays_with_negative_zero_components_hit() {
        let mut scene = Scene::default();
        scene.materials.push(Default::default());
        scene.primitives.push(mrshade_scene::Primitive {
            positions: vec![Vec3::new(-1.0, 2.0, -1.0), Vec3::new(1.0, 2.0, -1.0), Vec3::new(0.0, 2.0, 1.0)],
            normals: vec![Vec3::Y; 3],
            uvs: vec![Vec2::ZERO; 3],
            indices: vec![0, 1, 2],
            ..Default::default()
        });
        scene.instances.push(mrshade_scene::Instance {
            node_name: "t".into(),
            primitive: 0,
            world_from_object: glam::Mat4::IDENTITY,
            realness: Realness::Real,
            skin: None,
            morph_weights: Vec::new(),
        });
        let g = Geometry::new(&scene);
        for dir in [Vec3::new(-0.0, 1.0, 0.0), Vec3::new(0.0, 1.0, -0.0), Vec3::new(-0.0, 1.0, -0.0)] {
            assert!(g.intersect(&scene, Vec3::ZERO, dir, f32::INFINITY, World::RealAndVirtual).is_some(), "{dir:?}");
            assert_eq!(g.visibility(&scene, Vec3::ZERO, dir, f32::INFINITY), Differential { rv: false, r: false });
        }
    }

    #[test]
    fn tangent_follows_u() {
        let [t, b] = uv_tangents([Vec3::ZERO, Vec3::Z * 2.0, Vec3::X], [Vec2::ZERO, Vec2::X, Vec2::Y]);
        assert!(t.abs_diff_eq(Vec3::Z, 1e-6) && b.abs_diff_eq(Vec3::NEG_X, 1e-6));
    }
}
