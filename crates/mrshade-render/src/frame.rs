//! THE frame (Knecht §1.4): per-frame inputs in (uploaded first: photo, camera, instance and
//! light transforms), a composite out. Every pass is recorded into
//! one encoder and timed on its own; the comments name what each pass reads and what it hands
//! on (the bindings themselves are made once, when the renderer is built).

use crate::methods::FrameChange;
use crate::passes::upload::PackedPhoto;
use crate::renderer::Renderer;
use anyhow::Result;
use glam::{Mat4, Vec2};
use mrshade_core::camera::CameraView;
use mrshade_gpu::GpuContext;
use mrshade_gpu::timing::Recorder;
use mrshade_scene::Deformation;
use wgpu_profiler::GpuProfiler;

/// What changes from frame to frame: the camera, the photo, where things are.
#[derive(Clone, Copy)]
pub struct FrameInputs<'a> {
    /// This frame's camera pose and intrinsics.
    pub camera: CameraView,
    /// Sub-pixel offset of the camera's image, in pixels (still images average jittered frames).
    pub jitter: Vec2,
    /// The photo, packed at the output size; `None` keeps the last one.
    pub photo: Option<&'a PackedPhoto>,
    /// `world_from_object` per scene instance; `None` keeps the last.
    pub instances: Option<&'a [Mat4]>,
    /// `world_from_light` per scene light; `None` keeps the last.
    pub lights: Option<&'a [Mat4]>,
    /// Skin joint matrices and morph weights per scene instance; `None` keeps the last.
    pub deformations: Option<&'a [Deformation]>,
}

impl<'a> FrameInputs<'a> {
    /// A frame through `camera` with everything else as it was.
    pub fn camera(camera: CameraView) -> Self {
        Self { camera, jitter: Vec2::ZERO, photo: None, instances: None, lights: None, deformations: None }
    }
}

impl Renderer {
    /// Records one frame: the passes in order, each reading what the ones before wrote.
    pub fn record_frame(&mut self, rec: &mut Recorder) {
        // 0. rest vertices, joint matrices, morph weights ─▶ deformed vertices (skinned and
        //    morphing instances only, when they changed), read by every pass below.
        if let Some(deform) = &mut self.deform {
            deform.record(rec);
        }
        let raster = &self.rasterizer;
        // 1. geometry, lights ─▶ shadow maps, real-only and virtual-only casters per light
        //    (when either changed).
        self.shadows.record(rec, raster);
        // 2. geometry, camera ─▶ G-buffer: visibility, then depth + motion, normals,
        //    materials, real/virtual flags.
        self.gbuffer_pass.record(rec, raster);
        // 2b. G-buffer, geometry, lights ─▶ reflection/refraction G-buffers (rays through
        //     impostors), photons (caustics): handed to the method's host pass, which runs
        //     them beside its own dispatch (they read nothing the method writes).
        if let Some(specular) = &mut self.specular {
            specular.record_rays(rec, raster);
        }
        // 3. G-buffer, lights, scene ─▶ the method's indirect light (`IndirectLight`: the
        //    `Differential { rv, r }` of indirect radiance and the probe's visibility), from
        //    the same paths for both solutions. `dir`: RSMs → VPLs → ISMs → interleaved
        //    shading → temporal smoothing and merge (Knecht §1.4, steps 5–9).
        self.method.record(rec, raster);
        // 3b. probe ─▶ its nine SH coefficients (when virtual objects are shaded with them,
        //     `[ibl] virtual`), every frame so that a changing probe is followed.
        if let Some(probe_sh) = &self.probe_sh {
            probe_sh.record(rec);
        }
        // 3c. visibility, geometry, baked transfer, SH coefficients ─▶ PRT irradiance of
        //     rigid virtual objects (`[ibl] virtual = "prt"`).
        if let Some(prt) = &self.prt {
            prt.record(rec);
        }
        // 4. G-buffer, shadow maps, probe, indirect light ─▶ `Differential { rv: L_rv, r: L_r }`.
        self.direct.record(rec);
        // 5. specular G-buffers, photons, L_rv, L_r, photo ─▶ caustic buffer, the light of
        //    reflections and refractions on traced pixels (back-projection).
        //    Hit surfaces off screen are shaded with the method's light at any point (its
        //    VPLs of this frame). Smoothed over frames through the motion vectors.
        if let Some(specular) = &mut self.specular {
            let vpl_parity = self.method.point_light().map_or(0, |p| p.parity);
            specular.record_light(rec, vpl_parity);
        }
        // 6. L_rv, L_r, specular light, flags, photo ─▶ the composite and α.
        self.composite.record(rec);
    }

    /// Uploads `inputs` and tells the method what changed.
    fn prepare(&mut self, queue: &wgpu::Queue, inputs: &FrameInputs) {
        if let Some(photo) = inputs.photo {
            self.photo.write(queue, photo);
        }
        if let Some(instances) = inputs.instances {
            for (i, &m) in instances.iter().enumerate() {
                self.scene.geometry.set_transform(i, m);
            }
        }
        if let (Some(deform), Some(deformations)) = (&mut self.deform, inputs.deformations) {
            for (instance, object_box) in deform.update(queue, deformations) {
                self.scene.geometry.set_deformed_box(instance, object_box);
            }
        }
        let lights_moved = inputs.lights.is_some_and(|l| self.scene.set_light_transforms(queue, l));
        if lights_moved {
            self.shadows.set_layers(queue, &self.scene.shadow_layers);
        }
        self.scene.geometry.begin_frame(queue);
        self.shadows.geometry_changed(self.scene.geometry.moved_casters());
        let (w, h) = self.internal_size();
        let unjittered = inputs.camera.clip_from_world(w, h);
        let camera_moved = self.previous_clip_from_world.is_some_and(|p| p != unjittered);
        let changed = camera_moved || self.scene.geometry.moved() || lights_moved || inputs.photo.is_some();
        self.uniforms.set_camera(&inputs.camera, inputs.jitter, self.previous_clip_from_world);
        self.previous_clip_from_world = Some(unjittered);
        self.gbuffer_pass.camera.set_clip_from_world(queue, 0, self.uniforms.clip_from_world);
        if let Some(specular) = &mut self.specular {
            let eye = self.uniforms.camera_position.truncate();
            specular.prepare(queue, &self.scene.geometry, self.uniforms.clip_from_world, eye, changed);
        }
        self.uniforms.exposure_env.w = self.frame_index as f32;
        queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&self.uniforms));
        let change = FrameChange {
            geometry: &self.scene.geometry,
            geometry_moved: self.scene.geometry.moved(),
            vertices_deformed: self.scene.geometry.deformed(),
            moved_light_layers: lights_moved.then_some(&self.scene.shadow_layers[..]),
            camera_moved,
            photo_changed: inputs.photo.is_some(),
        };
        self.method.prepare(queue, &change);
    }

    /// Submits one frame of `inputs` (without waiting for it); timings (if enabled) go to
    /// `profiler`.
    pub fn render(
        &mut self,
        ctx: &GpuContext,
        profiler: &mut GpuProfiler,
        inputs: &FrameInputs,
    ) -> Result<wgpu::SubmissionIndex> {
        self.prepare(&ctx.queue, inputs);
        let submitted = ctx.checked("rendering a frame", || {
            let mut rec = Recorder::new(ctx, profiler, "frame").serial(self.serial_passes);
            self.record_frame(&mut rec);
            Ok(ctx.queue.submit([rec.finish()]))
        })?;
        self.frame_index += 1;
        Ok(submitted)
    }

    /// Forgets all temporal history; the next frame is numbered `frame` (its sampling seed).
    pub fn seek(&mut self, frame: u32) {
        self.frame_index = frame;
        self.previous_clip_from_world = None;
        self.method.seek(frame);
        if let Some(specular) = &mut self.specular {
            specular.seek();
        }
    }

    /// The session's own camera (its glTF camera, or the first pose of a sequence).
    pub fn session_camera(&self) -> CameraView {
        self.session_camera
    }
}
