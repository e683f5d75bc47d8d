//! Skinned and morphing models in the style of Khronos' `SimpleSkin` and
//! `AnimatedMorphCube`, small enough that their vertex positions at any time follow from a
//! few lines of hand math ([`SimpleSkin::expected`], [`MorphBox::expected`]).

use crate::gltf::{GltfBuilder, Shape, cuboid};
use glam::{Mat4, Quat, Vec3};
use serde_json::json;

/// Rows of the strip, at y = 0, 0.5, …, 2 (two vertices each, x = 0 and x = `WIDTH`).
const ROWS: usize = 5;
/// Width of the strip (metres).
pub const WIDTH: f32 = 0.5;

/// A strip 2 m tall in the XY plane, skinned to two joints: `root` at the origin and its
/// child `bend` at y = 1. Rows at y ≤ 0.5 follow `root`, the row at y = 1 both equally, rows
/// above follow `bend`. The animation "bend" turns `bend` about its +Z from 0 at t = 0 to
/// `angle` at t = 1 (LINEAR).
pub struct SimpleSkin {
    /// The node with the mesh and the skin.
    pub mesh_node: usize,
    /// The root joint (place the whole model by moving it).
    pub root: usize,
    /// The bending joint.
    pub bend: usize,
    /// The bend at t = 1, radians.
    pub angle: f32,
}

/// Rest positions of the strip, row by row.
pub fn strip_positions() -> Vec<Vec3> {
    (0..ROWS).flat_map(|r| [Vec3::new(0.0, 0.5 * r as f32, 0.0), Vec3::new(WIDTH, 0.5 * r as f32, 0.0)]).collect()
}

/// Weight of the `bend` joint for row `r`.
fn bend_weight(r: usize) -> f32 {
    match r {
        0 | 1 => 0.0,
        2 => 0.5,
        _ => 1.0,
    }
}

/// Adds the skinned strip to `b` (see [`SimpleSkin`]), its root joint at `root_translation`
/// turned by `root_rotation`.
pub fn simple_skin(b: &mut GltfBuilder, angle: f32, root_translation: [f32; 3], root_rotation: [f32; 4]) -> SimpleSkin {
    let positions: Vec<f32> = strip_positions().iter().flat_map(|p| p.to_array()).collect();
    let normals: Vec<f32> = (0..2 * ROWS).flat_map(|_| [0.0, 0.0, 1.0]).collect();
    let indices: Vec<u32> = (0..ROWS as u32 - 1)
        .flat_map(|r| {
            let (a, b, c, d) = (2 * r, 2 * r + 1, 2 * r + 2, 2 * r + 3);
            [a, b, d, a, d, c]
        })
        .collect();
    let joints: Vec<u8> = (0..2 * ROWS).flat_map(|_| [0u16, 1, 0, 0]).flat_map(|j| j.to_le_bytes()).collect();
    let weights: Vec<f32> = (0..2 * ROWS)
        .flat_map(|v| {
            let w = bend_weight(v / 2);
            [1.0 - w, w, 0.0, 0.0]
        })
        .collect();
    let position = b.accessor_f32(&positions, "VEC3", true);
    let normal = b.accessor_f32(&normals, "VEC3", false);
    let joint = b.accessor_bytes(&joints, 5123, "VEC4", 2 * ROWS, false);
    let weight = b.accessor_f32(&weights, "VEC4", false);
    let index = b.accessor_u32(&indices);
    let material = b.material(json!({"name": "skin", "doubleSided": true,
        "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.3, 0.2, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}}));
    let mesh = b.mesh_raw(json!({
        "attributes": {"POSITION": position, "NORMAL": normal, "JOINTS_0": joint, "WEIGHTS_0": weight},
        "indices": index, "material": material
    }));
    let inverse_bind: Vec<f32> = [Mat4::IDENTITY, Mat4::from_translation(Vec3::new(0.0, -1.0, 0.0))]
        .iter()
        .flat_map(|m| m.to_cols_array())
        .collect();
    let ibm = b.accessor_f32(&inverse_bind, "MAT4", false);
    let root = b.node(json!({"name": "root", "translation": root_translation, "rotation": root_rotation}));
    let bend = b.child(root, json!({"name": "bend", "translation": [0.0, 1.0, 0.0]}));
    let skin = b.skin(json!({"name": "strip", "joints": [root, bend], "inverseBindMatrices": ibm}));
    let mesh_node = b.node(json!({"name": "strip", "mesh": mesh, "skin": skin}));
    let times = b.accessor_f32(&[0.0, 1.0], "SCALAR", true);
    let turned = Quat::from_rotation_z(angle);
    let values = b.accessor_f32(&[0.0, 0.0, 0.0, 1.0, turned.x, turned.y, turned.z, turned.w], "VEC4", false);
    b.animation(json!({"name": "bend",
        "samplers": [{"input": times, "output": values, "interpolation": "LINEAR"}],
        "channels": [{"sampler": 0, "target": {"node": bend, "path": "rotation"}}]}));
    SimpleSkin { mesh_node, root, bend, angle }
}

impl SimpleSkin {
    /// World positions of the strip's vertices at `time`, with the root joint at
    /// `world_from_root`: `Σ w_j · world_from_joint_j · inverse_bind_j · v`, by hand.
    pub fn expected(&self, time: f32, world_from_root: Mat4) -> Vec<Vec3> {
        let t = time.clamp(0.0, 1.0);
        let world_from_bend = world_from_root
            * Mat4::from_translation(Vec3::Y)
            * Mat4::from_quat(Quat::IDENTITY.slerp(Quat::from_rotation_z(self.angle), t));
        let bend_from_bind = Mat4::from_translation(-Vec3::Y);
        strip_positions()
            .iter()
            .enumerate()
            .map(|(v, &p)| {
                let w = bend_weight(v / 2);
                (1.0 - w) * world_from_root.transform_point3(p)
                    + w * (world_from_bend * bend_from_bind).transform_point3(p)
            })
            .collect()
    }
}

/// A unit box with two morph targets: "grow" lifts its top face by 1 m, "shift" moves every
/// vertex +X by 0.5 m. Its weights go from [0, 0] at t = 0 to [1, 0.5] at t = 1 (LINEAR).
pub struct MorphBox {
    /// The node with the mesh.
    pub node: usize,
    /// Rest positions.
    pub rest: Shape,
}

/// Adds the morphing box (see [`MorphBox`]) at `translation`.
pub fn morph_box(b: &mut GltfBuilder, translation: [f32; 3]) -> MorphBox {
    let shape = cuboid([0.5, 0.5, 0.5]);
    let flat = |v: &[[f32; 3]]| v.iter().flatten().copied().collect::<Vec<f32>>();
    let position = b.accessor_f32(&flat(&shape.positions), "VEC3", true);
    let normal = b.accessor_f32(&flat(&shape.normals), "VEC3", false);
    let grow: Vec<[f32; 3]> =
        shape.positions.iter().map(|p| if p[1] > 0.0 { [0.0, 1.0, 0.0] } else { [0.0; 3] }).collect();
    let shift = vec![[0.5, 0.0, 0.0]; shape.positions.len()];
    let grow = b.accessor_f32(&flat(&grow), "VEC3", true);
    let shift = b.accessor_f32(&flat(&shift), "VEC3", true);
    let index = b.accessor_u32(&shape.indices);
    let mesh = b.mesh_raw(json!({
        "attributes": {"POSITION": position, "NORMAL": normal},
        "targets": [{"POSITION": grow}, {"POSITION": shift}],
        "indices": index
    }));
    let node = b.node(json!({"name": "morph", "mesh": mesh, "translation": translation}));
    let times = b.accessor_f32(&[0.0, 1.0], "SCALAR", true);
    let values = b.accessor_f32(&[0.0, 0.0, 1.0, 0.5], "SCALAR", false);
    b.animation(json!({"name": "morph",
        "samplers": [{"input": times, "output": values, "interpolation": "LINEAR"}],
        "channels": [{"sampler": 0, "target": {"node": node, "path": "weights"}}]}));
    MorphBox { node, rest: shape }
}

impl MorphBox {
    /// Object-space positions at `time`: rest + w₀ · grow + w₁ · shift, by hand.
    pub fn expected(&self, time: f32) -> Vec<Vec3> {
        let t = time.clamp(0.0, 1.0);
        let (w0, w1) = (t, 0.5 * t);
        self.rest
            .positions
            .iter()
            .map(|&p| {
                let p = Vec3::from(p);
                p + w0 * if p.y > 0.0 { Vec3::Y } else { Vec3::ZERO } + w1 * Vec3::new(0.5, 0.0, 0.0)
            })
            .collect()
    }
}
