//! Diffuse precomputed radiance transfer with self-shadowing (Franke §2.4, Sloan et al.
//! 2002), baked on the CPU per vertex of a rigid primitive in its object space:
//! `T_i(p) = ∫ V(p, ω) max(0, n·ω) y_i(ω) dω` for the first 9 or 16 SH functions, so that
//! under a distant probe of SH radiance coefficients `c_i` (in the same frame) the irradiance
//! is `E(p) = Σ c_i T_i(p)`. Estimated
//! with `samples` cosine-distributed directions (Hammersley) per vertex, `T_i ≈ π/N Σ V·y_i`,
//! `V` from rays against the primitive's own triangles (obvhs BVH).

use glam::{Vec3, Vec3A};
use mrshade_core::sh::basis16;
use mrshade_scene::Primitive;
use obvhs::{BvhBuildParams, aabb::Aabb, cwbvh::builder::build_cwbvh, ray::Ray, triangle::Triangle as BvhTriangle};
use rayon::prelude::*;
use std::f32::consts::PI;

/// The transfer vectors of `primitive`'s vertices, `coefficients` (9 or 16) floats each, one
/// vertex after the other.
pub fn bake(primitive: &Primitive, samples: u32, coefficients: usize) -> Vec<f32> {
    assert!(coefficients <= 16, "at most 16 SH coefficients");
    let tris: Vec<BvhTriangle> = primitive
        .indices
        .chunks_exact(3)
        .map(|t| {
            let p = |k: u32| primitive.positions[k as usize].into();
            BvhTriangle { v0: p(t[0]), v1: p(t[1]), v2: p(t[2]) }
        })
        .collect();
    let bvh = (!tris.is_empty()).then(|| {
        let boxes: Vec<Aabb> = tris.iter().map(|t| t.aabb()).collect();
        build_cwbvh(&boxes, BvhBuildParams::medium_build(), &mut Default::default())
    });
    let (lo, hi) = mrshade_core::math::bounding_box(&primitive.positions);
    // Rays start a hair off the surface, relative to the object's size.
    let epsilon = (hi - lo).max_element().max(1e-6) * 1e-4;
    let directions: Vec<Vec3> = (0..samples).map(|i| cosine_direction(i, samples)).collect();
    primitive
        .positions
        .par_iter()
        .zip(primitive.normals.par_iter())
        .map(|(&p, &n)| {
            let (t, b) = n.any_orthonormal_pair();
            let mut transfer = vec![0.0f32; coefficients];
            for local in &directions {
                let d = t * local.x + b * local.y + n * local.z;
                let free = bvh.as_ref().is_none_or(|bvh| {
                    let ray = Ray::new(Vec3A::from(p + n * epsilon), Vec3A::from(d) + Vec3A::ZERO, 0.0, f32::INFINITY);
                    bvh.ray_traverse_miss(ray, |ray, id| {
                        let t = tris[bvh.primitive_indices[id] as usize].intersect(ray);
                        if t > ray.tmin && t < ray.tmax { t } else { f32::INFINITY }
                    })
                });
                if free {
                    for (ti, yi) in transfer.iter_mut().zip(basis16(d)) {
                        *ti += yi;
                    }
                }
            }
            transfer.into_iter().map(|t| t * PI / samples as f32).collect::<Vec<_>>()
        })
        .flatten()
        .collect()
}

/// The `i`-th of `n` cosine-distributed directions about +z (Hammersley, Malley's method).
fn cosine_direction(i: u32, n: u32) -> Vec3 {
    let u = (i as f32 + 0.5) / n as f32;
    let v = i.reverse_bits() as f32 * 2.328_306_4e-10;
    let r = u.sqrt();
    let phi = 2.0 * PI * v;
    Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u).max(0.0).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrshade_core::sh::{Sh9, basis16};

    /// An untextured mesh of material 0.
    fn primitive(name: &str, positions: Vec<Vec3>, normals: Vec<Vec3>, indices: Vec<u32>) -> Primitive {
        Primitive {
            name: name.into(),
            uvs: vec![glam::Vec2::ZERO; positions.len()],
            normals,
            positions,
            indices,
            material: 0,
            skin: Vec::new(),
            targets: Vec::new(),
        }
    }

    /// Σ c_i T_i: the irradiance the transfer `t` gives under the probe `c`.
    fn shaded(c: &[Vec3; 16], t: &[f32]) -> Vec3 {
        c.iter().zip(t).map(|(c, t)| *c * *t).sum()
    }

    /// A UV sphere of radius 1 with outward normals.
    fn sphere(rings: u32, segments: u32) -> Primitive {
        let mut positions = Vec::new();
        for r in 0..=rings {
            let theta = PI * r as f32 / rings as f32;
            for s in 0..=segments {
                let phi = 2.0 * PI * s as f32 / segments as f32;
                positions.push(Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()));
            }
        }
        let mut indices = Vec::new();
        let row = segments + 1;
        for r in 0..rings {
            for s in 0..segments {
                let (a, b) = (r * row + s, (r + 1) * row + s);
                indices.extend([a, b, a + 1, a + 1, b, b + 1]);
            }
        }
        primitive("sphere", positions.clone(), positions, indices)
    }

    /// A probe with light in every band up to 3.
    fn probe() -> [Vec3; 16] {
        let mut c = [Vec3::ZERO; 16];
        c[0] = Vec3::new(2.0, 2.2, 2.6);
        c[2] = Vec3::new(0.8, 0.9, 1.0);
        c[3] = Vec3::new(-0.3, 0.1, 0.2);
        c[6] = Vec3::new(0.2, 0.1, -0.1);
        c[10] = Vec3::new(0.3, -0.2, 0.1);
        c[12] = Vec3::new(-0.4, 0.2, 0.3);
        c
    }

    fn sh9(c: &[Vec3; 16]) -> Sh9 {
        Sh9(std::array::from_fn(|i| c[i]))
    }

    #[test]
    fn an_unoccluded_convex_object_gets_plain_sh_irradiance() {
        // A sphere never shadows itself: Σ c_i T_i(p) = Σ Â_l c_i y_i(n), with 9 or 16
        // coefficients (the clamped cosine has no band 3: Â_3 = 0).
        let sphere = sphere(12, 24);
        let c = probe();
        for n in [9, 16] {
            let transfer = bake(&sphere, 1024, n);
            for (k, t) in transfer.chunks_exact(n).enumerate().step_by(17) {
                let prt = shaded(&c, t);
                let want = sh9(&c).irradiance(sphere.normals[k]);
                assert!(
                    (prt - want).abs().max_element() < 0.02 * want.max_element(),
                    "{n}, vertex {k}: {prt} vs {want}"
                );
            }
        }
    }

    #[test]
    fn sixteen_coefficients_extend_nine() {
        // The first nine of a 16-coefficient bake are the 9-coefficient bake's, and band 3
        // of an unoccluded vertex is about zero.
        let sphere = sphere(6, 12);
        let (nine, sixteen) = (bake(&sphere, 256, 9), bake(&sphere, 256, 16));
        for (a, b) in nine.chunks_exact(9).zip(sixteen.chunks_exact(16)) {
            assert_eq!(a, &b[..9]);
            assert!(b[9..].iter().all(|t| t.abs() < 0.05), "{b:?}");
        }
        assert_eq!(basis16(Vec3::Y)[..9], mrshade_core::sh::basis9(Vec3::Y));
    }

    #[test]
    fn a_concave_object_shadows_itself() {
        // The centre of an open box's floor (2 × 2 m, walls 2 m high) sees the sky only
        // through the opening: far less light than the same normal unoccluded.
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let mut positions = vec![v(0., 0., 0.)];
        let mut indices = Vec::new();
        let corners = [v(-1., 0., -1.), v(1., 0., -1.), v(1., 0., 1.), v(-1., 0., 1.)];
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            let base = positions.len() as u32;
            positions.extend([a, b, b + Vec3::Y * 2.0, a + Vec3::Y * 2.0]);
            // A floor triangle to the centre and the wall above the edge.
            indices.extend([0, base, base + 1, base, base + 1, base + 2, base, base + 2, base + 3]);
        }
        let normals = vec![Vec3::Y; positions.len()];
        let open_box = primitive("open box", positions, normals, indices);
        let c = probe();
        let open = sh9(&c).irradiance(Vec3::Y);
        for n in [9, 16] {
            let transfer = bake(&open_box, 1024, n);
            let prt = shaded(&c, &transfer[..n]);
            assert!(prt.x < 0.6 * open.x && prt.x > 0.05 * open.x, "{n}: {prt} vs unoccluded {open}");
        }
    }
}
