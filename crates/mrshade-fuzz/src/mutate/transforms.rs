//! `transforms.json` mutations (posed image sequences): frames dropped, duplicated or
//! multiplied; matrices scaled, mirrored, reshaped, given huge or wrong-typed values; intrinsics
//! and distortion at their boundaries, at the top level or per frame; camera models mrshade
//! does not render; file paths that lead nowhere, outside or to another image; frame images
//! removed or resized (their PNG header); raw text damage.

use super::{bytes, images, values};
use arbitrary::Unstructured;
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// The number keys mrshade reads, top level or per frame.
const NUMBER_KEYS: &[&str] =
    &["fl_x", "fl_y", "cx", "cy", "w", "h", "camera_angle_x", "camera_angle_y", "k1", "k2", "k3", "k4", "p1", "p2"];

/// Camera models: the two accepted, those refused, and other types.
const MODELS: &[&str] = &["PINHOLE", "SIMPLE_PINHOLE", "OPENCV", "OPENCV_FISHEYE", "EQUIRECTANGULAR", "", "pinhole"];

/// Mutates `transforms.json` (and the frame images it names).
pub fn mutate(files: &mut BTreeMap<String, Vec<u8>>, u: &mut Unstructured) -> String {
    let Some(data) = files.get("transforms.json").cloned() else { return "no transforms.json".into() };
    if u.ratio(1, 10).unwrap_or(false) {
        let mut raw = data;
        let step = bytes::mutate(&mut raw, u);
        files.insert("transforms.json".into(), raw);
        return format!("transforms.json bytes: {step}");
    }
    let Ok(mut doc) = serde_json::from_slice::<Value>(&data) else { return "transforms.json not JSON".into() };
    let mut steps = Vec::new();
    for _ in 0..u.int_in_range(1..=3u8).unwrap_or(1) {
        steps.push(mutate_document(&mut doc, files, u));
    }
    files.insert("transforms.json".into(), serde_json::to_vec_pretty(&doc).unwrap_or_default());
    format!("transforms.json: {}", steps.join("; "))
}

/// One change to the document (or to an image it names).
fn mutate_document(doc: &mut Value, files: &mut BTreeMap<String, Vec<u8>>, u: &mut Unstructured) -> String {
    let count = doc["frames"].as_array().map_or(0, Vec::len);
    let k = u.choose_index(count.max(1)).unwrap_or(0);
    match u.int_in_range(0..=12u8).unwrap_or(0) {
        0 => match doc["frames"].as_array_mut() {
            Some(frames) if !frames.is_empty() => {
                frames.remove(k);
                format!("dropped frame {k}")
            }
            _ => "no frame to drop".into(),
        },
        1 => {
            // Copies: the same image twice, or many frames (the limit, the time per frame).
            // Copies: the same image twice, or many frames of images of their own (the limit,
            // the time per frame).
            let copies = [1usize, 1, 40, 400][u.choose_index(4).unwrap_or(0)];
            let image = images_of(files).first().and_then(|n| Some((n.clone(), files.get(n)?.clone())));
            match doc["frames"].as_array_mut() {
                Some(frames) if !frames.is_empty() => {
                    let frame = frames[k].clone();
                    for j in 0..copies {
                        let mut copy = frame.clone();
                        if let (true, Some((name, bytes))) = (copies > 1, &image) {
                            let ext = name.rsplit_once('.').map_or("png", |(_, e)| e);
                            let file = format!("frame_{:04}.{ext}", 1000 + j);
                            copy["file_path"] = json!(file);
                            files.insert(file, bytes.clone());
                        }
                        frames.push(copy);
                    }
                    format!("frame {k} repeated {copies} times")
                }
                _ => "no frame to repeat".into(),
            }
        }
        2 => {
            // Not rigid: a scale, a mirror, a shear.
            let (r, c) = (u.choose_index(3).unwrap_or(0), u.choose_index(3).unwrap_or(0));
            let factor = [2.0, -1.0, 0.0, 1.0001, 1.01, 1e-20][u.choose_index(6).unwrap_or(0)];
            match doc.pointer_mut(&format!("/frames/{k}/transform_matrix/{r}/{c}")) {
                Some(v) => {
                    let scaled = v.as_f64().unwrap_or(1.0) * factor + if factor == 0.0 { 0.3 } else { 0.0 };
                    *v = json!(scaled);
                    format!("frame {k} matrix [{r}][{c}] × {factor}")
                }
                None => "no matrix to scale".into(),
            }
        }
        3 => {
            // Any element, the bottom row and the translation included: huge, tiny, boundary.
            let (r, c) = (u.choose_index(4).unwrap_or(0), u.choose_index(4).unwrap_or(0));
            match doc.pointer_mut(&format!("/frames/{k}/transform_matrix/{r}/{c}")) {
                Some(v) => {
                    let n = values::number(u, v.as_f64());
                    *v = json!(n);
                    format!("frame {k} matrix [{r}][{c}] = {n}")
                }
                None => "no matrix element".into(),
            }
        }
        4 => {
            let shapes = [
                json!([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]),
                json!([[1, 0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]),
                json!([[1, 0, 0], [0, 1, 0], [0, 0, 1]]),
                json!([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]),
                json!([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1], [0, 0, 0, 1]]),
                json!([[1, 0, 0, "0"], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]),
                json!([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, null]]),
                json!([]),
                json!([[]]),
                json!("identity"),
                json!({"0": [1, 0, 0, 0]}),
                json!(1),
            ];
            let i = u.choose_index(shapes.len()).unwrap_or(0);
            set(doc, &format!("/frames/{k}/transform_matrix"), shapes[i].clone());
            format!("frame {k} matrix shape {i}")
        }
        5 | 6 => {
            let key = NUMBER_KEYS[u.choose_index(NUMBER_KEYS.len()).unwrap_or(0)];
            let at = if u.ratio(1, 2).unwrap_or(false) { String::new() } else { format!("/frames/{k}") };
            let around = doc.pointer(&format!("{at}/{key}")).and_then(Value::as_f64);
            let value = match u.int_in_range(0..=9u8).unwrap_or(0) {
                0 => json!(values::string(u)),
                1 => Value::Null,
                2 => json!([1.0]),
                _ => json!(values::number(u, around.or(Some(100.0)))),
            };
            let shown = value.to_string();
            set(doc, &format!("{at}/{key}"), value);
            format!("{}{key} = {shown}", if at.is_empty() { "" } else { "frame's " })
        }
        7 => {
            let model = MODELS[u.choose_index(MODELS.len()).unwrap_or(0)];
            let value = if u.ratio(1, 8).unwrap_or(false) { json!(7) } else { json!(model) };
            let at = if u.ratio(3, 4).unwrap_or(false) { String::new() } else { format!("/frames/{k}") };
            set(doc, &format!("{at}/camera_model"), value);
            format!("camera_model = {model}")
        }
        8 => {
            // Paths: hostile ones, an image without its extension, another frame's image.
            let path = match u.int_in_range(0..=3u8).unwrap_or(0) {
                0 => values::string(u).to_string(),
                1 => "frame_9999.png".into(),
                2 => images_of(files).first().map(|n| n.trim_end_matches(".png").to_string()).unwrap_or_default(),
                _ => images_of(files).last().cloned().unwrap_or_default(),
            };
            set(doc, &format!("/frames/{k}/file_path"), json!(path));
            format!("frame {k} file_path = {path:?}")
        }
        9 => {
            let keys = ["frames", "fl_x", "w", "h", "cx", "/frames/K/file_path", "/frames/K/transform_matrix"];
            let key = keys[u.choose_index(keys.len()).unwrap_or(0)];
            let path = if key.starts_with('/') { key.replace('K', &k.to_string()) } else { format!("/{key}") };
            remove(doc, &path);
            format!("removed {path}")
        }
        10 => {
            // Another size (an IHDR rewritten, checksum fixed), or damaged data.
            let names = images_of(files);
            match names.get(u.choose_index(names.len().max(1)).unwrap_or(0)) {
                Some(name) => images::mutate_photo(files, &name.clone(), u),
                None => "no frame image".into(),
            }
        }
        11 => {
            let names = images_of(files);
            match names.get(u.choose_index(names.len().max(1)).unwrap_or(0)) {
                Some(name) => {
                    files.remove(name);
                    format!("deleted {name}")
                }
                None => "no frame image".into(),
            }
        }
        _ => {
            // Keys mrshade skips, holding anything: deep nesting, long text, wrong types.
            let junk = [
                json!("x".repeat(1 << 16)),
                (0..100).fold(json!(1), |inner, _| json!([inner])),
                json!({"nested": {"frames": 5}}),
                json!(null),
            ];
            let i = u.choose_index(junk.len()).unwrap_or(0);
            let at = if u.ratio(1, 2).unwrap_or(false) {
                "/aabb_scale".to_string()
            } else {
                format!("/frames/{k}/mask_path")
            };
            set(doc, &at, junk[i].clone());
            format!("{at} = junk {i}")
        }
    }
}

/// The frame images of the case (PNG or JPEG files other than a background).
fn images_of(files: &BTreeMap<String, Vec<u8>>) -> Vec<String> {
    files.keys().filter(|n| n.starts_with("frame_")).cloned().collect()
}

/// Sets the value at a JSON pointer whose parent exists.
fn set(doc: &mut Value, pointer: &str, value: Value) {
    let (parent, key) = pointer.rsplit_once('/').unwrap_or(("", pointer));
    if let Some(object) = doc.pointer_mut(parent).and_then(Value::as_object_mut) {
        object.insert(key.to_string(), value);
    }
}

/// Removes the value at a JSON pointer.
fn remove(doc: &mut Value, pointer: &str) {
    let (parent, key) = pointer.rsplit_once('/').unwrap_or(("", pointer));
    if let Some(object) = doc.pointer_mut(parent).and_then(Value::as_object_mut) {
        object.remove(key);
    }
}
