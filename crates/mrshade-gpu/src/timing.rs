//! GPU timing of passes through timestamp queries (wgpu-profiler), never CPU clocks around
//! `submit`. Without `TIMESTAMP_QUERY` the same code records the same passes, untimed.

use crate::GpuContext;
use anyhow::Result;
use wgpu_profiler::{GpuProfiler, GpuProfilerSettings, GpuTimerQueryResult};

/// A command encoder whose passes are each a timed scope.
pub struct Recorder<'a> {
    /// The encoder passes are recorded into.
    pub encoder: wgpu::CommandEncoder,
    profiler: &'a mut GpuProfiler,
}

impl<'a> Recorder<'a> {
    /// Starts recording a frame.
    pub fn new(ctx: &GpuContext, profiler: &'a mut GpuProfiler, label: &str) -> Self {
        let encoder = ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
        Self { encoder, profiler }
    }

    /// Records one compute pass named `label`.
    pub fn compute<R>(&mut self, label: &str, f: impl FnOnce(&mut wgpu::ComputePass<'_>) -> R) -> R {
        let query = self.profiler.begin_pass_query(label, &mut self.encoder);
        let out = {
            let mut pass = self.encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: query.compute_pass_timestamp_writes(),
            });
            f(&mut pass)
        };
        self.profiler.end_query(&mut self.encoder, query);
        out
    }

    /// Records one render pass named `label` into the given attachments.
    pub fn render<R>(
        &mut self,
        label: &str,
        color: &[Option<wgpu::RenderPassColorAttachment>],
        depth: Option<wgpu::RenderPassDepthStencilAttachment>,
        f: impl FnOnce(&mut wgpu::RenderPass<'_>) -> R,
    ) -> R {
        let query = self.profiler.begin_pass_query(label, &mut self.encoder);
        let out = {
            let mut pass = self.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: color,
                depth_stencil_attachment: depth,
                timestamp_writes: query.render_pass_timestamp_writes(),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            f(&mut pass)
        };
        self.profiler.end_query(&mut self.encoder, query);
        out
    }

    /// Finishes the frame's commands (resolving its timestamps).
    pub fn finish(mut self) -> wgpu::CommandBuffer {
        self.profiler.resolve_queries(&mut self.encoder);
        self.encoder.finish()
    }
}

/// Creates a profiler; queries are enabled only when `timed` and the device supports them.
pub fn profiler(ctx: &GpuContext, timed: bool) -> Result<GpuProfiler> {
    let settings = GpuProfilerSettings {
        enable_timer_queries: timed && ctx.timestamps,
        enable_debug_groups: false,
        max_num_pending_frames: 4,
    };
    GpuProfiler::new(&ctx.device, settings).map_err(|e| anyhow::anyhow!("cannot create the GPU profiler: {e}"))
}

/// One frame's pass timings: `(label, start s, end s)` in submission order.
pub fn flatten(results: &[GpuTimerQueryResult]) -> Vec<(String, f64, f64)> {
    let mut out = Vec::new();
    for r in results {
        if let Some(t) = &r.time {
            out.push((r.label.clone(), t.start, t.end));
        }
        out.extend(flatten(&r.nested_queries));
    }
    out
}

/// One frame's GPU time in milliseconds: from its first pass's start to its last pass's end
/// (`passes` as [`flatten`] gives them); `None` without any timed pass.
pub fn frame_ms(passes: &[(String, f64, f64)]) -> Option<f64> {
    let start = passes.iter().map(|p| p.1).reduce(f64::min)?;
    let end = passes.iter().map(|p| p.2).reduce(f64::max)?;
    Some((end - start) * 1e3)
}
