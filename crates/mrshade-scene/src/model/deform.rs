//! Skinning and morphing (glTF 2.0 §3.7.3, §3.7.2.2) on the CPU: the known answer the GPU's
//! deformation pass is tested against, and what the reference path tracer and the bounds
//! of a deformed instance are computed from.
//!
//! A skinned instance is skinned in world space, as glTF defines it (the mesh node's own
//! transform is ignored): vertex `v` moves to `Σ_j w_j · world_from_joint_j · joint_from_bind_j
//! · v`, after its morph targets displaced it by `Σ_t w_t · Δ_t`. Normals move by the
//! cofactor matrix of the blended joint matrix (the inverse transpose up to its scale), and
//! are renormalised.

use super::{Primitive, Scene};
use glam::{Mat3, Mat4, Vec3};
use mrshade_core::math::bounding_box;

/// How one instance's vertices are moved at one time (empty for a rigid instance).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Deformation {
    /// `world_from_joint · joint_from_bind` per joint of its skin (empty when not skinned).
    pub joint_matrices: Vec<Mat4>,
    /// Morph-target weights, one per target of its primitive (empty without targets).
    pub morph_weights: Vec<f32>,
    /// The box of the deformed positions (world space when skinned, else object space),
    /// where the deformation was computed by [`Scene::pose_at`] (`None` where built by hand).
    pub bounds: Option<(Vec3, Vec3)>,
}

impl Deformation {
    /// Whether it moves nothing.
    pub fn is_empty(&self) -> bool {
        self.joint_matrices.is_empty() && self.morph_weights.is_empty()
    }
}

/// The primitive's positions and unit normals after `deformation` (in world space when it
/// is skinned, else in object space).
pub fn deform_vertices(primitive: &Primitive, deformation: &Deformation) -> (Vec<Vec3>, Vec<Vec3>) {
    let count = primitive.positions.len();
    let mut positions = primitive.positions.clone();
    let mut normals = primitive.normals.clone();
    for (target, &w) in primitive.targets.iter().zip(&deformation.morph_weights) {
        if w == 0.0 {
            continue;
        }
        for (p, d) in positions.iter_mut().zip(&target.positions) {
            *p += w * *d;
        }
        for (n, d) in normals.iter_mut().zip(&target.normals) {
            *n += w * *d;
        }
    }
    if !deformation.joint_matrices.is_empty() && primitive.skin.len() == count {
        for ((p, n), skin) in positions.iter_mut().zip(normals.iter_mut()).zip(&primitive.skin) {
            let m = blended(&deformation.joint_matrices, skin.joints, skin.weights);
            *p = m.transform_point3(*p);
            *n = cofactor(Mat3::from_mat4(m)) * *n;
        }
    }
    for n in &mut normals {
        *n = n.normalize_or(Vec3::Y);
    }
    (positions, normals)
}

/// `Σ w_j · M_j` over a vertex's four joints (a joint out of range counts as identity; the
/// loader refuses such files).
pub(crate) fn blended(matrices: &[Mat4], joints: [u16; 4], weights: [f32; 4]) -> Mat4 {
    let mut m = Mat4::ZERO;
    for (j, w) in joints.into_iter().zip(weights) {
        if w != 0.0 {
            m += *matrices.get(j as usize).unwrap_or(&Mat4::IDENTITY) * w;
        }
    }
    m
}

/// The cofactor matrix: `det(m) · m⁻ᵀ`, defined for singular `m` too.
pub(crate) fn cofactor(m: Mat3) -> Mat3 {
    Mat3::from_cols(m.y_axis.cross(m.z_axis), m.z_axis.cross(m.x_axis), m.x_axis.cross(m.y_axis))
}

impl Scene {
    /// Whether any instance is skinned or morphed.
    pub fn has_deformations(&self) -> bool {
        self.instances.iter().any(|i| self.primitives.get(i.primitive).is_some_and(Primitive::is_deformable))
    }

    /// Instance `i`'s deformation given the world transform of every node and the morph
    /// weights animated per node (`None`: the instance's rest weights).
    pub(crate) fn deformation_of(&self, i: usize, world: &[Mat4], node_weights: Option<&[f32]>) -> Deformation {
        let instance = &self.instances[i];
        let Some(primitive) = self.primitives.get(instance.primitive).filter(|p| p.is_deformable()) else {
            return Deformation::default();
        };
        let joint_matrices = match instance.skin.and_then(|s| self.skins.get(s)) {
            Some(skin) if !primitive.skin.is_empty() => skin
                .joints
                .iter()
                .zip(&skin.inverse_bind)
                .map(|(&joint, ibm)| world.get(joint).copied().unwrap_or(Mat4::IDENTITY) * *ibm)
                .collect(),
            _ => Vec::new(),
        };
        let mut morph_weights = node_weights.map_or_else(|| instance.morph_weights.clone(), <[f32]>::to_vec);
        morph_weights.resize(primitive.targets.len(), 0.0);
        let mut deformation = Deformation { joint_matrices, morph_weights, bounds: None };
        // A non-finite position makes the box NaN, which the extent check refuses (a plain
        // box would drop it).
        let (positions, _) = deform_vertices(primitive, &deformation);
        let finite = positions.iter().all(|p| p.is_finite());
        deformation.bounds = Some(if finite { bounding_box(&positions) } else { (Vec3::NAN, Vec3::NAN) });
        deformation
    }

    /// The scene as posed: instances, lights and cameras moved, deformed primitives replaced
    /// by their deformed vertices (each deformed instance gets its own primitive), skins and
    /// morph targets removed: a rigid scene for renderers that build their structures once
    /// per frame (the reference path tracer's BVH).
    pub fn posed(&self, pose: &super::ScenePose) -> Scene {
        let mut scene = self.clone();
        for (instance, &m) in scene.instances.iter_mut().zip(&pose.instances) {
            instance.world_from_object = m;
        }
        for (light, &m) in scene.lights.iter_mut().zip(&pose.lights) {
            light.world_from_light = m;
        }
        for (camera, &m) in scene.cameras.iter_mut().zip(&pose.cameras) {
            camera.world_from_camera = m;
        }
        for (i, deformation) in pose.deformations.iter().enumerate() {
            let Some(instance) = scene.instances.get(i) else { break };
            let source = &self.primitives[instance.primitive];
            if !source.is_deformable() {
                continue;
            }
            let (positions, normals) = deform_vertices(source, deformation);
            let mut rigid = Primitive { positions, normals, skin: Vec::new(), targets: Vec::new(), ..source.clone() };
            rigid.name = format!("{} (posed)", source.name);
            scene.instances[i].primitive = scene.primitives.len();
            scene.instances[i].skin = None;
            scene.instances[i].morph_weights.clear();
            scene.primitives.push(rigid);
        }
        scene.animations.clear();
        scene.skins.clear();
        scene
    }
}
