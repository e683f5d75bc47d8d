//! The session file (TOML): which glTF, which photo, which probe, how to render.
//!
//! ```toml
//! scene = "scene.gltf"          # glTF 2.0 (.gltf or .glb), relative to this file
//! background = "background.png" # the camera photo: PNG/JPEG (sRGB) or EXR (linear)
//! exposure = 0.96               # linear camera value = exposure × scene radiance
//! camera = "camera"             # optional: glTF camera by node or camera name (default: the first)
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
//! [reference]                   # optional: see mrshade_core::settings::ReferenceSettings
//! ```
//! Parsing is strict: an unknown key, a wrong type, a missing file, or a photo whose aspect
//! ratio does not match the camera is an error naming the file and the field.

use crate::assets::ReadPolicy;
use crate::budget::Budget;
use crate::{AssetSource, Scene, gltf::load_gltf, images};
use anyhow::{Context, Result, bail};
use mrshade_core::HdrImage;
use mrshade_core::settings::{
    CompositeSettings, DirSettings, Limits, Method, ReferenceSettings, RenderSettings, ShadowSettings,
};
use mrshade_core::text::number;
use serde::Deserialize;
use std::path::PathBuf;

/// Largest accepted output side, in pixels.
pub const MAX_OUTPUT_SIDE: u32 = 16384;
/// Smallest accepted output side, in pixels. The real-time methods shade one sample at the
/// centre of each pixel (× supersample²) while the photo is averaged over it; a pixel that
/// covers much of the scene shows whatever lies at its centre (a 1×1 render of a desk was the
/// white of a lamp-lit torus). Render larger and downscale.
pub const MIN_OUTPUT_SIDE: u32 = 16;
/// Relative aspect-ratio mismatch tolerated between photo, camera and output size.
const ASPECT_TOLERANCE: f32 = 0.01;
/// Largest session file read, in bytes (a session is a few lines of TOML).
const MAX_SESSION_BYTES: u64 = 16 << 20;
/// Range of `exposure`: outside it the camera values over- or underflow single precision.
const EXPOSURE_RANGE: std::ops::RangeInclusive<f32> = 1e-12..=1e12;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SessionFile {
    scene: String,
    background: String,
    #[serde(default = "one")]
    exposure: f32,
    camera: Option<String>,
    #[serde(default)]
    method: Method,
    environment: Option<EnvironmentFile>,
    #[serde(default)]
    output: OutputFile,
    #[serde(default)]
    composite: CompositeSettings,
    #[serde(default)]
    shadows: ShadowSettings,
    #[serde(default)]
    dir: DirSettings,
    #[serde(default)]
    reference: ReferenceSettings,
    #[serde(default)]
    limits: Limits,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct EnvironmentFile {
    image: String,
    #[serde(default)]
    rotation_deg: f32,
    #[serde(default = "one")]
    intensity: f32,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct OutputFile {
    width: Option<u32>,
    height: Option<u32>,
    supersample: Option<u32>,
    frames: Option<u32>,
}

fn one() -> f32 {
    1.0
}

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

/// Output resolution and shading rate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OutputSize {
    /// Output width in pixels.
    pub width: u32,
    /// Output height in pixels.
    pub height: u32,
    /// Shading samples per output pixel along each axis (1 = none).
    pub supersample: u32,
    /// Frames rendered for one still image. Temporal methods converge over the first half;
    /// the still is the mean of the second half (VPL sampling then averages out).
    pub frames: u32,
}

/// Frames a still image takes by default: one for `direct`; 256 for `dir`, whose multiple
/// bounces build up over the first frames and whose still-scene smoothing then averages the
/// VPLs of about 250 frames (`dir.temporal.static_confidence`), the last 128 frames' composites
/// being averaged with sub-pixel jitter. Milliseconds on a GPU; minutes on lavapipe.
pub fn default_frames(method: Method) -> u32 {
    match method {
        Method::Direct => 1,
        Method::Dir => 256,
    }
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

/// A loaded, checked session: everything a renderer needs for one frame.
#[derive(Clone, Debug)]
pub struct Session {
    /// Where it came from, for messages.
    pub origin: String,
    /// Real proxy and virtual content.
    pub scene: Scene,
    /// Index of the render camera in `scene.cameras`.
    pub camera: usize,
    /// The photo, linear, resampled to the output size.
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
        load(source, rel, overrides, origin.clone()).with_context(|| format!("session {origin}"))
    }
}

fn load(source: &AssetSource, rel: &str, overrides: &SessionOverrides, origin: String) -> Result<Session> {
    let text = String::from_utf8(source.read(rel)?).context("the file is not UTF-8 text")?;
    let file = parse(&text, overrides)?;
    let field = |name: &str| format!("field `{name}`");
    file.limits.validate().map_err(anyhow::Error::msg)?;
    let folder = readable_folder(source, rel, &file.limits, overrides);
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
        reference: file.reference,
    };
    settings.validate().map_err(anyhow::Error::msg)?;

    let scene = load_gltf(&folder, &file.scene, &limits).with_context(|| field("scene"))?;
    if scene.lights.len() > limits.lights as usize {
        bail!(
            "{}: the scene has {} lights, more than `limits.lights` = {} (each needs up to 12 shadow-map layers on \
             the GPU; raise it with --set limits.lights=N)",
            field("scene"),
            scene.lights.len(),
            limits.lights
        );
    }
    let camera = pick_camera(&scene, file.camera.as_deref()).with_context(|| field("camera"))?;
    // A weight for a source that does not exist (a misspelt light name) would be ignored.
    let sources: Vec<&str> =
        scene.lights.iter().map(|l| l.name.as_str()).chain(["environment", "environment_bounce", "bounce"]).collect();
    if let Some(name) = settings.dir.weights.keys().find(|k| !sources.contains(&k.as_str())) {
        bail!("{}: no light or VPL source is named '{name}' (known: {})", field("dir.weights"), sources.join(", "));
    }

    let budget = Budget::new(&limits);
    let photo = images::decode_photo(&folder.read(&file.background).with_context(|| field("background"))?, &budget)
        .with_context(|| format!("{}: {}", field("background"), folder.display(&file.background)))?;
    if let Some(aspect) = scene.cameras[camera].aspect_ratio.filter(|_| !overrides.stretch_photo) {
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
    })
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

/// Parses the TOML after applying `--set` overrides to its table.
fn parse(text: &str, overrides: &SessionOverrides) -> Result<SessionFile> {
    if overrides.set.is_empty() {
        return toml::from_str(text).map_err(|e| toml_error(text, &e));
    }
    let mut table: toml::Table = toml::from_str(text).map_err(|e| toml_error(text, &e))?;
    for pair in &overrides.set {
        apply_set(&mut table, pair)?;
    }
    let merged = toml::to_string(&table)?;
    toml::from_str(&merged).map_err(|e| toml_error(&merged, &e).context("with the --set overrides"))
}

/// A TOML error as one line: where, the offending line's text, and what is wrong.
fn toml_error(text: &str, e: &toml::de::Error) -> anyhow::Error {
    let message = e.message().trim().replace('\n', " ");
    let Some(span) = e.span() else { return anyhow::anyhow!("{message}") };
    let start = span.start.min(text.len());
    let line = text[..start].matches('\n').count() + 1;
    let source = text.lines().nth(line - 1).unwrap_or("").trim();
    let source = mrshade_core::text::printable(source);
    anyhow::anyhow!("line {line} (`{source}`): {}", mrshade_core::text::printable(&message))
}

/// Applies one `dotted.key=value` override.
fn apply_set(table: &mut toml::Table, pair: &str) -> Result<()> {
    let (key, value) = pair.split_once('=').with_context(|| format!("--set {pair}: expected KEY=VALUE"))?;
    let value: toml::Value = match toml::from_str::<toml::Table>(&format!("v = {value}")) {
        Ok(mut t) => t.remove("v").context("unreachable")?,
        Err(_) => toml::Value::String(value.to_string()),
    };
    let parts: Vec<&str> = key.trim().split('.').collect();
    let mut node = table;
    for part in &parts[..parts.len() - 1] {
        let entry = node.entry(part.to_string()).or_insert_with(|| toml::Value::Table(toml::Table::new()));
        node = entry.as_table_mut().with_context(|| format!("--set {pair}: `{part}` is not a table"))?;
    }
    node.insert(parts[parts.len() - 1].to_string(), value);
    Ok(())
}

fn pick_camera(scene: &Scene, name: Option<&str>) -> Result<usize> {
    if scene.cameras.is_empty() {
        bail!("the glTF has no perspective camera; add a camera node");
    }
    match name {
        None => Ok(0),
        Some(name) => scene.cameras.iter().position(|c| c.is_named(name)).with_context(|| {
            let known: Vec<_> = scene.cameras.iter().map(|c| c.node_name.as_str()).collect();
            format!("no camera named '{name}' (cameras: {})", known.join(", "))
        }),
    }
}

fn check_aspect(a: f32, b: f32) -> Result<()> {
    if (a / b - 1.0).abs() > ASPECT_TOLERANCE {
        bail!("aspect ratios {a:.4} and {b:.4} differ");
    }
    Ok(())
}

fn output_size(
    file: &OutputFile,
    overrides: &SessionOverrides,
    photo: &HdrImage,
    method: Method,
    budget: &Budget,
) -> Result<OutputSize> {
    let width = overrides.width.or(file.width);
    let height = overrides.height.or(file.height);
    // What was asked for is checked as asked, before anything is derived from it.
    for (name, v) in [("width", width), ("height", height)] {
        if let Some(v) = v
            && !(MIN_OUTPUT_SIDE..=MAX_OUTPUT_SIDE).contains(&v)
        {
            bail!("{name} must be between {MIN_OUTPUT_SIDE} and {MAX_OUTPUT_SIDE}, got {v}");
        }
    }
    let aspect = photo.aspect();
    let derived = |v: f32, name: &str, from: &str, given: u32| -> Result<u32> {
        let v = v.round() as u32;
        if !(MIN_OUTPUT_SIDE..=MAX_OUTPUT_SIDE).contains(&v) {
            bail!(
                "{from} {given} gives a {name} of {v} at the photo's aspect ratio ({}×{}), outside \
                 {MIN_OUTPUT_SIDE}..={MAX_OUTPUT_SIDE}",
                photo.width,
                photo.height
            );
        }
        Ok(v)
    };
    let (width, height) = match (width, height) {
        (None, None) => {
            if photo.width.min(photo.height) < MIN_OUTPUT_SIDE {
                bail!(
                    "the photo is {}×{}; outputs are at least {MIN_OUTPUT_SIDE} pixels a side: give --width",
                    photo.width,
                    photo.height
                );
            }
            (photo.width, photo.height)
        }
        (Some(w), None) => (w, derived(w as f32 / aspect, "height", "width", w)?),
        (None, Some(h)) => (derived(h as f32 * aspect, "width", "height", h)?, h),
        (Some(w), Some(h)) => {
            if !overrides.stretch_photo {
                check_aspect(w as f32 / h as f32, aspect).with_context(|| {
                    format!("{w}×{h} does not have the photo's aspect ratio ({}×{})", photo.width, photo.height)
                })?;
            }
            (w, h)
        }
    };
    budget.check_image(width, height).context("the output size")?;
    let supersample = file.supersample.unwrap_or(1);
    if !(1..=4).contains(&supersample) {
        bail!("supersample must be between 1 and 4, got {supersample}");
    }
    let frames = file.frames.unwrap_or(default_frames(method));
    if !(1..=10_000).contains(&frames) {
        bail!("frames must be between 1 and 10000, got {frames}");
    }
    Ok(OutputSize { width, height, supersample, frames })
}
