//! THE frame: the passes in order (Knecht §1.4, restricted to what the selected method
//! computes). Every pass is recorded into one encoder and timed on its own.

use crate::outputs::Composite;
use crate::renderer::Renderer;
use anyhow::Result;
use mrshade_core::settings::Method;
use mrshade_gpu::GpuContext;
use mrshade_gpu::timing::Recorder;
use wgpu_profiler::GpuProfiler;

impl Renderer {
    /// Records one frame.
    pub fn record_frame(&mut self, rec: &mut Recorder) {
        // 1. Shadow maps: real-only and virtual-only casters per light.
        self.shadows.record(rec, &self.rasterizer);
        // 2. G-buffer of real and virtual surfaces: visibility, then attributes.
        self.gbuffer_pass.record(rec, &self.rasterizer);
        // 3. Light transport into L_rv and L_r from the same evaluation.
        // Indirect light first (RSMs → VPLs → ISMs → interleaved shading → temporal smoothing
        // and merge), then direct light on top of it (Knecht §1.4, steps 5–9).
        if let (Method::Dir, Some(dir)) = (&self.settings.method, &mut self.dir) {
            dir.record(rec, &self.rasterizer);
        }
        self.direct.record(rec);
        // 4. Differential composite with the photo.
        self.composite.record(rec);
    }

    /// Records and submits one frame; timings (if enabled) go to `profiler`.
    pub fn render(&mut self, ctx: &GpuContext, profiler: &mut GpuProfiler) -> Result<()> {
        self.scene.geometry.begin_frame(&ctx.queue);
        self.uniforms.exposure_env.w = self.frame_index as f32;
        ctx.queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&self.uniforms));
        // The camera does not move between frames yet: the previous frame's is this one's.
        self.uniforms.previous_clip_from_world = self.uniforms.clip_from_world;
        if let Some(dir) = &mut self.dir {
            dir.prepare(&ctx.queue, &self.scene.geometry);
        }
        ctx.checked("rendering a frame", || {
            let mut rec = Recorder::new(ctx, profiler, "frame");
            self.record_frame(&mut rec);
            ctx.queue.submit([rec.finish()]);
            Ok(())
        })?;
        self.frame_index += 1;
        Ok(())
    }

    /// Renders one untimed frame and waits for it.
    pub fn render_once(&mut self, ctx: &GpuContext) -> Result<()> {
        self.render_frames(ctx, 1, |_| {})
    }

    /// Renders a still image of `frames` untimed frames, calling `progress(i)` after each:
    /// the composite averaged over the last half (`frames / 2`, at least one), once a
    /// temporal method's smoothing and bounces have converged over the first half.
    pub fn render_still(&mut self, ctx: &GpuContext, frames: u32, mut progress: impl FnMut(u32)) -> Result<Composite> {
        let averaged = (frames / 2).max(1);
        self.render_frames(ctx, frames - averaged, &mut progress)?;
        let mut sum: Option<Composite> = None;
        for i in 0..averaged {
            // Sub-pixel jitter (Halton 2, 3): the mean over the frames is an anti-aliased
            // image, as a path tracer's pixel is; the temporal smoothing follows the jitter
            // through the motion vectors.
            let jitter = glam::Vec2::new(halton(2, i + 1), halton(3, i + 1)) - 0.5;
            self.set_pixel_offset(&ctx.queue, if averaged > 1 { jitter } else { glam::Vec2::ZERO });
            self.render_frames(ctx, 1, |_| {})?;
            progress(frames - averaged + i + 1);
            let c = self.read_composite(ctx)?;
            match &mut sum {
                None => sum = Some(c),
                Some(s) => {
                    for (a, b) in s.image.pixels.iter_mut().zip(&c.image.pixels) {
                        for k in 0..3 {
                            a[k] += b[k];
                        }
                    }
                }
            }
        }
        self.set_pixel_offset(&ctx.queue, glam::Vec2::ZERO);
        let mut still = sum.expect("at least one frame");
        let scale = 1.0 / averaged as f32;
        for p in &mut still.image.pixels {
            *p = p.map(|c| c * scale);
        }
        // Never a silent black image: NaN is written as black.
        if let Some((count, (x, y))) = still.image.non_finite() {
            anyhow::bail!(
                "the composite holds {count} NaN or infinite pixel(s), the first at ({x}, {y}) (a bug in mrshade, \
                 please report it with the session)"
            );
        }
        Ok(still)
    }

    /// Shifts the camera's image by `offset` pixels (sub-pixel jitter).
    fn set_pixel_offset(&mut self, queue: &wgpu::Queue, offset: glam::Vec2) {
        let (w, h) = self.uniforms.internal_size();
        let ndc = glam::Vec3::new(2.0 * offset.x / w as f32, -2.0 * offset.y / h as f32, 0.0);
        let clip_from_world = glam::Mat4::from_translation(ndc) * self.camera_clip_from_world;
        self.uniforms.clip_from_world = clip_from_world;
        self.uniforms.world_from_clip = clip_from_world.inverse();
        // Motion vectors leave the jitter out (as in TAA): the temporal smoothing reuses the
        // same pixel's history instead of letting it wander by up to a pixel every frame,
        // which would blur contact shadows. (The camera itself does not move yet.)
        self.uniforms.previous_clip_from_world = clip_from_world;
        self.gbuffer_pass.camera.set_clip_from_world(queue, clip_from_world);
    }

    /// Renders `frames` untimed frames, calling `progress(i)` after each, and waits for the
    /// last.
    pub fn render_frames(&mut self, ctx: &GpuContext, frames: u32, mut progress: impl FnMut(u32)) -> Result<()> {
        let mut profiler = mrshade_gpu::timing::profiler(ctx, false)?;
        for i in 0..frames {
            self.render(ctx, &mut profiler)?;
            profiler.end_frame().map_err(|e| anyhow::anyhow!("profiler: {e}"))?;
            ctx.wait_idle()?;
            progress(i + 1);
        }
        Ok(())
    }
}

/// The radical inverse of `i` in base `base` (a Halton sequence).
fn halton(base: u32, mut i: u32) -> f32 {
    let (mut f, mut r) = (1.0f32, 0.0f32);
    while i > 0 {
        f /= base as f32;
        r += f * (i % base) as f32;
        i /= base;
    }
    r
}
