//! The node hierarchy a scene keeps for animation, the checks every world transform must
//! pass (the loader's rest pose and every sampled pose go through the same functions), and
//! [`Scene::pose_at`]: the world transforms of instances, lights and cameras at a time.
//!
//! Transforms are checked where they are used, after composition: nested scales that are
//! finite locally can make a world matrix infinite (1e30 × 1e30), and a zero scale or a zero
//! quaternion makes it singular. A camera or a light needs an orientation, so a singular
//! transform is an error there; a mesh with one is flat and invisible. Geometry, cameras and
//! lights must stay within [`MAX_WORLD_EXTENT`] metres of the origin.

use super::animation::{Channel, TargetPath};
use super::{Deformation, Primitive, Scene};
use anyhow::{Context, Result, bail};
use glam::{Mat3, Mat4, Quat, Vec3};
use mrshade_core::math::{bounding_box, box_corners};
use mrshade_core::text::printable;

/// Farthest a surface, camera or light may be from the origin, in metres (the contract's
/// unit): 1000 km. Past it single precision cannot place a millimetre, and squared
/// distances in the renderers overflow long before 10¹⁹.
pub const MAX_WORLD_EXTENT: f32 = 1e6;

/// A local transform as translation, rotation and scale (glTF 2.0 §3.5.2), applied in the
/// order scale, rotation, translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trs {
    /// Translation (metres).
    pub translation: Vec3,
    /// Rotation, a unit quaternion.
    pub rotation: Quat,
    /// Scale along the local axes.
    pub scale: Vec3,
}

impl Trs {
    /// No translation, rotation or scaling.
    pub const IDENTITY: Self = Self { translation: Vec3::ZERO, rotation: Quat::IDENTITY, scale: Vec3::ONE };

    /// `T · R · S` as a matrix.
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// A node of the loaded scene's hierarchy (every node of the default scene), kept so that
/// animated world transforms can be recomposed.
#[derive(Clone, Debug)]
pub struct SceneNode {
    /// The glTF node's name (or `node N`), as in [`super::Instance::node_name`].
    pub name: String,
    /// Its parent, an index into [`Scene::nodes`]; parents come before their children, so
    /// the nodes in order are an evaluation order.
    pub parent: Option<usize>,
    /// The rest (unanimated) local transform as TRS, the base that animation channels
    /// override. For a node given by a `matrix` it is the matrix's decomposition (any shear
    /// is lost), but glTF forbids animating such nodes, so it only informs.
    pub rest: Trs,
    /// The exact rest local transform: the node's matrix, or `rest` composed.
    pub local: Mat4,
}

/// Which node places each instance, light and camera: indices into [`Scene::nodes`], in the
/// order of [`Scene::instances`], [`Scene::lights`] and [`Scene::cameras`]. An instance,
/// light or camera without an entry, or with an entry past the nodes (`usize::MAX`: one
/// added by hand), stays where it is.
#[derive(Clone, Debug, Default)]
pub struct NodeLinks {
    /// The node of each instance.
    pub instances: Vec<usize>,
    /// The node of each light.
    pub lights: Vec<usize>,
    /// The node of each camera.
    pub cameras: Vec<usize>,
}

/// World transforms of a scene at one time, in the orders of the scene's lists.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ScenePose {
    /// `world_from_object` of each instance ([`Scene::instances`]). Finite, but singular
    /// where an animated scale is zero: the instance is flat and invisible then.
    pub instances: Vec<Mat4>,
    /// `world_from_light` of each light ([`Scene::lights`]): rigid.
    pub lights: Vec<Mat4>,
    /// `world_from_camera` of each camera ([`Scene::cameras`]): rigid (scale removed).
    pub cameras: Vec<Mat4>,
    /// How each instance's vertices are moved (skin joint matrices, morph weights); empty
    /// for a rigid instance, and empty altogether for a scene without any deformation.
    pub deformations: Vec<Deformation>,
}

impl Scene {
    /// Whether any animation moves a node of the scene.
    pub fn is_animated(&self) -> bool {
        self.animations.iter().any(|a| !a.channels.is_empty())
    }

    /// The first and last key times (seconds) over all animations, or `None` without any.
    pub fn time_range(&self) -> Option<(f32, f32)> {
        let ranges = self.animations.iter().flat_map(|a| {
            a.channels.iter().filter_map(Channel::time_range).map(|(t0, t1)| (t0 - a.time_offset, t1 - a.time_offset))
        });
        ranges.reduce(|(a0, a1), (b0, b1)| (a0.min(b0), a1.max(b1)))
    }

    /// The rest pose: the loaded transforms, and the deformations of skinned and morphing
    /// instances with their joints where the nodes place them and the rest morph weights
    /// (what a still renders).
    pub fn rest_pose(&self) -> ScenePose {
        if !self.has_deformations() {
            return self.loaded_pose();
        }
        let world: Vec<Mat4> = (0..self.nodes.len()).map(|i| self.rest_world_from_node(i)).collect();
        let mut pose = self.loaded_pose();
        pose.deformations = (0..self.instances.len()).map(|i| self.deformation_of(i, &world, None)).collect();
        pose
    }

    /// World transforms of every instance, light and camera `time` seconds into the scene's
    /// animations. All animations play at once, from the same clock; where several channels
    /// animate the same property of the same node, the one of the later animation wins.
    /// Properties no channel animates keep their rest values, and before its first key and
    /// after its last a channel holds that key's value.
    ///
    /// What nothing animates (no channel on the node or its ancestors) keeps its loaded
    /// transform exactly, so a scene without animations poses as loaded at every time. Note
    /// that the loaded transforms are the rest pose, the nodes' own TRS or matrix, which is
    /// not `pose_at(0.0)` where an animation starts elsewhere.
    ///
    /// Sampled world transforms pass the loader's checks: an infinite one, a camera or light
    /// made singular (a zero scale: no orientation) or geometry, a camera or a light beyond
    /// [`MAX_WORLD_EXTENT`] is an error naming the node, the animation moving it and the time.
    /// An instance whose animated scale is zero is not: its matrix is kept, singular.
    ///
    /// The cost is one matrix product per node and one sample per channel (a binary search
    /// over its keys), plus the bounds of the primitives of moving instances.
    pub fn pose_at(&self, time: f32) -> Result<ScenePose> {
        self.pose_with(time, &[])
    }

    /// [`Scene::pose_at`] with the local transforms of some nodes replaced (`(node, trs)`,
    /// node an index into [`Scene::nodes`]): an inserted model moved per frame by a live
    /// stream's poses. An override wins over any animation of the node.
    pub fn pose_with(&self, time: f32, overrides: &[(usize, Trs)]) -> Result<ScenePose> {
        if !time.is_finite() {
            bail!("animation time {time} is not finite");
        }
        let deforms = self.has_deformations();
        if !self.is_animated() && overrides.is_empty() && !deforms {
            return Ok(self.loaded_pose());
        }
        let n = self.nodes.len();
        // Per node: its animated TRS, if a channel targets it, and the animation that moves it
        // (its own last, or its nearest animated ancestor's), for messages.
        let mut animated: Vec<Option<Trs>> = vec![None; n];
        let mut weights: Vec<Option<Vec<f32>>> = vec![None; n];
        let mut mover: Vec<Option<usize>> = vec![None; n];
        for (a, animation) in self.animations.iter().enumerate() {
            let local_time = time + animation.time_offset;
            for (c, channel) in animation.channels.iter().enumerate() {
                let Some(node) = self.nodes.get(channel.node) else {
                    bail!(
                        "animation '{}' channel {c}: node {} is not one of the scene's {n} nodes",
                        printable(&animation.name),
                        channel.node
                    );
                };
                if let TargetPath::Weights(_) = channel.path {
                    weights[channel.node] = Some(channel.sample_weights(local_time));
                    continue;
                }
                let trs = animated[channel.node].get_or_insert(node.rest);
                let value = channel.sample(local_time);
                match channel.path {
                    TargetPath::Translation => trs.translation = value.truncate(),
                    TargetPath::Rotation => trs.rotation = Quat::from_vec4(value),
                    TargetPath::Scale => trs.scale = value.truncate(),
                    TargetPath::Weights(_) => {}
                }
                mover[channel.node] = Some(a);
            }
        }
        // Overrides are named like an animation in messages: "the stream's poses".
        let overridden = self.animations.len();
        for &(node, trs) in overrides {
            if node >= n {
                bail!("a pose override names node {node}, but the scene has {n} nodes");
            }
            animated[node] = Some(trs);
            mover[node] = Some(overridden);
        }
        let mut world: Vec<Mat4> = Vec::with_capacity(n);
        for (i, node) in self.nodes.iter().enumerate() {
            let local = animated[i].map_or(node.local, |trs| trs.matrix());
            let parent_from_world = match node.parent {
                None => Mat4::IDENTITY,
                Some(p) if p < i => {
                    mover[i] = mover[i].or(mover[p]);
                    world[p]
                }
                Some(p) => bail!("node '{}': its parent {p} does not come before it", printable(&node.name)),
            };
            world.push(parent_from_world * local);
        }

        let at = |node: usize| {
            let animation = match mover[node] {
                Some(a) if a == overridden => "the stream's poses",
                Some(a) => self.animations[a].name.as_str(),
                None => "",
            };
            format!(
                "node '{}' at t = {time} s (animation '{}')",
                printable(&self.nodes[node].name),
                printable(animation)
            )
        };
        // The node of item `i` of `links`, if an animation moves it.
        let moving =
            |links: &[usize], i: usize| links.get(i).copied().filter(|&node| node < n && mover[node].is_some());
        let mut bounds = vec![None; self.primitives.len()];
        let mut pose = self.loaded_pose();
        for (i, instance) in self.instances.iter().enumerate() {
            let Some(node) = moving(&self.node_of.instances, i) else { continue };
            if instance.skin.is_some() {
                continue; // skinned in world space: its joints place it
            }
            let world_from_object = world[node];
            check_finite(world_from_object).with_context(|| at(node))?;
            if let Some(primitive) = self.primitives.get(instance.primitive) {
                let b = *bounds[instance.primitive].get_or_insert_with(|| bounding_box(&primitive.positions));
                check_extent(primitive, b, world_from_object).with_context(|| at(node))?;
            }
            pose.instances[i] = world_from_object;
        }
        if deforms {
            pose.deformations = (0..self.instances.len())
                .map(|i| {
                    let node = self.node_of.instances.get(i).copied();
                    let node_weights = node.and_then(|node| weights.get(node)?.as_deref());
                    self.deformation_of(i, &world, node_weights)
                })
                .collect();
            self.check_deformed(&pose, |i| {
                let node = self.node_of.instances.get(i).copied().filter(|&node| node < n);
                node.map_or_else(|| format!("instance {i} at t = {time} s"), at)
            })?;
        }
        for (i, light) in pose.lights.iter_mut().enumerate() {
            if let Some(node) = moving(&self.node_of.lights, i) {
                *light = oriented(world[node]).with_context(|| at(node))?;
            }
        }
        for (i, camera) in pose.cameras.iter_mut().enumerate() {
            if let Some(node) = moving(&self.node_of.cameras, i) {
                *camera = oriented(world[node]).with_context(|| at(node))?;
            }
        }
        Ok(pose)
    }

    /// The deformed geometry of `pose` must be finite and within [`MAX_WORLD_EXTENT`], as
    /// rigid geometry must (a morph weight of 10⁹ is finite, its displacements are not
    /// usable); `at(i)` names instance `i` in messages.
    pub(crate) fn check_deformed(&self, pose: &ScenePose, at: impl Fn(usize) -> String) -> Result<()> {
        for (i, deformation) in pose.deformations.iter().enumerate() {
            let Some(bounds) = deformation.bounds else { continue };
            let primitive = &self.primitives[self.instances[i].primitive];
            check_extent(primitive, bounds, pose.instances[i]).with_context(|| at(i))?;
        }
        Ok(())
    }

    /// The loaded transforms.
    fn loaded_pose(&self) -> ScenePose {
        ScenePose {
            instances: self.instances.iter().map(|i| i.world_from_object).collect(),
            lights: self.lights.iter().map(|l| l.world_from_light).collect(),
            cameras: self.cameras.iter().map(|c| c.world_from_camera).collect(),
            deformations: Vec::new(),
        }
    }
}

/// A world transform must be finite.
pub(crate) fn check_finite(world_from_node: Mat4) -> Result<()> {
    if !world_from_node.is_finite() {
        bail!("its world transform is infinite (the scales down the hierarchy multiply past 3·10³⁸)");
    }
    Ok(())
}

/// The rigid transform of a camera or light (scale removed) from its node's world transform,
/// which must be finite, non-singular and within [`MAX_WORLD_EXTENT`].
pub(crate) fn oriented(world_from_node: Mat4) -> Result<Mat4> {
    check_finite(world_from_node)?;
    if !is_invertible(world_from_node) {
        bail!("its world transform is singular (a zero scale or a degenerate matrix): it has no orientation");
    }
    let rigid = rigid(world_from_node);
    if !rigid.is_finite() || rigid.w_axis.truncate().abs().max_element() > MAX_WORLD_EXTENT {
        bail!("it lies farther than {MAX_WORLD_EXTENT:e} m from the origin");
    }
    Ok(rigid)
}

/// Whether the linear part of `m` can be inverted: not flattened by a zero scale.
pub(crate) fn is_invertible(m: Mat4) -> bool {
    let linear = Mat3::from_mat4(m);
    let scale = linear.x_axis.length() * linear.y_axis.length() * linear.z_axis.length();
    let det = linear.determinant();
    det.is_finite() && scale.is_finite() && det.abs() > 1e-9 * scale && scale > 0.0
}

/// The primitive's world-space box (from its object-space `bounds`) must be finite and
/// within [`MAX_WORLD_EXTENT`].
pub(crate) fn check_extent(primitive: &Primitive, bounds: (Vec3, Vec3), world_from_object: Mat4) -> Result<()> {
    // Corner by corner: a NaN corner would vanish in a min/max fold.
    for c in box_corners(bounds) {
        let w = world_from_object.transform_point3(c);
        if !(w.is_finite() && w.abs().max_element() <= MAX_WORLD_EXTENT) {
            bail!(
                "{}: its geometry reaches beyond {MAX_WORLD_EXTENT:e} m from the origin (mrshade works in metres; check the scales)",
                primitive.name
            );
        }
    }
    Ok(())
}

/// The rotation and translation of `m` (scale removed): cameras and lights are rigid.
fn rigid(m: Mat4) -> Mat4 {
    let (_, rotation, translation) = m.to_scale_rotation_translation();
    Mat4::from_rotation_translation(rotation.normalize(), translation)
}
