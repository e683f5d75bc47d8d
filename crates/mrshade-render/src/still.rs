//! Still images: many frames of one unchanging view, averaged. This lives outside the frame:
//! a frame knows nothing of accumulation, only of its inputs.

use crate::frame::FrameInputs;
use crate::outputs::Composite;
use crate::renderer::Renderer;
use anyhow::Result;
use glam::Vec2;
use mrshade_gpu::GpuContext;

impl Renderer {
    /// Renders one untimed frame of the session's own view and waits for it.
    pub fn render_once(&mut self, ctx: &GpuContext) -> Result<()> {
        self.render_frames(ctx, 1, |_| {})
    }

    /// Renders a still image of the session's own view: see [`Renderer::render_still_of`].
    pub fn render_still(&mut self, ctx: &GpuContext, frames: u32, progress: impl FnMut(u32)) -> Result<Composite> {
        let inputs = FrameInputs::camera(self.session_camera);
        self.render_still_of(ctx, frames, &inputs, progress)
    }

    /// Renders a still image of `inputs` from `frames` untimed frames, calling `progress(i)`
    /// after each: the composite averaged over the last half (`frames / 2`, at least one),
    /// once a temporal method's smoothing and bounces have converged over the first half.
    pub fn render_still_of(
        &mut self,
        ctx: &GpuContext,
        frames: u32,
        inputs: &FrameInputs,
        progress: impl FnMut(u32),
    ) -> Result<Composite> {
        Ok(self.still(ctx, frames, inputs, false, progress)?.0)
    }

    /// [`Renderer::render_still`], also returning every frame's GPU milliseconds from the
    /// timestamp queries (empty where the adapter has none): what the still cost the GPU.
    pub fn render_still_timed(
        &mut self,
        ctx: &GpuContext,
        frames: u32,
        progress: impl FnMut(u32),
    ) -> Result<(Composite, Vec<f64>)> {
        let inputs = FrameInputs::camera(self.session_camera);
        self.still(ctx, frames, &inputs, ctx.timestamps, progress)
    }

    fn still(
        &mut self,
        ctx: &GpuContext,
        frames: u32,
        inputs: &FrameInputs,
        timed: bool,
        mut progress: impl FnMut(u32),
    ) -> Result<(Composite, Vec<f64>)> {
        let averaged = (frames / 2).max(1);
        let mut profiler = mrshade_gpu::timing::profiler(ctx, timed)?;
        let mut gpu_ms = Vec::new();
        let mut mean = Average::default();
        // The average is the still's own smoothing of the specular light (unbiased).
        self.with_specular_smoothing_paused(true, |renderer| {
            for i in 0..frames {
                let averaging = i + averaged >= frames;
                // Sub-pixel jitter over the averaged frames: their mean is an anti-aliased image,
                // as a path tracer's pixel is; the temporal smoothing follows the jitter through
                // the motion vectors.
                let jitter = if averaging && averaged > 1 { jitter((i + averaged + 1) - frames) } else { Vec2::ZERO };
                // The photo and transforms are uploaded once; later frames keep them.
                let frame = if i == 0 { *inputs } else { FrameInputs::camera(inputs.camera) };
                renderer.render_untimed(ctx, &mut profiler, &FrameInputs { jitter, ..frame })?;
                while let Some(results) = profiler.process_finished_frame(ctx.queue.get_timestamp_period()) {
                    gpu_ms.extend(mrshade_gpu::timing::frame_ms(&mrshade_gpu::timing::flatten(&results)));
                }
                progress(i + 1);
                if averaging {
                    mean.add(renderer.read_composite(ctx)?);
                }
            }
            Ok(())
        })?;
        Ok((mean.finish()?, gpu_ms))
    }

    /// Runs `f` with the specular stage's temporal smoothing off while `paused` (then on
    /// again): where frames are averaged (stills, footage of several samples a frame), the
    /// average smooths without the bias of a running mean that began before the method
    /// converged.
    pub(crate) fn with_specular_smoothing_paused<T>(
        &mut self,
        paused: bool,
        f: impl FnOnce(&mut Self) -> Result<T>,
    ) -> Result<T> {
        if let Some(specular) = &mut self.specular {
            specular.pause_smoothing(paused);
        }
        let result = f(self);
        if let Some(specular) = &mut self.specular {
            specular.pause_smoothing(false);
        }
        result
    }

    /// Renders `frames` untimed frames of the session's own view, calling `progress(i)` after
    /// each, and waits for the last.
    pub fn render_frames(&mut self, ctx: &GpuContext, frames: u32, mut progress: impl FnMut(u32)) -> Result<()> {
        let mut profiler = mrshade_gpu::timing::profiler(ctx, false)?;
        let inputs = FrameInputs::camera(self.session_camera);
        for i in 0..frames {
            self.render_untimed(ctx, &mut profiler, &inputs)?;
            progress(i + 1);
        }
        Ok(())
    }

    /// Renders one frame of `inputs` and waits for it.
    pub fn render_untimed(
        &mut self,
        ctx: &GpuContext,
        profiler: &mut wgpu_profiler::GpuProfiler,
        inputs: &FrameInputs,
    ) -> Result<()> {
        self.render(ctx, profiler, inputs)?;
        profiler.end_frame().map_err(|e| anyhow::anyhow!("profiler: {e}"))?;
        ctx.wait_idle()
    }
}

/// Never a silent black image: NaN would be written as black.
pub fn check_finite(composite: &Composite) -> Result<()> {
    if let Some((count, (x, y))) = composite.image.non_finite() {
        anyhow::bail!(
            "the composite holds {count} NaN or infinite pixel(s), the first at ({x}, {y}) (a bug in mrshade, \
             please report it with the session)"
        );
    }
    Ok(())
}

/// The sub-pixel offset of the `k`-th (from 1) averaged frame: Halton (2, 3), centred.
pub(crate) fn jitter(k: u32) -> Vec2 {
    Vec2::new(halton(2, k), halton(3, k)) - 0.5
}

/// The mean of composites.
#[derive(Default)]
pub(crate) struct Average {
    sum: Option<Composite>,
    count: u32,
}

impl Average {
    /// Adds one composite.
    pub(crate) fn add(&mut self, c: Composite) {
        self.count += 1;
        match &mut self.sum {
            None => self.sum = Some(c),
            Some(s) => {
                for (a, b) in s.image.pixels.iter_mut().zip(&c.image.pixels) {
                    for k in 0..3 {
                        a[k] += b[k];
                    }
                }
                for (a, b) in s.coverage.iter_mut().zip(&c.coverage) {
                    *a += b;
                }
            }
        }
    }

    /// The mean, checked for NaN.
    pub(crate) fn finish(self) -> Result<Composite> {
        let mut mean = self.sum.expect("at least one composite");
        let scale = 1.0 / self.count as f32;
        for p in &mut mean.image.pixels {
            *p = p.map(|c| c * scale);
        }
        for c in &mut mean.coverage {
            *c *= scale;
        }
        check_finite(&mean)?;
        Ok(mean)
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
