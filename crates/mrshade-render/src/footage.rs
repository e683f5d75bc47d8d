//! Footage: a session's frames played in order, each with its own inputs (camera pose and
//! intrinsics, photo, animated transforms), one renderer frame per footage frame, so that
//! temporal reuse carries over from frame to frame as in a live stream (Knecht §2.10 assumes a
//! tracked, moving camera).
//!
//! Each footage frame is `[sequence] samples` renderer frames with sub-pixel jitter, averaged
//! (anti-aliasing, as a still's frames are; 1 for a live stream's real time). Before the first
//! frame it plays, the renderer settles on that frame's inputs (half of
//! `output.frames`, the frames a still converges over), as a live session does once tracking
//! starts. A range `A..B` of a long sequence starts [`RANGE_WARMUP_FRAMES`] frames earlier,
//! unwritten, with every frame numbered as in the whole run (the same VPL samples): the
//! temporal history it reaches at `A` is then the whole run's, up to what the history keeps
//! from before the warm-up. This is how a sequence is sharded across machines.

use crate::frame::FrameInputs;
use crate::outputs::Composite;
use crate::passes::upload::PackedPhoto;
use crate::renderer::Renderer;
use crate::still::{Average, jitter};
use anyhow::{Context, Result};
use glam::Mat4;
use mrshade_core::HdrImage;
use mrshade_core::camera::CameraView;
use mrshade_gpu::GpuContext;
use mrshade_scene::{Deformation, Session};
use std::ops::Range;

/// Frames a range renders before its first written frame, unwritten.
pub const RANGE_WARMUP_FRAMES: usize = 128;

/// The inputs of one footage frame, loaded.
pub struct FrameData {
    /// Index in the session's frames.
    pub index: usize,
    /// Name for numbering outputs (the input image's stem, e.g. `0007`).
    pub name: String,
    /// Camera pose and intrinsics.
    pub camera: CameraView,
    /// The photo, linear, at the output size.
    pub photo: HdrImage,
    /// The same, packed for upload.
    pub packed: PackedPhoto,
    /// Animated `world_from_object` per instance (`None` for a scene without animations).
    pub instances: Option<Vec<Mat4>>,
    /// Animated `world_from_light` per light.
    pub lights: Option<Vec<Mat4>>,
    /// Skin joint matrices and morph weights per instance (`None` without animations).
    pub deformations: Option<Vec<Deformation>>,
}

impl FrameData {
    /// Loads frame `k` of `session`: its pose, its photo and the scene posed at its time.
    pub fn load(session: &Session, k: usize) -> Result<Self> {
        let mut camera = session.view_at(k);
        let photo = session.photo_at(k)?;
        let (mut instances, mut lights, mut deformations) = (None, None, None);
        if session.scene.is_animated() {
            let time = session.sequence.as_ref().map_or(0.0, |seq| seq.time(k));
            let pose = session.scene.pose_at(time).with_context(|| format!("frame {k} (t = {time} s)"))?;
            camera = session.animated_view(camera, &pose);
            instances = Some(pose.instances);
            lights = Some(pose.lights);
            deformations = Some(pose.deformations);
        }
        let name = match &session.sequence {
            Some(seq) => seq.frames.get(k).map_or_else(|| format!("{k:04}"), |f| f.name.clone()),
            None => format!("{k:04}"),
        };
        let packed = PackedPhoto::new(&photo, (session.output.width, session.output.height));
        Ok(Self { index: k, name, camera, photo, packed, instances, lights, deformations })
    }

    /// The frame's inputs for the renderer.
    pub fn inputs(&self) -> FrameInputs<'_> {
        FrameInputs {
            camera: self.camera,
            jitter: glam::Vec2::ZERO,
            photo: Some(&self.packed),
            instances: self.instances.as_deref(),
            lights: self.lights.as_deref(),
            deformations: self.deformations.as_deref(),
        }
    }
}

impl Renderer {
    /// Plays frames `written` of `session` (see the module doc), calling `each` with the
    /// renderer (for AOVs), every frame of `written` and its composite, and `progress(i)`
    /// after every frame rendered (warm-up frames count, out of [`playback_length`]), with
    /// [`RANGE_WARMUP_FRAMES`] before a range.
    pub fn play(
        &mut self,
        ctx: &GpuContext,
        session: &Session,
        written: Range<usize>,
        progress: impl FnMut(usize),
        each: impl FnMut(&Renderer, &FrameData, &Composite) -> Result<()>,
    ) -> Result<()> {
        self.play_with_warmup(ctx, session, written, RANGE_WARMUP_FRAMES, progress, each)
    }

    /// [`Renderer::play`] with `warmup` unwritten frames before a range.
    pub fn play_with_warmup(
        &mut self,
        ctx: &GpuContext,
        session: &Session,
        written: Range<usize>,
        warmup: usize,
        mut progress: impl FnMut(usize),
        mut each: impl FnMut(&Renderer, &FrameData, &Composite) -> Result<()>,
    ) -> Result<()> {
        let start = written.start.saturating_sub(warmup);
        let settle = session.output.frames / 2;
        let samples = session.sequence.as_ref().map_or(1, |seq| seq.samples);
        // Several samples a frame are averaged: the specular light's smoothing stays off.
        self.with_specular_smoothing_paused(samples > 1, |renderer| {
            let mut profiler = mrshade_gpu::timing::profiler(ctx, false)?;
            // Renderer frames are numbered as in the whole run (footage frame k's samples follow
            // the settling frames and k × samples others): a range draws the whole run's samples.
            renderer.seek(start as u32 * samples);
            let first = FrameData::load(session, start)?;
            for i in 0..settle {
                let inputs = if i == 0 { first.inputs() } else { FrameInputs::camera(first.camera) };
                renderer.render_untimed(ctx, &mut profiler, &inputs)?;
            }
            for k in start..written.end {
                let loaded = if k == start { None } else { Some(FrameData::load(session, k)?) };
                let data = loaded.as_ref().unwrap_or(&first);
                let write = k >= written.start;
                let mut mean = Average::default();
                for s in 0..samples {
                    // The frame's own inputs once; its jittered samples (anti-aliasing) keep them.
                    let inputs = if s == 0 && !(k == start && settle > 0) {
                        data.inputs()
                    } else {
                        FrameInputs::camera(data.camera)
                    };
                    let jitter = if samples > 1 { jitter(s + 1) } else { glam::Vec2::ZERO };
                    renderer.render_untimed(ctx, &mut profiler, &FrameInputs { jitter, ..inputs })?;
                    if write {
                        mean.add(renderer.read_composite(ctx)?);
                    }
                }
                progress(k + 1 - start);
                if write {
                    let composite = mean.finish().with_context(|| format!("frame {}", data.name))?;
                    each(renderer, data, &composite)?;
                }
            }
            Ok(())
        })
    }
}

/// Frames a playback of `written` renders with `warmup` frames before it (settling not counted).
pub fn playback_length(written: &Range<usize>, warmup: usize) -> usize {
    written.end - written.start.saturating_sub(warmup)
}
