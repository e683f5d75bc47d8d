//! `[[insert]]`: models from their own glTF files placed into the scene.
//!
//! ```toml
//! [[insert]]
//! model = "models/Duck.glb"      # glTF 2.0, relative to the session file
//! name = "duck"                  # optional: the insert's node name (default: the file's stem)
//! translation = [0.1, 0.74, 0.0] # metres (default 0)
//! rotation = [0, 0.3827, 0, 0.9239] # a unit quaternion x, y, z, w; or instead
//! # rotation_deg = [0, 45, 0]    # Euler angles in degrees, about X, then Y, then Z (fixed axes)
//! scale = 0.1                    # one factor or three (default 1); or instead
//! # fit = 0.25                   # scale the model so that its largest side is 0.25 m, and
//!                                # put the centre of its base at `translation`
//! parent = "desk"                # optional: a node of the scene it moves with
//! animation = "Walk"             # optional: play only this animation (default: all)
//! time_offset = 0.5              # seconds added to the clock for its animations (default 0)
//! real = false                   # a proxy of something real (default: virtual)
//! ```

use crate::model::{Placement, Trs, checked_rotation, checked_scale, checked_translation};
use crate::{AssetSource, Scene, gltf::load_gltf};
use anyhow::{Context, Result};
use glam::{EulerRot, Quat, Vec3};
use mrshade_core::flags::Realness;
use mrshade_core::settings::Limits;
use mrshade_core::text::printable;
use serde::Deserialize;

/// One `[[insert]]` table.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct InsertFile {
    model: String,
    name: Option<String>,
    #[serde(default)]
    translation: [f32; 3],
    rotation: Option<[f32; 4]>,
    rotation_deg: Option<[f32; 3]>,
    scale: Option<Scale>,
    fit: Option<f32>,
    parent: Option<String>,
    animation: Option<String>,
    #[serde(default)]
    time_offset: f32,
    #[serde(default)]
    real: bool,
}

#[derive(Clone, Copy, Deserialize)]
#[serde(untagged)]
enum Scale {
    Uniform(f32),
    Axes([f32; 3]),
}

/// An inserted model: its node in the scene, by name (a live stream moves it per frame).
#[derive(Clone, Debug)]
pub struct Insert {
    /// The insert's name (its node's).
    pub name: String,
    /// Its node: an index into [`Scene::nodes`].
    pub node: usize,
    /// Where the session file placed it (relative to its parent).
    pub placement: Trs,
}

/// Loads every insert of the session into `scene`, in order; `field` names the table in
/// messages (`insert[2].rotation`).
pub(super) fn load_inserts(
    scene: &mut Scene,
    inserts: &[InsertFile],
    folder: &AssetSource,
    limits: &Limits,
) -> Result<Vec<Insert>> {
    let mut loaded = Vec::new();
    for (i, insert) in inserts.iter().enumerate() {
        let field = |name: &str| format!("field `insert[{i}].{name}`");
        let mut placement = placement(insert).map_err(|(name, e)| e.context(field(name)))?;
        let parent =
            match &insert.parent {
                None => None,
                Some(name) => Some(scene.node_named(name).with_context(|| {
                    format!("{}: the scene has no node named '{}'", field("parent"), printable(name))
                })?),
            };
        let name = insert.name.clone().unwrap_or_else(|| stem(&insert.model));
        let model = load_gltf(folder, &insert.model, limits).with_context(|| field("model"))?;
        let mut model = model;
        if let Some(size) = insert.fit
            && !fit(&mut placement, &model, size).with_context(|| field("fit"))?
        {
            model.warnings.push(format!("{}: the model has no triangles to fit; it is placed unscaled", field("fit")));
        }
        let placement = Placement {
            name: name.clone(),
            local: placement,
            parent,
            realness: Realness::from_real(insert.real),
            animation: insert.animation.clone(),
            time_offset: insert.time_offset,
        };
        let node = scene.insert(model, &placement).with_context(|| format!("`insert[{i}]`"))?;
        loaded.push(Insert { name, node, placement: placement.local });
    }
    Ok(loaded)
}

/// The insert's transform, or the name of the field that is wrong and why.
fn placement(insert: &InsertFile) -> Result<Trs, (&'static str, anyhow::Error)> {
    let err = |name, msg: String| (name, anyhow::anyhow!(msg));
    let translation = checked_translation(insert.translation).map_err(|m| err("translation", m))?;
    let rotation = match (insert.rotation, insert.rotation_deg) {
        (Some(_), Some(_)) => return Err(err("rotation", "give `rotation` or `rotation_deg`, not both".into())),
        (Some(q), None) => {
            checked_rotation(q).map_err(|m| err("rotation", format!("{m}, or Euler angles as `rotation_deg`")))?
        }
        (None, Some(deg)) => {
            let [x, y, z] = deg;
            if !Vec3::from(deg).is_finite() {
                return Err(err("rotation_deg", "must be finite angles in degrees".into()));
            }
            Quat::from_euler(EulerRot::ZYX, z.to_radians(), y.to_radians(), x.to_radians())
        }
        (None, None) => Quat::IDENTITY,
    };
    let scale = match (insert.scale, insert.fit) {
        (Some(_), Some(_)) => return Err(err("fit", "give `scale` or `fit`, not both".into())),
        (None, Some(size)) if !(size.is_finite() && size > 0.0) => {
            return Err(err("fit", format!("must be a positive size in metres, got {size}")));
        }
        (None, _) => Vec3::ONE,
        (Some(Scale::Uniform(s)), None) => Vec3::splat(s),
        (Some(Scale::Axes(s)), None) => Vec3::from(s),
    };
    let scale = checked_scale(scale).map_err(|m| err("scale", m))?;
    if let Some(a) = &insert.animation
        && a.is_empty()
    {
        return Err(err("animation", "must name an animation of the model".into()));
    }
    if !insert.time_offset.is_finite() {
        return Err(err("time_offset", "must be a finite number of seconds".into()));
    }
    if insert.name.as_deref().is_some_and(str::is_empty) {
        return Err(err("name", "must not be empty".into()));
    }
    Ok(Trs { translation, rotation, scale })
}

/// Scales `placement` so that `model`'s largest side (in its rest pose) is `size` metres and
/// moves it so that the centre of the model's base lands at the placement's translation;
/// `false` for a model without triangles (points and lines only, or nothing), left as it is.
fn fit(placement: &mut Trs, model: &Scene, size: f32) -> Result<bool> {
    let Some((lo, hi)) = model.bounds() else { return Ok(false) };
    let extent = (hi - lo).max_element();
    if extent.is_nan() || extent <= 0.0 {
        anyhow::bail!("the model is flat or a point (its largest side is {extent} m)");
    }
    placement.scale = Vec3::splat(size / extent);
    let base = Vec3::new((lo.x + hi.x) * 0.5, lo.y, (lo.z + hi.z) * 0.5);
    placement.translation -= placement.rotation * (placement.scale * base);
    Ok(true)
}

/// The file name without folders and extension (`models/Duck.glb` → `Duck`).
fn stem(model: &str) -> String {
    let file = model.rsplit(['/', '\\']).next().unwrap_or(model);
    let stem = file.rsplit_once('.').map_or(file, |(s, _)| s);
    if stem.is_empty() { "insert".into() } else { stem.into() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quaternions_must_be_unit_and_euler_angles_turn_about_fixed_axes() {
        assert!(checked_rotation([0.0, 0.0, 0.0, 1.0]).is_ok());
        assert!(checked_rotation([0.0, 0.7072, 0.0, 0.7072]).is_ok(), "rounded by hand");
        assert!(checked_rotation([0.0, 1.0, 0.0, 1.0]).unwrap_err().contains("not a unit quaternion"));
        assert!(checked_rotation([f32::NAN, 0.0, 0.0, 1.0]).is_err());
        let insert: InsertFile = toml::from_str("model = \"a.glb\"\nrotation_deg = [90, 0, 0]").unwrap();
        let trs = placement(&insert).ok().unwrap();
        assert!(trs.rotation.mul_vec3(Vec3::Y).abs_diff_eq(Vec3::Z, 1e-6));
        let both: InsertFile = toml::from_str("model = \"a\"\nrotation = [0,0,0,1]\nrotation_deg = [0,0,0]").unwrap();
        assert_eq!(placement(&both).err().unwrap().0, "rotation");
        assert_eq!(stem("models/Duck.glb"), "Duck");
        assert_eq!(stem("x"), "x");
    }
}
