//! The node hierarchy: world transforms (TRS or matrix), the real/virtual flag with
//! inheritance, and what nodes carry (meshes, lights, cameras).
//!
//! Transforms are checked where they are used, after composition: nested scales that are
//! finite locally can make a world matrix infinite (1e30 × 1e30), and a zero scale or a zero
//! quaternion makes it singular. A mesh with a singular transform is flat and invisible, and
//! is left out with a warning; a camera or a light needs an orientation, so there it is an
//! error. Geometry must stay within [`MAX_WORLD_EXTENT`] metres of the origin.

use super::describe;
use crate::budget::Budget;
use crate::images::MAX_RADIANCE;
use crate::{Camera, Instance, Light, LightKind, Primitive, Scene};
use anyhow::{Context, Result, bail};
use glam::{Mat3, Mat4, Vec3};
use gltf::khr_lights_punctual::Kind;
use mrshade_core::flags::Realness;
use mrshade_core::math::{bounding_box, box_corners};

/// The node graph is a forest (checked by `document`); depth is still bounded, for the stack.
const MAX_DEPTH: usize = 256;
/// Farthest a surface, camera or light may be from the origin, in metres (the contract's
/// unit): 1000 km. Past it single precision cannot place a millimetre, and squared
/// distances in the renderers overflow long before 10¹⁹.
pub const MAX_WORLD_EXTENT: f32 = 1e6;

/// Walks the default scene (or scene 0) and places instances, lights and cameras.
pub fn place_nodes(
    document: &gltf::Document,
    mesh_primitives: &[Vec<usize>],
    budget: &mut Budget,
    scene: &mut Scene,
) -> Result<()> {
    let Some(root) = document.default_scene().or_else(|| document.scenes().next()) else {
        bail!("the file has no scene");
    };
    for node in root.nodes() {
        visit(&node, Mat4::IDENTITY, Realness::Virtual, 0, mesh_primitives, budget, scene)?;
    }
    Ok(())
}

fn visit(
    node: &gltf::Node,
    parent_from_world: Mat4,
    parent_realness: Realness,
    depth: usize,
    mesh_primitives: &[Vec<usize>],
    budget: &mut Budget,
    scene: &mut Scene,
) -> Result<()> {
    let name = node.name().map(str::to_string).unwrap_or_else(|| format!("node {}", node.index()));
    let here = || format!("node {}", describe(Some(node.index()), node.name()));
    if depth > MAX_DEPTH {
        bail!("{}: the node hierarchy is deeper than {MAX_DEPTH} levels (a cycle?)", here());
    }
    let local = local_transform(node).with_context(here)?;
    let world_from_node = parent_from_world * local;
    if !world_from_node.is_finite() {
        bail!("{}: its world transform is infinite (the scales down the hierarchy multiply past 3·10³⁸)", here());
    }
    let realness = node_realness(node).with_context(here)?.unwrap_or(parent_realness);

    if let Some(mesh) = node.mesh() {
        for &primitive in &mesh_primitives[mesh.index()] {
            if !is_invertible(world_from_node) {
                scene.warnings.push(format!("{}: its world transform has a zero scale; not rendered", here()));
                break;
            }
            check_extent(&scene.primitives[primitive], world_from_node).with_context(here)?;
            budget.charge(here(), 1, (std::mem::size_of::<Instance>() + name.len()) as u64)?;
            scene.instances.push(Instance {
                node_name: name.clone(),
                primitive,
                world_from_object: world_from_node,
                realness,
            });
        }
    }
    let oriented = || -> Result<Mat4> {
        if !is_invertible(world_from_node) {
            bail!("its world transform is singular (a zero scale or a degenerate matrix): it has no orientation");
        }
        let rigid = rigid(world_from_node);
        if !rigid.is_finite() || rigid.w_axis.truncate().abs().max_element() > MAX_WORLD_EXTENT {
            bail!("it lies farther than {MAX_WORLD_EXTENT:e} m from the origin");
        }
        Ok(rigid)
    };
    if let Some(light) = node.light() {
        let world_from_light = oriented().with_context(here)?;
        budget.charge(here(), 1, (std::mem::size_of::<Light>() + name.len()) as u64)?;
        scene
            .lights
            .push(load_light(&light, &name, world_from_light, realness, &mut scene.warnings).with_context(here)?);
    }
    if let Some(camera) = node.camera() {
        match camera.projection() {
            gltf::camera::Projection::Perspective(p) => {
                budget.charge(here(), 1, (std::mem::size_of::<Camera>() + name.len()) as u64)?;
                check_perspective(&p)
                    .with_context(|| format!("{}: camera {}", here(), describe(Some(camera.index()), camera.name())))?;
                scene.cameras.push(Camera {
                    node_name: name.clone(),
                    camera_name: camera.name().map(str::to_string),
                    yfov: p.yfov(),
                    aspect_ratio: p.aspect_ratio(),
                    znear: p.znear(),
                    world_from_camera: oriented().with_context(here)?,
                })
            }
            gltf::camera::Projection::Orthographic(_) => {
                scene.warnings.push(format!("{}: orthographic cameras are not supported; camera ignored", here()))
            }
        }
    }
    for child in node.children() {
        visit(&child, world_from_node, realness, depth + 1, mesh_primitives, budget, scene)?;
    }
    Ok(())
}

/// The node's local transform, as glTF 2.0 §3.5.2 allows it: TRS with a unit quaternion, or
/// an affine matrix. A quaternion that is not unit length but close is normalised (exporters
/// round); a zero or non-finite one is an error.
fn local_transform(node: &gltf::Node) -> Result<Mat4> {
    let local = match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            let m = Mat4::from_cols_array_2d(&matrix);
            if m.row(3) != glam::Vec4::W {
                bail!("matrix is not affine: its last row is {} (glTF needs 0, 0, 0, 1)", m.row(3));
            }
            m
        }
        gltf::scene::Transform::Decomposed { translation, rotation, scale } => {
            let q = glam::Quat::from_array(rotation);
            let length = q.length();
            if !(length.is_finite() && (length - 1.0).abs() < 0.1) {
                bail!("rotation {rotation:?} is not a unit quaternion");
            }
            let (t, s) = (Vec3::from(translation), Vec3::from(scale));
            Mat4::from_scale_rotation_translation(s, q / length, t)
        }
    };
    if !local.is_finite() {
        bail!("transform holds NaN or infinite values");
    }
    Ok(local)
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

/// Whether the linear part of `m` can be inverted: not flattened by a zero scale.
fn is_invertible(m: Mat4) -> bool {
    let linear = Mat3::from_mat4(m);
    let scale = linear.x_axis.length() * linear.y_axis.length() * linear.z_axis.length();
    let det = linear.determinant();
    det.is_finite() && scale.is_finite() && det.abs() > 1e-9 * scale && scale > 0.0
}

/// The primitive's world-space box must be finite and within [`MAX_WORLD_EXTENT`].
fn check_extent(primitive: &Primitive, world_from_object: Mat4) -> Result<()> {
    // Corner by corner: a NaN corner would vanish in a min/max fold.
    for c in box_corners(bounding_box(&primitive.positions)) {
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

/// The rotation and translation of `m` (scale removed): cameras and lights are rigid.
fn rigid(m: Mat4) -> Mat4 {
    let (_, rotation, translation) = m.to_scale_rotation_translation();
    Mat4::from_rotation_translation(rotation.normalize(), translation)
}
