//! The node hierarchy: world transforms (TRS or matrix), the real/virtual flag with
//! inheritance, what nodes carry (meshes, lights, cameras), and the nodes themselves
//! ([`crate::Scene::nodes`]) for animation.
//!
//! World transforms are checked after composition, by the functions that check animated
//! poses too (`crate::model::pose`). A mesh with a singular transform is flat and invisible,
//! and is left out with a warning, unless an animation moves its node or an ancestor (it may
//! scale it up); a camera or a light needs an orientation, so there it is an error.

use super::describe;
use crate::budget::Budget;
use crate::images::MAX_RADIANCE;
use crate::model::{check_extent, check_finite, is_invertible, oriented};
use crate::{Camera, Instance, Light, LightKind, Scene, SceneNode, Trs};
use anyhow::{Context, Result, bail};
use glam::{Mat4, Quat, Vec3};
use gltf::khr_lights_punctual::Kind;
use mrshade_core::flags::Realness;
use mrshade_core::math::bounding_box;

/// The node graph is a forest (checked by `document`); depth is still bounded, for the stack.
const MAX_DEPTH: usize = 256;

/// Walks the default scene (or scene 0) and places instances, lights and cameras; `animated`
/// says, per glTF node, whether an animation channel moves it. Returns, per glTF node, its
/// index in `scene.nodes` (`None` for nodes outside the scene).
pub fn place_nodes(
    document: &gltf::Document,
    mesh_primitives: &[Vec<usize>],
    animated: &[bool],
    budget: &mut Budget,
    scene: &mut Scene,
) -> Result<Vec<Option<usize>>> {
    let Some(root) = document.default_scene().or_else(|| document.scenes().next()) else {
        bail!("the file has no scene");
    };
    let used = vec![false; scene.primitives.len()];
    let mut walk =
        Walk { mesh_primitives, animated, budget, scene, scene_node_of: vec![None; document.nodes().len()], used };
    for node in root.nodes() {
        let top = Parent { index: None, world_from_node: Mat4::IDENTITY, realness: Realness::Virtual, moving: false };
        walk.visit(&node, &top, 0)?;
    }
    Ok(walk.scene_node_of)
}

/// What a node's children inherit.
struct Parent {
    /// Its index in `scene.nodes`.
    index: Option<usize>,
    world_from_node: Mat4,
    realness: Realness,
    /// Whether an animation moves it or an ancestor.
    moving: bool,
}

struct Walk<'a> {
    mesh_primitives: &'a [Vec<usize>],
    animated: &'a [bool],
    budget: &'a mut Budget,
    scene: &'a mut Scene,
    scene_node_of: Vec<Option<usize>>,
    /// Per loaded primitive, whether an instance uses it already: a skinned or morphing
    /// primitive is deformed per instance, so a second instance gets its own copy.
    used: Vec<bool>,
}

impl Walk<'_> {
    fn visit(&mut self, node: &gltf::Node, parent: &Parent, depth: usize) -> Result<()> {
        let name = node.name().map(str::to_string).unwrap_or_else(|| format!("node {}", node.index()));
        let here = || format!("node {}", describe(Some(node.index()), node.name()));
        if depth > MAX_DEPTH {
            bail!("{}: the node hierarchy is deeper than {MAX_DEPTH} levels (a cycle?)", here());
        }
        let (local, rest) = local_transform(node).with_context(here)?;
        let world_from_node = parent.world_from_node * local;
        check_finite(world_from_node).with_context(here)?;
        let realness = node_realness(node).with_context(here)?.unwrap_or(parent.realness);
        let moving = parent.moving || self.animated.get(node.index()).copied().unwrap_or(false);
        let scene = &mut *self.scene;
        self.budget.charge(here(), 1, (std::mem::size_of::<SceneNode>() + name.len()) as u64)?;
        let index = scene.nodes.len();
        scene.nodes.push(SceneNode { name: name.clone(), parent: parent.index, rest, local });
        self.scene_node_of[node.index()] = Some(index);

        if let Some(mesh) = node.mesh() {
            let rest_weights = node.weights().or(mesh.weights()).unwrap_or(&[]);
            if let Some(w) = rest_weights.iter().find(|w| !w.is_finite()) {
                bail!("{}: morph weight {w} is not finite", here());
            }
            for &loaded in &self.mesh_primitives[mesh.index()] {
                let skinned = node.skin().is_some() && !scene.primitives[loaded].skin.is_empty();
                if !moving && !skinned && !is_invertible(world_from_node) {
                    scene.warnings.push(format!("{}: its world transform has a zero scale; not rendered", here()));
                    break;
                }
                let primitive = if scene.primitives[loaded].is_deformable() && self.used[loaded] {
                    let copy = scene.primitives[loaded].clone();
                    let bytes = (copy.positions.len() * (32 + 24 * copy.targets.len() + 24)) as u64;
                    self.budget.charge(format!("{} (deformed per instance)", here()), 1, bytes)?;
                    scene.primitives.push(copy);
                    scene.primitives.len() - 1
                } else {
                    loaded
                };
                self.used[loaded] = true;
                let p = &scene.primitives[primitive];
                // A skinned mesh is placed by its joints, in world space (glTF 2.0 §3.7.3.3:
                // the transform of its node is ignored).
                let world_from_object = if skinned { Mat4::IDENTITY } else { world_from_node };
                if !skinned {
                    check_extent(p, bounding_box(&p.positions), world_from_node).with_context(here)?;
                }
                let mut morph_weights = rest_weights.to_vec();
                morph_weights.resize(p.targets.len(), 0.0);
                self.budget.charge(here(), 1, (std::mem::size_of::<Instance>() + name.len() + 8) as u64)?;
                scene.instances.push(Instance {
                    node_name: name.clone(),
                    primitive,
                    world_from_object,
                    realness,
                    skin: node.skin().filter(|_| skinned).map(|s| s.index()),
                    morph_weights,
                });
                scene.node_of.instances.push(index);
            }
        }
        if let Some(light) = node.light() {
            let world_from_light = oriented(world_from_node).with_context(here)?;
            self.budget.charge(here(), 1, (std::mem::size_of::<Light>() + name.len() + 8) as u64)?;
            let light =
                load_light(&light, &name, world_from_light, realness, &mut scene.warnings).with_context(here)?;
            scene.lights.push(light);
            scene.node_of.lights.push(index);
        }
        if let Some(camera) = node.camera() {
            match camera.projection() {
                gltf::camera::Projection::Perspective(p) => {
                    self.budget.charge(here(), 1, (std::mem::size_of::<Camera>() + name.len() + 8) as u64)?;
                    check_perspective(&p).with_context(|| {
                        format!("{}: camera {}", here(), describe(Some(camera.index()), camera.name()))
                    })?;
                    scene.cameras.push(Camera {
                        node_name: name.clone(),
                        camera_name: camera.name().map(str::to_string),
                        yfov: p.yfov(),
                        aspect_ratio: p.aspect_ratio(),
                        znear: p.znear(),
                        world_from_camera: oriented(world_from_node).with_context(here)?,
                    });
                    scene.node_of.cameras.push(index);
                }
                gltf::camera::Projection::Orthographic(_) => {
                    scene.warnings.push(format!("{}: orthographic cameras are not supported; camera ignored", here()))
                }
            }
        }
        let inherited = Parent { index: Some(index), world_from_node, realness, moving };
        for child in node.children() {
            self.visit(&child, &inherited, depth + 1)?;
        }
        Ok(())
    }
}

/// The node's local transform, as glTF 2.0 §3.5.2 allows it: TRS with a unit quaternion, or
/// an affine matrix; and as TRS (a matrix decomposed, its shear lost). A quaternion that is
/// not unit length but close is normalised (exporters round); a zero or non-finite one is an
/// error.
fn local_transform(node: &gltf::Node) -> Result<(Mat4, Trs)> {
    let (local, trs) = match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            let m = Mat4::from_cols_array_2d(&matrix);
            if m.row(3) != glam::Vec4::W {
                bail!("matrix is not affine: its last row is {} (glTF needs 0, 0, 0, 1)", m.row(3));
            }
            (m, decompose(m))
        }
        gltf::scene::Transform::Decomposed { translation, rotation, scale } => {
            let q = Quat::from_array(rotation);
            let length = q.length();
            if !(length.is_finite() && (length - 1.0).abs() < 0.1) {
                bail!("rotation {rotation:?} is not a unit quaternion");
            }
            let trs = Trs { translation: Vec3::from(translation), rotation: q / length, scale: Vec3::from(scale) };
            (trs.matrix(), trs)
        }
    };
    if !local.is_finite() {
        bail!("transform holds NaN or infinite values");
    }
    Ok((local, trs))
}

/// `m` as TRS, finite whatever `m` is (a singular matrix has no rotation: identity then).
fn decompose(m: Mat4) -> Trs {
    let (scale, rotation, translation) = m.to_scale_rotation_translation();
    let rotation = if rotation.is_finite() && rotation.length() > 0.5 { rotation.normalize() } else { Quat::IDENTITY };
    Trs {
        translation: if translation.is_finite() { translation } else { Vec3::ZERO },
        rotation,
        scale: if scale.is_finite() { scale } else { Vec3::ZERO },
    }
}

/// A perspective projection that sees something: 0 < yfov < π, 0 < znear < zfar, a positive
/// aspect ratio (glTF 2.0 §5.13).
fn check_perspective(p: &gltf::camera::Perspective) -> Result<()> {
    let yfov = p.yfov();
    if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
        bail!("yfov {yfov} must be between 0 and π radians (exclusive)");
    }
    if !(p.znear() > 0.0 && p.znear().is_finite()) {
        bail!("znear {} must be a positive distance", p.znear());
    }
    if let Some(zfar) = p.zfar()
        && !(zfar > p.znear() && zfar.is_finite())
    {
        bail!("zfar {zfar} must be farther than znear {}", p.znear());
    }
    if let Some(aspect) = p.aspect_ratio()
        && !(aspect > 0.0 && aspect.is_finite())
    {
        bail!("aspectRatio {aspect} must be positive");
    }
    Ok(())
}

/// `extras.real` of the contract: `Some(true/false)` when the node sets it.
fn node_realness(node: &gltf::Node) -> Result<Option<Realness>> {
    let Some(raw) = node.extras() else { return Ok(None) };
    let value: serde_json::Value = serde_json::from_str(raw.get()).context("extras are not valid JSON")?;
    match value.get("real") {
        None => Ok(None),
        Some(serde_json::Value::Bool(b)) => Ok(Some(Realness::from_real(*b))),
        Some(other) => bail!("extras.real must be true or false, got {other}"),
    }
}

fn load_light(
    light: &gltf::khr_lights_punctual::Light,
    node_name: &str,
    world_from_light: Mat4,
    realness: Realness,
    warnings: &mut Vec<String>,
) -> Result<Light> {
    let name = light.name().unwrap_or(node_name).to_string();
    let shown = mrshade_core::text::printable(&name).into_owned();
    let color = Vec3::from(light.color());
    if !(color.is_finite() && color.min_element() >= 0.0 && light.intensity().is_finite() && light.intensity() >= 0.0) {
        bail!("light '{shown}': color and intensity must be finite and ≥ 0");
    }
    if (color * light.intensity()).max_element() > MAX_RADIANCE {
        bail!("light '{shown}': intensity × color is larger than {MAX_RADIANCE:e}, beyond what mrshade computes with");
    }
    if light.range().is_some() {
        warnings.push(format!("light '{shown}': range is ignored (inverse-square falloff, per the data contract)"));
    }
    let kind = match light.kind() {
        Kind::Point => LightKind::Point,
        Kind::Directional => LightKind::Directional,
        Kind::Spot { inner_cone_angle, outer_cone_angle } => {
            let half_pi = std::f32::consts::FRAC_PI_2;
            if !(0.0..half_pi + 1e-6).contains(&outer_cone_angle)
                || !(0.0..=outer_cone_angle).contains(&inner_cone_angle)
            {
                bail!(
                    "light '{shown}': spot cone angles must satisfy 0 ≤ inner ({inner_cone_angle}) ≤ outer ({outer_cone_angle}) ≤ π/2"
                );
            }
            LightKind::Spot { inner_cone: inner_cone_angle, outer_cone: outer_cone_angle }
        }
    };
    Ok(Light { name, kind, intensity: color * light.intensity(), world_from_light, realness })
}
