//! Temporal smoothing (Knecht §2.10, Eq. 5.11–5.15) and the geometry-aware merge of the
//! interleaved buffers. The history is double-buffered; the previous frame's depth and
//! normals are kept for the confidence test.

use crate::methods::{INDIRECT_TARGETS, IndirectLight};
use crate::passes::gbuffer::GBuffer;
use bytemuck::{Pod, Zeroable};
use glam::{UVec4, Vec4};
use mrshade_core::settings::{DirSettings, TemporalSettings};
use mrshade_gpu::timing::Recorder;
use mrshade_gpu::{GpuContext, Target, bind, wgsl};
use wgpu::util::DeviceExt;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable, PartialEq)]
struct TemporalParams {
    weights: Vec4,
    values: Vec4,
    /// Interleave I, 1 if geometry moved (then the history is clamped to the range of an
    /// I×I window of new values), 1 while a still scene accumulates (no illumination test).
    block: UVec4,
}

/// Frames a still scene keeps the thesis's smoothing before it accumulates: the multiple-
/// bounce source adds one bounce per frame, so the first frames lack light that a running
/// mean would keep for long.
pub const STILL_WARMUP_FRAMES: u32 = 8;

/// The history's weight after `still_frames` frames in which nothing moved (0 on the frame
/// of a change): `c_B`, then, after the warm-up, a running mean over the still frames
/// (1 − 1/n) once that exceeds `c_B`, up to `static_confidence`. Returns the weight and
/// whether the scene accumulates.
pub fn history_weight(t: &TemporalSettings, still_frames: u32) -> (f32, bool) {
    if !t.enabled {
        return (0.0, false);
    }
    let n = still_frames.saturating_sub(STILL_WARMUP_FRAMES) as f32;
    let running = 1.0 - 1.0 / (n + 1.0);
    let c = running.min(t.static_confidence);
    if c > t.base_confidence { (c, true) } else { (t.base_confidence, false) }
}

impl TemporalParams {
    fn new(t: &TemporalSettings, interleave: u32, exposure: f32, history: History) -> Self {
        let [wx, wy, wd] = t.position_weights;
        let (mut confidence, accumulating) = history_weight(t, history.still_frames);
        if history.camera_moved {
            confidence = confidence.min(t.moving_camera_confidence);
        }
        Self {
            weights: Vec4::new(wx, wy, wd, t.normal_weight),
            values: Vec4::new(t.illumination_weight, confidence, exposure, history.exists as u32 as f32),
            block: UVec4::new(interleave, history.moved as u32, accumulating as u32, 0),
        }
    }
}

/// What the temporal step needs to know of the frames before this one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct History {
    /// A previous frame exists (false after a reset).
    pub exists: bool,
    /// Geometry or a light moved since it (light in the world changed).
    pub moved: bool,
    /// The camera moved since it (the history is reprojected).
    pub camera_moved: bool,
    /// Frames since anything moved (0 on the frame of a change).
    pub still_frames: u32,
}

/// Temporal smoothing then filtering of the indirect buffers.
pub struct FilterPass {
    /// Smoothed history, `[parity]`.
    pub history: [IndirectLight; 2],
    /// The filtered result the final shading reads.
    pub merged: IndirectLight,
    temporal: wgpu::ComputePipeline,
    filter: wgpu::ComputePipeline,
    temporal_params: wgpu::Buffer,
    settings: TemporalSettings,
    interleave: u32,
    params: TemporalParams,
    exposure: f32,
    /// `[parity]`: temporal groups 0, 1, 2, then filter groups 0, 1, 2.
    groups: [[wgpu::BindGroup; 6]; 2],
    size: (u32, u32),
}

impl FilterPass {
    /// GPU timing label of the temporal step.
    pub const TEMPORAL_LABEL: &'static str = "temporal";
    /// GPU timing label of the filter.
    pub const LABEL: &'static str = "filter";

    /// Builds both steps over `input` (the interleaved shading output).
    pub fn new(
        ctx: &GpuContext,
        frame: &wgpu::Buffer,
        settings: &DirSettings,
        exposure: f32,
        gbuffer: &GBuffer,
        input: &IndirectLight,
    ) -> Self {
        let device = &ctx.device;
        let size = input.size();
        let history = [
            IndirectLight::new(device, "temporal/history0", size),
            IndirectLight::new(device, "temporal/history1", size),
        ];
        let merged = IndirectLight::new(device, "filter/merged", size);
        // Written by the filter step, pixel by pixel, once the temporal step has read them: a
        // texture copy here cost 0.9 ms at 1080p on an H100 (layout transitions).
        let copy_usage = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING;
        let previous_depth_motion = Target::new_2d(
            device,
            "temporal/previous_depth_motion",
            size,
            gbuffer.depth_motion.texture.format(),
            copy_usage,
        );
        let previous_normal_roughness = Target::new_2d(
            device,
            "temporal/previous_normal_roughness",
            size,
            gbuffer.normal_roughness.texture.format(),
            copy_usage,
        );
        let cs = wgpu::ShaderStages::COMPUTE;
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let d2 = wgpu::TextureViewDimension::D2;
        let params = TemporalParams::new(&settings.temporal, settings.interleave, exposure, History::default());
        let temporal_params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("temporal/params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let filter_params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("filter/params"),
            contents: bytemuck::bytes_of(&UVec4::new(settings.interleave, settings.filter as u32, 0, 0)),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let tex = |b| bind::texture(b, cs, unfilterable, d2);
        let temporal_layout = bind::layout(
            device,
            "temporal/gbuffer_layout",
            &[bind::uniform(0, cs), bind::uniform(1, cs), tex(2), tex(3), tex(4), tex(5)],
        );
        let mut temporal_inputs = IndirectLight::sampled_entries(0).to_vec();
        temporal_inputs.extend(IndirectLight::sampled_entries(INDIRECT_TARGETS as u32));
        let temporal_in_layout = bind::layout(device, "temporal/in_layout", &temporal_inputs);
        let filter_layout = bind::layout(
            device,
            "filter/gbuffer_layout",
            &[
                bind::uniform(0, cs),
                bind::uniform(1, cs),
                tex(2),
                tex(3),
                bind::storage_texture(4, gbuffer.depth_motion.texture.format()),
                bind::storage_texture(5, gbuffer.normal_roughness.texture.format()),
            ],
        );
        let in_layout = bind::layout(device, "filter/in_layout", &IndirectLight::sampled_entries(0));
        let out_layout = bind::layout(device, "filter/out_layout", &IndirectLight::storage_entries());
        use wgpu::BindingResource::TextureView;
        let groups = [0usize, 1].map(|parity| {
            let (now, before) = (&history[parity], &history[1 - parity]);
            let mut temporal_inputs: Vec<wgpu::BindingResource> = input.resources().into();
            temporal_inputs.extend(before.resources());
            [
                bind::group(
                    device,
                    "temporal/gbuffer_group",
                    &temporal_layout,
                    &[
                        frame.as_entire_binding(),
                        temporal_params.as_entire_binding(),
                        TextureView(&gbuffer.depth_motion.view),
                        TextureView(&gbuffer.normal_roughness.view),
                        TextureView(&previous_depth_motion.view),
                        TextureView(&previous_normal_roughness.view),
                    ],
                ),
                bind::group(device, "temporal/in_group", &temporal_in_layout, &temporal_inputs),
                bind::group(device, "temporal/out_group", &out_layout, &now.resources()),
                bind::group(
                    device,
                    "filter/gbuffer_group",
                    &filter_layout,
                    &[
                        frame.as_entire_binding(),
                        filter_params.as_entire_binding(),
                        TextureView(&gbuffer.depth_motion.view),
                        TextureView(&gbuffer.normal_roughness.view),
                        TextureView(&previous_depth_motion.view),
                        TextureView(&previous_normal_roughness.view),
                    ],
                ),
                bind::group(device, "filter/in_group", &in_layout, &now.resources()),
                bind::group(device, "filter/out_group", &out_layout, &merged.resources()),
            ]
        });
        let temporal = mrshade_gpu::shader::compute_pipeline(
            device,
            "temporal",
            TEMPORAL_SHADER,
            &[&temporal_layout, &temporal_in_layout, &out_layout],
        );
        let filter = mrshade_gpu::shader::compute_pipeline(
            device,
            "filter",
            FILTER_SHADER,
            &[&filter_layout, &in_layout, &out_layout],
        );
        Self {
            history,
            merged,
            temporal,
            filter,
            temporal_params,
            settings: settings.temporal,
            interleave: settings.interleave,
            exposure,
            groups,
            size,
            params,
        }
    }

    /// Tells the temporal step what happened in the frames before this one (see
    /// temporal.wgsl: clamping after motion, accumulation while still).
    pub fn prepare(&mut self, queue: &wgpu::Queue, history: History) {
        let p = TemporalParams::new(&self.settings, self.interleave, self.exposure, history);
        if p != self.params {
            self.params = p;
            queue.write_buffer(&self.temporal_params, 0, bytemuck::bytes_of(&p));
        }
    }

    /// Smooths into history `parity`, then filters into `merged` and keeps this frame's
    /// depth and normals for the next one.
    pub fn record(&self, rec: &mut Recorder, parity: usize) {
        let [t0, t1, t2, f0, f1, f2] = &self.groups[parity];
        let (x, y) = (self.size.0.div_ceil(8), self.size.1.div_ceil(8));
        rec.compute(Self::TEMPORAL_LABEL, |pass| {
            pass.set_pipeline(&self.temporal);
            pass.set_bind_group(0, t0, &[]);
            pass.set_bind_group(1, t1, &[]);
            pass.set_bind_group(2, t2, &[]);
            pass.dispatch_workgroups(x, y, 1);
        });
        rec.compute(Self::LABEL, |pass| {
            pass.set_pipeline(&self.filter);
            pass.set_bind_group(0, f0, &[]);
            pass.set_bind_group(1, f1, &[]);
            pass.set_bind_group(2, f2, &[]);
            pass.dispatch_workgroups(x, y, 1);
        });
    }
}

/// The temporal module.
pub const TEMPORAL_SHADER: &str =
    wgsl!("../../../../shaders/lib/frame.wgsl", "../../../../shaders/lib/env_visibility.wgsl", "temporal.wgsl");
/// The filter module.
pub const FILTER_SHADER: &str =
    wgsl!("../../../../shaders/lib/frame.wgsl", "../../../../shaders/lib/geometry_weight.wgsl", "filter.wgsl");

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_still_scene_accumulates_after_the_warm_up_and_only_when_asked_to() {
        let thesis = TemporalSettings { static_confidence: 0.9, ..TemporalSettings::default() };
        for still in [0, 5, 50, 5000] {
            assert_eq!(history_weight(&thesis, still), (0.9, false), "static_confidence = c_B: the thesis's c_B");
        }
        let t = TemporalSettings { static_confidence: 0.99, ..thesis };
        assert_eq!(history_weight(&t, STILL_WARMUP_FRAMES), (0.9, false));
        // A running mean (1 − 1/n over the n frames after the warm-up) once above c_B…
        assert_eq!(history_weight(&t, STILL_WARMUP_FRAMES + 9), (0.9, false));
        assert_eq!(history_weight(&t, STILL_WARMUP_FRAMES + 19), (0.95, true));
        // …up to static_confidence.
        assert_eq!(history_weight(&t, STILL_WARMUP_FRAMES + 1000), (0.99, true));
        // The default accumulates up to 0.996 (a window of about 250 frames).
        let default = TemporalSettings::default();
        assert_eq!(history_weight(&default, 0), (0.9, false));
        assert_eq!(history_weight(&default, 5000), (0.996, true));
        let off = TemporalSettings { enabled: false, ..t };
        assert_eq!(history_weight(&off, 1000), (0.0, false));
    }
}
