//! Skins (glTF 2.0 §3.7.3): joints and inverse bind matrices, read after the nodes are placed
//! (a joint may come after the mesh it moves), one scene skin per glTF skin so an instance's
//! skin index carries over. Every joint must be a node of the loaded scene, every inverse bind
//! matrix finite and invertible, and every joint index of a skinned primitive must name one
//! of its skin's joints.

use super::{accessors, describe};
use crate::Scene;
use crate::budget::Budget;
use crate::model::{Skin, is_invertible};
use anyhow::{Context, Result, bail};
use glam::Mat4;
use gltf::accessor::{DataType, Dimensions};

/// Reads every skin into `scene.skins` (in file order) and checks the skinned instances'
/// joint indices; `scene_node_of` maps glTF nodes to `scene.nodes`.
pub fn load_skins(
    document: &gltf::Document,
    buffers: &[Vec<u8>],
    scene_node_of: &[Option<usize>],
    budget: &mut Budget,
    scene: &mut Scene,
) -> Result<()> {
    for skin in document.skins() {
        let here = || format!("skin {}", describe(Some(skin.index()), skin.name()));
        let mut joints = Vec::new();
        for joint in skin.joints() {
            let Some(node) = scene_node_of.get(joint.index()).copied().flatten() else {
                bail!(
                    "{}: joint node {} is not in the scene that is loaded (joints must be nodes of the scene)",
                    here(),
                    describe(Some(joint.index()), joint.name())
                );
            };
            joints.push(node);
        }
        let inverse_bind = match skin.inverse_bind_matrices() {
            None => vec![Mat4::IDENTITY; joints.len()],
            Some(accessor) => {
                accessors::check(&accessor, "inverseBindMatrices", Dimensions::Mat4, &[DataType::F32], buffers, budget)
                    .with_context(here)?;
                if accessor.count() != joints.len() {
                    bail!(
                        "{}: inverseBindMatrices has {} matrices for {} joints",
                        here(),
                        accessor.count(),
                        joints.len()
                    );
                }
                let reader = skin.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
                let read = reader.read_inverse_bind_matrices().context("inverseBindMatrices data out of range");
                let matrices: Vec<Mat4> = read.with_context(here)?.map(|m| Mat4::from_cols_array_2d(&m)).collect();
                if let Some(j) = matrices.iter().position(|m| !m.is_finite() || !is_invertible(*m)) {
                    bail!("{}: inverse bind matrix {j} is not finite or not invertible", here());
                }
                matrices
            }
        };
        budget.charge(here(), joints.len() as u64, 72)?;
        let name = skin.name().map_or_else(|| format!("skin {}", skin.index()), str::to_string);
        scene.skins.push(Skin { name, joints, inverse_bind });
    }
    for instance in &scene.instances {
        let Some(skin) = instance.skin.and_then(|s| scene.skins.get(s)) else { continue };
        let primitive = &scene.primitives[instance.primitive];
        let joint_count = skin.joints.len();
        for (v, vertex) in primitive.skin.iter().enumerate() {
            if let Some(&j) = vertex
                .joints
                .iter()
                .zip(vertex.weights)
                .find(|(j, w)| **j as usize >= joint_count && *w > 0.0)
                .map(|(j, _)| j)
            {
                bail!(
                    "{}: JOINTS_0 of vertex {v} names joint {j}, but skin '{}' has {joint_count} joints",
                    primitive.name,
                    mrshade_core::text::printable(&skin.name)
                );
            }
        }
    }
    Ok(())
}
