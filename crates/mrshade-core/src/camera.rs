//! The pinhole camera of one frame: where it is (`world_from_camera`) and how it projects
//! (`Intrinsics`, in pixels as tracked footage gives them: nerfstudio / instant-ngp / COLMAP
//! `fl_x`, `fl_y`, `cx`, `cy` of a `width × height` image, origin at the top-left corner).

use glam::{Mat4, Vec4};

/// Pinhole intrinsics in pixels of a `width × height` image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intrinsics {
    /// Focal length along x, in pixels.
    pub fl_x: f32,
    /// Focal length along y, in pixels.
    pub fl_y: f32,
    /// Principal point x, in pixels from the left edge.
    pub cx: f32,
    /// Principal point y, in pixels from the top edge.
    pub cy: f32,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl Intrinsics {
    /// A centred camera with vertical field of view `yfov` (radians) and square pixels, as a
    /// glTF perspective camera is.
    pub fn from_yfov(yfov: f32, width: u32, height: u32) -> Self {
        let fl = 0.5 * height as f32 / (0.5 * yfov).tan();
        Self { fl_x: fl, fl_y: fl, cx: 0.5 * width as f32, cy: 0.5 * height as f32, width, height }
    }

    /// Vertical field of view in radians.
    pub fn yfov(&self) -> f32 {
        2.0 * (0.5 * self.height as f32 / self.fl_y).atan()
    }

    /// The same camera for an image of `width × height` (the same field of view).
    pub fn scaled_to(&self, width: u32, height: u32) -> Self {
        let (sx, sy) = (width as f32 / self.width as f32, height as f32 / self.height as f32);
        Self { fl_x: self.fl_x * sx, fl_y: self.fl_y * sy, cx: self.cx * sx, cy: self.cy * sy, width, height }
    }

    /// Perspective projection with reversed infinite depth (as
    /// [`crate::math::clip_from_view_perspective`], which it equals for a centred camera),
    /// shifted off-axis by the principal point: pixel `u = cx + fl_x·x/(−z)`, `v = cy − fl_y·y/(−z)`.
    pub fn clip_from_view(&self, znear: f32) -> Mat4 {
        let (w, h) = (self.width as f32, self.height as f32);
        Mat4::from_cols(
            Vec4::new(2.0 * self.fl_x / w, 0.0, 0.0, 0.0),
            Vec4::new(0.0, 2.0 * self.fl_y / h, 0.0, 0.0),
            Vec4::new(1.0 - 2.0 * self.cx / w, 2.0 * self.cy / h - 1.0, 0.0, -1.0),
            Vec4::new(0.0, 0.0, znear, 0.0),
        )
    }
}

/// The camera of one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraView {
    /// Camera → world, rigid; the camera looks down its −Z with +Y up (OpenGL and glTF axes).
    pub world_from_camera: Mat4,
    /// Projection, in pixels of the image it was given for (scaled to the render size).
    pub intrinsics: Intrinsics,
    /// Near plane distance in metres.
    pub znear: f32,
}

impl CameraView {
    /// World → clip for an image of `width × height`.
    pub fn clip_from_world(&self, width: u32, height: u32) -> Mat4 {
        self.intrinsics.scaled_to(width, height).clip_from_view(self.znear) * self.world_from_camera.inverse()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::clip_from_view_perspective;
    use glam::Vec3;

    #[test]
    fn a_centred_camera_is_the_symmetric_projection() {
        let k = Intrinsics::from_yfov(0.7, 320, 240);
        let a = k.clip_from_view(0.05);
        let b = clip_from_view_perspective(0.7, 320.0 / 240.0, 0.05);
        assert!(a.abs_diff_eq(b, 1e-6), "{a} vs {b}");
        assert!((k.yfov() - 0.7).abs() < 1e-6);
    }

    #[test]
    fn a_point_lands_on_the_pixel_of_the_pinhole_formula() {
        let k = Intrinsics { fl_x: 300.0, fl_y: 280.0, cx: 150.0, cy: 130.0, width: 320, height: 240 };
        let p = Vec3::new(0.3, -0.2, -2.0);
        let clip = k.clip_from_view(0.01) * p.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        let (u, v) = ((ndc.x * 0.5 + 0.5) * 320.0, (0.5 - ndc.y * 0.5) * 240.0);
        assert!((u - (150.0 + 300.0 * 0.3 / 2.0)).abs() < 1e-3, "u {u}");
        assert!((v - (130.0 + 280.0 * 0.2 / 2.0)).abs() < 1e-3, "v {v}");
        assert!((ndc.z - 0.01 / 2.0).abs() < 1e-6, "reversed depth {}", ndc.z);
        // Halving the image halves the pixel coordinates.
        let half = k.scaled_to(160, 120).clip_from_view(0.01) * p.extend(1.0);
        assert!((half.truncate() / half.w - ndc).length() < 1e-6);
    }
}
