//! Posed image sequences: a session's `[sequence]`, read from a nerfstudio / instant-ngp
//! `transforms.json`, or one photo repeated for a number of frames.
//!
//! ```json
//! { "camera_model": "PINHOLE", "w": 320, "h": 240, "fl_x": 289.7, "fl_y": 289.7, "cx": 160, "cy": 120,
//!   "frames": [ { "file_path": "frames/0000.png", "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,2],[0,0,0,1]] } ] }
//! ```
//! Intrinsics are in pixels (`fl_x`, `fl_y`, `cx`, `cy` of a `w × h` image; or `camera_angle_x`
//! [+ `camera_angle_y`] in radians, as instant-ngp writes), at the top level or per frame (a
//! frame's own keys win; `cx`, `cy` default to the centre, `w`, `h` to the image's size). Each
//! frame has a `file_path` (relative to the JSON's folder; when it does not exist as written,
//! `.png`, `.jpg`, `.jpeg` and `.exr` are tried after it, as nerfstudio may omit them) and a
//! 4×4 camera-to-world `transform_matrix`, by rows, in OpenGL axes (x right, y up, looking down
//! −z: a glTF camera's axes), which becomes the frame's `world_from_camera`. Frames keep the
//! order of the list: frame k is at time k / fps.
//!
//! mrshade renders pinhole cameras: `camera_model` must be absent, `PINHOLE` or
//! `SIMPLE_PINHOLE`, and the distortion keys (`k1`–`k4`, `p1`, `p2`) zero; undistort the images
//! first. This is a foreign format: keys mrshade does not use (`aabb_scale`, `mask_path`,
//! `applied_transform`, …) are skipped unread, but those it uses are checked strictly, with
//! one-line errors that name the file, the frame and the key. The frame list is counted against
//! `limits.sequence_frames` while it is parsed. At load, each frame's image header (not its
//! pixels) is read: every image must exist, all must have one size, and the intrinsics must
//! match it, or its aspect ratio within 1 % (then they are scaled to the image, as for
//! nerfstudio's downscaled `images_2/` folders).

mod parse;

use crate::AssetSource;
use crate::budget::Budget;
use crate::images;
use anyhow::{Context, Result, anyhow, bail};
use glam::Mat4;
use mrshade_core::HdrImage;
use mrshade_core::camera::Intrinsics;
use mrshade_core::settings::Limits;
use mrshade_core::text::printable;
use parse::{
    ANGLE_X, ANGLE_Y, CX, CY, DISTORTION, FL_X, FL_Y, H, Keys, NUMBER_KEYS, RawMatrix, RawObject, W, parse, parse_frame,
};
use std::collections::HashMap;
use std::fmt;
use std::path::Path;

/// Frames per second when `[sequence] fps` is not given.
pub const DEFAULT_FPS: f32 = 30.0;
/// Near plane of a `transforms` session's cameras when its glTF has no camera, in metres.
pub const DEFAULT_ZNEAR: f32 = 0.01;
/// Largest `[sequence] fps`.
pub const MAX_FPS: f32 = 1000.0;
/// Extensions tried, in order, after a `file_path` that does not exist as written.
pub const IMAGE_EXTENSIONS: [&str; 4] = ["png", "jpg", "jpeg", "exr"];
/// Largest deviation of a pose's rotation part from orthonormal with determinant +1.
const RIGID_TOLERANCE: f64 = 1e-3;
/// Relative aspect-ratio mismatch tolerated between the intrinsics' `w × h` and the image.
const ASPECT_TOLERANCE: f64 = 0.01;
/// Farthest camera position from the origin, in metres (as glTF geometry).
const MAX_POSITION: f64 = 1e6;
/// Longest focal length, in pixels (a field of view of a nanoradian per pixel).
const MAX_FOCAL: f64 = 1e9;
/// Largest `w` or `h`, in pixels.
const MAX_SIDE: f64 = (1u32 << 24) as f64;
/// Longest piece of a file's text quoted in a message, in characters.
const MAX_QUOTE: usize = 120;

/// One frame of a sequence: its photo and its camera.
#[derive(Clone, Debug, PartialEq)]
pub struct SequenceFrame {
    /// The image file's stem (`0000` for `frames/0000.png`), unique in the sequence: outputs
    /// are numbered by it. For a repeated photo, the zero-padded frame index.
    pub name: String,
    /// The photo, relative to the session's folder (as [`Sequence::source`] reads it).
    pub file: String,
    /// Camera → world, rigid; the camera looks down its −Z with +Y up.
    pub world_from_camera: Mat4,
    /// Projection in pixels of the frame's image (its own size, not the output's).
    pub intrinsics: Intrinsics,
}

/// Renderer frames per footage frame unless `[sequence] samples` says otherwise: an eighth of
/// a `dir` still's 256. A footage frame is the mean of these jittered frames, as a still is of
/// its last 128: on `desk-orbit` the mean region FLIP of frames 4–23 is 1.68× that of the
/// converged stills with 1 (a live stream's real time), 1.45× with 4, 1.29× with 16 and 1.14×
/// with 32 (the noise of the interleaved VPL subsets averages out; anti-aliasing alone is
/// reached by 4).
pub const DEFAULT_SAMPLES: u32 = 32;
/// Most renderer frames per footage frame.
pub const MAX_SAMPLES: u32 = 256;

/// The frames of a session, in order.
#[derive(Clone, Debug)]
pub struct Sequence {
    /// Frames per second: frame k is at time k / fps (for glTF animations).
    pub fps: f32,
    /// At least one frame.
    pub frames: Vec<SequenceFrame>,
    /// Whether the frames come from a `transforms.json` (their own photos and cameras), or
    /// repeat the session's photo and glTF camera (`background` with `[sequence] frames`).
    pub from_transforms: bool,
    /// Where the frames' photos are read from: the session's folder, under its read policy.
    pub source: AssetSource,
    /// Jittered renderer frames averaged per footage frame (`[sequence] samples`): its
    /// anti-aliasing, as a still's averaged frames are. 1 for a live stream's real time.
    pub samples: u32,
}

impl Sequence {
    /// The time of frame `k`, in seconds.
    pub fn time(&self, k: usize) -> f32 {
        k as f32 / self.fps
    }

    /// `count` frames of one `photo` (relative to `source`) seen by one camera.
    pub fn repeated(
        source: &AssetSource,
        photo: &str,
        count: usize,
        fps: f32,
        world_from_camera: Mat4,
        intrinsics: Intrinsics,
    ) -> Sequence {
        let frames = (0..count)
            .map(|k| SequenceFrame { name: format!("{k:04}"), file: photo.to_string(), world_from_camera, intrinsics })
            .collect();
        Sequence { fps, frames, from_transforms: false, source: source.clone(), samples: DEFAULT_SAMPLES }
    }

    /// Reads the `transforms.json` file `rel` of `source` and checks every frame (see the
    /// module documentation), within `limits`.
    pub fn load_transforms(source: &AssetSource, rel: &str, fps: f32, limits: &Limits) -> Result<Sequence> {
        let shown = source.display(rel);
        check_fps(fps)?;
        let bytes = source.read(rel)?;
        let raw = parse(&bytes, limits.sequence_frames as usize).map_err(|e| one_line(&shown, &e))?;
        let folder = Path::new(rel).parent().unwrap_or(Path::new(""));
        let frames = check_frames(source, folder, &raw, limits).map_err(|e| one_line(&shown, &e))?;
        Ok(Sequence { fps, frames, from_transforms: true, source: source.clone(), samples: DEFAULT_SAMPLES })
    }

    /// Frame `k`'s photo, decoded to linear RGB at its own size under `limits`.
    pub fn photo(&self, k: usize, limits: &Limits) -> Result<HdrImage> {
        let frame =
            self.frames.get(k).with_context(|| format!("there is no frame {k} ({} frames)", self.frames.len()))?;
        let shown = self.source.display(&frame.file);
        let what = || format!("frame {k}: {}", printable(&shown));
        let bytes = self.source.read(&frame.file).with_context(what)?;
        let photo = images::decode_photo(&bytes, &Budget::new(limits)).with_context(what)?;
        let expected = (frame.intrinsics.width, frame.intrinsics.height);
        if self.from_transforms && (photo.width, photo.height) != expected {
            bail!(
                "{}: the image is {}×{}, but it was {}×{} when the sequence was loaded",
                what(),
                photo.width,
                photo.height,
                expected.0,
                expected.1
            );
        }
        Ok(photo)
    }
}

/// Checks `[sequence] fps`.
pub fn check_fps(fps: f32) -> Result<()> {
    if !(fps > 0.0 && fps <= MAX_FPS) {
        bail!("field `sequence.fps`: must be a number of frames per second above 0 and at most {MAX_FPS}, got {fps}");
    }
    Ok(())
}

/// A camera given as one frame of a `transforms.json` gives it, on its own: a JSON object with
/// an optional `transform_matrix` (checked as a file's: rigid, OpenGL axes, camera-to-world)
/// and optional intrinsics (`fl_x`, `fl_y`, `cx`, `cy`, `w`, `h` or `camera_angle_x` [+
/// `camera_angle_y`]; `w × h` defaults to `size` and is scaled to it when its aspect ratio is
/// within 1 %). Other keys are skipped unread. This is how `mrshade stream --poses` reads its
/// pose lines. Returns `world_from_camera` and the intrinsics in pixels of `size`, each `None`
/// when not given.
pub fn camera_from_json(json: &[u8], size: (u32, u32)) -> Result<(Option<Mat4>, Option<Intrinsics>)> {
    let raw = parse_frame(json)?;
    check_pinhole(&raw.keys)?;
    let world_from_camera = raw.matrix.as_ref().map(pose).transpose().map_err(anyhow::Error::msg)?;
    let given = [FL_X, FL_Y, CX, CY, W, H, ANGLE_X, ANGLE_Y].iter().any(|&k| raw.keys.numbers[k].is_some());
    let intrinsics =
        given.then(|| intrinsics(&Keys::default(), &raw.keys, size)).transpose().map_err(anyhow::Error::msg)?;
    Ok((world_from_camera, intrinsics))
}

/// `{file}: {error}` on one line, control characters escaped.
fn one_line(shown: &str, e: &anyhow::Error) -> anyhow::Error {
    anyhow!("{}", printable(&format!("{shown}: {e:#}")))
}

/// `s` cut to [`MAX_QUOTE`] characters.
fn quote(s: &str) -> String {
    match s.char_indices().nth(MAX_QUOTE) {
        Some((at, _)) => format!("{}…", &s[..at]),
        None => s.to_string(),
    }
}

/// Checks the frames and their images; errors name the frame and the key (not the file).
fn check_frames(source: &AssetSource, folder: &Path, raw: &RawObject, limits: &Limits) -> Result<Vec<SequenceFrame>> {
    let top = &raw.keys;
    check_pinhole(top).context("top level")?;
    let Some(list) = &raw.frames else { bail!("`frames` is missing: the file lists no frames") };
    if list.is_empty() {
        bail!("`frames` is empty: a sequence needs at least one frame");
    }
    let mut budget = Budget::new(limits);
    budget.charge("the frame list", list.len() as u64, std::mem::size_of::<SequenceFrame>() as u64 + 64)?;
    let mut frames: Vec<SequenceFrame> = Vec::with_capacity(list.len());
    let mut names: HashMap<String, usize> = HashMap::new();
    for (i, raw) in list.iter().enumerate() {
        let label = match &raw.file_path {
            Some(p) => format!("frame {i} ({})", quote(p)),
            None => format!("frame {i}"),
        };
        let frame = check_frame(source, folder, raw, top, &budget).with_context(|| label.clone())?;
        if let Some(first) = frames.first()
            && (frame.intrinsics.width, frame.intrinsics.height) != (first.intrinsics.width, first.intrinsics.height)
        {
            bail!(
                "{label}: the image is {}×{} but frame 0's ({}) is {}×{}; every frame's image must have the same size",
                frame.intrinsics.width,
                frame.intrinsics.height,
                quote(&first.file),
                first.intrinsics.width,
                first.intrinsics.height
            );
        }
        if let Some(&j) = names.get(&frame.name) {
            bail!(
                "{label}: its image has the name `{}` of frame {j}'s ({}); outputs are named after the image files",
                quote(&frame.name),
                quote(&frames[j].file)
            );
        }
        names.insert(frame.name.clone(), i);
        frames.push(frame);
    }
    Ok(frames)
}

fn check_frame(
    source: &AssetSource,
    folder: &Path,
    raw: &RawObject,
    top: &Keys,
    budget: &Budget,
) -> Result<SequenceFrame> {
    check_pinhole(&raw.keys)?;
    let Some(file_path) = &raw.file_path else { bail!("`file_path` is missing") };
    let Some(matrix) = &raw.matrix else { bail!("`transform_matrix` is missing") };
    let world_from_camera = pose(matrix).map_err(anyhow::Error::msg)?;
    let (file, size) = find_image(source, &folder.join(file_path).to_string_lossy(), budget).context("`file_path`")?;
    let intrinsics = intrinsics(top, &raw.keys, size).map_err(anyhow::Error::msg)?;
    let name = Path::new(&file).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    Ok(SequenceFrame { name, file, world_from_camera, intrinsics })
}

/// Refuses camera models and distortion that a pinhole camera cannot render.
fn check_pinhole(keys: &Keys) -> Result<()> {
    if let Some(model) = &keys.camera_model
        && !matches!(model.as_str(), "PINHOLE" | "SIMPLE_PINHOLE")
    {
        bail!(
            "`camera_model` is \"{}\": mrshade renders pinhole cameras (PINHOLE or SIMPLE_PINHOLE); undistort the \
             images first",
            quote(model)
        );
    }
    for (name, value) in DISTORTION.iter().map(|&k| (NUMBER_KEYS[k], keys.numbers[k])) {
        if let Some(v) = value.filter(|v| *v != 0.0) {
            bail!(
                "`{name}` is {v}: mrshade renders pinhole cameras without lens distortion; undistort the images first"
            );
        }
    }
    Ok(())
}

/// The rows of a `transform_matrix` as a rigid camera-to-world transform.
fn pose(m: &RawMatrix) -> Result<Mat4, String> {
    let shape = "`transform_matrix` must be 4×4 (4 rows of 4 numbers, camera-to-world)";
    if let Some((row, len)) = m.bad_row {
        return Err(format!("{shape}; row {row} has {len} numbers"));
    }
    if m.row_count != 4 {
        return Err(format!("{shape}; it has {} rows", m.row_count));
    }
    let r = &m.rows;
    for (i, row) in r.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            if !(*v as f32).is_finite() {
                return Err(format!(
                    "`transform_matrix` row {i} column {j} is {v:e}, not a finite single-precision number"
                ));
            }
        }
    }
    if r[3].iter().zip([0.0, 0.0, 0.0, 1.0]).any(|(a, b)| (a - b).abs() > 1e-6) {
        return Err(format!(
            "`transform_matrix`: the bottom row is [{}, {}, {}, {}], not [0, 0, 0, 1]",
            r[3][0], r[3][1], r[3][2], r[3][3]
        ));
    }
    // Columns of the rotation part: the camera's axes in the world.
    let col = |j: usize| [r[0][j], r[1][j], r[2][j]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (x, y, z) = (col(0), col(1), col(2));
    let cross = [x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]];
    let det = dot(cross, z);
    let off = [dot(x, x) - 1.0, dot(y, y) - 1.0, dot(z, z) - 1.0, dot(x, y), dot(y, z), dot(z, x)];
    if off.iter().any(|e| e.abs() > RIGID_TOLERANCE) || (det - 1.0).abs() > RIGID_TOLERANCE {
        return Err(format!(
            "`transform_matrix` is not a rigid transform: its rotation part is not orthonormal with determinant +1 \
             within {RIGID_TOLERANCE:e} (axis lengths {:.4}, {:.4}, {:.4}, determinant {:.4}); a scale or a mirror is \
             not a camera pose",
            dot(x, x).sqrt(),
            dot(y, y).sqrt(),
            dot(z, z).sqrt(),
            det
        ));
    }
    let distance = dot([r[0][3], r[1][3], r[2][3]], [r[0][3], r[1][3], r[2][3]]).sqrt();
    if distance > MAX_POSITION {
        return Err(format!(
            "`transform_matrix`: the camera is {distance:e} m from the origin, farther than {MAX_POSITION:e} m (mrshade \
             works in metres)"
        ));
    }
    let rows = r.map(|row| row.map(|v| v as f32));
    Ok(Mat4::from_cols_array_2d(&rows).transpose())
}

/// Reads the image `file` (or `file` with one of [`IMAGE_EXTENSIONS`] after it, when it does
/// not exist as written): the file actually read and its size from the header.
fn find_image(source: &AssetSource, file: &str, budget: &Budget) -> Result<(String, (u32, u32))> {
    let (file, bytes) = match source.read(file) {
        Ok(bytes) => (file.to_string(), bytes),
        Err(e) => IMAGE_EXTENSIONS
            .iter()
            .map(|ext| format!("{file}.{ext}"))
            .find_map(|f| source.read(&f).ok().map(|bytes| (f, bytes)))
            .ok_or(e)?,
    };
    let size = image_size(&bytes).with_context(|| source.display(&file))?;
    budget.check_image(size.0, size.1).with_context(|| source.display(&file))?;
    Ok((file, size))
}

/// `width × height` of a photo from its header alone.
fn image_size(bytes: &[u8]) -> Result<(u32, u32)> {
    use image::ImageFormat::{Hdr, Jpeg, OpenExr, Png};
    let format = image::guess_format(bytes).context("unrecognised image format (expected PNG, JPEG, EXR or HDR)")?;
    if !matches!(format, Png | Jpeg | OpenExr | Hdr) {
        bail!("unsupported image format {format:?} (expected PNG, JPEG, EXR or HDR)");
    }
    let (w, h) = image::ImageReader::with_format(std::io::Cursor::new(bytes), format)
        .into_dimensions()
        .context("cannot read the image header")?;
    if w == 0 || h == 0 {
        bail!("the image is empty ({w}×{h})");
    }
    Ok((w, h))
}

/// A number the file gave, and where: the frame's own keys or the top level.
#[derive(Clone, Copy)]
struct Given {
    value: f64,
    key: usize,
    top: bool,
}

impl fmt::Display for Given {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "`{}`{}", NUMBER_KEYS[self.key], if self.top { " (top level)" } else { "" })
    }
}

/// `keys`' value of `key`, if given.
fn given(keys: &Keys, key: usize, top: bool) -> Option<Given> {
    keys.numbers[key].map(|value| Given { value, key, top })
}

/// The frame's intrinsics (its keys over the top level's), matched to its image of `size`.
fn intrinsics(top: &Keys, own: &Keys, size: (u32, u32)) -> Result<Intrinsics, String> {
    let get = |key: usize| given(own, key, false).or(given(top, key, true));
    let side = |key: usize, image: u32| match get(key) {
        None => Ok(image as f64),
        Some(g) if g.value.fract() == 0.0 && (1.0..=MAX_SIDE).contains(&g.value) => Ok(g.value),
        Some(g) => Err(format!("{g} must be a whole number of pixels between 1 and {MAX_SIDE}, got {}", g.value)),
    };
    let (w, h) = (side(W, size.0)?, side(H, size.1)?);
    // A frame's own focal length, in either form, overrides the top level's.
    let focal = |fl: usize, angle: usize, extent: f64| -> Result<Option<f64>, String> {
        let first = given(own, fl, false).or(given(own, angle, false));
        let Some(g) = first.or(given(top, fl, true)).or(given(top, angle, true)) else { return Ok(None) };
        let value = if g.key == angle {
            if !(g.value > 0.0 && g.value < std::f64::consts::PI) {
                return Err(format!("{g} must be a field of view in radians between 0 and π, got {}", g.value));
            }
            0.5 * extent / (0.5 * g.value).tan()
        } else {
            g.value
        };
        if !(value > 0.0 && value <= MAX_FOCAL && (value as f32) > 0.0) {
            return Err(format!("{g} must give a focal length above 0 and at most {MAX_FOCAL:e} pixels, got {value}"));
        }
        Ok(Some(value))
    };
    let (fl_x, fl_y) = match (focal(FL_X, ANGLE_X, w)?, focal(FL_Y, ANGLE_Y, h)?) {
        (Some(x), Some(y)) => (x, y),
        (Some(f), None) | (None, Some(f)) => (f, f),
        (None, None) => {
            return Err(
                "the intrinsics are missing: give `fl_x` (and `fl_y`) in pixels or `camera_angle_x` in radians, at the \
                 top level or per frame"
                    .into(),
            );
        }
    };
    let centre = |key: usize, extent: f64, what: &str| match get(key) {
        None => Ok(0.5 * extent),
        Some(g) if (0.0..=extent).contains(&g.value) => Ok(g.value),
        Some(g) => Err(format!("{g} = {} puts the principal point outside the image, {what} 0 to {extent}", g.value)),
    };
    let (cx, cy) = (centre(CX, w, "whose columns run from")?, centre(CY, h, "whose rows run from")?);
    let k = Intrinsics {
        fl_x: fl_x as f32,
        fl_y: fl_y as f32,
        cx: cx as f32,
        cy: cy as f32,
        width: w as u32,
        height: h as u32,
    };
    if (k.width, k.height) == size {
        return Ok(k);
    }
    let (given, image) = (w / h, size.0 as f64 / size.1 as f64);
    if (given / image - 1.0).abs() > ASPECT_TOLERANCE {
        return Err(format!(
            "`w` × `h` is {w}×{h} but the image is {}×{}, of another aspect ratio (more than 1 % apart)",
            size.0, size.1
        ));
    }
    Ok(k.scaled_to(size.0, size.1))
}
