//! What a path needs at a hit: position, normals and shading frame, the material as a BSDF
//! with its textures applied, emission, and the volume behind the surface.

use crate::bsdf::Bsdf;
use crate::geometry::{Geometry, Hit, interpolate};
use crate::texture;
use glam::{Vec3, Vec4};
use mrshade_core::flags::Realness;
use mrshade_scene::Scene;

/// An orthonormal frame whose +z is a normal.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    x: Vec3,
    y: Vec3,
    /// The normal.
    pub z: Vec3,
}

impl Frame {
    /// Any frame around the unit normal `z`.
    pub fn new(z: Vec3) -> Frame {
        let (x, y) = z.any_orthonormal_pair();
        Frame { x, y, z }
    }

    /// World → local.
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z))
    }

    /// Local → world.
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.x * v.x + self.y * v.y + self.z * v.z
    }
}

/// A shading point.
#[derive(Clone, Copy, Debug)]
pub struct Surface {
    /// World position.
    pub position: Vec3,
    /// Unit geometric normal on the viewer's side.
    pub geometric: Vec3,
    /// Shading frame, +z on the viewer's side.
    pub frame: Frame,
    /// The material here.
    pub bsdf: Bsdf,
    /// Emitted radiance.
    pub emission: Vec3,
    /// Real proxy or virtual object.
    pub realness: Realness,
    /// Absorption coefficient (per metre) of the volume inside, where the material has one
    /// (`KHR_materials_volume`: `−ln(attenuationColor) / attenuationDistance`).
    pub absorption: Vec3,
}

impl Surface {
    /// The shading point of `hit` on a ray travelling along `dir`.
    pub fn new(scene: &Scene, geometry: &Geometry, hit: &Hit, origin: Vec3, dir: Vec3) -> Surface {
        let tri = &geometry.triangles[hit.triangle];
        let material = &scene.materials[tri.material];
        let position = origin + dir * hit.t;
        let uv = interpolate(tri.uv, hit.bary);
        let sample =
            |t: Option<mrshade_scene::TextureRef>, default: Vec4| t.map_or(default, |t| texture::sample(scene, t, uv));
        let mut normal = interpolate(tri.n, hit.bary).normalize_or_zero();
        let mut geometric = (tri.p[1] - tri.p[0]).cross(tri.p[2] - tri.p[0]).normalize_or_zero();
        if normal == Vec3::ZERO {
            normal = geometric;
        }
        if let Some((tex, scale)) = material.normal_texture {
            let [t, b] = tri.tangents;
            if t != Vec3::ZERO && b != Vec3::ZERO {
                let m = sample(Some(tex), Vec4::ONE).truncate() * 2.0 - Vec3::ONE;
                let m = (m * Vec3::new(scale, scale, 1.0)).normalize_or_zero();
                let t = (t - normal * normal.dot(t)).normalize_or_zero();
                let b = normal.cross(t) * normal.cross(t).dot(b).signum();
                normal = (t * m.x + b * m.y + normal * m.z).normalize_or(normal);
            }
        }
        // The outer side is the one the vertex normals point to.
        if geometric.dot(normal) < 0.0 {
            geometric = -geometric;
        }
        let front = dir.dot(geometric) < 0.0;
        if !front {
            geometric = -geometric;
            normal = -normal;
        }
        // Interpolated normals can face away from a viewer the triangle faces.
        if normal.dot(-dir) <= 1e-4 {
            normal = geometric;
        }
        let base = material.base_color * sample(material.base_color_texture, Vec4::ONE);
        let mr = sample(material.metallic_roughness_texture, Vec4::ONE);
        let roughness = (material.roughness * mr.y).clamp(0.0, 1.0);
        let emission = material.emissive * sample(material.emissive_texture, Vec4::ONE).truncate();
        let has_volume = material.thickness > 0.0;
        let absorption = if has_volume && material.attenuation_distance.is_finite() {
            -material.attenuation_color.max(Vec3::splat(1e-6)).min(Vec3::ONE).map(f32::ln)
                / material.attenuation_distance
        } else {
            Vec3::ZERO
        };
        let bsdf = Bsdf {
            base: base.truncate(),
            metallic: (material.metallic * mr.z).clamp(0.0, 1.0),
            alpha: roughness * roughness,
            f0: material.dielectric_f0(),
            f90: material.specular,
            transmission: material.transmission.clamp(0.0, 1.0),
            ior: material.ior,
            thin: !has_volume,
            front,
        };
        Surface { position, geometric, frame: Frame::new(normal), bsdf, emission, realness: tri.realness, absorption }
    }

    /// A ray origin for leaving the surface along `dir`: nudged off the surface to the side
    /// `dir` goes, so that the new ray does not hit the surface it starts on.
    pub fn spawn(&self, dir: Vec3) -> Vec3 {
        let eps = 1e-4 * (1.0 + self.position.abs().max_element());
        let side = if dir.dot(self.geometric) >= 0.0 { 1.0 } else { -1.0 };
        self.position + self.geometric * (eps * side)
    }
}
