//! Reading `transforms.json`: the keys mrshade uses, typed, through serde seeds that count
//! the frames against `limits.sequence_frames` as they come and keep no more of a matrix than
//! its 4×4 numbers and its shape; every other key is skipped unread (no allocation, whatever
//! it holds). Errors say where the parser was: the frame and the key.

use anyhow::{Result, anyhow};
use serde::de::{self, DeserializeSeed, IgnoredAny, MapAccess, SeqAccess, Visitor};
use std::cell::RefCell;
use std::fmt;

/// The number keys read, top level or per frame.
pub(super) const NUMBER_KEYS: [&str; 14] =
    ["fl_x", "fl_y", "cx", "cy", "w", "h", "camera_angle_x", "camera_angle_y", "k1", "k2", "k3", "k4", "p1", "p2"];
pub(super) const FL_X: usize = 0;
pub(super) const FL_Y: usize = 1;
pub(super) const CX: usize = 2;
pub(super) const CY: usize = 3;
pub(super) const W: usize = 4;
pub(super) const H: usize = 5;
pub(super) const ANGLE_X: usize = 6;
pub(super) const ANGLE_Y: usize = 7;
/// Indices of the distortion coefficients in [`NUMBER_KEYS`].
pub(super) const DISTORTION: [usize; 6] = [8, 9, 10, 11, 12, 13];

/// Camera keys of the top level or of a frame.
#[derive(Default)]
pub(super) struct Keys {
    pub(super) camera_model: Option<String>,
    pub(super) numbers: [Option<f64>; NUMBER_KEYS.len()],
}

/// A `transform_matrix` as given: up to four rows of up to four numbers, and its shape.
#[derive(Default)]
pub(super) struct RawMatrix {
    pub(super) rows: [[f64; 4]; 4],
    pub(super) row_count: usize,
    /// The first row whose length is not 4, and its length.
    pub(super) bad_row: Option<(usize, usize)>,
}

/// The top level (with `frames`) or one frame (with `file_path` and `transform_matrix`).
#[derive(Default)]
pub(super) struct RawObject {
    pub(super) keys: Keys,
    pub(super) file_path: Option<String>,
    pub(super) matrix: Option<RawMatrix>,
    pub(super) frames: Option<Vec<RawObject>>,
}

/// Where the parser is, for its error messages.
#[derive(Default)]
struct Where {
    frame: Option<usize>,
    key: Option<&'static str>,
}

/// Parses the file, at most `max_frames` frames.
pub(super) fn parse(bytes: &[u8], max_frames: usize) -> Result<RawObject> {
    parse_object(bytes, Some(max_frames))
}

/// Parses one frame object on its own (`transform_matrix` and the camera keys).
pub(super) fn parse_frame(bytes: &[u8]) -> Result<RawObject> {
    parse_object(bytes, None)
}

/// The top level (`max_frames` given) or one frame.
fn parse_object(bytes: &[u8], max_frames: Option<usize>) -> Result<RawObject> {
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let at = RefCell::new(Where::default());
    let mut de = serde_json::Deserializer::from_slice(bytes);
    let parsed = ObjectSeed { at: &at, max_frames }.deserialize(&mut de).and_then(|raw| {
        de.end()?;
        Ok(raw)
    });
    parsed.map_err(|e| {
        let at = at.borrow();
        let frame = at.frame.map(|i| format!("frame {i}{}", if at.key.is_some() { ", " } else { ": " }));
        let key = at.key.map(|k| format!("`{k}`: "));
        anyhow!("{}{}{e}", frame.unwrap_or_default(), key.unwrap_or_default())
    })
}

/// A key of an object: one mrshade reads, or another (skipped).
enum Key {
    Number(usize),
    CameraModel,
    FilePath,
    Matrix,
    Frames,
    Other,
}

impl Key {
    fn name(&self) -> Option<&'static str> {
        match self {
            Key::Number(i) => Some(NUMBER_KEYS[*i]),
            Key::CameraModel => Some("camera_model"),
            Key::FilePath => Some("file_path"),
            Key::Matrix => Some("transform_matrix"),
            Key::Frames => Some("frames"),
            Key::Other => None,
        }
    }
}

impl<'de> serde::Deserialize<'de> for Key {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Key, D::Error> {
        struct KeyVisitor;
        impl Visitor<'_> for KeyVisitor {
            type Value = Key;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a key")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Key, E> {
                Ok(match v {
                    "camera_model" => Key::CameraModel,
                    "file_path" => Key::FilePath,
                    "transform_matrix" => Key::Matrix,
                    "frames" => Key::Frames,
                    _ => NUMBER_KEYS.iter().position(|k| *k == v).map_or(Key::Other, Key::Number),
                })
            }
        }
        d.deserialize_str(KeyVisitor)
    }
}

/// Stores `value` in an empty `slot`.
fn set<T, E: de::Error>(slot: &mut Option<T>, value: T) -> Result<(), E> {
    if slot.is_some() {
        return Err(E::custom("the key is given twice"));
    }
    *slot = Some(value);
    Ok(())
}

/// Reads the top level (`max_frames` given) or a frame.
struct ObjectSeed<'a> {
    at: &'a RefCell<Where>,
    max_frames: Option<usize>,
}

impl<'de> DeserializeSeed<'de> for ObjectSeed<'_> {
    type Value = RawObject;
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<RawObject, D::Error> {
        d.deserialize_map(self)
    }
}

impl<'de> Visitor<'de> for ObjectSeed<'_> {
    type Value = RawObject;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(if self.max_frames.is_some() { "a JSON object with `frames`" } else { "a frame (a JSON object)" })
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<RawObject, A::Error> {
        let mut out = RawObject::default();
        let top = self.max_frames.is_some();
        while let Some(key) = map.next_key::<Key>()? {
            self.at.borrow_mut().key = key.name();
            match key {
                Key::Number(i) => set(&mut out.keys.numbers[i], map.next_value::<f64>()?)?,
                Key::CameraModel => set(&mut out.keys.camera_model, map.next_value::<String>()?)?,
                Key::FilePath if !top => set(&mut out.file_path, map.next_value::<String>()?)?,
                Key::Matrix if !top => set(&mut out.matrix, map.next_value_seed(MatrixSeed)?)?,
                Key::Frames if top => {
                    let seed = FramesSeed { at: self.at, max: self.max_frames.unwrap_or(0) };
                    set(&mut out.frames, map.next_value_seed(seed)?)?
                }
                _ => {
                    map.next_value::<IgnoredAny>()?;
                }
            }
            self.at.borrow_mut().key = None;
        }
        Ok(out)
    }
}

/// Reads `frames`, refusing more than `max`.
struct FramesSeed<'a> {
    at: &'a RefCell<Where>,
    max: usize,
}

impl<'de> DeserializeSeed<'de> for FramesSeed<'_> {
    type Value = Vec<RawObject>;
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<Vec<RawObject>, D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for FramesSeed<'_> {
    type Value = Vec<RawObject>;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a list of frames")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<RawObject>, A::Error> {
        let mut frames = Vec::new();
        loop {
            self.at.borrow_mut().frame = Some(frames.len());
            let Some(frame) = seq.next_element_seed(ObjectSeed { at: self.at, max_frames: None })? else { break };
            if frames.len() == self.max {
                *self.at.borrow_mut() = Where { frame: None, key: Some("frames") };
                return Err(de::Error::custom(format!(
                    "more than `limits.sequence_frames` = {} frames (raise it with --set limits.sequence_frames=N)",
                    self.max
                )));
            }
            frames.push(frame);
        }
        self.at.borrow_mut().frame = None;
        Ok(frames)
    }
}

/// Reads a `transform_matrix`: rows past the fourth and numbers past a row's fourth are
/// counted, not kept.
struct MatrixSeed;

impl<'de> DeserializeSeed<'de> for MatrixSeed {
    type Value = RawMatrix;
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<RawMatrix, D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for MatrixSeed {
    type Value = RawMatrix;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("4 rows of 4 numbers")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<RawMatrix, A::Error> {
        let mut m = RawMatrix::default();
        while let Some((values, len)) = seq.next_element_seed(RowSeed)? {
            if m.row_count < 4 {
                m.rows[m.row_count] = values;
            }
            if len != 4 && m.bad_row.is_none() {
                m.bad_row = Some((m.row_count, len));
            }
            m.row_count += 1;
        }
        Ok(m)
    }
}

/// Reads one row: its first four numbers and its length.
struct RowSeed;

impl<'de> DeserializeSeed<'de> for RowSeed {
    type Value = ([f64; 4], usize);
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<([f64; 4], usize), D::Error> {
        d.deserialize_seq(self)
    }
}

impl<'de> Visitor<'de> for RowSeed {
    type Value = ([f64; 4], usize);
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a row of 4 numbers")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<([f64; 4], usize), A::Error> {
        let (mut values, mut len) = ([0.0; 4], 0);
        while let Some(v) = seq.next_element::<f64>()? {
            if len < 4 {
                values[len] = v;
            }
            len += 1;
        }
        Ok((values, len))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sequence::pose;

    fn parsed(json: &str) -> Result<RawObject> {
        parse(json.as_bytes(), 3)
    }

    #[test]
    fn unused_keys_are_skipped_and_used_ones_typed() {
        let raw = parsed(
            r#"{"aabb_scale": 16, "applied_transform": [[1,2],[3]], "fl_x": 100, "frames": [
                {"file_path": "a.png", "transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]],
                 "colmap_im_id": 3, "mask_path": null, "w": 32}]}"#,
        )
        .unwrap();
        assert_eq!(raw.keys.numbers[FL_X], Some(100.0));
        let frame = &raw.frames.as_ref().unwrap()[0];
        assert_eq!((frame.file_path.as_deref(), frame.keys.numbers[W]), (Some("a.png"), Some(32.0)));
        assert_eq!(frame.matrix.as_ref().unwrap().row_count, 4);
        let msg = format!("{:#}", parsed(r#"{"frames": [{}, {"fl_y": "big"}]}"#).err().unwrap());
        assert!(msg.starts_with("frame 1, `fl_y`: invalid type: string \"big\"") && msg.contains("line 1"), "{msg}");
        let msg = format!("{:#}", parsed(r#"{"frames": [{}, {}, {}, {}]}"#).err().unwrap());
        assert!(msg.starts_with("`frames`: more than `limits.sequence_frames` = 3"), "{msg}");
        assert!(
            format!("{:#}", parsed(r#"{"fl_x": 1, "fl_x": 2}"#).err().unwrap())
                .contains("`fl_x`: the key is given twice")
        );
        assert!(parsed("[1]").is_err() && parsed(r#"{"frames": []} x"#).is_err());
    }

    #[test]
    fn matrix_shapes_are_counted_not_kept() {
        let raw = parsed(r#"{"frames": [{"transform_matrix": [[1,2,3,4,5,6],[1],[],[],[],[]]}]}"#).unwrap();
        let m = raw.frames.unwrap().remove(0).matrix.unwrap();
        assert_eq!((m.row_count, m.bad_row), (6, Some((0, 6))));
        assert!(pose(&m).unwrap_err().contains("row 0 has 6 numbers"));
    }
}
