//! THE frame: the passes in order (Knecht §1.4, restricted to what the selected method
//! computes). Every pass is recorded into one encoder and timed on its own.

use crate::renderer::Renderer;
use anyhow::Result;
use mrshade_core::settings::Method;
use mrshade_gpu::GpuContext;
use mrshade_gpu::timing::Recorder;
use wgpu_profiler::GpuProfiler;

impl Renderer {
    /// Records one frame.
    pub fn record_frame(&self, rec: &mut Recorder) {
        // 1. Shadow maps: real-only and virtual-only casters per light.
        self.shadows.record(rec, &self.rasterizer);
        // 2. G-buffer of real and virtual surfaces: visibility, then attributes.
        self.gbuffer_pass.record(rec, &self.rasterizer);
        // 3. Light transport into L_rv and L_r from the same evaluation.
        match self.settings.method {
            Method::Direct => self.direct.record(rec),
        }
        // 4. Differential composite with the photo.
        self.composite.record(rec);
    }

    /// Records and submits one frame; timings (if enabled) go to `profiler`.
    pub fn render(&mut self, ctx: &GpuContext, profiler: &mut GpuProfiler) -> Result<()> {
        self.scene.geometry.begin_frame(&ctx.queue);
        ctx.checked("rendering a frame", || {
            let mut rec = Recorder::new(ctx, profiler, "frame");
            self.record_frame(&mut rec);
            ctx.queue.submit([rec.finish()]);
            Ok(())
        })
    }

    /// Renders one untimed frame and waits for it.
    pub fn render_once(&mut self, ctx: &GpuContext) -> Result<()> {
        let mut profiler = mrshade_gpu::timing::profiler(ctx, false)?;
        self.render(ctx, &mut profiler)?;
        profiler.end_frame().map_err(|e| anyhow::anyhow!("profiler: {e}"))?;
        ctx.wait_idle()
    }
}
