//! Live streams: a session composited onto frames that arrive one at a time (a webcam, a
//! video decoded by ffmpeg), each with its own photo and, where a tracker gives them, its own
//! camera pose, intrinsics and insert poses ([`StreamFrame`]). One renderer frame per stream
//! frame, without jitter: real time, as footage with `[sequence] samples = 1`, and the
//! method's temporal reuse carries over from frame to frame as it does in footage.
//!
//! A frame's photo is 8-bit sRGB RGB at the output size, decoded as a PNG photo is (the exact
//! 8-bit table of `srgb_u8_decode_table`, no exposure applied: the session's `exposure`
//! relates photo values to radiance), and its composite is encoded to 8-bit sRGB as `mrshade
//! render` writes a PNG ([`mrshade_core::HdrImage::to_srgb8`]'s codes, computed on the GPU by
//! the encode pass: the same thresholds, searched the same way). A streamed frame is therefore the frame
//! rendered from a PNG of the same pixels with the same inputs.
//!
//! ```no_run
//! # fn main() -> anyhow::Result<()> {
//! use mrshade_render::stream::{Stream, StreamFrame};
//! let ctx = mrshade_gpu::GpuContext::new(&Default::default())?;
//! let session = mrshade_scene::Session::load("session.toml".as_ref(), &Default::default())?;
//! let mut stream = Stream::new(&ctx, session)?;
//! let (w, h) = stream.size();
//! let photo = vec![128u8; (w * h * 3) as usize];
//! let out = stream.composite(&ctx, &StreamFrame::photo(&photo, 0.0))?;
//! assert_eq!(out.rgb.len(), photo.len());
//! # Ok(()) }
//! ```

use crate::frame::FrameInputs;
use crate::passes::encode::EncodePass;
use crate::passes::upload::PackedPhoto;
use crate::renderer::Renderer;
use anyhow::{Context, Result, bail};
use glam::{Mat4, Quat, Vec3};
use mrshade_core::camera::Intrinsics;
use mrshade_core::text::printable;
use mrshade_gpu::GpuContext;
use mrshade_gpu::timing::{flatten, frame_ms, profiler};
use mrshade_scene::{ScenePose, Session, Trs, checked_rotation, checked_scale, checked_translation};
use std::collections::BTreeMap;
use wgpu_profiler::GpuProfiler;

/// The inputs of one stream frame.
#[derive(Clone, Copy, Debug)]
pub struct StreamFrame<'a> {
    /// The photo: `width × height × 3` bytes of 8-bit sRGB RGB at the output size, row by row
    /// from the top (ffmpeg's `rawvideo` `rgb24`).
    pub rgb: &'a [u8],
    /// Seconds since the stream started: the clock of the scene's animations (frame k of a
    /// source of f frames per second is at k / f).
    pub time: f32,
    /// Camera → world, rigid, in the axes of glTF and `transforms.json` (x right, y up,
    /// looking down −z); `None`: the session's camera (where the scene's animations put it).
    pub world_from_camera: Option<Mat4>,
    /// Pinhole intrinsics in pixels of the output size (scaled to it if given for another);
    /// `None`: the session's camera's.
    pub intrinsics: Option<Intrinsics>,
    /// Poses of the session's inserted models, by insert name.
    pub inserts: &'a BTreeMap<String, InsertPose>,
}

/// No insert poses.
static NO_INSERTS: BTreeMap<String, InsertPose> = BTreeMap::new();

impl<'a> StreamFrame<'a> {
    /// A frame of `rgb` at `time` seen by the session's camera, nothing moved.
    pub fn photo(rgb: &'a [u8], time: f32) -> Self {
        Self { rgb, time, world_from_camera: None, intrinsics: None, inserts: &NO_INSERTS }
    }
}

/// Where an inserted model is: its insert node's local transform (relative to the node it
/// hangs under, or the world), as translation, rotation and scale. What is not given keeps
/// the node's own (loaded) value, as for a glTF animation channel; a given pose wins over any
/// animation of the node.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InsertPose {
    /// Translation in metres.
    pub translation: Option<Vec3>,
    /// Rotation, a unit quaternion.
    pub rotation: Option<Quat>,
    /// Scale along the local axes.
    pub scale: Option<Vec3>,
}

impl InsertPose {
    /// A pose from numbers as given (`rotation` as x, y, z, w), checked as a session's
    /// `[[insert]]` is: the translation finite and within [`MAX_WORLD_EXTENT`] metres, the
    /// rotation of unit length within 10⁻³ (then normalised), the scale finite and non-zero.
    pub fn new(translation: Option<[f32; 3]>, rotation: Option<[f32; 4]>, scale: Option<[f32; 3]>) -> Result<Self> {
        let field = |name: &'static str| move |m: String| anyhow::anyhow!("`{name}` {m}");
        Ok(Self {
            translation: translation.map(checked_translation).transpose().map_err(field("translation"))?,
            rotation: rotation.map(checked_rotation).transpose().map_err(field("rotation"))?,
            scale: scale.map(|s| checked_scale(Vec3::from(s))).transpose().map_err(field("scale"))?,
        })
    }

    /// This pose over the node's own transform `rest`.
    pub fn over(&self, rest: Trs) -> Trs {
        Trs {
            translation: self.translation.unwrap_or(rest.translation),
            rotation: self.rotation.unwrap_or(rest.rotation),
            scale: self.scale.unwrap_or(rest.scale),
        }
    }
}

/// One composited frame.
pub struct StreamOutput {
    /// The composite: 8-bit sRGB RGB at the output size, as [`StreamFrame::rgb`].
    pub rgb: Vec<u8>,
    /// GPU time of the frame's passes (timestamp queries), where the device has them.
    pub gpu_ms: Option<f64>,
    /// What could not be honoured in this frame (the frame is rendered without it).
    pub warnings: Vec<String>,
}

/// A session's renderer fed one frame at a time (see the module documentation).
pub struct Stream {
    session: Session,
    renderer: Renderer,
    profiler: GpuProfiler,
    /// The composite to sRGB bytes on the GPU.
    encode: EncodePass,
    /// Extra renderer frames the next frame gets first.
    settle: u32,
    /// The local transform of each insert node the stream has moved, as last applied.
    inserts: BTreeMap<usize, Trs>,
}

impl Stream {
    /// Builds the renderer of `session` (at its output size) and its GPU timer, which times
    /// frames where the device has timestamp queries.
    pub fn new(ctx: &GpuContext, session: Session) -> Result<Self> {
        let renderer = Renderer::new(ctx, &session)?;
        let profiler = profiler(ctx, true)?;
        let encode = ctx.checked("creating the stream's encoder", || {
            Ok(EncodePass::new(ctx, &renderer.composite_targets.composite))
        })?;
        Ok(Self { session, renderer, profiler, encode, settle: 0, inserts: BTreeMap::new() })
    }

    /// The session streamed.
    pub fn session(&self) -> &Session {
        &self.session
    }

    /// Settings this device could not honour, and what was used instead.
    pub fn warnings(&self) -> &[String] {
        &self.renderer.warnings
    }

    /// The frame size, in and out: the session's output size.
    pub fn size(&self) -> (u32, u32) {
        self.renderer.output_size()
    }

    /// Bytes of one frame, in and out.
    pub fn frame_bytes(&self) -> usize {
        let (w, h) = self.size();
        w as usize * h as usize * 3
    }

    /// Renders the next frame's inputs `frames` more times before it (unread), so that a
    /// temporal method has converged on them: what footage does before its first frame, and
    /// a live session once tracking starts.
    pub fn settle(&mut self, frames: u32) {
        self.settle = frames;
    }

    /// Composites `frame` (see the module documentation): one renderer frame, waited for and
    /// read back.
    pub fn composite(&mut self, ctx: &GpuContext, frame: &StreamFrame) -> Result<StreamOutput> {
        let (w, h) = self.size();
        if frame.rgb.len() != self.frame_bytes() {
            bail!("a {w}×{h} RGB frame is {} bytes, this one is {}", self.frame_bytes(), frame.rgb.len());
        }
        let packed = PackedPhoto::from_srgb8(frame.rgb, (w, h));
        let mut warnings = Vec::new();
        let pose = self.scene_pose(frame, &mut warnings)?;
        let mut camera = self.renderer.session_camera();
        if let Some(m) = frame.world_from_camera {
            camera.world_from_camera = m;
        } else if let Some(pose) = &pose {
            camera = self.session.animated_view(camera, pose);
        }
        if let Some(k) = frame.intrinsics {
            camera.intrinsics = k.scaled_to(w, h);
        }
        let inputs = FrameInputs {
            photo: Some(&packed),
            instances: pose.as_ref().map(|p| &p.instances[..]),
            lights: pose.as_ref().map(|p| &p.lights[..]),
            deformations: pose.as_ref().map(|p| &p.deformations[..]),
            ..FrameInputs::camera(camera)
        };
        // The frame's inputs once; settling frames repeat them as they are.
        for i in 0..=std::mem::take(&mut self.settle) {
            let frame = if i == 0 { inputs } else { FrameInputs::camera(camera) };
            self.renderer.render_untimed(ctx, &mut self.profiler, &frame)?;
        }
        let mut gpu_ms = None;
        while let Some(results) = self.profiler.process_finished_frame(ctx.queue.get_timestamp_period()) {
            gpu_ms = frame_ms(&flatten(&results));
        }
        Ok(StreamOutput { rgb: self.encode.read(ctx)?, gpu_ms, warnings })
    }

    /// The scene posed at the frame's time with the inserts where the stream last put them,
    /// or `None` where nothing moves (the renderer keeps the transforms it has). Insert poses
    /// that cannot be applied (an unknown name, geometry sent beyond the world's extent) are
    /// warnings, and the inserts keep their last poses.
    fn scene_pose(&mut self, frame: &StreamFrame, warnings: &mut Vec<String>) -> Result<Option<ScenePose>> {
        let scene = &self.session.scene;
        let mut wanted = self.inserts.clone();
        wanted.extend(apply_insert_poses(&self.session, frame.inserts, warnings));
        let time = frame.time;
        if wanted != self.inserts {
            match scene.pose_with(time, &wanted.iter().map(|(&n, &trs)| (n, trs)).collect::<Vec<_>>()) {
                Ok(pose) => {
                    self.inserts = wanted;
                    return Ok(Some(pose));
                }
                Err(e) => warnings.push(format!("insert poses: {e:#}; the inserts keep their last poses")),
            }
        }
        if !scene.is_animated() {
            return Ok(None);
        }
        let kept: Vec<(usize, Trs)> = self.inserts.iter().map(|(&n, &trs)| (n, trs)).collect();
        scene.pose_with(time, &kept).map(Some).with_context(|| format!("the scene at t = {time} s"))
    }
}

/// The node overrides that place the session's inserts where `inserts` says: each insert's
/// node and its local transform ([`InsertPose::over`] its loaded one). A name that is not one
/// of the session's inserts is a warning.
fn apply_insert_poses(
    session: &Session,
    inserts: &BTreeMap<String, InsertPose>,
    warnings: &mut Vec<String>,
) -> Vec<(usize, Trs)> {
    let mut overrides = Vec::with_capacity(inserts.len());
    for (name, pose) in inserts {
        match session.insert_node(name).and_then(|node| Some((node, session.scene.nodes.get(node)?.rest))) {
            Some((node, rest)) => overrides.push((node, pose.over(rest))),
            None => {
                let known: Vec<String> = session.inserts.iter().map(|i| format!("'{}'", printable(&i.name))).collect();
                warnings.push(format!(
                    "the session has no insert named '{}' ({}); its pose is ignored",
                    printable(name),
                    if known.is_empty() {
                        "it has no [[insert]]".to_string()
                    } else {
                        format!("its inserts: {}", known.join(", "))
                    }
                ));
            }
        }
    }
    overrides
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn insert_poses_are_checked_and_fill_in_the_rest() {
        let pose = InsertPose::new(Some([1.0, 2.0, 3.0]), None, Some([2.0; 3])).unwrap();
        let rest = Trs { translation: Vec3::ZERO, rotation: Quat::from_rotation_y(1.0), scale: Vec3::ONE };
        let trs = pose.over(rest);
        assert_eq!(
            (trs.translation, trs.rotation, trs.scale),
            (Vec3::new(1.0, 2.0, 3.0), rest.rotation, Vec3::splat(2.0))
        );
        let q = InsertPose::new(None, Some([0.0, 0.0, 0.0, 1.0005]), None).unwrap().rotation.unwrap();
        assert!((q.length() - 1.0).abs() < 1e-6, "normalised");
        let err = format!("{:#}", InsertPose::new(None, Some([0.0, 0.0, 0.0, 2.0]), None).unwrap_err());
        assert!(err.contains("not a unit quaternion") && err.contains("length is 2"), "{err}");
        assert!(InsertPose::new(Some([f32::INFINITY, 0.0, 0.0]), None, None).is_err());
        assert!(InsertPose::new(None, None, Some([f32::NAN, 1.0, 1.0])).is_err());
        assert!(InsertPose::new(None, None, Some([1.0, 0.0, 1.0])).is_err());
        assert!(InsertPose::new(Some([0.0, 2e6, 0.0]), None, None).is_err());
        assert!(InsertPose::new(None, Some([f32::NAN, 0.0, 0.0, 1.0]), None).is_err());
    }
}
