//! The pinhole camera both ways: the camera ray through an image position (camera paths), and
//! the image position and importance of a world point (light paths splatting caustics). One
//! type for both keeps the two estimates of a pixel on the same image plane and filter.

use glam::{Mat3, Vec3, Vec4Swizzles};
use mrshade_scene::Camera;

/// A pinhole camera over a `width × height` image, box-filtered pixels.
#[derive(Clone, Copy, Debug)]
pub struct Pinhole {
    /// The eye.
    pub origin: Vec3,
    world_from_camera: Mat3,
    camera_from_world: Mat3,
    /// `|det world_from_camera|`, for the solid angle of an image-plane area (1 when rigid).
    det: f32,
    tan_half: f32,
    aspect: f32,
    width: u32,
    height: u32,
}

/// Where a world point lands in the image.
#[derive(Clone, Copy, Debug)]
pub struct Projection {
    /// Row-major pixel index.
    pub pixel: u32,
    /// The camera's importance per solid angle at that direction: `1 / (A_pixel · dω/du)`,
    /// with `A_pixel` the pixel's area on the image plane at distance 1 and `dω/du` the solid
    /// angle per unit of that plane. A radiance `L` arriving over a solid angle `dω` adds
    /// `L · importance · dω` to the pixel's box-filtered mean, the quantity the camera's own
    /// samples estimate.
    pub importance: f32,
}

impl Pinhole {
    /// The camera `camera` rendering a `width × height` image.
    pub fn new(camera: &Camera, width: u32, height: u32) -> Pinhole {
        let world_from_camera = Mat3::from_mat4(camera.world_from_camera);
        Pinhole {
            origin: camera.world_from_camera.w_axis.xyz(),
            world_from_camera,
            camera_from_world: world_from_camera.inverse(),
            det: world_from_camera.determinant().abs(),
            tan_half: (camera.yfov * 0.5).tan(),
            aspect: width as f32 / height as f32,
            width,
            height,
        }
    }

    /// The unit direction of the camera ray through image position (`x`, `y`) in pixels
    /// (fractional: a sub-pixel position).
    pub fn ray(&self, x: f32, y: f32) -> Vec3 {
        let sx = (2.0 * x / self.width as f32 - 1.0) * self.tan_half * self.aspect;
        let sy = (1.0 - 2.0 * y / self.height as f32) * self.tan_half;
        (self.world_from_camera * Vec3::new(sx, sy, -1.0)).normalize()
    }

    /// The pixel that sees world point `p` (ignoring occlusion), or `None` outside the image
    /// or behind the camera.
    pub fn project(&self, p: Vec3) -> Option<Projection> {
        let local = self.camera_from_world * (p - self.origin);
        if local.z >= 0.0 {
            return None;
        }
        // The image-plane point v = (sx, sy, −1) whose ray passes through p.
        let v = Vec3::new(local.x / -local.z, local.y / -local.z, -1.0);
        let x = (v.x / (self.tan_half * self.aspect) + 1.0) * 0.5 * self.width as f32;
        let y = (1.0 - v.y / self.tan_half) * 0.5 * self.height as f32;
        if !(x >= 0.0 && y >= 0.0 && x < self.width as f32 && y < self.height as f32) {
            return None;
        }
        let (px, py) = ((x as u32).min(self.width - 1), (y as u32).min(self.height - 1));
        // Directions M·v/|M·v| over the plane: dω/du = |det M| / |M·v|³ (cos³θ when rigid).
        let d_omega_du = self.det / (self.world_from_camera * v).length().powi(3);
        let pixel_area =
            (2.0 * self.tan_half * self.aspect / self.width as f32) * (2.0 * self.tan_half / self.height as f32);
        Some(Projection { pixel: py * self.width + px, importance: 1.0 / (pixel_area * d_omega_du) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    fn camera() -> Camera {
        let eye = Vec3::new(0.3, 1.0, 2.0);
        let forward = Vec3::new(-0.2, -0.4, -1.0).normalize();
        Camera {
            node_name: "camera".into(),
            camera_name: None,
            yfov: 0.8,
            aspect_ratio: None,
            znear: 0.01,
            world_from_camera: glam::camera::rh::view::look_to_mat4(eye, forward, Vec3::Y).inverse(),
        }
    }

    #[test]
    fn projection_inverts_the_camera_ray() {
        let cam = Pinhole::new(&camera(), 64, 48);
        for (x, y) in [(0.5, 0.5), (10.25, 40.75), (63.9, 0.1), (32.0, 24.0)] {
            let p = cam.origin + cam.ray(x, y) * 3.7;
            let proj = cam.project(p).unwrap();
            assert_eq!(proj.pixel, y as u32 * 64 + x as u32, "({x}, {y})");
        }
        assert!(cam.project(cam.origin - cam.ray(32.0, 24.0)).is_none(), "behind the camera");
    }

    #[test]
    fn importance_integrates_to_one_over_a_pixel() {
        // Σ importance · dω over the directions of one pixel is 1: the pixel's mean of a
        // constant radiance is that radiance.
        let cam = Pinhole::new(&camera(), 64, 48);
        let (px, py, n) = (5.0, 7.0, 64);
        let mut sum = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let (x, y) = (px + (i as f32 + 0.5) / n as f32, py + (j as f32 + 0.5) / n as f32);
                let h = 0.5 / n as f32;
                // The solid angle of the sub-pixel: |(d(x+h) − d(x−h)) × (d(y+h) − d(y−h))|.
                let dx = cam.ray(x + h, y) - cam.ray(x - h, y);
                let dy = cam.ray(x, y + h) - cam.ray(x, y - h);
                let omega = dx.cross(dy).length();
                sum += (cam.project(cam.origin + cam.ray(x, y)).unwrap().importance * omega) as f64;
            }
        }
        assert!((sum - 1.0).abs() < 1e-3, "{sum}");
    }
}
