//! glTF mutations: the JSON document (any value, references, the node graph, transforms,
//! cameras, lights, accessors, URIs, animations with their keyframes in the BIN buffer) and
//! its container (GLB chunks, external `.bin`, data URIs).

use super::{bytes, values};
use arbitrary::Unstructured;
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// Mutates the glTF `name` of `files` (and the session, if the file is renamed).
pub fn mutate(files: &mut BTreeMap<String, Vec<u8>>, name: &str, u: &mut Unstructured) -> String {
    let data = files.remove(name).unwrap_or_default();
    let (json, mut bin) = if name.ends_with(".glb") {
        mrshade_testkit::gltf::unpack_glb(&data)
    } else {
        (data.clone(), files.get("scene.bin").cloned().unwrap_or_default())
    };
    let Ok(mut doc) = serde_json::from_slice::<Value>(&json) else {
        files.insert(name.to_string(), data);
        return format!("{name}: not JSON, left alone");
    };
    let mut steps = Vec::new();
    for _ in 0..u.int_in_range(1..=3u8).unwrap_or(1) {
        steps.push(mutate_document(&mut doc, &mut bin, u));
    }
    if u.ratio(1, 6).unwrap_or(false) {
        steps.push(format!("BIN chunk: {}", bytes::mutate(&mut bin, u)));
    }
    let json = serde_json::to_vec(&doc).unwrap_or_default();
    let container = match u.int_in_range(0..=9u8).unwrap_or(0) {
        0..=6 => {
            files.insert("scene.glb".into(), mrshade_testkit::gltf::pack_glb(&json, &bin));
            rename_scene(files, name, "scene.glb");
            "as GLB".to_string()
        }
        7 => {
            let mut glb = mrshade_testkit::gltf::pack_glb(&json, &bin);
            let what = bytes::mutate(&mut glb, u);
            files.insert("scene.glb".into(), glb);
            rename_scene(files, name, "scene.glb");
            format!("as a damaged GLB ({what})")
        }
        _ => {
            // A .gltf beside its .bin: the buffer's URI is read from disk.
            if let Some(buffer) = doc.pointer_mut("/buffers/0").and_then(Value::as_object_mut) {
                buffer.entry("uri").or_insert(json!("scene.bin"));
            }
            files.insert("scene.gltf".into(), serde_json::to_vec(&doc).unwrap_or_default());
            files.insert("scene.bin".into(), bin);
            rename_scene(files, name, "scene.gltf");
            "as .gltf + .bin".to_string()
        }
    };
    format!("{name}: {} ({container})", steps.join("; "))
}

fn rename_scene(files: &mut BTreeMap<String, Vec<u8>>, from: &str, to: &str) {
    if from != to
        && let Some(session) = files.get_mut("session.toml")
    {
        *session = String::from_utf8_lossy(session).replace(from, to).into_bytes();
    }
}

/// A step into a JSON tree.
#[derive(Clone)]
enum Step {
    Key(String),
    Index(usize),
}

fn paths(v: &Value, prefix: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    out.push(prefix.clone());
    match v {
        Value::Array(items) => {
            for (i, item) in items.iter().enumerate().take(64) {
                prefix.push(Step::Index(i));
                paths(item, prefix, out);
                prefix.pop();
            }
        }
        Value::Object(map) => {
            for (k, item) in map {
                prefix.push(Step::Key(k.clone()));
                paths(item, prefix, out);
                prefix.pop();
            }
        }
        _ => {}
    }
}

fn at<'a>(v: &'a mut Value, path: &[Step]) -> Option<&'a mut Value> {
    path.iter().try_fold(v, |v, step| match step {
        Step::Key(k) => v.get_mut(k.as_str()),
        Step::Index(i) => v.get_mut(*i),
    })
}

fn mutate_document(doc: &mut Value, bin: &mut Vec<u8>, u: &mut Unstructured) -> String {
    match u.int_in_range(0..=13u8).unwrap_or(0) {
        0..=4 => mutate_any_value(doc, u),
        5 => graph(doc, u),
        6 => transform(doc, u),
        7 => camera_or_light(doc, u),
        8 => accessor(doc, u),
        9 => uris(doc, u),
        10 => many(doc, u),
        11 => animation(doc, bin, u),
        12 => super::deformers::mutate(doc, bin, u),
        _ => references(doc, u),
    }
}

/// Any value anywhere: a number, a string, a type change, a deletion, a duplicate.
fn mutate_any_value(doc: &mut Value, u: &mut Unstructured) -> String {
    let mut all = Vec::new();
    paths(doc, &mut Vec::new(), &mut all);
    let path = all[u.choose_index(all.len()).unwrap_or(0)].clone();
    let shown: Vec<String> = path
        .iter()
        .map(|s| match s {
            Step::Key(k) => k.clone(),
            Step::Index(i) => i.to_string(),
        })
        .collect();
    let shown = shown.join("/");
    let op = u.int_in_range(0..=7u8).unwrap_or(0);
    let Some(target) = at(doc, &path) else { return "nothing".into() };
    // Numbers where there were numbers, mostly: past the type check, into the range checks.
    let op = if target.is_number() && op >= 5 { 0 } else { op };
    match op {
        0 | 1 => {
            let n = values::number(u, target.as_f64());
            *target = json_number(n);
            format!("{shown} = {n}")
        }
        2 => {
            let s = values::string(u);
            *target = json!(s);
            format!("{shown} = {s:?}")
        }
        3 => {
            let kinds = [json!(null), json!(true), json!([]), json!({}), json!([0, 0, 0]), json!(-1)];
            *target = kinds[u.choose_index(kinds.len()).unwrap_or(0)].clone();
            format!("{shown} changed type")
        }
        4 => match target {
            Value::Array(items) if !items.is_empty() => {
                let i = u.choose_index(items.len()).unwrap_or(0);
                let copy = items[i].clone();
                items.push(copy);
                format!("{shown}: element {i} repeated")
            }
            Value::Object(map) if !map.is_empty() => {
                let keys: Vec<String> = map.keys().cloned().collect();
                let k = &keys[u.choose_index(keys.len()).unwrap_or(0)];
                map.remove(k);
                format!("{shown}: removed {k}")
            }
            _ => "nothing".into(),
        },
        _ => {
            *target = json!(null);
            format!("{shown} = null")
        }
    }
}

pub(super) fn json_number(n: f64) -> Value {
    if n.fract() == 0.0 && n.abs() < 1.8e19 {
        if n >= 0.0 { json!(n as u64) } else { json!(n as i64) }
    } else {
        serde_json::Number::from_f64(n).map_or(json!(0), Value::Number)
    }
}

pub(super) fn count(doc: &Value, key: &str) -> usize {
    doc.get(key).and_then(Value::as_array).map_or(0, Vec::len)
}

/// The node graph: second parents, repeated children, cycles, roots that are children, DAGs.
fn graph(doc: &mut Value, u: &mut Unstructured) -> String {
    let n = count(doc, "nodes");
    if n == 0 {
        return "no nodes".into();
    }
    let (a, b) = (u.choose_index(n).unwrap_or(0), u.choose_index(n).unwrap_or(0));
    match u.int_in_range(0..=3u8).unwrap_or(0) {
        0 => {
            push_child(doc, a, b);
            format!("nodes[{a}] gets child {b}")
        }
        1 => {
            push_child(doc, a, b);
            push_child(doc, a, b);
            format!("nodes[{a}] gets child {b} twice")
        }
        2 => {
            if let Some(roots) = doc.pointer_mut("/scenes/0/nodes").and_then(Value::as_array_mut) {
                roots.push(json!(b));
            }
            format!("scene 0 gets root {b}")
        }
        _ => {
            // A chain where every node has the next two as children: 2^depth paths.
            let depth = u.int_in_range(2..=40usize).unwrap_or(2);
            let first = n;
            if let Some(nodes) = doc.get_mut("nodes").and_then(Value::as_array_mut) {
                for i in 0..depth {
                    let children: Vec<usize> =
                        [first + i + 1, first + i + 2].into_iter().filter(|&c| c < first + depth).collect();
                    nodes.push(json!({"name": format!("dag{i}"), "children": children, "mesh": 0}));
                }
            }
            if let Some(roots) = doc.pointer_mut("/scenes/0/nodes").and_then(Value::as_array_mut) {
                roots.push(json!(first));
            }
            format!("a DAG of {depth} nodes")
        }
    }
}

fn push_child(doc: &mut Value, parent: usize, child: usize) {
    if let Some(node) = doc.pointer_mut(&format!("/nodes/{parent}")).and_then(Value::as_object_mut) {
        let children = node.entry("children").or_insert(json!([]));
        if let Some(c) = children.as_array_mut() {
            c.push(json!(child));
        }
    }
}

/// A node's scale, rotation, translation or matrix.
fn transform(doc: &mut Value, u: &mut Unstructured) -> String {
    let n = count(doc, "nodes");
    if n == 0 {
        return "no nodes".into();
    }
    let i = u.choose_index(n).unwrap_or(0);
    let which = u.int_in_range(0..=3u8).unwrap_or(0);
    let mut v = || values::number(u, Some(1.0));
    let (key, value) = match which {
        0 => ("scale", json!([json_number(v()), json_number(v()), json_number(v())])),
        1 => ("rotation", json!([json_number(v()), json_number(v()), json_number(v()), json_number(v())])),
        2 => ("translation", json!([json_number(v()), json_number(v()), json_number(v())])),
        _ => ("matrix", Value::Array((0..16).map(|_| json_number(v())).collect())),
    };
    if let Some(node) = doc.pointer_mut(&format!("/nodes/{i}")).and_then(Value::as_object_mut) {
        if key == "matrix" {
            for k in ["scale", "rotation", "translation"] {
                node.remove(k);
            }
        }
        node.insert(key.into(), value);
    }
    format!("nodes[{i}].{key} changed")
}

/// Camera projections and light parameters.
fn camera_or_light(doc: &mut Value, u: &mut Unstructured) -> String {
    let pointers = [
        "/cameras/0/perspective/yfov",
        "/cameras/0/perspective/znear",
        "/cameras/0/perspective/zfar",
        "/cameras/0/perspective/aspectRatio",
        "/extensions/KHR_lights_punctual/lights/0/intensity",
        "/extensions/KHR_lights_punctual/lights/0/color",
        "/extensions/KHR_lights_punctual/lights/0/spot/outerConeAngle",
        "/extensions/KHR_lights_punctual/lights/0/spot/innerConeAngle",
        "/extensions/KHR_lights_punctual/lights/0/type",
        "/materials/0/pbrMetallicRoughness/baseColorFactor",
        "/materials/0/emissiveFactor",
        "/materials/0/normalTexture",
    ];
    let p = pointers[u.choose_index(pointers.len()).unwrap_or(0)];
    let n = values::number(u, Some(1.0));
    let value = if p.ends_with("Factor") || p.ends_with("color") {
        json!([json_number(n), 0.5, 0.5])
    } else if p.ends_with("normalTexture") {
        json!({"index": 0, "scale": json_number(n)})
    } else if p.ends_with("type") {
        json!(["spot", "point", "directional", "area"][u.choose_index(4).unwrap_or(0)])
    } else {
        json_number(n)
    };
    if let Some(target) = doc.pointer_mut(p) {
        *target = value;
    }
    format!("{p} = {n}")
}

/// An accessor's count, offset, type, bounds, or a sparse part.
fn accessor(doc: &mut Value, u: &mut Unstructured) -> String {
    let n = count(doc, "accessors");
    if n == 0 {
        return "no accessors".into();
    }
    let i = u.choose_index(n).unwrap_or(0);
    let big = values::number(u, Some(4.0));
    let Some(acc) = doc.pointer_mut(&format!("/accessors/{i}")).and_then(Value::as_object_mut) else {
        return "nothing".into();
    };
    match u.int_in_range(0..=4u8).unwrap_or(0) {
        0 => {
            acc.insert("count".into(), json_number(big));
            format!("accessors[{i}].count = {big}")
        }
        1 => {
            acc.insert("byteOffset".into(), json_number(big));
            format!("accessors[{i}].byteOffset = {big}")
        }
        2 => {
            acc.remove("bufferView");
            acc.insert(
                "sparse".into(),
                json!({"count": 1, "indices": {"bufferView": 0, "componentType": 5125}, "values": {"bufferView": 0}}),
            );
            acc.insert("count".into(), json_number(big));
            format!("accessors[{i}] sparse only, count {big}")
        }
        3 => {
            acc.insert("max".into(), json!([0, 0, 0]));
            format!("accessors[{i}].max = 0")
        }
        _ => {
            let ct = [5120, 5121, 5122, 5123, 5125, 5126, 5130, 0][u.choose_index(8).unwrap_or(0)];
            acc.insert("componentType".into(), json!(ct));
            format!("accessors[{i}].componentType = {ct}")
        }
    }
}

/// Buffers and images that point outside, to devices, to bad data URIs.
fn uris(doc: &mut Value, u: &mut Unstructured) -> String {
    let uri = values::string(u);
    if u.ratio(1, 2).unwrap_or(false) {
        if let Some(buffer) = doc.pointer_mut("/buffers/0").and_then(Value::as_object_mut) {
            buffer.insert("uri".into(), json!(uri));
        }
        return format!("buffers[0].uri = {uri:?}");
    }
    let Some(root) = doc.as_object_mut() else { return "not an object".into() };
    root.insert("images".into(), json!([{"uri": uri}]));
    root.insert("textures".into(), json!([{"source": 0}]));
    if let Some(m) = doc.pointer_mut("/materials/0").and_then(Value::as_object_mut) {
        m.insert("pbrMetallicRoughness".into(), json!({"baseColorTexture": {"index": 0}}));
    }
    format!("a texture from {uri:?}")
}

/// Many of something: lights, nodes, materials.
fn many(doc: &mut Value, u: &mut Unstructured) -> String {
    let k = [10usize, 33, 100, 1000, 5000][u.choose_index(5).unwrap_or(0)];
    let has_light = doc.pointer("/extensions/KHR_lights_punctual/lights/0").is_some();
    let Some(nodes) = doc.get_mut("nodes").and_then(Value::as_array_mut) else { return "no nodes".into() };
    let first = nodes.len();
    for i in 0..k {
        let mut node = json!({"name": format!("n{i}"), "translation": [0.0, 1.0, 0.0]});
        if has_light {
            node["extensions"] = json!({"KHR_lights_punctual": {"light": 0}});
        } else {
            node["mesh"] = json!(0);
        }
        nodes.push(node);
    }
    if let Some(roots) = doc.pointer_mut("/scenes/0/nodes").and_then(Value::as_array_mut) {
        roots.extend((first..first + k).map(|i| json!(i)));
    }
    format!("{k} more nodes")
}

/// References one past the end, far past it, or to the wrong kind of thing.
fn references(doc: &mut Value, u: &mut Unstructured) -> String {
    let pointers = [
        ("/meshes/0/primitives/0/attributes/POSITION", "accessors"),
        ("/meshes/0/primitives/0/attributes/NORMAL", "accessors"),
        ("/meshes/0/primitives/0/indices", "accessors"),
        ("/meshes/0/primitives/0/material", "materials"),
        ("/nodes/0/mesh", "meshes"),
        ("/nodes/0/camera", "cameras"),
        ("/accessors/0/bufferView", "bufferViews"),
        ("/bufferViews/0/buffer", "buffers"),
        ("/scene", "scenes"),
    ];
    let (p, kind) = pointers[u.choose_index(pointers.len()).unwrap_or(0)];
    let len = count(doc, kind);
    let index = [len, len + 1, 4294967296 + len.min(3), 0][u.choose_index(4).unwrap_or(0)];
    if let Some((parent, key)) = p.rsplit_once('/')
        && let Some(obj) =
            if parent.is_empty() { doc.as_object_mut() } else { doc.pointer_mut(parent).and_then(Value::as_object_mut) }
    {
        obj.insert(key.into(), json!(index));
    }
    format!("{p} = {index} (of {len} {kind})")
}

/// Animations: a new one (keyframes appended to the BIN buffer, plausible or hostile: times
/// that repeat, go back or are NaN; zero scales, zero quaternions, 1e30, counts one off,
/// normalized integer rotations, the wrong accessor types), or an existing one corrupted
/// (interpolation and path strings, targets, sampler and accessor references, a matrix on the
/// animated node, a repeated channel), or a channel on every node.
fn animation(doc: &mut Value, bin: &mut Vec<u8>, u: &mut Unstructured) -> String {
    let animations = count(doc, "animations");
    match u.int_in_range(0..=9u8).unwrap_or(0) {
        0..=4 => new_animation(doc, bin, u),
        _ if animations == 0 => new_animation(doc, bin, u),
        5 => {
            let a = u.choose_index(animations).unwrap_or(0);
            let text = ["LINEAR", "STEP", "CUBICSPLINE", "SMOOTH", "linear", ""][u.choose_index(6).unwrap_or(0)];
            if let Some(sampler) =
                doc.pointer_mut(&format!("/animations/{a}/samplers/0")).and_then(Value::as_object_mut)
            {
                sampler.insert("interpolation".into(), json!(text));
            }
            format!("animations[{a}].samplers[0].interpolation = {text:?}")
        }
        6 => {
            let a = u.choose_index(animations).unwrap_or(0);
            let paths = ["translation", "rotation", "scale", "weights", "matrix", ""];
            let path = paths[u.choose_index(paths.len()).unwrap_or(0)];
            let nodes = count(doc, "nodes");
            let node = [0, nodes.saturating_sub(1), nodes, 4294967296][u.choose_index(4).unwrap_or(0)];
            if let Some(target) = doc.pointer_mut(&format!("/animations/{a}/channels/0/target")) {
                *target = json!({"node": node, "path": path});
            }
            format!("animations[{a}].channels[0].target = {path:?} of node {node}")
        }
        7 => {
            let a = u.choose_index(animations).unwrap_or(0);
            let accessors = count(doc, "accessors");
            let index = [0, accessors.saturating_sub(1), accessors, 4294967296][u.choose_index(4).unwrap_or(0)];
            let key = ["input", "output", "sampler"][u.choose_index(3).unwrap_or(0)];
            let at = if key == "sampler" { "channels" } else { "samplers" };
            if let Some(item) = doc.pointer_mut(&format!("/animations/{a}/{at}/0")).and_then(Value::as_object_mut) {
                item.insert(key.into(), json!(index));
            }
            format!("animations[{a}].{at}[0].{key} = {index}")
        }
        8 => {
            let a = u.choose_index(animations).unwrap_or(0);
            let node = doc.pointer(&format!("/animations/{a}/channels/0/target/node")).and_then(Value::as_u64);
            let matrix: Vec<f32> = vec![1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0];
            if let Some(node) =
                node.and_then(|n| doc.pointer_mut(&format!("/nodes/{n}"))).and_then(Value::as_object_mut)
            {
                node.insert("matrix".into(), json!(matrix));
            }
            format!("the node of animations[{a}].channels[0] gets a matrix")
        }
        _ => {
            if u.ratio(1, 2).unwrap_or(false) {
                let a = u.choose_index(animations).unwrap_or(0);
                if let Some(channels) =
                    doc.pointer_mut(&format!("/animations/{a}/channels")).and_then(Value::as_array_mut)
                    && let Some(first) = channels.first().cloned()
                {
                    channels.push(first);
                }
                return format!("animations[{a}].channels[0] repeated");
            }
            // One sampler, a channel on every node: the pose of every node is computed.
            let sampler = new_sampler(doc, bin, "translation", "LINEAR", u);
            let channels: Vec<Value> = (0..count(doc, "nodes"))
                .map(|n| json!({"sampler": 0, "target": {"node": n, "path": "translation"}}))
                .collect();
            push(doc, "animations", json!({"name": "everything", "samplers": [sampler], "channels": channels}));
            format!("an animation of all {} nodes", count(doc, "nodes"))
        }
    }
}

/// An animation of 1 to 3 channels on random nodes (mostly the camera's, the lights', the
/// meshes'), each with its own new sampler.
fn new_animation(doc: &mut Value, bin: &mut Vec<u8>, u: &mut Unstructured) -> String {
    let nodes = count(doc, "nodes").max(1);
    let (mut samplers, mut channels, mut shown) = (Vec::new(), Vec::new(), Vec::new());
    for c in 0..u.int_in_range(1..=3usize).unwrap_or(1) {
        let paths = ["translation", "rotation", "scale", "rotation", "scale", "weights"];
        let path = paths[u.choose_index(paths.len()).unwrap_or(0)];
        let interpolations = ["LINEAR", "STEP", "CUBICSPLINE", "LINEAR"];
        let interpolation = interpolations[u.choose_index(interpolations.len()).unwrap_or(0)];
        let node = if u.ratio(1, 12).unwrap_or(false) { nodes } else { u.choose_index(nodes).unwrap_or(0) };
        samplers.push(new_sampler(doc, bin, path, interpolation, u));
        channels.push(json!({"sampler": c, "target": {"node": node, "path": path}}));
        shown.push(format!("{interpolation} {path} of node {node}"));
    }
    push(doc, "animations", json!({"name": "fuzz", "samplers": samplers, "channels": channels}));
    format!("an animation: {}", shown.join(", "))
}

/// A sampler for `path` whose keyframes are appended to `bin`: well-formed two times in
/// three (so that poses get sampled), else with one fault.
fn new_sampler(doc: &mut Value, bin: &mut Vec<u8>, path: &str, interpolation: &str, u: &mut Unstructured) -> Value {
    let fault = u.int_in_range(0..=11u8).unwrap_or(11);
    let keys = u.int_in_range(1..=5usize).unwrap_or(2);
    let step = [1.0 / 24.0, 0.5, 1.0, 1e-7, 1e30][u.choose_index(5).unwrap_or(0)];
    let mut times: Vec<f32> = (0..keys).map(|k| k as f32 * step).collect();
    if fault == 0 {
        let k = u.choose_index(keys).unwrap_or(0);
        times[k] =
            [f32::NAN, -1.0, 0.0, f32::INFINITY, values::number(u, Some(1.0)) as f32][u.choose_index(5).unwrap_or(0)];
    }
    let input = push_floats(doc, bin, &times, "SCALAR");
    let per_key = if interpolation == "CUBICSPLINE" { 3 } else { 1 };
    let off_by_one = if fault == 1 { [1, -1][u.choose_index(2).unwrap_or(0)] } else { 0 };
    let elements = (keys * per_key).saturating_add_signed(off_by_one);
    let (ty, n) = match path {
        "rotation" => ("VEC4", 4),
        "weights" => ("SCALAR", 1),
        _ => ("VEC3", 3),
    };
    let plausible: &[f32] = match path {
        "rotation" => &[0.0, 1.0, -1.0, std::f32::consts::FRAC_1_SQRT_2, 0.5],
        "scale" => &[1.0, 0.5, 2.0, 1.5, 0.0],
        _ => &[0.0, 1.0, -1.0, 0.25, 3.0],
    };
    let values: Vec<f32> = (0..elements * n)
        .map(|_| {
            if fault == 2 && u.ratio(1, 3).unwrap_or(false) {
                [f32::NAN, 0.0, 1e30, -1e30, 3e38, values::number(u, Some(1.0)) as f32][u.choose_index(6).unwrap_or(0)]
            } else {
                plausible[u.choose_index(plausible.len()).unwrap_or(0)]
            }
        })
        .collect();
    let output = match fault {
        // The wrong type: the same numbers as other vectors.
        3 => {
            let other = ["SCALAR", "VEC2", "VEC3", "VEC4"][u.choose_index(4).unwrap_or(0)];
            push_floats(doc, bin, &values, other)
        }
        // Normalized (or, as a fault, not) SHORT rotations.
        4 | 5 if path == "rotation" => {
            let shorts: Vec<u8> =
                values.iter().flat_map(|v| ((v.clamp(-1.0, 1.0) * 32767.0) as i16).to_le_bytes()).collect();
            let accessor = json!({"componentType": 5122, "count": elements, "type": "VEC4", "normalized": fault == 4});
            push_accessor(doc, bin, &shorts, accessor)
        }
        _ => push_floats(doc, bin, &values, ty),
    };
    json!({"input": input, "output": output, "interpolation": interpolation})
}

/// Appends `floats` to `bin` as a new FLOAT accessor of `ty`; returns its index.
pub(super) fn push_floats(doc: &mut Value, bin: &mut Vec<u8>, floats: &[f32], ty: &str) -> usize {
    let n = match ty {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "MAT4" => 16,
        _ => 4,
    };
    let bytes: Vec<u8> = floats.iter().flat_map(|f| f.to_le_bytes()).collect();
    push_accessor(doc, bin, &bytes, json!({"componentType": 5126, "count": floats.len() / n, "type": ty}))
}

/// Appends `bytes` to `bin` (4-aligned) as a new bufferView of buffer 0 (whose length grows)
/// and an accessor over it, `accessor` giving its other fields; returns the accessor's index.
pub(super) fn push_accessor(doc: &mut Value, bin: &mut Vec<u8>, bytes: &[u8], mut accessor: Value) -> usize {
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let view = json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()});
    bin.extend_from_slice(bytes);
    if count(doc, "buffers") == 0 {
        push(doc, "buffers", json!({"byteLength": 0}));
    }
    if let Some(buffer) = doc.pointer_mut("/buffers/0").and_then(Value::as_object_mut) {
        buffer.insert("byteLength".into(), json!(bin.len()));
    }
    accessor["bufferView"] = json!(push(doc, "bufferViews", view));
    push(doc, "accessors", accessor)
}

/// Appends `item` to the array `key` of the document (made if missing); returns its index.
pub(super) fn push(doc: &mut Value, key: &str, item: Value) -> usize {
    let Some(root) = doc.as_object_mut() else { return 0 };
    let entry = root.entry(key).or_insert(json!([]));
    if !entry.is_array() {
        *entry = json!([]);
    }
    let array = entry.as_array_mut().expect("an array");
    array.push(item);
    array.len() - 1
}
