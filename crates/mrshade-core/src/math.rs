//! Projection and environment-map conventions. Matrices are named `a_from_b`: they map
//! coordinates of space `b` into space `a`, so `clip_from_world = clip_from_view * view_from_world`.

use glam::{Mat3, Mat4, Vec2, Vec3};
use std::f32::consts::{PI, TAU};

/// Perspective projection with reversed depth (near → 1, infinity → 0) for wgpu's [0, 1]
/// clip depth. Reversed-Z keeps float depth precise across the metre-scale scenes and
/// 1 cm near planes of the contract; the far plane is at infinity so nothing is clipped.
pub fn clip_from_view_perspective(yfov: f32, aspect: f32, znear: f32) -> Mat4 {
    glam::camera::rh::proj::directx::perspective_infinite_reverse(yfov, aspect, znear)
}

/// Environment lookup of the data contract: `u = atan2(x, −z) / 2π` wrapped to [0, 1),
/// `v = acos(y) / π`, row 0 at the top (+Y).
pub fn equirect_uv_from_dir(d: Vec3) -> Vec2 {
    let u = d.x.atan2(-d.z) / TAU;
    let u = if u < 0.0 { u + 1.0 } else { u };
    let v = d.y.clamp(-1.0, 1.0).acos() / PI;
    Vec2::new(u, v)
}

/// Inverse of [`equirect_uv_from_dir`]: the unit direction at texture coordinate `uv`.
pub fn dir_from_equirect_uv(uv: Vec2) -> Vec3 {
    let phi = uv.x * TAU;
    let theta = uv.y * PI;
    Vec3::new(theta.sin() * phi.sin(), theta.cos(), -theta.sin() * phi.cos())
}

/// `[environment] rotation_deg` rotates the probe about +Y (right-handed): a world
/// direction `d` sees the probe texel at `probe_from_world * d`.
pub fn probe_from_world(rotation_deg: f32) -> Mat3 {
    Mat3::from_rotation_y(-rotation_deg.to_radians())
}

/// Solid angle of texel row `y` of a `width × height` equirectangular map.
pub fn equirect_texel_solid_angle(y: u32, width: u32, height: u32) -> f32 {
    let theta0 = PI * y as f32 / height as f32;
    let theta1 = PI * (y + 1) as f32 / height as f32;
    (TAU / width as f32) * (theta0.cos() - theta1.cos())
}

/// The box around `points` (a point at the origin if there are none).
pub fn bounding_box(points: &[Vec3]) -> (Vec3, Vec3) {
    let lo = points.iter().fold(Vec3::INFINITY, |a, &p| a.min(p));
    let hi = points.iter().fold(Vec3::NEG_INFINITY, |a, &p| a.max(p));
    if lo.x > hi.x { (Vec3::ZERO, Vec3::ZERO) } else { (lo, hi) }
}

/// The eight corners of the box `(lo, hi)`.
pub fn box_corners((lo, hi): (Vec3, Vec3)) -> [Vec3; 8] {
    std::array::from_fn(|k| {
        Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// The matrix that carries object-space normals to world space under `world_from_object`:
/// the cofactor matrix of its linear part (det · M⁻ᵀ: the directions of the inverse
/// transpose, which normals are normalised after anyway), signed like the determinant and
/// scaled so that its largest entry is 1. Unlike the inverse, it is finite for every finite
/// matrix (a scale of 10⁻³⁰ on one axis gives the inverse entries of 10³⁰, whose squares
/// overflow) and still right for a flattened one (a zero scale keeps the plane's normal).
pub fn normal_from_object(world_from_object: Mat4) -> Mat4 {
    let m = Mat3::from_mat4(world_from_object);
    let largest = m.to_cols_array().iter().fold(0.0f32, |a, v| a.max(v.abs()));
    if !(largest > 0.0 && largest.is_finite()) {
        return Mat4::IDENTITY;
    }
    let m = m * (1.0 / largest);
    let cofactor = Mat3::from_cols(m.y_axis.cross(m.z_axis), m.z_axis.cross(m.x_axis), m.x_axis.cross(m.y_axis));
    let sign = if m.determinant() < 0.0 { -1.0 } else { 1.0 };
    let largest = cofactor.to_cols_array().iter().fold(0.0f32, |a, v| a.max(v.abs()));
    if largest > 0.0 { Mat4::from_mat3(cofactor * (sign / largest)) } else { Mat4::IDENTITY }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_follow_the_inverse_transpose_and_stay_finite() {
        use glam::{Quat, Vec3};
        let transforms = [
            Mat4::from_scale_rotation_translation(Vec3::new(2.0, 0.5, 3.0), Quat::from_rotation_y(0.7), Vec3::ONE),
            Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)),
            Mat4::from_cols_array(&[1.0, 0.3, 0.0, 0.0, 0.0, 1.0, 0.2, 0.0, 0.1, 0.0, 1.0, 0.0, 5.0, 6.0, 7.0, 1.0]),
        ];
        for m in transforms {
            let reference = m.inverse().transpose();
            for n in [Vec3::X, Vec3::Y, Vec3::new(0.3, -0.5, 0.8).normalize()] {
                let want = reference.transform_vector3(n).normalize();
                let got = normal_from_object(m).transform_vector3(n).normalize();
                assert!(got.abs_diff_eq(want, 1e-5), "{m:?} {n}: {got} vs {want}");
            }
        }
        // Nearly flat and flat: the plane's normal, finite.
        for z in [1e-30, 0.0] {
            let n = normal_from_object(Mat4::from_scale(Vec3::new(1.0, 1.0, z))).transform_vector3(Vec3::Z);
            assert!(n.is_finite() && n.normalize().abs_diff_eq(Vec3::Z, 1e-6), "{z}: {n}");
        }
    }

    #[test]
    fn contract_axes() {
        // −Z is the centre column's left edge (u = 0), +Y the top row.
        assert!(equirect_uv_from_dir(Vec3::NEG_Z).abs_diff_eq(Vec2::new(0.0, 0.5), 1e-6));
        assert!(equirect_uv_from_dir(Vec3::X).abs_diff_eq(Vec2::new(0.25, 0.5), 1e-6));
        assert!(equirect_uv_from_dir(Vec3::Z).abs_diff_eq(Vec2::new(0.5, 0.5), 1e-6));
        assert!(equirect_uv_from_dir(Vec3::NEG_X).abs_diff_eq(Vec2::new(0.75, 0.5), 1e-6));
        assert!((equirect_uv_from_dir(Vec3::Y).y).abs() < 1e-6);
    }

    #[test]
    fn uv_round_trip() {
        for &(u, v) in &[(0.1, 0.2), (0.6, 0.7), (0.9, 0.45)] {
            let uv = Vec2::new(u, v);
            assert!(equirect_uv_from_dir(dir_from_equirect_uv(uv)).abs_diff_eq(uv, 1e-5));
        }
    }

    #[test]
    fn rotating_the_probe_by_90_degrees_moves_its_content() {
        // Content at −Z in the probe appears at −X after a +90° right-handed turn about +Y.
        let d = probe_from_world(90.0) * Vec3::NEG_X;
        assert!(d.abs_diff_eq(Vec3::NEG_Z, 1e-6));
    }

    #[test]
    fn texel_solid_angles_sum_to_the_sphere() {
        let total: f32 = (0..64).map(|y| 128.0 * equirect_texel_solid_angle(y, 128, 64)).sum();
        assert!((total - 4.0 * PI).abs() < 1e-3);
    }

    #[test]
    fn reversed_depth_maps_near_to_one() {
        let clip_from_view = clip_from_view_perspective(1.0, 1.5, 0.1);
        let near = clip_from_view.project_point3(Vec3::new(0.0, 0.0, -0.1));
        let far = clip_from_view.project_point3(Vec3::new(0.0, 0.0, -1e6));
        assert!((near.z - 1.0).abs() < 1e-6 && far.z < 1e-6);
    }
}
