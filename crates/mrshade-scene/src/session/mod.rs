//! The session file (TOML): which glTF, which photo (or posed image sequence), which probe,
//! how to render.
//!
//! ```toml
//! scene = "scene.gltf"          # glTF 2.0 (.gltf or .glb), relative to this file
//! background = "background.png" # the camera photo: PNG/JPEG (sRGB) or EXR (linear)
//!                               # (or, instead, [sequence] transforms)
//! exposure = 0.96               # linear camera value = exposure × scene radiance
//! camera = "camera"             # optional: glTF camera by node or camera name (default: the first),
//!                               # or a [camera] table placing one (see `camera`)
//! method = "dir"                # optional: light-transport method ("dir" or "direct")
//! [environment]                 # optional: the real light probe
//! image = "environment.exr"     # equirectangular EXR or Radiance HDR
//! rotation_deg = 0.0            # about +Y, right-handed
//! intensity = 1.0               # radiance scale
//! [output]                      # optional: defaults to the photo's size
//! width = 640
//! height = 480
//! supersample = 1               # shading samples per pixel per axis (1–4)
//! frames = 256                  # frames for a still, the last half averaged (default: 256 for dir, 1 for direct)
//! [composite]                   # optional: see mrshade_core::settings::CompositeSettings
//! [shadows]                     # optional: see mrshade_core::settings::ShadowSettings
//! [dir]                         # optional: see mrshade_core::settings::DirSettings
//! [specular]                    # optional: see mrshade_core::settings::SpecularSettings
//! [caustics]                    # optional: see mrshade_core::settings::CausticsSettings
//! [reference]                   # optional: see mrshade_core::settings::ReferenceSettings
//! [sequence]                    # optional: a posed image sequence (see crate::sequence)
//! transforms = "transforms.json" # nerfstudio / instant-ngp poses and photos, instead of `background`
//! fps = 30                      # frames per second (default 30): frame k is at time k / fps
//! samples = 32                  # jittered renderer frames averaged per footage frame (1 = real time)
//! # frames = 48                 # instead of `transforms`, with `background`: 48 frames of that photo
//! [[insert]]                    # optional, repeated: a model from its own glTF file (see `insert`)
//! model = "Duck.glb"
//! ```
//! Parsing is strict: an unknown key, a wrong type, a missing file, or a photo whose aspect
//! ratio does not match the camera is an error naming the file and the field.
//!
//! Exactly one of `background` and `[sequence] transforms` is given. A `transforms` session
//! takes its cameras from the JSON: the glTF's camera, if any, gives only the near plane, and
//! its aspect ratio is not checked. `background` holds frame 0's photo and the output size
//! defaults to its size; [`Session::photo_at`] and [`Session::view_at`] give any frame's.

mod camera;
mod file;
mod insert;
mod output;

pub use camera::SESSION_CAMERA;
pub use insert::Insert;

pub use output::{MAX_OUTPUT_SIDE, MIN_OUTPUT_SIDE, OutputSize};

use camera::{CameraChoice, parse_camera, pick_camera};
use file::{SessionFile, parse};
use output::{check_aspect, output_size};

use crate::assets::ReadPolicy;
use crate::budget::Budget;
use crate::sequence::{DEFAULT_FPS, DEFAULT_ZNEAR, MAX_SAMPLES, Sequence, SequenceFrame, check_fps};
use crate::{AssetSource, Camera, Scene, gltf::load_gltf, images};
use anyhow::{Context, Result, bail};
use glam::Mat4;
use mrshade_core::HdrImage;
use mrshade_core::camera::{CameraView, Intrinsics};
use mrshade_core::settings::{Limits, Method, RenderSettings};
use mrshade_core::text::number;
use std::path::PathBuf;

/// Largest session file read, in bytes (a session is a few lines of TOML).
const MAX_SESSION_BYTES: u64 = 16 << 20;
/// Range of `exposure`: outside it the camera values over- or underflow single precision.
const EXPOSURE_RANGE: std::ops::RangeInclusive<f32> = 1e-12..=1e12;

/// The real light probe.
#[derive(Clone, Debug)]
pub struct Environment {
    /// Equirectangular linear radiance.
    pub image: HdrImage,
    /// Rotation about +Y in degrees (right-handed).
    pub rotation_deg: f32,
    /// Radiance scale.
    pub intensity: f32,
}

/// Command-line changes applied before the session is parsed, so they are checked as
/// strictly as the file itself.
#[derive(Clone, Debug, Default)]
pub struct SessionOverrides {
    /// Output width.
    pub width: Option<u32>,
    /// Output height.
    pub height: Option<u32>,
    /// Light-transport method.
    pub method: Option<Method>,
    /// `key=value` pairs with dotted keys (`shadows.resolution=4096`), values in TOML syntax.
    pub set: Vec<String>,
    /// Accept an output size of another aspect ratio than the photo and camera, stretching
    /// the photo (for `bench`, which measures speed at standard sizes).
    pub stretch_photo: bool,
    /// Folders that files may also be read from (`--allow-read`), besides the session's.
    pub allow_read: Vec<PathBuf>,
}

/// Name of the camera a `transforms` session adds to `scene.cameras` when its glTF has none.
pub const SEQUENCE_CAMERA: &str = "sequence frame 0";

/// A loaded, checked session: everything a renderer needs for one frame (or, with a
/// [`Sequence`], for each: [`Session::photo_at`], [`Session::view_at`]).
#[derive(Clone, Debug)]
pub struct Session {
    /// Where it came from, for messages.
    pub origin: String,
    /// Real proxy and virtual content.
    pub scene: Scene,
    /// Index of the render camera in `scene.cameras`: always valid. When a `transforms`
    /// session's glTF has no camera, one is appended, named [`SEQUENCE_CAMERA`], with frame 0's
    /// pose and vertical field of view and a near plane of [`DEFAULT_ZNEAR`].
    pub camera: usize,
    /// The photo (frame 0's in a `transforms` session), linear, resampled to the output size.
    pub background: HdrImage,
    /// Linear camera value = exposure × radiance.
    pub exposure: f32,
    /// The real light probe, if any.
    pub environment: Option<Environment>,
    /// Output size.
    pub output: OutputSize,
    /// Method and pass settings.
    pub settings: RenderSettings,
    /// The input budgets the session was loaded with.
    pub limits: Limits,
    /// What could not be honoured exactly (from the glTF and the probe).
    pub warnings: Vec<String>,
    /// The frames of a sequence (`[sequence]`); `None` for a still.
    pub sequence: Option<Sequence>,
    /// The models of `[[insert]]`, in order.
    pub inserts: Vec<Insert>,
    /// The folder of a session on disk, where what is computed from its files is cached
    /// (baked PRT); `None` for a built-in one.
    pub folder: Option<std::path::PathBuf>,
}

impl Session {
    /// Loads the session file at `path` on disk.
    pub fn load(path: &std::path::Path, overrides: &SessionOverrides) -> Result<Session> {
        // `session.toml` alone has the parent "": the current folder.
        let folder = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => std::path::PathBuf::from("."),
        };
        let file = path
            .file_name()
            .with_context(|| format!("session {}: the path names no file", path.display()))?
            .to_string_lossy()
            .into_owned();
        let policy = ReadPolicy::new(std::slice::from_ref(&folder), MAX_SESSION_BYTES);
        Self::load_from(&AssetSource::dir_with_policy(folder, policy), &file, overrides)
    }

    /// Loads the session file `rel` of `source`.
    pub fn load_from(source: &AssetSource, rel: &str, overrides: &SessionOverrides) -> Result<Session> {
        let origin = source.display(rel);
        let mut session = load(source, rel, overrides, origin.clone()).with_context(|| format!("session {origin}"))?;
        session.folder = source.folder();
        Ok(session)
    }

    /// The node of the insert named `name`.
    pub fn insert_node(&self, name: &str) -> Option<usize> {
        self.inserts.iter().find(|i| i.name == name).map(|i| i.node)
    }

    /// `view` with the render camera where `pose` puts it (an animation moving its node),
    /// unless the sequence's own poses place the camera (a `transforms` session).
    pub fn animated_view(&self, mut view: CameraView, pose: &crate::ScenePose) -> CameraView {
        let from_transforms = self.sequence.as_ref().is_some_and(|s| s.from_transforms);
        if !from_transforms && let Some(&m) = pose.cameras.get(self.camera) {
            view.world_from_camera = m;
        }
        view
    }

    /// Frames to render: the sequence's, or 1 for a still.
    pub fn frame_count(&self) -> usize {
        self.sequence.as_ref().map_or(1, |s| s.frames.len())
    }

    /// Frame `k`'s photo, linear, resampled to the output size (for a still and a repeated
    /// photo, `background`); a `transforms` frame's is read and decoded now, under the
    /// session's limits.
    pub fn photo_at(&self, k: usize) -> Result<HdrImage> {
        let count = self.frame_count();
        if k >= count {
            bail!("session {}: there is no frame {k} (the session has {count})", self.origin);
        }
        let (width, height) = (self.output.width, self.output.height);
        match &self.sequence {
            Some(seq) if seq.from_transforms => {
                let photo = seq
                    .photo(k, &self.limits)
                    .with_context(|| format!("session {}: field `sequence.transforms`", self.origin))?;
                Ok(photo.resized(width, height))
            }
            _ => Ok(self.background.resized(width, height)),
        }
    }

    /// Frame `k`'s camera (the last frame's past the end), its intrinsics in pixels of the
    /// output size. A `transforms` frame's pose and intrinsics, with the near plane of the
    /// render camera; otherwise the render camera (its rest pose) as a centred pinhole of its
    /// vertical field of view.
    pub fn view_at(&self, k: usize) -> CameraView {
        let (width, height) = (self.output.width, self.output.height);
        let camera = self.scene.cameras.get(self.camera);
        let znear = camera.map_or(DEFAULT_ZNEAR, |c| c.znear);
        if let Some(seq) = self.sequence.as_ref().filter(|s| s.from_transforms)
            && let Some(frame) = seq.frames.get(k.min(seq.frames.len().saturating_sub(1)))
        {
            let intrinsics = frame.intrinsics.scaled_to(width, height);
            return CameraView { world_from_camera: frame.world_from_camera, intrinsics, znear };
        }
        let (world_from_camera, yfov) =
            camera.map_or((Mat4::IDENTITY, DEFAULT_YFOV), |c| (c.world_from_camera, c.yfov));
        CameraView { world_from_camera, intrinsics: Intrinsics::from_yfov(yfov, width, height), znear }
    }
}

/// Vertical field of view of [`Session::view_at`] for a session without a camera (one built
/// by hand), in radians.
const DEFAULT_YFOV: f32 = 0.8;

fn load(source: &AssetSource, rel: &str, overrides: &SessionOverrides, origin: String) -> Result<Session> {
    let text = String::from_utf8(source.read(rel)?).context("the file is not UTF-8 text")?;
    let file = parse(&text, overrides)?;
    let field = |name: &str| format!("field `{name}`");
    file.limits.validate().map_err(anyhow::Error::msg)?;
    let folder = readable_folder(source, rel, &file.limits, overrides);
    let (background, transforms, repeat) = photo_sources(&file, &file.limits)?;
    let fps = file.sequence.as_ref().map_or(DEFAULT_FPS, |s| s.fps);
    let limits = file.limits;

    if !EXPOSURE_RANGE.contains(&file.exposure) {
        bail!(
            "{}: must be a number between {:e} and {:e}, got {}",
            field("exposure"),
            EXPOSURE_RANGE.start(),
            EXPOSURE_RANGE.end(),
            number(file.exposure)
        );
    }
    let settings = RenderSettings {
        method: overrides.method.unwrap_or(file.method),
        composite: file.composite,
        shadows: file.shadows,
        dir: file.dir,
        dvct: file.dvct,
        dlpv: file.dlpv,
        ibl: file.ibl,
        specular: file.specular,
        caustics: file.caustics,
        reference: file.reference,
    };
    settings.validate().map_err(anyhow::Error::msg)?;

    let mut scene = load_gltf(&folder, &file.scene, &limits).with_context(|| field("scene"))?;
    let inserts = insert::load_inserts(&mut scene, &file.inserts, &folder, &limits)?;
    if scene.lights.len() > limits.lights as usize {
        bail!(
            "{}: the scene has {} lights, more than `limits.lights` = {} (each needs up to 12 shadow-map layers on \
             the GPU; raise it with --set limits.lights=N)",
            field("scene"),
            scene.lights.len(),
            limits.lights
        );
    }
    let sequence = match &transforms {
        Some(rel) => {
            Some(Sequence::load_transforms(&folder, rel, fps, &limits).with_context(|| field("sequence.transforms"))?)
        }
        None => None,
    };
    // The poses give a `transforms` session its cameras; a glTF without one gets frame 0's.
    let choice = file.camera.as_ref().map(parse_camera).transpose().with_context(|| field("camera"))?;
    let camera = match (choice, sequence.as_ref().and_then(|s| s.frames.first())) {
        (Some(CameraChoice::Placed(placed)), _) => {
            scene.cameras.push(placed);
            scene.cameras.len() - 1
        }
        (None, Some(first)) if scene.cameras.is_empty() => {
            scene.cameras.push(sequence_camera(first));
            scene.cameras.len() - 1
        }
        (Some(CameraChoice::Named(name)), _) => pick_camera(&scene, Some(&name)).with_context(|| field("camera"))?,
        (None, _) => pick_camera(&scene, None).with_context(|| field("camera"))?,
    };
    // A weight for a source that does not exist (a misspelt light name) would be ignored.
    let sources: Vec<&str> = scene
        .lights
        .iter()
        .map(|l| l.name.as_str())
        .chain(["environment", "environment_bounce", "bounce", "caustics"])
        .collect();
    if let Some(name) = settings.dir.weights.keys().find(|k| !sources.contains(&k.as_str())) {
        bail!("{}: no light or VPL source is named '{name}' (known: {})", field("dir.weights"), sources.join(", "));
    }

    let budget = Budget::new(&limits);
    let photo = match (&sequence, background.as_deref()) {
        (Some(seq), _) => seq.photo(0, &limits).with_context(|| field("sequence.transforms"))?,
        (None, background) => {
            let background = background.unwrap_or_default();
            images::decode_photo(&folder.read(background).with_context(|| field("background"))?, &budget)
                .with_context(|| format!("{}: {}", field("background"), folder.display(background)))?
        }
    };
    if let Some(aspect) = scene.cameras[camera].aspect_ratio.filter(|_| !overrides.stretch_photo && sequence.is_none())
    {
        check_aspect(photo.aspect(), aspect).with_context(|| {
            format!(
                "{}: the photo is {}×{} but camera '{}' has aspectRatio {aspect:.4}",
                field("background"),
                photo.width,
                photo.height,
                scene.cameras[camera].node_name
            )
        })?;
    }
    let output =
        output_size(&file.output, overrides, &photo, settings.method, &budget).with_context(|| field("output"))?;
    if let Some(k) = sequence.as_ref().and_then(|s| s.frames.first()).map(|f| f.intrinsics)
        && !overrides.stretch_photo
    {
        check_aspect(output.width as f32 / output.height as f32, k.width as f32 / k.height as f32).with_context(
            || {
                format!(
                    "{}: the output is {}×{} but the cameras of `sequence.transforms` are {}×{}",
                    field("output"),
                    output.width,
                    output.height,
                    k.width,
                    k.height
                )
            },
        )?;
    }
    let sequence = match (sequence, repeat, background.as_deref()) {
        (Some(seq), ..) => Some(seq),
        (None, Some(count), Some(background)) => {
            let c = &scene.cameras[camera];
            let intrinsics = Intrinsics::from_yfov(c.yfov, photo.width, photo.height);
            Some(Sequence::repeated(&folder, background, count, fps, c.world_from_camera, intrinsics))
        }
        _ => None,
    };
    let sequence = match (sequence, &file.sequence) {
        (Some(mut seq), Some(table)) => {
            if !(1..=MAX_SAMPLES).contains(&table.samples) {
                bail!("{}: must be between 1 and {MAX_SAMPLES}, got {}", field("sequence.samples"), table.samples);
            }
            seq.samples = table.samples;
            Some(seq)
        }
        (seq, _) => seq,
    };
    let background = photo.resized(output.width, output.height);

    let mut warnings = scene.warnings.clone();
    let environment = match file.environment {
        None => None,
        Some(env) => {
            let what = field("environment.image");
            if !(env.intensity.is_finite() && env.intensity >= 0.0) {
                bail!("{}: must be a number ≥ 0, got {}", field("environment.intensity"), env.intensity);
            }
            if !env.rotation_deg.is_finite() {
                bail!("{}: must be a finite number", field("environment.rotation_deg"));
            }
            let bytes = folder.read(&env.image).with_context(|| what.clone())?;
            let (image, warning) = images::decode_probe(&bytes, &budget)
                .with_context(|| format!("{what}: {}", folder.display(&env.image)))?;
            if image.max_value() * env.intensity > images::MAX_RADIANCE {
                bail!(
                    "{}: {} × the probe's brightest value {} is larger than {:e}, beyond what mrshade computes with",
                    field("environment.intensity"),
                    number(env.intensity),
                    number(image.max_value()),
                    images::MAX_RADIANCE
                );
            }
            warnings.extend(warning.map(|w| format!("{}: {w}", folder.display(&env.image))));
            Some(Environment { image, rotation_deg: env.rotation_deg, intensity: env.intensity })
        }
    };

    Ok(Session {
        origin,
        scene,
        camera,
        background,
        exposure: file.exposure,
        environment,
        output,
        settings,
        limits,
        warnings,
        sequence,
        inserts,
        folder: None,
    })
}

/// Checks that exactly one of `background` and `[sequence] transforms` is given, and the rest
/// of `[sequence]`: the photo, the transforms file and the number of frames of the photo.
fn photo_sources(file: &SessionFile, limits: &Limits) -> Result<(Option<String>, Option<String>, Option<usize>)> {
    let field = |name: &str| format!("field `{name}`");
    let Some(seq) = &file.sequence else {
        let background = file.background.clone();
        background.as_ref().with_context(|| {
            format!(
                "{}: missing: give the camera photo, or `[sequence] transforms` (posed images)",
                field("background")
            )
        })?;
        return Ok((background, None, None));
    };
    check_fps(seq.fps)?;
    match (&file.background, &seq.transforms, seq.frames) {
        (Some(_), Some(_), _) => bail!(
            "{}: give either `background` (one photo) or `[sequence] transforms` (posed images), not both",
            field("background")
        ),
        (None, None, _) => bail!(
            "{}: missing: give the camera photo (with `[sequence] frames`), or `[sequence] transforms` (posed images)",
            field("background")
        ),
        (_, Some(_), Some(_)) => {
            bail!("{}: not with `sequence.transforms`, whose file lists the frames", field("sequence.frames"))
        }
        (Some(_), None, None) => bail!(
            "{}: missing: with `background`, `[sequence]` needs the number of frames of that photo",
            field("sequence.frames")
        ),
        (_, _, Some(n)) if !(1..=limits.sequence_frames).contains(&n) => bail!(
            "{}: must be between 1 and `limits.sequence_frames` = {}, got {n}",
            field("sequence.frames"),
            limits.sequence_frames
        ),
        _ => Ok((file.background.clone(), seq.transforms.clone(), seq.frames.map(|n| n as usize))),
    }
}

/// The render camera of a `transforms` session whose glTF has none: frame 0's.
fn sequence_camera(frame: &SequenceFrame) -> Camera {
    Camera {
        node_name: SEQUENCE_CAMERA.into(),
        camera_name: None,
        yfov: frame.intrinsics.yfov(),
        aspect_ratio: None,
        znear: DEFAULT_ZNEAR,
        world_from_camera: frame.world_from_camera,
    }
}

/// The session's folder, readable under the session's folder, the folders `limits.allow_read`
/// names (relative to it) and those given on the command line, with files of at most
/// `limits.file_mib`.
fn readable_folder(source: &AssetSource, rel: &str, limits: &Limits, overrides: &SessionOverrides) -> AssetSource {
    match source.folder_of(rel) {
        AssetSource::Dir { folder, .. } => {
            let mut roots = vec![folder.clone()];
            roots.extend(limits.allow_read.iter().map(|p| folder.join(p)));
            roots.extend(overrides.allow_read.iter().cloned());
            AssetSource::dir_with_policy(&folder, ReadPolicy::new(&roots, limits.file_bytes()))
        }
        embedded => embedded,
    }
}
