//! Planar reflection (reflections spec §2.13, `specular.intersection = "planar"`): a flat
//! traced instance sees the scene through the camera mirrored about its plane. The mirrored
//! camera's view, clipped at the plane, is drawn by the compute rasteriser at the frame's size;
//! a smooth camera reflection leaving a point of the plane is exactly that view's ray through
//! the same pixel (the point is its own mirror image), so the trace reads its surface there.
//! The thesis draws surface attributes; the view here holds triangle ids, which the trace
//! meets exactly, as with every other slice.

use glam::{Mat4, Vec3, Vec4};
use mrshade_core::flags::Realness;
use mrshade_core::settings::{Intersection, SpecularSettings};
use mrshade_scene::Scene;

/// Positions within this fraction of their extent from one plane are flat.
const FLATNESS: f32 = 1e-4;

/// The object-space plane `(n, c)` (unit `n`, `n·p + c = 0`) in which every position of a
/// triangle mesh lies, or `None` when it is not flat: the plane of its largest triangle,
/// checked against every position.
pub fn flat_plane(positions: &[Vec3], indices: &[u32]) -> Option<Vec4> {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for &p in positions {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let extent = (hi - lo).length();
    if !extent.is_finite() || extent <= 0.0 {
        return None;
    }
    let largest = indices
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [0, 1, 2].map(|k| positions.get(t[k] as usize).copied().unwrap_or(Vec3::ZERO));
            (b - a).cross(c - a)
        })
        .max_by(|x, y| x.length_squared().total_cmp(&y.length_squared()))?;
    let n = largest.try_normalize()?;
    let c = -n.dot(positions[indices[0] as usize]);
    positions.iter().all(|p| (n.dot(*p) + c).abs() <= FLATNESS * extent).then(|| n.extend(c))
}

/// A flat traced instance that reflects through its mirrored camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reflector {
    /// The scene instance.
    pub instance: usize,
    /// Its plane in object space.
    pub object_plane: Vec4,
    /// Whether it is real: its real pixels need the real-only world's view too.
    pub real: bool,
}

impl Reflector {
    /// Views it draws: the whole world, and the real-only one for a real reflector.
    pub fn views(&self) -> u32 {
        1 + self.real as u32
    }
}

/// The rigid flat instances among the traced ones, when `settings.intersection` is `planar`.
pub fn reflectors(scene: &Scene, settings: &SpecularSettings) -> Vec<Reflector> {
    if settings.intersection != Intersection::Planar {
        return Vec::new();
    }
    scene
        .instances
        .iter()
        .enumerate()
        .filter(|(_, i)| crate::specular::traces_instance(scene, settings, i))
        .filter_map(|(instance, i)| {
            let primitive = &scene.primitives[i.primitive];
            if primitive.is_deformable() {
                return None;
            }
            let object_plane = flat_plane(&primitive.positions, &primitive.indices)?;
            Some(Reflector { instance, object_plane, real: i.realness == Realness::Real })
        })
        .collect()
}

/// `plane` (object space) in world space, normalised, for an instance at `world_from_object`.
pub fn world_plane(world_from_object: Mat4, plane: Vec4) -> Vec4 {
    let p = world_from_object.inverse().transpose() * plane;
    p / p.truncate().length().max(1e-30)
}

/// The affine reflection about the world-space `plane` (unit normal):
/// `x ↦ x − 2(n·x + c)n`.
pub fn mirror_from_world(plane: Vec4) -> Mat4 {
    let n = plane.truncate();
    let linear = glam::Mat3::IDENTITY - 2.0 * glam::Mat3::from_cols(n * n.x, n * n.y, n * n.z);
    Mat4::from_cols(
        linear.x_axis.extend(0.0),
        linear.y_axis.extend(0.0),
        linear.z_axis.extend(0.0),
        (-2.0 * plane.w * n).extend(1.0),
    )
}

/// The mirrored camera of a planar reflector: its `clip_from_world` (the camera's, of the
/// mirrored world) and the plane, turned toward `eye`, that clips away what lies behind the
/// mirror (and the mirror itself, by `margin` metres).
pub fn mirrored_view(clip_from_world: Mat4, eye: Vec3, plane: Vec4, margin: f32) -> (Mat4, Vec4) {
    let side = if plane.truncate().dot(eye) + plane.w >= 0.0 { 1.0 } else { -1.0 };
    let facing = plane * side;
    (clip_from_world * mirror_from_world(plane), facing - Vec4::new(0.0, 0.0, 0.0, margin))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quad_is_flat_and_a_box_is_not() {
        let quad =
            [Vec3::new(0.0, 1.0, 0.0), Vec3::new(2.0, 1.0, 0.0), Vec3::new(2.0, 1.0, 3.0), Vec3::new(0.0, 1.0, 3.0)];
        let plane = flat_plane(&quad, &[0, 1, 2, 0, 2, 3]).unwrap();
        assert!((plane.truncate().abs() - Vec3::Y).length() < 1e-6 && (plane.w + plane.y).abs() < 1e-6, "{plane}");
        let mut bent = quad;
        bent[3].y += 0.01;
        assert_eq!(flat_plane(&bent, &[0, 1, 2, 0, 2, 3]), None);
        assert_eq!(flat_plane(&quad, &[]), None);
    }

    #[test]
    fn the_mirror_image_of_a_point_reflects_about_the_plane() {
        // The plane z = 1 of an instance moved up by 2: world z = 3.
        let object = Vec4::new(0.0, 0.0, 1.0, -1.0);
        let plane = world_plane(Mat4::from_translation(Vec3::new(0.0, 0.0, 2.0)), object);
        assert!((plane - Vec4::new(0.0, 0.0, 1.0, -3.0)).length() < 1e-6, "{plane}");
        let m = mirror_from_world(plane);
        assert!((m.transform_point3(Vec3::new(1.0, 2.0, 5.0)) - Vec3::new(1.0, 2.0, 1.0)).length() < 1e-5);
        // A point of the plane is its own image: the mirrored camera sees it at the same pixel.
        let on = Vec3::new(-0.4, 0.7, 3.0);
        assert!((m.transform_point3(on) - on).length() < 1e-6);
        let (_, clip) = mirrored_view(Mat4::IDENTITY, Vec3::new(0.0, 0.0, 10.0), plane, 1e-3);
        assert!(clip.dot(Vec3::new(0.0, 0.0, 4.0).extend(1.0)) > 0.0 && clip.dot(on.extend(1.0)) < 0.0);
    }
}
