//! Inserting one scene into another: a model loaded from its own glTF file (a downloaded
//! asset, an animated character) is placed under a new node of the session's scene, with all
//! it carries (primitives, materials, textures, lights, skins, animations), as the session's
//! `[[insert]]` tables ask.
//!
//! Everything of the model keeps its meaning: its nodes hang under the insert node (which
//! hangs under `parent`, or is a root), so the scene's [`Scene::pose_at`] moves them with
//! their own animations and with any animated ancestor; its indices (materials, textures,
//! primitives, nodes, skins) are offset by what the scene already holds.

use super::{Scene, SceneNode, Trs, check_extent, check_finite, oriented};
use anyhow::{Context, Result, bail};
use glam::{Mat4, Quat, Vec3};
use mrshade_core::flags::Realness;
use mrshade_core::math::bounding_box;
use mrshade_core::text::printable;

/// Where and how a model is placed.
#[derive(Clone, Debug)]
pub struct Placement {
    /// Name of the new node that holds the model (unique in the scene, for messages and
    /// for moving it per frame).
    pub name: String,
    /// The node's transform relative to `parent` (or the world).
    pub local: Trs,
    /// The scene node it hangs under (an index into [`Scene::nodes`]), or `None` for a root.
    pub parent: Option<usize>,
    /// Every object and light of the model is this (a proxy of something real, or virtual).
    pub realness: Realness,
    /// Play only the animation of this name (`None`: all of them).
    pub animation: Option<String>,
    /// Seconds added to the scene's clock for the model's animations.
    pub time_offset: f32,
}

/// How far from one a hand-given quaternion's length may be (rounding of typed values).
pub const UNIT_TOLERANCE: f32 = 1e-3;

/// A hand-given translation (a session's `[[insert]]`, a stream's pose line): finite and
/// within [`super::MAX_WORLD_EXTENT`] metres of the origin; otherwise why not.
pub fn checked_translation(t: [f32; 3]) -> Result<Vec3, String> {
    let t = Vec3::from(t);
    if !(t.is_finite() && t.abs().max_element() <= super::MAX_WORLD_EXTENT) {
        return Err(format!("must be finite and within {:e} m of the origin", super::MAX_WORLD_EXTENT));
    }
    Ok(t)
}

/// A hand-given rotation `[x, y, z, w]`: a unit quaternion within [`UNIT_TOLERANCE`], then
/// normalised; otherwise why not.
pub fn checked_rotation([x, y, z, w]: [f32; 4]) -> Result<Quat, String> {
    let q = Quat::from_xyzw(x, y, z, w);
    let length = q.length();
    if !(length.is_finite() && (length - 1.0).abs() <= UNIT_TOLERANCE) {
        return Err(format!(
            "[{x}, {y}, {z}, {w}] is not a unit quaternion (its length is {length}); give x, y, z, w with \
             x² + y² + z² + w² = 1"
        ));
    }
    Ok(q / length)
}

/// A hand-given scale: finite and non-zero on every axis; otherwise why not.
pub fn checked_scale(s: Vec3) -> Result<Vec3, String> {
    if !(s.is_finite() && s.abs().min_element() > 0.0) {
        return Err(format!("must be finite and non-zero, got {s}"));
    }
    Ok(s)
}

impl Scene {
    /// World transform of node `node` in the rest pose (its own and its ancestors' loaded
    /// transforms composed).
    pub fn rest_world_from_node(&self, node: usize) -> Mat4 {
        let mut m = Mat4::IDENTITY;
        let mut at = Some(node);
        while let Some(i) = at.filter(|&i| i < self.nodes.len()) {
            m = self.nodes[i].local * m;
            at = self.nodes[i].parent;
        }
        m
    }

    /// The node of this name, if any.
    pub fn node_named(&self, name: &str) -> Option<usize> {
        self.nodes.iter().position(|n| n.name == name)
    }

    /// Places `model` under a new node (see the module doc) and returns that node's index.
    /// The model's cameras are not added (the session's camera renders); its warnings are
    /// kept, prefixed with the insert's name.
    pub fn insert(&mut self, model: Scene, placement: &Placement) -> Result<usize> {
        let shown = printable(&placement.name).into_owned();
        if self.node_named(&placement.name).is_some() {
            bail!("insert '{shown}': the scene already has a node of that name (give the insert another `name`)");
        }
        if let Some(p) = placement.parent
            && p >= self.nodes.len()
        {
            bail!("insert '{shown}': parent node {p} is not one of the scene's {} nodes", self.nodes.len());
        }
        let parent_world = placement.parent.map_or(Mat4::IDENTITY, |p| self.rest_world_from_node(p));
        let world_from_model = parent_world * placement.local.matrix();
        check_finite(world_from_model).with_context(|| format!("insert '{shown}'"))?;

        let animations = match &placement.animation {
            None => model.animations,
            Some(name) => {
                let Some(found) = model.animations.iter().find(|a| &a.name == name) else {
                    let known: Vec<_> = model.animations.iter().map(|a| printable(&a.name).into_owned()).collect();
                    let known = if known.is_empty() { "it has none".into() } else { known.join(", ") };
                    bail!("insert '{shown}': the model has no animation '{}' ({known})", printable(name));
                };
                vec![found.clone()]
            }
        };

        let (material_base, texture_base) = (self.materials.len(), self.textures.len());
        let (primitive_base, skin_base) = (self.primitives.len(), self.skins.len());
        let insert_node = self.nodes.len();
        let node_base = insert_node + 1;

        self.textures.extend(model.textures);
        for mut material in model.materials {
            material.offset_textures(texture_base);
            self.materials.push(material);
        }
        for mut primitive in model.primitives {
            primitive.material += material_base;
            self.primitives.push(primitive);
        }
        self.nodes.push(SceneNode {
            name: placement.name.clone(),
            parent: placement.parent,
            rest: placement.local,
            local: placement.local.matrix(),
        });
        for mut node in model.nodes {
            node.parent = Some(node.parent.map_or(insert_node, |p| p + node_base));
            self.nodes.push(node);
        }
        for (mut instance, node) in model.instances.into_iter().zip(model.node_of.instances) {
            instance.primitive += primitive_base;
            instance.realness = placement.realness;
            // A skinned instance is placed by its joints (in world space), which hang under
            // the insert node: its own transform stays the identity.
            if instance.skin.is_none() {
                instance.world_from_object = world_from_model * instance.world_from_object;
                let primitive = &self.primitives[instance.primitive];
                check_extent(primitive, bounding_box(&primitive.positions), instance.world_from_object)
                    .with_context(|| format!("insert '{shown}'"))?;
            }
            instance.skin = instance.skin.map(|s| s + skin_base);
            link(&mut self.node_of.instances, self.instances.len(), node + node_base);
            self.instances.push(instance);
        }
        for (mut light, node) in model.lights.into_iter().zip(model.node_of.lights) {
            light.world_from_light = oriented(world_from_model * light.world_from_light)
                .with_context(|| format!("insert '{shown}': light '{}'", printable(&light.name)))?;
            light.realness = placement.realness;
            link(&mut self.node_of.lights, self.lights.len(), node + node_base);
            self.lights.push(light);
        }
        for mut skin in model.skins {
            skin.offset_nodes(node_base);
            self.skins.push(skin);
        }
        for mut animation in animations {
            for channel in &mut animation.channels {
                channel.node += node_base;
            }
            animation.time_offset += placement.time_offset;
            self.animations.push(animation);
        }
        if !model.cameras.is_empty() {
            self.warnings.push(format!("insert '{shown}': its cameras are not used (the session's camera renders)"));
        }
        self.warnings.extend(model.warnings.into_iter().map(|w| format!("insert '{shown}': {w}")));
        // Skinned geometry follows its joints, which the placement has just moved.
        let rest = self.rest_pose();
        self.check_deformed(&rest, |i| format!("insert '{shown}': node '{}'", self.instances[i].node_name))?;
        Ok(insert_node)
    }
}

/// Links item `index` of a list to `node`; items before it without a link (added by hand)
/// get none (`usize::MAX`, which is no node).
fn link(links: &mut Vec<usize>, index: usize, node: usize) {
    links.resize(index, usize::MAX);
    links.push(node);
}
