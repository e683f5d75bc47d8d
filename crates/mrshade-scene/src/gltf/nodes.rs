//! The node hierarchy: world transforms (TRS or matrix), the real/virtual flag with
//! inheritance, and what nodes carry (meshes, lights, cameras).

use super::describe;
use crate::{Camera, Instance, Light, LightKind, Scene};
use anyhow::{Context, Result, bail};
use glam::{Mat4, Vec3};
use gltf::khr_lights_punctual::Kind;
use mrshade_core::flags::Realness;

/// glTF allows arbitrary depth; a deeper chain is almost certainly a cycle.
const MAX_DEPTH: usize = 256;

/// Walks the default scene (or scene 0) and places instances, lights and cameras.
pub fn place_nodes(document: &gltf::Document, mesh_primitives: &[Vec<usize>], scene: &mut Scene) -> Result<()> {
    let Some(root) = document.default_scene().or_else(|| document.scenes().next()) else {
        bail!("the file has no scene");
    };
    for node in root.nodes() {
        visit(&node, Mat4::IDENTITY, Realness::Virtual, 0, mesh_primitives, scene)?;
    }
    Ok(())
}

fn visit(
    node: &gltf::Node,
    parent_from_world: Mat4,
    parent_realness: Realness,
    depth: usize,
    mesh_primitives: &[Vec<usize>],
    scene: &mut Scene,
) -> Result<()> {
    let name = node.name().map(str::to_string).unwrap_or_else(|| format!("node {}", node.index()));
    let here = || format!("node {}", describe(Some(node.index()), node.name()));
    if depth > MAX_DEPTH {
        bail!("{}: the node hierarchy is deeper than {MAX_DEPTH} levels (a cycle?)", here());
    }
    let local = Mat4::from_cols_array_2d(&node.transform().matrix());
    if !local.is_finite() {
        bail!("{}: transform holds NaN or infinite values", here());
    }
    let world_from_node = parent_from_world * local;
    let realness = node_realness(node).with_context(here)?.unwrap_or(parent_realness);

    if let Some(mesh) = node.mesh() {
        for &primitive in &mesh_primitives[mesh.index()] {
            scene.instances.push(Instance {
                node_name: name.clone(),
                primitive,
                world_from_object: world_from_node,
                realness,
            });
        }
    }
    if let Some(light) = node.light() {
        scene
            .lights
            .push(load_light(&light, &name, world_from_node, realness, &mut scene.warnings).with_context(here)?);
    }
    if let Some(camera) = node.camera() {
        match camera.projection() {
            gltf::camera::Projection::Perspective(p) => scene.cameras.push(Camera {
                node_name: name.clone(),
                camera_name: camera.name().map(str::to_string),
                yfov: p.yfov(),
                aspect_ratio: p.aspect_ratio(),
                znear: p.znear(),
                world_from_camera: rigid(world_from_node),
            }),
            gltf::camera::Projection::Orthographic(_) => {
                scene.warnings.push(format!("{}: orthographic cameras are not supported; camera ignored", here()))
            }
        }
    }
    for child in node.children() {
        visit(&child, world_from_node, realness, depth + 1, mesh_primitives, scene)?;
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
    world_from_node: Mat4,
    realness: Realness,
    warnings: &mut Vec<String>,
) -> Result<Light> {
    let name = light.name().unwrap_or(node_name).to_string();
    let color = Vec3::from(light.color());
    if !(color.is_finite() && color.min_element() >= 0.0 && light.intensity().is_finite() && light.intensity() >= 0.0) {
        bail!("light '{name}': color and intensity must be finite and ≥ 0");
    }
    if light.range().is_some() {
        warnings.push(format!("light '{name}': range is ignored (inverse-square falloff, per the data contract)"));
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
                    "light '{name}': spot cone angles must satisfy 0 ≤ inner ({inner_cone_angle}) ≤ outer ({outer_cone_angle}) ≤ π/2"
                );
            }
            LightKind::Spot { inner_cone: inner_cone_angle, outer_cone: outer_cone_angle }
        }
    };
    Ok(Light { name, kind, intensity: color * light.intensity(), world_from_light: rigid(world_from_node), realness })
}

/// The rotation and translation of `m` (scale removed): cameras and lights are rigid.
fn rigid(m: Mat4) -> Mat4 {
    let (_, rotation, translation) = m.to_scale_rotation_translation();
    Mat4::from_rotation_translation(rotation.normalize(), translation)
}
