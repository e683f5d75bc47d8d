//! Skin and morph-target mutations (glTF 2.0 §3.7.3, §3.7.2.2): a skin on a node of a mesh
//! whose joints may lie outside the scene or the node list, with inverse bind matrices of any
//! count and value, `JOINTS_0` that name joints past the skin and `WEIGHTS_0` that do not sum
//! to one; morph targets with any displacements and `weights` of any length.

use super::gltf::{count, json_number, push, push_accessor, push_floats};
use super::values;
use arbitrary::Unstructured;
use serde_json::{Value, json};

/// Adds a skin or morph targets to a mesh of `doc`.
pub(super) fn mutate(doc: &mut Value, bin: &mut Vec<u8>, u: &mut Unstructured) -> String {
    let (meshes, nodes) = (count(doc, "meshes"), count(doc, "nodes"));
    if meshes == 0 || nodes == 0 {
        return "no mesh to deform".into();
    }
    let mesh = u.choose_index(meshes).unwrap_or(0);
    let position = doc.pointer(&format!("/meshes/{mesh}/primitives/0/attributes/POSITION")).and_then(Value::as_u64);
    let declared = position.and_then(|a| doc.pointer(&format!("/accessors/{a}/count"))).and_then(Value::as_u64);
    // As many vertices as the mesh has (bounded), or one fewer.
    let vertices = declared.unwrap_or(3).clamp(1, 4096) as usize - usize::from(u.ratio(1, 8).unwrap_or(false));
    let attributes = format!("/meshes/{mesh}/primitives/0/attributes");
    if u.ratio(1, 2).unwrap_or(false) {
        let joints = u.int_in_range(1..=4u16).unwrap_or(1);
        let joint_nodes: Vec<usize> = (0..joints)
            .map(|_| {
                [0, nodes.saturating_sub(1), nodes, u.choose_index(nodes).unwrap_or(0)][u.choose_index(4).unwrap_or(0)]
            })
            .collect();
        let mut matrices = Vec::new();
        for _ in 0..joints + u16::from(u.ratio(1, 6).unwrap_or(false)) {
            let mut m = [1.0f32, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0];
            if u.ratio(1, 5).unwrap_or(false) {
                m[u.choose_index(16).unwrap_or(0)] = values::number(u, Some(1.0)) as f32;
            }
            matrices.extend(m);
        }
        let ibm = push_floats(doc, bin, &matrices, "MAT4");
        let skin = push(doc, "skins", json!({"joints": joint_nodes, "inverseBindMatrices": ibm}));
        let most = joints + u16::from(u.ratio(1, 6).unwrap_or(false));
        let joint_bytes: Vec<u8> =
            (0..vertices * 4).map(|_| u.int_in_range(0..=most - 1).unwrap_or(0)).flat_map(u16::to_le_bytes).collect();
        let weights: Vec<f32> = (0..vertices)
            .flat_map(|_| {
                let w = u.int_in_range(0..=4u8).unwrap_or(0) as f32 / 4.0;
                let spill = if u.ratio(1, 10).unwrap_or(false) { values::number(u, Some(0.5)) as f32 } else { 0.0 };
                [w, 1.0 - w + spill, 0.0, 0.0]
            })
            .collect();
        let joints_accessor =
            push_accessor(doc, bin, &joint_bytes, json!({"componentType": 5123, "count": vertices, "type": "VEC4"}));
        let weights_accessor = push_floats(doc, bin, &weights, "VEC4");
        if let Some(a) = doc.pointer_mut(&attributes).and_then(Value::as_object_mut) {
            a.insert("JOINTS_0".into(), json!(joints_accessor));
            a.insert("WEIGHTS_0".into(), json!(weights_accessor));
        }
        let node = u.choose_index(nodes).unwrap_or(0);
        if let Some(n) = doc.pointer_mut(&format!("/nodes/{node}")).and_then(Value::as_object_mut) {
            n.insert("mesh".into(), json!(mesh));
            n.insert("skin".into(), json!(skin));
        }
        format!("meshes[{mesh}] skinned to {joint_nodes:?} by nodes[{node}] ({vertices} vertices)")
    } else {
        let targets = u.int_in_range(1..=3usize).unwrap_or(1);
        let mut list = Vec::new();
        for _ in 0..targets {
            let scale = values::number(u, Some(0.1)) as f32;
            let deltas: Vec<f32> = (0..vertices * 3).map(|i| scale * ((i % 7) as f32 - 3.0)).collect();
            list.push(json!({"POSITION": push_floats(doc, bin, &deltas, "VEC3")}));
        }
        let weights: Vec<Value> = (0..targets + u.int_in_range(0..=1usize).unwrap_or(0))
            .map(|_| json_number(values::number(u, Some(0.5))))
            .collect();
        if let Some(p) = doc.pointer_mut(&format!("/meshes/{mesh}/primitives/0")).and_then(Value::as_object_mut) {
            p.insert("targets".into(), json!(list));
        }
        if let Some(m) = doc.pointer_mut(&format!("/meshes/{mesh}")).and_then(Value::as_object_mut) {
            m.insert("weights".into(), json!(weights));
        }
        format!("meshes[{mesh}]: {targets} morph targets, weights {weights:?} ({vertices} vertices)")
    }
}
