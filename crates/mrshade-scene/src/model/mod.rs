//! The scene model: flattened, world-placed geometry with materials, lights and cameras,
//! each marked real or virtual, and the node hierarchy and animations that move them over
//! time ([`Scene::pose_at`]). Built by `crate::gltf`, consumed by the renderers.

mod animation;
mod deform;
mod insert;
mod material;
mod pose;

pub(crate) use animation::unit_quaternion;
pub use animation::{Animation, Channel, Interpolation, TargetPath};
pub use deform::{Deformation, deform_vertices};
pub use insert::{Placement, UNIT_TOLERANCE, checked_rotation, checked_scale, checked_translation};
pub use material::{AlphaMode, Material, Texture, TextureRef};
pub use pose::{MAX_WORLD_EXTENT, NodeLinks, SceneNode, ScenePose, Trs};
pub(crate) use pose::{check_extent, check_finite, is_invertible, oriented};

use glam::{Mat4, Vec2, Vec3};
use mrshade_core::flags::Realness;

/// A triangle list in object space with one material.
#[derive(Clone, Debug, Default)]
pub struct Primitive {
    /// `mesh name / primitive index`, for messages.
    pub name: String,
    /// Vertex positions (metres, object space).
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<Vec3>,
    /// `TEXCOORD_0`, one per position (zero where the mesh has none).
    pub uvs: Vec<Vec2>,
    /// Three indices per triangle, each `< positions.len()`.
    pub indices: Vec<u32>,
    /// Index into [`Scene::materials`].
    pub material: usize,
    /// `JOINTS_0`/`WEIGHTS_0` per position (empty when the mesh is not skinned): joints are
    /// indices into the instance's [`Skin::joints`], weights sum to one.
    pub skin: Vec<VertexSkin>,
    /// Morph targets (glTF 2.0 §3.7.2.2): displacements added with the instance's weights.
    pub targets: Vec<MorphTarget>,
}

impl Primitive {
    /// Whether skinning or morphing moves its vertices (per instance, per frame).
    pub fn is_deformable(&self) -> bool {
        !self.skin.is_empty() || !self.targets.is_empty()
    }
}

/// The four joints and weights that move one vertex.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VertexSkin {
    /// Indices into the skin's joints.
    pub joints: [u16; 4],
    /// Their weights, summing to one.
    pub weights: [f32; 4],
}

/// One morph target of a primitive: per-vertex displacements.
#[derive(Clone, Debug, Default)]
pub struct MorphTarget {
    /// Position displacement per vertex (object space).
    pub positions: Vec<Vec3>,
    /// Normal displacement per vertex (empty when the target has none).
    pub normals: Vec<Vec3>,
}

/// A glTF skin: the joints that move a skinned mesh and their inverse bind matrices.
#[derive(Clone, Debug)]
pub struct Skin {
    /// The skin's name, or `skin N`.
    pub name: String,
    /// The joint nodes: indices into [`Scene::nodes`].
    pub joints: Vec<usize>,
    /// `joint_from_mesh_at_bind`, one per joint: finite and invertible.
    pub inverse_bind: Vec<Mat4>,
}

impl Skin {
    /// Moves the joint indices by `base` (the skin's scene was appended after `base` nodes).
    pub(crate) fn offset_nodes(&mut self, base: usize) {
        for j in &mut self.joints {
            *j += base;
        }
    }
}

/// A primitive placed in the world by a node.
#[derive(Clone, Debug)]
pub struct Instance {
    /// The glTF node's name (or `node N`).
    pub node_name: String,
    /// Index into [`Scene::primitives`].
    pub primitive: usize,
    /// Object → world transform accumulated down the node hierarchy, in the rest pose
    /// ([`Scene::pose_at`] gives it at a time). Invertible, except for an animated node
    /// whose rest scale is zero (kept: its animation may scale it up).
    pub world_from_object: Mat4,
    /// Real proxy or inserted virtual object.
    pub realness: Realness,
    /// The skin that deforms it (an index into [`Scene::skins`]), if its primitive is skinned.
    pub skin: Option<usize>,
    /// Morph-target weights in the rest pose (the node's or the mesh's `weights`, else zeros),
    /// one per target of its primitive.
    pub morph_weights: Vec<f32>,
}

/// The kind of a `KHR_lights_punctual` light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Omnidirectional point light.
    Point,
    /// Cone light; angles in radians from the axis, `0 ≤ inner < outer ≤ π/2`.
    Spot {
        /// Full intensity inside this angle.
        inner_cone: f32,
        /// Zero intensity outside this angle.
        outer_cone: f32,
    },
    /// Parallel light along the node's −Z.
    Directional,
}

/// A punctual light. Intensity is radiometric (contract): radiant intensity
/// `intensity × color` per steradian for point and spot lights, irradiance for directional.
#[derive(Clone, Debug)]
pub struct Light {
    /// The light's or node's name.
    pub name: String,
    /// Point, spot or directional.
    pub kind: LightKind,
    /// `intensity × color`, linear RGB.
    pub intensity: Vec3,
    /// Light → world, rigid, in the rest pose; the light sits at the origin and shines down
    /// its −Z.
    pub world_from_light: Mat4,
    /// A real lamp (already in the photo) or an inserted virtual one.
    pub realness: Realness,
}

impl Light {
    /// World-space position.
    pub fn position(&self) -> Vec3 {
        self.world_from_light.transform_point3(Vec3::ZERO)
    }

    /// World-space unit direction the light shines along.
    pub fn direction(&self) -> Vec3 {
        self.world_from_light.transform_vector3(Vec3::NEG_Z).normalize_or(Vec3::NEG_Z)
    }
}

/// A perspective camera placed by a node.
#[derive(Clone, Debug)]
pub struct Camera {
    /// The node's name.
    pub node_name: String,
    /// The glTF camera's own name, if any.
    pub camera_name: Option<String>,
    /// Vertical field of view in radians.
    pub yfov: f32,
    /// Width / height, if the file fixes it.
    pub aspect_ratio: Option<f32>,
    /// Near plane distance (metres).
    pub znear: f32,
    /// Camera → world, rigid (scale removed), in the rest pose; the camera looks down its −Z.
    pub world_from_camera: Mat4,
}

impl Camera {
    /// Whether `name` names this camera (node name or camera name).
    pub fn is_named(&self, name: &str) -> bool {
        self.node_name == name || self.camera_name.as_deref() == Some(name)
    }
}

/// Everything loaded from one glTF file.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// All triangle lists.
    pub primitives: Vec<Primitive>,
    /// All materials (at least one: the default material is appended when needed).
    pub materials: Vec<Material>,
    /// Decoded textures referenced by materials.
    pub textures: Vec<Texture>,
    /// Primitives placed in the world.
    pub instances: Vec<Instance>,
    /// Punctual lights.
    pub lights: Vec<Light>,
    /// Perspective cameras, in scene traversal order.
    pub cameras: Vec<Camera>,
    /// Every node of the loaded glTF scene, parents before children: the hierarchy that
    /// [`Scene::pose_at`] recomposes.
    pub nodes: Vec<SceneNode>,
    /// The node of each instance, light and camera.
    pub node_of: NodeLinks,
    /// Skins of skinned instances.
    pub skins: Vec<Skin>,
    /// Animations of node transforms; all play at once ([`Scene::pose_at`]).
    pub animations: Vec<Animation>,
    /// What the loader could not honour and skipped (unsupported extensions, …).
    pub warnings: Vec<String>,
}

impl Scene {
    /// World-space bounding box of all instances in the rest pose (skinned and morphing ones
    /// deformed), or `None` for an empty scene.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let pose = self.rest_pose();
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for (i, inst) in self.instances.iter().enumerate() {
            let primitive = &self.primitives[inst.primitive];
            let deformed = pose.deformations.get(i).filter(|d| !d.is_empty()).map(|d| deform_vertices(primitive, d).0);
            for &p in deformed.as_deref().unwrap_or(&primitive.positions) {
                let w = inst.world_from_object.transform_point3(p);
                lo = lo.min(w);
                hi = hi.max(w);
            }
        }
        (lo.x <= hi.x).then_some((lo, hi))
    }

    /// Whether anything virtual is in the scene (objects or lights).
    pub fn has_virtual_content(&self) -> bool {
        self.instances.iter().any(|i| i.realness == Realness::Virtual) || self.has_virtual_lights()
    }

    /// Whether the scene holds a virtual light: its change then reaches every real surface it
    /// lights, not only those around the virtual objects.
    pub fn has_virtual_lights(&self) -> bool {
        self.lights.iter().any(|l| l.realness == Realness::Virtual)
    }
}
