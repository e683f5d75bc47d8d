//! Temporal smoothing of the specular stage's light (spec §2.19; the filter is ours, see
//! temporal.wgsl): the resolve writes this frame's light into `fresh`; the smoothing blends
//! in the last frame's result and writes what the composite reads, and the same again into
//! the other of two history textures (read next frame; a copy cost 0.3 ms at 1080p on the
//! H200).

use bytemuck::{Pod, Zeroable};
use glam::Vec4;
use mrshade_gpu::timing::{Dispatch, Recorder};
use mrshade_gpu::{Target, bind, wgsl};
use wgpu::util::DeviceExt;

/// Mirrors `TemporalParams` in temporal.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
struct TemporalParams {
    info: Vec4,
}

/// The running mean over still frames stops growing here (its weight 1 − 1/n).
const STILL_FRAMES_MAX: u32 = 1024;

/// The smoothing pass and its two textures.
pub struct SpecularTemporal {
    /// Where the resolve writes this frame's light.
    pub fresh: Target,
    size: (u32, u32),
    pipeline: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    /// `[p]` reads history `p` and writes history `1 − p`.
    groups: [wgpu::BindGroup; 2],
    /// Which history this frame reads.
    parity: usize,
    /// History weight on frames where something changed.
    weight: f32,
    /// Frames the history holds since the last change (0: no history).
    still_frames: u32,
    has_history: bool,
    /// Stills average their own frames: the smoothing passes the light through.
    paused: bool,
}

impl SpecularTemporal {
    /// GPU timing label.
    pub const LABEL: &'static str = "specular/temporal";

    /// The pass for a frame of `size`, smoothing into `output` with `weight` (the setting
    /// `specular.temporal_weight`).
    pub fn new(
        device: &wgpu::Device,
        frame: &wgpu::Buffer,
        depth_motion: &Target,
        output: &Target,
        size: (u32, u32),
        weight: f32,
    ) -> Self {
        let usage =
            wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_SRC;
        let format = output.texture.format();
        let fresh = Target::new_2d(device, "specular/light_fresh", size, format, usage);
        let history =
            [0, 1].map(|k| Target::new_2d(device, &format!("specular/light_history{k}"), size, format, usage));
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("specular/temporal_params"),
            contents: bytemuck::bytes_of(&TemporalParams::zeroed()),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let cs = wgpu::ShaderStages::COMPUTE;
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let d2 = wgpu::TextureViewDimension::D2;
        let layout = bind::layout(
            device,
            "specular/temporal",
            &[
                bind::uniform(0, cs),
                bind::uniform(1, cs),
                bind::texture(2, cs, unfilterable, d2),
                bind::texture(3, cs, unfilterable, d2),
                bind::texture(4, cs, unfilterable, d2),
                bind::storage_texture(5, format),
                bind::storage_texture(6, format),
            ],
        );
        use wgpu::BindingResource::TextureView;
        let groups = [0, 1].map(|p| {
            bind::group(
                device,
                &format!("specular/temporal_{p}"),
                &layout,
                &[
                    frame.as_entire_binding(),
                    params.as_entire_binding(),
                    TextureView(&depth_motion.view),
                    TextureView(&fresh.view),
                    TextureView(&history[p].view),
                    TextureView(&output.view),
                    TextureView(&history[1 - p].view),
                ],
            )
        });
        let pipeline = mrshade_gpu::shader::compute_pipeline(device, Self::LABEL, SHADER, &[&layout]);
        Self {
            fresh,
            size,
            pipeline,
            params,
            groups,
            parity: 0,
            weight,
            still_frames: 0,
            has_history: false,
            paused: false,
        }
    }

    /// Sets this frame's weights: `weight` and the window clamp when the camera, an instance,
    /// a light or the photo `changed` since the last frame, else the running mean of the
    /// still frames.
    pub fn prepare(&mut self, queue: &wgpu::Queue, changed: bool) {
        let (weight, clamp) = if changed {
            self.still_frames = 1;
            (self.weight, 1.0)
        } else {
            self.still_frames = (self.still_frames + 1).min(STILL_FRAMES_MAX);
            (1.0 - 1.0 / self.still_frames as f32, 0.0)
        };
        let has = if self.has_history && !self.paused { 1.0 } else { 0.0 };
        queue.write_buffer(
            &self.params,
            0,
            bytemuck::bytes_of(&TemporalParams { info: Vec4::new(weight, clamp, has, 0.0) }),
        );
    }

    /// Smooths `fresh` into the output and keeps the result for the next frame; `beside`
    /// runs in the same pass (work of the frame's end that nothing after it reads).
    pub fn record(&mut self, rec: &mut Recorder, beside: Option<&Dispatch>) {
        rec.compute(Self::LABEL, |pass| {
            if let Some(d) = beside {
                d.record(pass);
            }
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &self.groups[self.parity], &[]);
            pass.dispatch_workgroups(self.size.0.div_ceil(8), self.size.1.div_ceil(8), 1);
        });
        self.parity = 1 - self.parity;
        self.has_history = true;
    }

    /// Forgets the history (a seek).
    pub fn reset(&mut self) {
        self.has_history = false;
        self.still_frames = 0;
    }

    /// Passes the light through unsmoothed while `paused` (a still image averages its frames
    /// itself, without the bias of a running mean that starts before the method converged).
    pub fn pause(&mut self, paused: bool) {
        self.paused = paused;
        self.reset();
    }
}

/// The composed WGSL module.
pub const SHADER: &str = wgsl!("../../shaders/lib/frame.wgsl", "temporal.wgsl");
