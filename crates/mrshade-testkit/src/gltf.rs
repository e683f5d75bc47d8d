//! A small glTF 2.0 writer for synthetic test scenes, including deliberately broken ones.

use base64::Engine;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// Triangle mesh data.
#[derive(Clone, Debug, Default)]
pub struct Shape {
    /// Positions.
    pub positions: Vec<[f32; 3]>,
    /// Normals (same count as positions).
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinates (same count as positions).
    pub uvs: Vec<[f32; 2]>,
    /// Triangle indices.
    pub indices: Vec<u32>,
}

/// A square in the XZ plane facing +Y, side `2·half`, centred at the origin.
pub fn quad(half: f32) -> Shape {
    Shape {
        positions: vec![[-half, 0.0, -half], [-half, 0.0, half], [half, 0.0, half], [half, 0.0, -half]],
        normals: vec![[0.0, 1.0, 0.0]; 4],
        uvs: vec![[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

/// An axis-aligned box with the given half extents, centred at the origin, faces outward.
pub fn cuboid(h: [f32; 3]) -> Shape {
    let mut s = Shape::default();
    let axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for a in 0..3 {
        for sign in [1.0f32, -1.0] {
            let n = axes[a].map(|v| v * sign);
            let (u, v) = ((a + 1) % 3, (a + 2) % 3);
            let base = s.positions.len() as u32;
            for (du, dv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut p = [0.0; 3];
                p[a] = sign * h[a];
                p[u] = du * h[u];
                p[v] = dv * h[v];
                s.positions.push(p);
                s.normals.push(n);
                s.uvs.push([(du + 1.0) / 2.0, (dv + 1.0) / 2.0]);
            }
            let tri = if sign > 0.0 { [0, 1, 2, 0, 2, 3] } else { [0, 2, 1, 0, 3, 2] };
            s.indices.extend(tri.iter().map(|i| base + i));
        }
    }
    s
}

/// A UV sphere of `radius` with `n` segments around and `n/2` rings.
pub fn sphere(radius: f32, n: u32) -> Shape {
    let mut s = Shape::default();
    let rings = n / 2;
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for i in 0..=n {
            let phi = 2.0 * std::f32::consts::PI * i as f32 / n as f32;
            let d = [theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()];
            s.positions.push(d.map(|v| v * radius));
            s.normals.push(d);
            s.uvs.push([i as f32 / n as f32, r as f32 / rings as f32]);
        }
    }
    for r in 0..rings {
        for i in 0..n {
            let a = r * (n + 1) + i;
            let b = a + n + 1;
            s.indices.extend([a, a + 1, b, a + 1, b + 1, b]);
        }
    }
    s
}

/// Builds a glTF document with one binary buffer.
#[derive(Default)]
pub struct GltfBuilder {
    bin: Vec<u8>,
    buffer_views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
    materials: Vec<Value>,
    nodes: Vec<Value>,
    roots: Vec<usize>,
    lights: Vec<Value>,
    cameras: Vec<Value>,
    animations: Vec<Value>,
    skins: Vec<Value>,
    extensions_used: Vec<String>,
    extensions_required: Vec<String>,
}

impl GltfBuilder {
    /// An empty document.
    pub fn new() -> Self {
        Self::default()
    }

    fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.buffer_views.push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}));
        self.bin.extend_from_slice(bytes);
        self.buffer_views.len() - 1
    }

    /// A FLOAT accessor of `ty` ("VEC3", …) over `data`; POSITION-style min/max when `bounds`.
    pub fn accessor_f32(&mut self, data: &[f32], ty: &str, bounds: bool) -> usize {
        let n = match ty {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "MAT4" => 16,
            _ => 4,
        };
        let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes);
        let mut acc = json!({"bufferView": view, "componentType": 5126, "count": data.len() / n, "type": ty});
        if bounds {
            let (mut lo, mut hi) = (vec![f32::INFINITY; n], vec![f32::NEG_INFINITY; n]);
            for c in data.chunks(n) {
                for i in 0..n {
                    lo[i] = lo[i].min(c[i]);
                    hi[i] = hi[i].max(c[i]);
                }
            }
            acc["min"] = json!(lo);
            acc["max"] = json!(hi);
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    /// An accessor of `count` elements of `ty` ("VEC4", …) with glTF `component_type` (5120
    /// BYTE … 5126 FLOAT) over raw little-endian `bytes`; `normalized` integers.
    pub fn accessor_bytes(
        &mut self,
        bytes: &[u8],
        component_type: u32,
        ty: &str,
        count: usize,
        normalized: bool,
    ) -> usize {
        let view = self.view(bytes);
        let mut acc = json!({"bufferView": view, "componentType": component_type, "count": count, "type": ty});
        if normalized {
            acc["normalized"] = json!(true);
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    /// An UNSIGNED_INT SCALAR accessor (indices).
    pub fn accessor_u32(&mut self, data: &[u32]) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.accessors.push(json!({"bufferView": view, "componentType": 5125, "count": data.len(), "type": "SCALAR"}));
        self.accessors.len() - 1
    }

    /// Changes an accessor's JSON (to break it on purpose).
    pub fn patch_accessor(&mut self, index: usize, f: impl FnOnce(&mut Value)) {
        f(&mut self.accessors[index]);
    }

    /// A material from its JSON.
    pub fn material(&mut self, m: Value) -> usize {
        self.materials.push(m);
        self.materials.len() - 1
    }

    /// A mesh of `shape` with `material`; `normals: false` omits NORMAL.
    pub fn mesh(&mut self, shape: &Shape, material: Option<usize>, normals: bool) -> usize {
        let flat = |v: &[[f32; 3]]| v.iter().flatten().copied().collect::<Vec<f32>>();
        let pos = self.accessor_f32(&flat(&shape.positions), "VEC3", true);
        let mut attributes = json!({"POSITION": pos});
        if normals {
            attributes["NORMAL"] = json!(self.accessor_f32(&flat(&shape.normals), "VEC3", false));
        }
        if !shape.uvs.is_empty() {
            let uv: Vec<f32> = shape.uvs.iter().flatten().copied().collect();
            attributes["TEXCOORD_0"] = json!(self.accessor_f32(&uv, "VEC2", false));
        }
        let mut prim = json!({"attributes": attributes});
        if !shape.indices.is_empty() {
            prim["indices"] = json!(self.accessor_u32(&shape.indices));
        }
        if let Some(m) = material {
            prim["material"] = json!(m);
        }
        self.mesh_raw(prim)
    }

    /// A mesh with one primitive given as JSON.
    pub fn mesh_raw(&mut self, primitive: Value) -> usize {
        self.meshes.push(json!({"primitives": [primitive]}));
        self.meshes.len() - 1
    }

    /// A root node.
    pub fn node(&mut self, node: Value) -> usize {
        self.nodes.push(node);
        self.roots.push(self.nodes.len() - 1);
        self.nodes.len() - 1
    }

    /// A child node of `parent`.
    pub fn child(&mut self, parent: usize, node: Value) -> usize {
        self.nodes.push(node);
        let id = self.nodes.len() - 1;
        let children = self.nodes[parent].as_object_mut().expect("node object").entry("children").or_insert(json!([]));
        children.as_array_mut().expect("children array").push(json!(id));
        id
    }

    /// A `KHR_lights_punctual` light.
    pub fn light(&mut self, light: Value) -> usize {
        self.use_extension("KHR_lights_punctual", false);
        self.lights.push(light);
        self.lights.len() - 1
    }

    /// A camera.
    pub fn camera(&mut self, camera: Value) -> usize {
        self.cameras.push(camera);
        self.cameras.len() - 1
    }

    /// A perspective camera node at `translation` looking down −Z rotated by quaternion `rotation`.
    pub fn camera_node(
        &mut self,
        name: &str,
        yfov: f32,
        aspect: Option<f32>,
        translation: [f32; 3],
        rotation: [f32; 4],
    ) -> usize {
        let mut perspective = json!({"yfov": yfov, "znear": 0.01, "zfar": 100.0});
        if let Some(a) = aspect {
            perspective["aspectRatio"] = json!(a);
        }
        let cam = self.camera(json!({"type": "perspective", "perspective": perspective}));
        self.node(json!({"name": name, "camera": cam, "translation": translation, "rotation": rotation}))
    }

    /// An animation from its JSON (its samplers name accessors made here).
    pub fn animation(&mut self, animation: Value) -> usize {
        self.animations.push(animation);
        self.animations.len() - 1
    }

    /// A skin from its JSON (its joints name nodes, its matrices an accessor made here).
    pub fn skin(&mut self, skin: Value) -> usize {
        self.skins.push(skin);
        self.skins.len() - 1
    }

    /// Changes a node's JSON.
    pub fn patch_node(&mut self, index: usize, f: impl FnOnce(&mut Value)) {
        f(&mut self.nodes[index]);
    }

    /// Lists an extension as used (and required).
    pub fn use_extension(&mut self, name: &str, required: bool) {
        if !self.extensions_used.iter().any(|e| e == name) {
            self.extensions_used.push(name.into());
        }
        if required && !self.extensions_required.iter().any(|e| e == name) {
            self.extensions_required.push(name.into());
        }
    }

    /// The binary buffer.
    pub fn bin(&self) -> &[u8] {
        &self.bin
    }

    /// The JSON document; the buffer is at `buffer_uri` (or the GLB chunk when `None`).
    pub fn json(&self, buffer_uri: Option<&str>) -> Value {
        let mut buffer = json!({"byteLength": self.bin.len()});
        if let Some(uri) = buffer_uri {
            buffer["uri"] = json!(uri);
        }
        let mut doc = json!({
            "asset": {"version": "2.0", "generator": "mrshade-testkit"},
            "scene": 0,
            "scenes": [{"nodes": self.roots}],
            "nodes": self.nodes,
            "meshes": self.meshes,
            "materials": self.materials,
            "accessors": self.accessors,
            "bufferViews": self.buffer_views,
            "buffers": [buffer],
            "cameras": self.cameras,
        });
        if !self.animations.is_empty() {
            doc["animations"] = json!(self.animations);
        }
        if !self.skins.is_empty() {
            doc["skins"] = json!(self.skins);
        }
        if !self.lights.is_empty() {
            doc["extensions"] = json!({"KHR_lights_punctual": {"lights": self.lights}});
        }
        if !self.extensions_used.is_empty() {
            doc["extensionsUsed"] = json!(self.extensions_used);
        }
        if !self.extensions_required.is_empty() {
            doc["extensionsRequired"] = json!(self.extensions_required);
        }
        for key in ["materials", "cameras", "meshes"] {
            if doc[key].as_array().is_some_and(|a| a.is_empty()) {
                doc.as_object_mut().expect("object").remove(key);
            }
        }
        doc
    }

    /// Writes `<stem>.gltf` and `<stem>.bin` into `dir`; returns the .gltf path.
    pub fn write_gltf(&self, dir: &Path, stem: &str) -> PathBuf {
        let bin_name = format!("{stem}.bin");
        std::fs::write(dir.join(&bin_name), &self.bin).expect("write bin");
        let path = dir.join(format!("{stem}.gltf"));
        std::fs::write(&path, serde_json::to_vec_pretty(&self.json(Some(&bin_name))).expect("json"))
            .expect("write gltf");
        path
    }

    /// The document with its buffer as a base64 data URI (one self-contained .gltf).
    pub fn embedded_json(&self) -> Vec<u8> {
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&self.bin)
        );
        serde_json::to_vec(&self.json(Some(&uri))).expect("json")
    }

    /// The document as a binary `.glb`.
    pub fn glb(&self) -> Vec<u8> {
        pack_glb(&serde_json::to_vec(&self.json(None)).expect("json"), &self.bin)
    }
}

/// A binary glTF (`.glb`, glTF 2.0 §4.4) of a JSON chunk and a BIN chunk, each padded to four
/// bytes (JSON with spaces, BIN with zeros).
pub fn pack_glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |bytes: &[u8], with: u8| {
        let mut v = bytes.to_vec();
        while !v.len().is_multiple_of(4) {
            v.push(with);
        }
        v
    };
    let (json, bin) = (pad(json, b' '), pad(bin, 0));
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// Copies the session folder `from` (its `session.toml`, `scene.glb`, photo and probe) into
/// `to`, with the glTF document changed by `edit`: how hostile-input tests make one input of a
/// committed session.
pub fn copy_session_with(from: &Path, to: &Path, edit: impl FnOnce(&mut Value)) {
    for entry in std::fs::read_dir(from).expect("read the session folder") {
        let path = entry.expect("entry").path();
        if path.is_file() && path.file_name() != Some("scene.glb".as_ref()) {
            std::fs::copy(&path, to.join(path.file_name().expect("a file"))).expect("copy");
        }
    }
    let (json, bin) = unpack_glb(&std::fs::read(from.join("scene.glb")).expect("read scene.glb"));
    let mut doc: Value = serde_json::from_slice(&json).expect("JSON");
    edit(&mut doc);
    std::fs::write(to.join("scene.glb"), pack_glb(&serde_json::to_vec(&doc).expect("JSON"), &bin)).expect("write");
}

/// Appends `node` to the document's nodes and lists it as a root of scene 0; returns its index.
pub fn push_root(doc: &mut Value, node: Value) -> usize {
    let nodes = doc["nodes"].as_array_mut().expect("nodes");
    nodes.push(node);
    let index = nodes.len() - 1;
    doc["scenes"][0]["nodes"].as_array_mut().expect("scene 0").push(index.into());
    index
}

/// The JSON and BIN chunks of a `.glb`, read leniently (for tests that take a file apart and
/// change it; the loader's own reading is strict).
pub fn unpack_glb(glb: &[u8]) -> (Vec<u8>, Vec<u8>) {
    let word = |at: usize| glb.get(at..at + 4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize);
    let (mut json, mut bin) = (Vec::new(), Vec::new());
    let mut at = 12;
    while let (Some(len), Some(kind)) = (word(at), word(at + 4)) {
        let chunk = glb.get(at + 8..(at + 8).saturating_add(len)).unwrap_or_default();
        match &(kind as u32).to_le_bytes() {
            b"JSON" => json = chunk.to_vec(),
            b"BIN\0" => bin = chunk.to_vec(),
            _ => {}
        }
        at = at + 8 + len;
    }
    (json, bin)
}

/// Lambertian material JSON (`KHR_materials_specular` 0) of linear `color`.
pub fn lambert(name: &str, color: [f32; 3]) -> Value {
    json!({
        "name": name,
        "pbrMetallicRoughness": {"baseColorFactor": [color[0], color[1], color[2], 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0},
        "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}
    })
}

/// Quaternion (x, y, z, w) rotating by `angle` radians about unit `axis`.
pub fn quat(axis: [f32; 3], angle: f32) -> [f32; 4] {
    let s = (angle / 2.0).sin();
    [axis[0] * s, axis[1] * s, axis[2] * s, (angle / 2.0).cos()]
}

/// Writes an RGB8 PNG whose pixel (x, y) is `f(x, y)`.
pub fn write_png(path: &Path, width: u32, height: u32, f: impl Fn(u32, u32) -> [u8; 3]) {
    let img = image::RgbImage::from_fn(width, height, |x, y| image::Rgb(f(x, y)));
    img.save(path).expect("write png");
}

/// Writes a float EXR (linear) whose pixel (x, y) is `f(x, y)`.
pub fn write_exr(path: &Path, width: u32, height: u32, f: impl Fn(u32, u32) -> [f32; 3]) {
    let img = image::Rgb32FImage::from_fn(width, height, |x, y| image::Rgb(f(x, y)));
    image::DynamicImage::ImageRgb32F(img).save(path).expect("write exr");
}
