//! `--poses`: camera and insert poses, one JSON object a line, read by a thread of their own
//! from a file or a FIFO, so that a slow or silent tracker never holds up a frame.
//!
//! ```json
//! {"frame": 12, "transform_matrix": [[1,0,0,0],[0,1,0,0.4],[0,0,1,2],[0,0,0,1]],
//!  "fl_x": 580, "fl_y": 580, "cx": 320, "cy": 240, "w": 640, "h": 480,
//!  "inserts": {"duck": {"translation": [0,0,0.1], "rotation": [0,0,0,1], "scale": [1,1,1]}}}
//! ```
//! The camera is a frame of a `transforms.json` (nerfstudio / instant-ngp), read by the same
//! parser ([`mrshade_scene::sequence::camera_from_json`]): `transform_matrix` camera-to-world,
//! rigid, OpenGL axes; intrinsics in pixels of a `w × h` image (default: the frame size),
//! scaled to the frame size. Every key is optional, and what a line gives holds until a later
//! line gives it again: the camera pose (the session's until the first), the intrinsics (the
//! session's until the first), each insert's pose. A line with `frame` applies from that frame
//! on; one without, from the next frame rendered. Lines come in frame order: a line for a
//! frame older than one already applied is skipped. A line that is not JSON or fails a check
//! is skipped with one warning, and the last good pose holds.
//!
//! A regular file is read ahead before each frame up to its first line for a later frame, so
//! that its poses apply to exactly their frames (a run over a video file and its poses file
//! is reproducible). A FIFO is never waited for: a frame takes the lines that have arrived (a
//! live tracker), and the FIFO is opened again when its writer closes it.

use super::super::Log;
use anyhow::{Context, Result, anyhow};
use glam::Mat4;
use mrshade_core::camera::Intrinsics;
use mrshade_core::text::printable;
use mrshade_render::stream::InsertPose;
use mrshade_scene::sequence::camera_from_json;
use serde::Deserialize;
use serde_json::Value;
use serde_json::error::Category;
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, sync_channel};

/// Longest line read, in bytes: a longer one is skipped.
const MAX_LINE_BYTES: usize = 1 << 20;
/// Lines parsed ahead of the frame they are for.
const QUEUE_LINES: usize = 256;

/// What one line gives.
#[derive(Debug, Default)]
pub struct Update {
    /// Its line number, from 1.
    pub line: u64,
    /// The frame it applies from (`None`: the next one).
    pub frame: Option<u64>,
    /// Camera → world.
    pub world_from_camera: Option<Mat4>,
    /// Intrinsics in pixels of the frame size.
    pub intrinsics: Option<Intrinsics>,
    /// Insert poses by name.
    pub inserts: BTreeMap<String, InsertPose>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "an object with translation, rotation and scale")]
struct InsertLine {
    translation: Option<[f32; 3]>,
    rotation: Option<[f32; 4]>,
    scale: Option<[f32; 3]>,
}

/// Parses one line for frames of `size`.
pub fn parse_line(text: &[u8], size: (u32, u32)) -> Result<Update> {
    let line: serde_json::Map<String, Value> = serde_json::from_slice(text).map_err(|e| match e.classify() {
        Category::Syntax | Category::Eof | Category::Io => anyhow!("not JSON ({e})"),
        Category::Data => anyhow!("not a JSON object ({e})"),
    })?;
    let frame = match line.get("frame") {
        None => None,
        Some(v) => Some(v.as_u64().context("`frame` must be a frame number: a whole number from 0")?),
    };
    let (world_from_camera, intrinsics) = camera_from_json(text, size)?;
    let mut inserts = BTreeMap::new();
    if let Some(given) = line.get("inserts") {
        let given = given.as_object().context("`inserts` must be an object of insert names")?;
        for (name, pose) in given {
            let what = || format!("`inserts` '{}'", printable(name));
            let pose = InsertLine::deserialize(pose).with_context(what)?;
            let checked = InsertPose::new(pose.translation, pose.rotation, pose.scale).with_context(what)?;
            inserts.insert(name.clone(), checked);
        }
    }
    Ok(Update { line: 0, frame, world_from_camera, intrinsics, inserts })
}

/// Fails at once for a path that cannot be read (before the GPU is opened).
pub fn check_path(path: &Path) -> Result<()> {
    let meta = std::fs::metadata(path).with_context(|| format!("--poses {}", path.display()))?;
    if meta.is_dir() {
        anyhow::bail!("--poses {}: is a folder, not a file or a FIFO", path.display());
    }
    Ok(())
}

/// The poses in force, updated from the reader thread's lines before each frame.
pub struct Poses {
    lines: Receiver<Update>,
    /// A line read but not yet due.
    waiting: Option<Update>,
    /// The frame of the last line applied.
    applied: Option<u64>,
    /// Wait for the reader's next line (a regular file) rather than take what has arrived.
    wait: bool,
    /// Camera → world (`None`: the session's).
    pub world_from_camera: Option<Mat4>,
    /// Intrinsics (`None`: the session's).
    pub intrinsics: Option<Intrinsics>,
    /// Insert poses by name.
    pub inserts: BTreeMap<String, InsertPose>,
}

impl Poses {
    /// Starts a thread reading `path` for frames of `size` (see the module documentation).
    pub fn start(path: PathBuf, size: (u32, u32), log: Log) -> Self {
        let (send, lines) = sync_channel(QUEUE_LINES);
        let wait = std::fs::metadata(&path).is_ok_and(|m| m.is_file());
        std::thread::spawn(move || {
            let shown = path.display().to_string();
            let mut number = 0;
            loop {
                let file = match std::fs::File::open(&path) {
                    Ok(f) => f,
                    Err(e) => return log.warn(format!("--poses {shown}: {e}; no more poses are read")),
                };
                let mut reader = BufReader::new(file);
                loop {
                    number += 1;
                    let text = match read_line(&mut reader) {
                        Ok(Some(text)) => text,
                        Ok(None) => break,
                        Err(e) => return log.warn(format!("--poses {shown}: {e}; no more poses are read")),
                    };
                    let parsed = match text {
                        RawLine::Text(t) if t.trim_ascii().is_empty() => continue,
                        RawLine::Text(t) => parse_line(&t, size),
                        RawLine::TooLong => Err(anyhow!("longer than {MAX_LINE_BYTES} bytes")),
                    };
                    match parsed {
                        Ok(update) => {
                            if send.send(Update { line: number, ..update }).is_err() {
                                return;
                            }
                        }
                        Err(e) => log.warn(format!("poses line {number}: {e:#}; keeping the last good pose")),
                    }
                }
                if !is_fifo(&path) {
                    return;
                }
            }
        });
        Self::new(lines, wait)
    }

    fn new(lines: Receiver<Update>, wait: bool) -> Self {
        let (world_from_camera, intrinsics, inserts) = (None, None, BTreeMap::new());
        Self { lines, waiting: None, applied: None, wait, world_from_camera, intrinsics, inserts }
    }

    /// Applies the lines due by frame `k`, in order.
    pub fn advance(&mut self, k: u64, log: Log) {
        loop {
            let next = match self.waiting.take() {
                Some(u) => Some(u),
                None if self.wait => self.lines.recv().ok(),
                None => self.lines.try_recv().ok(),
            };
            let Some(update) = next else { return };
            let at = update.frame.unwrap_or(k);
            if at > k {
                self.waiting = Some(update);
                return;
            }
            if let Some(applied) = self.applied.filter(|&a| at < a) {
                log.warn(format!(
                    "poses line {}: frame {at} comes after a line for frame {applied}; skipped (lines go in frame order)",
                    update.line
                ));
                continue;
            }
            self.applied = Some(at);
            self.world_from_camera = update.world_from_camera.or(self.world_from_camera);
            self.intrinsics = update.intrinsics.or(self.intrinsics);
            self.inserts.extend(update.inserts);
        }
    }
}

/// A line of the poses file.
enum RawLine {
    Text(Vec<u8>),
    TooLong,
}

/// The next line (without its newline), `None` at the end of the file.
fn read_line(reader: &mut impl BufRead) -> std::io::Result<Option<RawLine>> {
    let (mut text, mut too_long, mut any) = (Vec::new(), false, false);
    loop {
        let buf = reader.fill_buf()?;
        if buf.is_empty() {
            break;
        }
        any = true;
        let newline = buf.iter().position(|&b| b == b'\n');
        let part = &buf[..newline.unwrap_or(buf.len())];
        too_long |= text.len() + part.len() > MAX_LINE_BYTES;
        if !too_long {
            text.extend_from_slice(part);
        }
        let used = newline.map_or(buf.len(), |i| i + 1);
        reader.consume(used);
        if newline.is_some() {
            break;
        }
    }
    Ok(any.then_some(if too_long { RawLine::TooLong } else { RawLine::Text(text) }))
}

/// Whether `path` is a named pipe (opened again after its writer closes it).
fn is_fifo(path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        std::fs::metadata(path).is_ok_and(|m| m.file_type().is_fifo())
    }
    #[cfg(not(unix))]
    {
        let _ = path;
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SIZE: (u32, u32) = (160, 120);

    #[test]
    fn a_line_gives_a_camera_intrinsics_and_inserts() {
        let line = br#"{"frame": 3, "transform_matrix": [[1,0,0,0],[0,1,0,0.4],[0,0,1,2],[0,0,0,1]],
            "fl_x": 100, "fl_y": 100, "w": 80, "h": 60,
            "inserts": {"duck": {"translation": [1,2,3], "rotation": [0,0,0,1]}}, "tracker": "x"}"#;
        let u = parse_line(line, SIZE).unwrap();
        assert_eq!(u.frame, Some(3));
        assert_eq!(u.world_from_camera.unwrap().w_axis.truncate(), glam::Vec3::new(0.0, 0.4, 2.0));
        let k = u.intrinsics.unwrap();
        assert_eq!((k.fl_x, k.cx, k.width, k.height), (200.0, 80.0, 160, 120), "scaled to the frame size");
        assert_eq!(u.inserts["duck"].translation, Some(glam::Vec3::new(1.0, 2.0, 3.0)));
        assert_eq!(u.inserts["duck"].scale, None);
        let empty = parse_line(b"{}", SIZE).unwrap();
        assert!(empty.world_from_camera.is_none() && empty.intrinsics.is_none() && empty.inserts.is_empty());
    }

    #[test]
    fn bad_lines_say_why() {
        let why = |line: &str| format!("{:#}", parse_line(line.as_bytes(), SIZE).unwrap_err());
        assert!(why("hello").starts_with("not JSON"), "{}", why("hello"));
        assert!(why("[1, 2]").starts_with("not a JSON object"), "{}", why("[1, 2]"));
        assert!(why(r#"{"frame": -1}"#).starts_with("`frame` must be"), "{}", why(r#"{"frame": -1}"#));
        assert!(why(r#"{"frame": 1.5}"#).starts_with("`frame` must be"), "{}", why(r#"{"frame": 1.5}"#));
        assert!(why(r#"{"inserts": [1]}"#).starts_with("`inserts` must be"), "{}", why(r#"{"inserts": [1]}"#));
        let scaled = r#"{"transform_matrix": [[2,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}"#;
        assert!(why(scaled).contains("not a rigid transform"), "{}", why(scaled));
        let aspect = r#"{"fl_x": 100, "w": 100, "h": 100}"#;
        assert!(why(aspect).contains("another aspect ratio"), "{}", why(aspect));
        let rotation = r#"{"inserts": {"duck": {"rotation": [0, 0, 0, 3]}}}"#;
        assert!(why(rotation).contains("'duck'") && why(rotation).contains("unit quaternion"), "{}", why(rotation));
        let unknown = r#"{"inserts": {"duck": {"rot": [0, 0, 0, 1]}}}"#;
        assert!(why(unknown).contains("unknown field `rot`"), "{}", why(unknown));
    }

    #[test]
    fn lines_apply_from_their_frame_and_hold() {
        let (send, lines) = sync_channel(8);
        let mut poses = Poses::new(lines, false);
        let at = |x: f32| Mat4::from_translation(glam::Vec3::X * x);
        let line = |line, frame, x| Update { line, frame, world_from_camera: Some(at(x)), ..Default::default() };
        for u in [line(1, Some(0), 0.0), line(2, Some(2), 2.0), line(3, Some(1), 1.0), line(4, None, 4.0)] {
            send.send(u).unwrap();
        }
        let log = Log { quiet: true };
        poses.advance(0, log);
        assert_eq!(poses.world_from_camera, Some(at(0.0)));
        poses.advance(1, log);
        assert_eq!(poses.world_from_camera, Some(at(0.0)), "line 2 waits for frame 2");
        poses.advance(2, log);
        // Line 3 (frame 1) is older than line 2 and skipped; line 4 applies from frame 2 on.
        assert_eq!(poses.world_from_camera, Some(at(4.0)));
        send.send(Update { line: 5, intrinsics: None, ..Default::default() }).unwrap();
        poses.advance(3, log);
        assert_eq!(poses.world_from_camera, Some(at(4.0)), "what a line does not give holds");
    }

    #[test]
    fn overlong_lines_are_skipped_whole() {
        let mut text = vec![b'x'; MAX_LINE_BYTES + 10];
        text.extend_from_slice(b"\n{}\nlast");
        let mut reader = BufReader::with_capacity(4096, std::io::Cursor::new(text));
        assert!(matches!(read_line(&mut reader).unwrap(), Some(RawLine::TooLong)));
        assert!(matches!(read_line(&mut reader).unwrap(), Some(RawLine::Text(t)) if t == b"{}"));
        assert!(matches!(read_line(&mut reader).unwrap(), Some(RawLine::Text(t)) if t == b"last"));
        assert!(read_line(&mut reader).unwrap().is_none());
    }
}
