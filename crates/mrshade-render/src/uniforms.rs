//! Per-frame constants (`Frame` in shaders/lib/frame.wgsl): the frame's camera, sizes, probe.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec4, Vec2, Vec3, Vec4};
use mrshade_core::camera::CameraView;
use mrshade_core::math::probe_from_world;
use mrshade_scene::Session;

/// Mirrors `struct Frame` in `shaders/lib/frame.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    /// World → clip of the render camera (reversed depth).
    pub clip_from_world: Mat4,
    /// Its inverse.
    pub world_from_clip: Mat4,
    /// `clip_from_world` of the previous frame (for reprojection).
    pub previous_clip_from_world: Mat4,
    /// Probe rotation (upper 3×3).
    pub probe_from_world: Mat4,
    /// Camera position (xyz).
    pub camera_position: Vec4,
    /// Internal width, height; output width, height.
    pub size: UVec4,
    /// Light count, probe present, supersampling factor, radiance mip count.
    pub counts: UVec4,
    /// Exposure, probe intensity, camera near plane, frame index.
    pub exposure_env: Vec4,
}

/// Where world point `p` falls in an image of `size` seen through `clip_from_world`, in
/// pixels (x right, y down, fractional; possibly outside the image), or `None` behind the
/// camera. The CPU's twin of the shaders' projection, for AOVs drawn over the image.
pub fn image_point(clip_from_world: Mat4, p: Vec3, size: (u32, u32)) -> Option<Vec2> {
    let clip = clip_from_world * p.extend(1.0);
    (clip.w > 0.0).then(|| {
        let ndc = clip.truncate().truncate() / clip.w;
        Vec2::new((ndc.x * 0.5 + 0.5) * size.0 as f32, (0.5 - ndc.y * 0.5) * size.1 as f32)
    })
}

impl FrameUniforms {
    /// Constants for rendering `session` through `camera` with `light_count` lights and
    /// `radiance_mips` probe levels.
    pub fn new(session: &Session, camera: &CameraView, light_count: u32, radiance_mips: u32) -> Self {
        let out = session.output;
        let (w, h) = (out.width * out.supersample, out.height * out.supersample);
        let clip_from_world = camera.clip_from_world(w, h);
        let (rotation, intensity, has_env) = match &session.environment {
            Some(env) => (env.rotation_deg, env.intensity, 1),
            None => (0.0, 0.0, 0),
        };
        Self {
            clip_from_world,
            world_from_clip: clip_from_world.inverse(),
            previous_clip_from_world: clip_from_world,
            probe_from_world: Mat4::from_mat3(probe_from_world(rotation)),
            camera_position: camera.world_from_camera.w_axis,
            size: UVec4::new(w, h, out.width, out.height),
            counts: UVec4::new(light_count, has_env, out.supersample, radiance_mips),
            exposure_env: Vec4::new(session.exposure, intensity, camera.znear, 0.0),
        }
    }

    /// Places the camera: `camera` shifted by `jitter` pixels, with `previous` (the last
    /// frame's unjittered `clip_from_world`) for reprojection. Motion vectors leave the jitter
    /// out (as in TAA): a still camera's pixel reuses its own history instead of one that
    /// wanders by up to a pixel every frame, which would blur contact shadows.
    pub fn set_camera(&mut self, camera: &CameraView, jitter: glam::Vec2, previous: Option<Mat4>) {
        let (w, h) = self.internal_size();
        let unjittered = camera.clip_from_world(w, h);
        let shift = Mat4::from_translation(glam::Vec3::new(2.0 * jitter.x / w as f32, -2.0 * jitter.y / h as f32, 0.0));
        self.clip_from_world = shift * unjittered;
        self.world_from_clip = self.clip_from_world.inverse();
        self.previous_clip_from_world = shift * previous.unwrap_or(unjittered);
        self.camera_position = camera.world_from_camera.w_axis;
        self.exposure_env.z = camera.znear;
    }

    /// Internal (shading) resolution.
    pub fn internal_size(&self) -> (u32, u32) {
        (self.size.x, self.size.y)
    }

    /// Output resolution.
    pub fn output_size(&self) -> (u32, u32) {
        (self.size.z, self.size.w)
    }
}
