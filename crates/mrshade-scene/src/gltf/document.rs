//! From bytes to a glTF document that every later loader may trust: one validation pass.
//!
//! The `gltf` crate's own validation assumes some references valid before it checks them (a
//! mesh attribute naming a missing accessor panicked inside it), reads indices above 2³²−1
//! modulo 2³² (mesh 2³²+4 became mesh 4), does not check animation targets, and accepts any
//! node graph. So, in order:
//! 1. the GLB container is split strictly (its header length must be the file's);
//! 2. the raw JSON is checked for what typed parsing would lose: `asset.version` and integers
//!    that cannot be indices or counts; then for required extensions mrshade lacks, and what
//!    glTF leaves optional but the dependency requires (a scene's `nodes`) is filled in;
//! 3. the references the dependency's validation dereferences unchecked are checked, and
//!    what it unwraps (animation paths and interpolations, camera projections);
//! 4. the dependency's structural validation runs;
//! 5. the node graph must be a forest (glTF 2.0 §3.5.3): no node with two parents or listed
//!    twice, no cycle, scene roots that are roots. A directed acyclic graph of 50 nodes can
//!    hold 2²⁵ paths; walking it would never end.

use anyhow::{Context, Result, bail};
use gltf::json::validation::{Error as ValidationError, Validate};
use serde_json::Value;

/// A parsed, validated document and the GLB's binary chunk, if any.
pub struct Parsed {
    /// The document; every index in it is in range.
    pub document: gltf::Document,
    /// The GLB `BIN` chunk.
    pub blob: Option<Vec<u8>>,
}

/// Parses and validates a `.gltf` (JSON) or `.glb` file.
pub fn parse(bytes: &[u8]) -> Result<Parsed> {
    if bytes.is_empty() {
        bail!("the file is empty");
    }
    let (json, blob) = if bytes.starts_with(b"glTF") { split_glb(bytes)? } else { (bytes, None) };
    let mut value: Value = serde_json::from_slice(json).context("not valid glTF 2.0 (the JSON does not parse)")?;
    check_raw(&value)?;
    super::extensions::check_required(&value)?;
    let compressed = super::draco::compressed_accessors(&value);
    // Parsed from the text where nothing was filled in: its errors name line and column.
    let root: gltf::json::Root = if fill_optional(&mut value) {
        serde_json::from_value(value).context("not valid glTF 2.0")?
    } else {
        serde_json::from_slice(json).context("not valid glTF 2.0")?
    };
    check_unchecked_references(&root)?;
    validate(&root, &compressed)?;
    check_forest(&root)?;
    Ok(Parsed { document: gltf::Document::from_json_without_validation(root), blob: blob.map(<[u8]>::to_vec) })
}

/// The JSON and BIN chunks of a GLB file (glTF 2.0 §4.4), every length checked.
fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>)> {
    let word = |at: usize| -> Option<u32> { Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?)) };
    let (Some(version), Some(length)) = (word(4), word(8)) else {
        bail!("the GLB header is truncated ({} bytes)", bytes.len());
    };
    if version != 2 {
        bail!("GLB version {version} is not supported (glTF 2.0 has version 2)");
    }
    if length as usize != bytes.len() {
        bail!("the GLB header declares {length} bytes but the file holds {}", bytes.len());
    }
    let mut at = 12;
    let mut chunks = Vec::new();
    while at < bytes.len() {
        let (Some(chunk_length), Some(kind)) = (word(at), word(at + 4)) else {
            bail!("GLB chunk {} has a truncated header", chunks.len());
        };
        let start = at + 8;
        let end = start.checked_add(chunk_length as usize).filter(|&e| e <= bytes.len());
        let Some(end) = end else {
            bail!(
                "GLB chunk {} declares {chunk_length} bytes but only {} remain",
                chunks.len(),
                bytes.len() - start.min(bytes.len())
            );
        };
        chunks.push((kind.to_le_bytes(), &bytes[start..end]));
        at = end;
    }
    match chunks.as_slice() {
        [([b'J', b'S', b'O', b'N'], json), rest @ ..] => {
            let bin = rest.iter().find(|(kind, _)| kind == b"BIN\0").map(|(_, data)| *data);
            Ok((json, bin))
        }
        _ => bail!("the first GLB chunk is not the JSON chunk"),
    }
}

/// Fills in what glTF 2.0 makes optional but the `gltf` crate's types require: a scene's
/// `nodes` (a scene may be empty). Returns whether it filled anything in.
fn fill_optional(value: &mut Value) -> bool {
    let mut filled = false;
    if let Some(scenes) = value.get_mut("scenes").and_then(Value::as_array_mut) {
        for scene in scenes.iter_mut().filter_map(Value::as_object_mut) {
            if !scene.contains_key("nodes") {
                scene.insert("nodes".into(), Value::Array(Vec::new()));
                filled = true;
            }
        }
    }
    filled
}

/// What typed parsing would silently lose.
fn check_raw(value: &Value) -> Result<()> {
    let version = value.pointer("/asset/version").and_then(Value::as_str).context("asset.version is missing")?;
    let major = |v: &str| v.split('.').next().and_then(|m| m.parse::<u32>().ok());
    if major(version) != Some(2) {
        bail!("asset.version is '{}': mrshade reads glTF 2.x", mrshade_core::text::printable(version));
    }
    if let Some(min) = value.pointer("/asset/minVersion").and_then(Value::as_str)
        && min != "2.0"
    {
        bail!("asset.minVersion is '{}': mrshade reads glTF 2.0", mrshade_core::text::printable(min));
    }
    check_integers(value, &mut String::new())
}

/// Keys whose values are indices into the document (`Index<T>` in the `gltf` crate, read as
/// `u32`: 2³²+4 would become 4). Counts, offsets and lengths are read as 64-bit and checked
/// against the buffers and the memory budget later.
const INDEX_KEYS: &[&str] = &[
    "scene",
    "nodes",
    "children",
    "mesh",
    "camera",
    "skin",
    "skeleton",
    "joints",
    "inverseBindMatrices",
    "material",
    "indices",
    "bufferView",
    "buffer",
    "source",
    "sampler",
    "index",
    "node",
    "input",
    "output",
    "light",
];

/// Every index (a value of an [`INDEX_KEYS`] key, an element of one, or a value of an
/// `attributes` or morph-target map) must fit in 32 bits. `extras` and unknown extensions
/// are not glTF's to judge.
fn check_integers(value: &Value, path: &mut String) -> Result<()> {
    walk(value, path, Holds::Other)
}

/// What the values under a key are.
#[derive(Clone, Copy, PartialEq)]
enum Holds {
    /// Indices (arrays of them too).
    Indices,
    /// Objects whose every value is an index (`attributes`, `targets`).
    IndexMaps,
    /// Anything else.
    Other,
}

fn walk(value: &Value, path: &mut String, holds: Holds) -> Result<()> {
    let descend = |path: &mut String, step: &str, item: &Value, holds: Holds| {
        let len = path.len();
        path.push_str(step);
        let r = walk(item, path, holds);
        path.truncate(len);
        r
    };
    match value {
        Value::Number(n) if holds == Holds::Indices => {
            if let Some(v) = n.as_u64()
                && v > u32::MAX as u64
            {
                bail!("{path}: {v} is larger than any index in glTF can be (2³²−1)");
            }
        }
        Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                descend(path, &format!("[{i}]"), item, holds)?;
            }
        }
        Value::Object(map) => {
            for (key, item) in map {
                let unknown_extension =
                    path.ends_with("extensions") && !super::SUPPORTED_EXTENSIONS.contains(&key.as_str());
                if key == "extras" || unknown_extension {
                    continue;
                }
                let inner = match key.as_str() {
                    _ if holds == Holds::IndexMaps => Holds::Indices,
                    "attributes" | "targets" => Holds::IndexMaps,
                    k if INDEX_KEYS.contains(&k) => Holds::Indices,
                    _ => Holds::Other,
                };
                let step = format!("{}{}", if path.is_empty() { "" } else { "." }, mrshade_core::text::printable(key));
                descend(path, &step, item, inner)?;
            }
        }
        _ => {}
    }
    Ok(())
}

/// What the `gltf` crate dereferences or unwraps before (or without) checking it: references
/// in mesh attributes and morph targets, animation targets, an image's source, a camera's
/// projection of its declared type.
fn check_unchecked_references(root: &gltf::json::Root) -> Result<()> {
    for (i, image) in root.images.iter().enumerate() {
        match (&image.uri, &image.buffer_view, &image.mime_type) {
            (Some(_), None, _) | (None, Some(_), Some(_)) => {}
            (None, Some(_), None) => bail!("invalid glTF: images[{i}] has a bufferView but no mimeType"),
            _ => bail!("invalid glTF: images[{i}] must have either a uri or a bufferView"),
        }
    }
    for (i, camera) in root.cameras.iter().enumerate() {
        use gltf::json::camera::Type;
        use gltf::json::validation::Checked;
        let present = match camera.type_ {
            Checked::Valid(Type::Perspective) => camera.perspective.is_some(),
            Checked::Valid(Type::Orthographic) => camera.orthographic.is_some(),
            Checked::Invalid => true, // the structural validation names it
        };
        if !present {
            bail!("invalid glTF: cameras[{i}] lacks the projection object of its type");
        }
    }
    let accessors = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let targets = primitive.targets.iter().flatten();
            let target_refs = targets.flat_map(|t| [t.positions, t.normals, t.tangents]).flatten();
            let refs = primitive.attributes.values().copied().chain(target_refs);
            if let Some(bad) = refs.map(|a| a.value()).find(|&a| a >= accessors) {
                bail!(
                    "invalid glTF: meshes[{m}].primitives[{p}] names accessor {bad}, but the file has {accessors} accessors"
                );
            }
        }
    }
    for (a, animation) in root.animations.iter().enumerate() {
        check_animation(root, a, animation)?;
    }
    Ok(())
}

/// An animation's references (samplers, nodes, accessors), its paths and interpolations
/// (the `gltf` crate unwraps them), and glTF 2.0 §3.11's rule that an animated node has no
/// `matrix`.
fn check_animation(root: &gltf::json::Root, a: usize, animation: &gltf::json::Animation) -> Result<()> {
    use gltf::json::animation::Property;
    use gltf::json::validation::Checked;
    let named = match &animation.name {
        Some(name) => format!(" (animation '{}')", mrshade_core::text::printable(name)),
        None => String::new(),
    };
    let accessors = root.accessors.len();
    for (s, sampler) in animation.samplers.iter().enumerate() {
        for (field, accessor) in [("input", sampler.input.value()), ("output", sampler.output.value())] {
            if accessor >= accessors {
                bail!(
                    "invalid glTF: animations[{a}].samplers[{s}].{field} is accessor {accessor}, but the file has {accessors} accessors{named}"
                );
            }
        }
        if sampler.interpolation == Checked::Invalid {
            bail!(
                "invalid glTF: animations[{a}].samplers[{s}].interpolation is not LINEAR, STEP or CUBICSPLINE{named}"
            );
        }
    }
    for (c, channel) in animation.channels.iter().enumerate() {
        let here = format!("animations[{a}].channels[{c}]");
        let node = channel.target.node.value();
        let Some(target) = root.nodes.get(node) else {
            bail!("invalid glTF: {here}.target.node is {node}, but the file has {} nodes{named}", root.nodes.len());
        };
        let sampler = channel.sampler.value();
        if sampler >= animation.samplers.len() {
            bail!(
                "invalid glTF: {here}.sampler is {sampler}, but the animation has {} samplers{named}",
                animation.samplers.len()
            );
        }
        match channel.target.path {
            Checked::Invalid => {
                bail!("invalid glTF: {here}.target.path is not translation, rotation, scale or weights{named}")
            }
            Checked::Valid(Property::MorphTargetWeights) => {}
            Checked::Valid(_) if target.matrix.is_some() => bail!(
                "invalid glTF: {here} animates nodes[{node}], which has a matrix (an animated node must use translation, rotation and scale){named}"
            ),
            Checked::Valid(_) => {}
        }
    }
    Ok(())
}

/// Runs the `gltf` crate's structural validation (indices in range, required fields), but
/// leaves `extensionsRequired` to `extensions::check_required`, which knows what mrshade
/// honours, and lets the accessors of Draco-compressed primitives (`compressed`) go without
/// a bufferView, as `KHR_draco_mesh_compression` has them.
fn validate(root: &gltf::json::Root, compressed: &[usize]) -> Result<()> {
    let mut errors = Vec::new();
    let draco_view = |path: &str| {
        let index = path.strip_prefix("accessors[").and_then(|p| p.strip_suffix("].bufferView"));
        index.and_then(|i| i.parse::<usize>().ok()).is_some_and(|i| compressed.contains(&i))
    };
    root.validate(root, gltf::json::Path::new, &mut |path, error| {
        let path = path().to_string();
        let required = error == ValidationError::Unsupported && path.starts_with("extensionsRequired");
        if !(required || (error == ValidationError::Missing && draco_view(&path))) {
            errors.push(format!("{}: {error}", mrshade_core::text::printable(&path)));
        }
    });
    if !errors.is_empty() {
        let shown: Vec<_> = errors.iter().take(5).cloned().collect();
        bail!("invalid glTF: {}{}", shown.join("; "), if errors.len() > 5 { "; …" } else { "" });
    }
    Ok(())
}

/// glTF 2.0 §3.5.3: "the node hierarchy MUST be a set of disjoint strict trees".
fn check_forest(root: &gltf::json::Root) -> Result<()> {
    let count = root.nodes.len();
    let mut parent: Vec<Option<usize>> = vec![None; count];
    for (p, node) in root.nodes.iter().enumerate() {
        for child in node.children.iter().flatten().map(|c| c.value()) {
            if child == p {
                bail!("invalid glTF: nodes[{p}] lists itself as a child");
            }
            if let Some(other) = parent[child] {
                let how = if other == p {
                    format!("twice by nodes[{p}]")
                } else {
                    format!("by nodes[{other}] and nodes[{p}]")
                };
                bail!("invalid glTF: nodes[{child}] is listed as a child {how}; the node hierarchy must be a forest");
            }
            parent[child] = Some(p);
        }
    }
    // With one parent each, a walk up either reaches a root or goes round a cycle.
    let mut state = vec![0u8; count]; // 0 unseen, 1 on the current walk, 2 leads to a root
    for start in 0..count {
        let mut walk = Vec::new();
        let mut n = Some(start);
        while let Some(i) = n {
            match state[i] {
                2 => break,
                1 => bail!("invalid glTF: nodes[{i}] is its own ancestor (a cycle in the node hierarchy)"),
                _ => {
                    state[i] = 1;
                    walk.push(i);
                    n = parent[i];
                }
            }
        }
        for i in walk {
            state[i] = 2;
        }
    }
    for (s, scene) in root.scenes.iter().enumerate() {
        let mut seen = vec![false; count];
        for node in scene.nodes.iter().map(|n| n.value()) {
            if let Some(p) = parent[node] {
                bail!("invalid glTF: scenes[{s}] lists nodes[{node}] as a root, but it is a child of nodes[{p}]");
            }
            if std::mem::replace(&mut seen[node], true) {
                bail!("invalid glTF: scenes[{s}] lists nodes[{node}] twice");
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glb(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend(0u32.to_le_bytes());
        for (kind, data) in [(*b"JSON", Some(json)), (*b"BIN\0", bin)] {
            if let Some(data) = data {
                out.extend((data.len() as u32).to_le_bytes());
                out.extend(kind);
                out.extend(data);
            }
        }
        let length = out.len() as u32;
        out[8..12].copy_from_slice(&length.to_le_bytes());
        out
    }

    #[test]
    fn glb_lengths_are_checked() {
        let json = br#"{"asset":{"version":"2.0"}}"#;
        let good = glb(json, Some(&[1, 2, 3, 4]));
        let (j, b) = split_glb(&good).unwrap();
        assert_eq!((j, b), (&json[..], Some(&[1u8, 2, 3, 4][..])));
        let mut longer = good.clone();
        longer.extend([0; 4]);
        assert!(split_glb(&longer).unwrap_err().to_string().contains("declares"));
        let mut wrong_chunk = good.clone();
        wrong_chunk[12] = 200;
        assert!(split_glb(&wrong_chunk).unwrap_err().to_string().contains("remain"));
        assert!(split_glb(b"glTF\x02\x00").unwrap_err().to_string().contains("truncated"));
        let mut v1 = good;
        v1[4] = 1;
        assert!(split_glb(&v1).unwrap_err().to_string().contains("version 1"));
    }

    #[test]
    fn versions_and_wide_integers_are_refused() {
        let parse_err = |s: &str| format!("{:#}", parse(s.as_bytes()).err().expect("must fail"));
        assert!(parse_err(r#"{"asset":{"version":"7.3"}}"#).contains("7.3"));
        assert!(parse_err(r#"{"asset":{"version":"1.0"}}"#).contains("glTF 2.x"));
        assert!(parse_err(r#"{"asset":{"version":"2.0","minVersion":"2.1"}}"#).contains("minVersion"));
        let wide = parse_err(r#"{"asset":{"version":"2.0"},"nodes":[{"mesh":4294967300}]}"#);
        assert!(wide.contains("nodes[0].mesh") && wide.contains("4294967300"), "{wide}");
        let attribute = parse_err(
            r#"{"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":4294967296}}]}]}"#,
        );
        assert!(attribute.contains("attributes.POSITION"), "{attribute}");
        // Floats written as integers, and extras, may hold any number.
        parse(br#"{"asset":{"version":"2.0"},"nodes":[{"translation":[4294967296,0,0]}],"extras":{"t":99999999999}}"#)
            .unwrap();
    }

    #[test]
    fn node_graphs_must_be_forests() {
        let doc = |nodes: &str, roots: &str| {
            format!(r#"{{"asset":{{"version":"2.0"}},"nodes":{nodes},"scenes":[{{"nodes":{roots}}}]}}"#)
        };
        let err = |nodes: &str, roots: &str| format!("{:#}", parse(doc(nodes, roots).as_bytes()).err().unwrap());
        assert!(err(r#"[{"children":[2]},{"children":[2]},{}]"#, "[0,1]").contains("by nodes[0] and nodes[1]"));
        assert!(err(r#"[{"children":[1,1]},{}]"#, "[0]").contains("twice"));
        assert!(err(r#"[{"children":[0]}]"#, "[0]").contains("itself"));
        assert!(err(r#"[{"children":[1]},{"children":[0]}]"#, "[]").contains("own ancestor"));
        assert!(err(r#"[{"children":[1]},{}]"#, "[0,1]").contains("child of nodes[0]"));
        assert!(err(r#"[{},{}]"#, "[0,0]").contains("twice"));
        parse(doc(r#"[{"children":[1,2]},{},{"children":[3]},{}]"#, "[0]").as_bytes()).unwrap();
    }

    #[test]
    fn dangling_attribute_references_are_errors_not_panics() {
        let doc =
            r#"{"asset":{"version":"2.0"},"accessors":[],"meshes":[{"primitives":[{"attributes":{"POSITION":99}}]}]}"#;
        let msg = format!("{:#}", parse(doc.as_bytes()).err().unwrap());
        assert!(msg.contains("accessor 99") && msg.contains("0 accessors"), "{msg}");
        let anim = r#"{"asset":{"version":"2.0"},"animations":[{"channels":[{"sampler":0,"target":{"node":7,"path":"rotation"}}],"samplers":[]}]}"#;
        assert!(format!("{:#}", parse(anim.as_bytes()).err().unwrap()).contains("target.node is 7"));
        // Found by the fuzzer: an image with neither source unwrapped None inside the crate.
        let image = r#"{"asset":{"version":"2.0"},"images":[{}]}"#;
        assert!(format!("{:#}", parse(image.as_bytes()).err().unwrap()).contains("images[0] must have either"));
        let camera = r#"{"asset":{"version":"2.0"},"cameras":[{"type":"perspective","orthographic":{"xmag":1,"ymag":1,"zfar":2,"znear":1}}]}"#;
        assert!(format!("{:#}", parse(camera.as_bytes()).err().unwrap()).contains("cameras[0] lacks"));
    }
}
