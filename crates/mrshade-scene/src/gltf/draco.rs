//! `KHR_draco_mesh_compression`: a primitive whose geometry is a Draco bitstream in a
//! bufferView, decoded by the pure-Rust `draco-core`. The extension names which Draco
//! attribute (by unique id) holds each glTF attribute; the primitive's accessors then only
//! describe the decoded data (count, type, bounds) and have no bufferView of their own
//! (`document` lets that pass for them alone). Positions, normals and `TEXCOORD_0` are read;
//! a compressed skin or other attribute is a warning.

use super::buffers::view_bytes;
use crate::budget::Budget;
use anyhow::{Context, Result, bail};
use glam::{Vec2, Vec3};
use serde_json::Value;

/// The extension's name.
pub const EXTENSION: &str = "KHR_draco_mesh_compression";

/// A decoded primitive: per point positions (and normals, uvs where compressed) and the
/// triangle list.
pub struct Decoded {
    pub positions: Vec<Vec3>,
    pub normals: Option<Vec<Vec3>>,
    pub uvs: Option<Vec<Vec2>>,
    pub indices: Vec<u32>,
    /// Compressed attributes that are not read.
    pub ignored: Vec<String>,
}

/// Decodes the Draco geometry of `prim` given its extension object `ext`.
pub fn decode(document: &gltf::Document, ext: &Value, buffers: &[Vec<u8>], budget: &mut Budget) -> Result<Decoded> {
    let view_index = ext.get("bufferView").and_then(Value::as_u64).context("its bufferView is missing")?;
    let view =
        document.views().nth(view_index as usize).with_context(|| format!("bufferView {view_index} does not exist"))?;
    let attributes = ext.get("attributes").and_then(Value::as_object).context("its attributes are missing")?;
    let bytes = view_bytes(&view, buffers)?;
    let mut mesh = draco_core::Mesh::new();
    draco_core::MeshDecoder::new()
        .decode(&mut draco_core::DecoderBuffer::new(bytes), &mut mesh)
        .map_err(|e| anyhow::anyhow!("the Draco bitstream in bufferView {view_index} does not decode: {e}"))?;
    let points = mesh.num_points();
    budget.charge("the decoded Draco points", points as u64, 32)?;
    budget.charge("the decoded Draco triangles", mesh.num_faces() as u64, 12)?;
    let read = |name: &str, components: usize| -> Result<Option<Vec<f32>>> {
        let Some(id) = attributes.get(name) else { return Ok(None) };
        let id = id
            .as_u64()
            .filter(|&i| i <= u32::MAX as u64)
            .with_context(|| format!("attribute {name}: {id} is not an id"))?;
        let attribute = mesh
            .attribute_by_unique_id(id as u32)
            .with_context(|| format!("attribute {name}: the bitstream has no attribute of unique id {id}"))?;
        let values = attribute.read_f32s(points, components);
        if values.iter().any(|v| !v.is_finite()) {
            bail!("attribute {name}: holds NaN or infinite values");
        }
        Ok(Some(values))
    };
    let positions: Vec<Vec3> =
        read("POSITION", 3)?.context("no POSITION attribute")?.chunks_exact(3).map(Vec3::from_slice).collect();
    let normals =
        read("NORMAL", 3)?.map(|n| n.chunks_exact(3).map(|n| Vec3::from_slice(n).normalize_or(Vec3::Y)).collect());
    let uvs = read("TEXCOORD_0", 2)?.map(|t| t.chunks_exact(2).map(Vec2::from_slice).collect());
    let ignored =
        attributes.keys().filter(|k| !["POSITION", "NORMAL", "TEXCOORD_0"].contains(&k.as_str())).cloned().collect();
    let mut indices = Vec::with_capacity(mesh.num_faces() * 3);
    for face in mesh.faces() {
        for p in face {
            if p.0 as usize >= points {
                bail!("a Draco face names point {} of {points}", p.0);
            }
            indices.push(p.0);
        }
    }
    Ok(Decoded { positions, normals, uvs, indices, ignored })
}

/// The accessors of the primitives that `root` compresses with Draco (their data is in the
/// bitstream, so they have no bufferView).
pub fn compressed_accessors(root: &Value) -> Vec<usize> {
    let primitives =
        root.get("meshes").and_then(Value::as_array).into_iter().flatten().filter_map(|m| m.get("primitives"));
    let primitives = primitives.filter_map(Value::as_array).flatten();
    let mut out = Vec::new();
    for p in primitives.filter(|p| p.pointer(&format!("/extensions/{EXTENSION}")).is_some()) {
        let attributes = p.get("attributes").and_then(Value::as_object).into_iter().flat_map(|a| a.values());
        out.extend(attributes.chain(p.get("indices")).filter_map(Value::as_u64).map(|i| i as usize));
    }
    out
}
