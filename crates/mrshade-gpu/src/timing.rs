//! GPU timing of passes through timestamp queries (wgpu-profiler), never CPU clocks around
//! `submit`. Without `TIMESTAMP_QUERY` the same code records the same passes, untimed.

use crate::GpuContext;
use anyhow::Result;
use wgpu_profiler::{GpuProfiler, GpuProfilerSettings, GpuTimerQueryResult};

/// A command encoder whose passes are each a timed scope.
///
/// The GPU runs one pass after another (a pass waits for all the work before it), but the
/// dispatches of one compute pass side by side where no barrier separates them. Work that
/// reads nothing the passes before a *host* pass write can therefore be handed to
/// [`Recorder::beside`]: the next [`Recorder::compute_hosting`] pass records it with its own
/// dispatch, so that a chain of dependent reads on a few threads (the specular rays) fills
/// the GPU beside a pass that has many threads (the method's shading).
pub struct Recorder<'a> {
    /// The encoder passes are recorded into.
    pub encoder: wgpu::CommandEncoder,
    profiler: &'a mut GpuProfiler,
    /// Jobs waiting for a host pass.
    waiting: Vec<SideJob>,
    /// Record every job as a pass of its own at once (`mrshade bench --serial`: per-pass
    /// times).
    serial: bool,
}

/// One compute dispatch, recorded later (see [`SideJob`]).
#[derive(Clone, Debug)]
pub struct Dispatch {
    /// The pipeline.
    pub pipeline: wgpu::ComputePipeline,
    /// Bind groups 0, 1, …
    pub groups: Vec<wgpu::BindGroup>,
    /// Workgroups along x, y, z.
    pub workgroups: [u32; 3],
}

impl Dispatch {
    /// Sets the pipeline and groups and dispatches.
    pub fn record(&self, pass: &mut wgpu::ComputePass) {
        set_pipeline_and_groups(pass, &self.pipeline, &self.groups);
        let [x, y, z] = self.workgroups;
        pass.dispatch_workgroups(x, y, z);
    }
}

/// Sets `pipeline` and its bind groups 0, 1, … in order (before a dispatch).
pub fn set_pipeline_and_groups<'g>(
    pass: &mut wgpu::ComputePass,
    pipeline: &wgpu::ComputePipeline,
    groups: impl IntoIterator<Item = &'g wgpu::BindGroup>,
) {
    pass.set_pipeline(pipeline);
    for (i, g) in groups.into_iter().enumerate() {
        pass.set_bind_group(i as u32, g, &[]);
    }
}

/// Dispatches that need nothing of the passes between where they are handed over and where
/// their results are read, run beside a host pass (see [`Recorder`]).
#[derive(Clone, Debug)]
pub struct SideJob {
    /// Its name in the timings (a host pass is named `host ∥ job`).
    pub label: String,
    /// Independent of each other and of the host's dispatches: recorded right after the
    /// host's last dispatch, which they run beside (no barrier precedes a resource's first
    /// use in a pass; barriers between the host's own dispatches would wait for them).
    pub first: Vec<Dispatch>,
    /// Reading what `first` wrote: recorded after it (a barrier before them waits for all
    /// the pass's work so far).
    pub then: Vec<Dispatch>,
}

impl<'a> Recorder<'a> {
    /// Starts recording a frame.
    pub fn new(ctx: &GpuContext, profiler: &'a mut GpuProfiler, label: &str) -> Self {
        let encoder = ctx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(label) });
        Self { encoder, profiler, waiting: Vec::new(), serial: false }
    }

    /// Records side jobs as passes of their own where they are handed over (per-pass times
    /// instead of the fastest frame).
    pub fn serial(mut self, serial: bool) -> Self {
        self.serial = serial;
        self
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

    /// Hands `job` to the next host pass ([`Recorder::compute_hosting`]); its results may be
    /// read after [`Recorder::flush_side_jobs`].
    pub fn beside(&mut self, job: SideJob) {
        self.waiting.push(job);
        if self.serial {
            self.flush_side_jobs();
        }
    }

    /// A compute pass named `label` that also runs the waiting side jobs beside the last of
    /// `f`'s dispatches.
    pub fn compute_hosting<R>(&mut self, label: &str, f: impl FnOnce(&mut wgpu::ComputePass<'_>) -> R) -> R {
        let jobs = std::mem::take(&mut self.waiting);
        if jobs.is_empty() {
            return self.compute(label, f);
        }
        let names: Vec<&str> = jobs.iter().map(|j| j.label.as_str()).collect();
        let label = format!("{label} ∥ {}", names.join(" ∥ "));
        self.compute(&label, |pass| {
            let out = f(pass);
            jobs.iter().flat_map(|j| &j.first).for_each(|d| d.record(pass));
            jobs.iter().flat_map(|j| &j.then).for_each(|d| d.record(pass));
            out
        })
    }

    /// Records the side jobs no host took, each as a pass of its own: their results are
    /// ready for the passes after this.
    pub fn flush_side_jobs(&mut self) {
        for job in std::mem::take(&mut self.waiting) {
            self.compute(&job.label, |pass| job.first.iter().chain(&job.then).for_each(|d| d.record(pass)));
        }
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
        self.flush_side_jobs();
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
