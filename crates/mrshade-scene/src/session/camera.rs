//! The render camera: a camera of the glTF by name, or one placed by the session itself,
//! for a proxy without cameras (a reconstruction, a downloaded model):
//!
//! ```toml
//! [camera]
//! position = [0.0, 1.2, 1.5]   # metres
//! look_at = [0.0, 0.75, 0.0]   # the point at the image centre
//! up = [0.0, 1.0, 0.0]         # optional (default +Y)
//! yfov_deg = 45.0              # vertical field of view; or `yfov` in radians, as in glTF
//! znear = 0.01                 # optional (default 0.01 m)
//! ```

use crate::sequence::DEFAULT_ZNEAR;
use crate::{Camera, Scene};
use anyhow::{Context, Result, bail};
use glam::{Mat4, Vec3};
use serde::Deserialize;

/// Node name of the camera a `[camera]` table places.
pub const SESSION_CAMERA: &str = "session camera";

/// The `camera` field: a name, or a `[camera]` table.
pub(super) enum CameraChoice {
    /// A camera of the glTF, by node or camera name.
    Named(String),
    /// A camera placed by the session.
    Placed(Camera),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlacedCamera {
    position: [f32; 3],
    look_at: [f32; 3],
    #[serde(default = "up")]
    up: [f32; 3],
    yfov: Option<f32>,
    yfov_deg: Option<f32>,
    znear: Option<f32>,
}

fn up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}

/// Reads the `camera` field (a string or a table).
pub(super) fn parse_camera(value: &toml::Value) -> Result<CameraChoice> {
    match value {
        toml::Value::String(name) => Ok(CameraChoice::Named(name.clone())),
        toml::Value::Table(_) => {
            let placed: PlacedCamera = value.clone().try_into().map_err(|e: toml::de::Error| {
                anyhow::anyhow!("{}", mrshade_core::text::printable(e.message().trim()))
            })?;
            Ok(CameraChoice::Placed(placed.camera()?))
        }
        other => bail!("must be a camera name or a [camera] table, got a {}", other.type_str()),
    }
}

impl PlacedCamera {
    fn camera(&self) -> Result<Camera> {
        let (eye, target, up) = (Vec3::from(self.position), Vec3::from(self.look_at), Vec3::from(self.up));
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            bail!("position, look_at and up must be finite");
        }
        let forward = (target - eye).normalize_or_zero();
        if forward == Vec3::ZERO {
            bail!("look_at must differ from position");
        }
        if forward.cross(up.normalize_or_zero()).length() < 1e-4 {
            bail!("up must not be parallel to the viewing direction (position → look_at)");
        }
        let yfov = match (self.yfov, self.yfov_deg) {
            (Some(_), Some(_)) => bail!("give `yfov` (radians) or `yfov_deg`, not both"),
            (Some(rad), None) => rad,
            (None, Some(deg)) => deg.to_radians(),
            (None, None) => bail!("the vertical field of view is missing: give `yfov_deg` (or `yfov` in radians)"),
        };
        if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
            bail!("the vertical field of view must be between 0 and 180° (exclusive), got {}°", yfov.to_degrees());
        }
        let znear = self.znear.unwrap_or(DEFAULT_ZNEAR);
        if !(znear > 0.0 && znear.is_finite()) {
            bail!("znear must be a positive distance, got {znear}");
        }
        // The camera looks down its −Z with +Y up (glTF's convention).
        let right = forward.cross(up).normalize();
        let camera_up = right.cross(forward);
        let world_from_camera =
            Mat4::from_cols(right.extend(0.0), camera_up.extend(0.0), (-forward).extend(0.0), eye.extend(1.0));
        Ok(Camera {
            node_name: SESSION_CAMERA.into(),
            camera_name: None,
            yfov,
            aspect_ratio: None,
            znear,
            world_from_camera,
        })
    }
}

/// Index of the glTF camera `name` (or the first), or why there is none.
pub(super) fn pick_camera(scene: &Scene, name: Option<&str>) -> Result<usize> {
    if scene.cameras.is_empty() {
        bail!("the glTF has no perspective camera; add a camera node, or place one with a [camera] table");
    }
    match name {
        None => Ok(0),
        Some(name) => scene.cameras.iter().position(|c| c.is_named(name)).with_context(|| {
            let known: Vec<_> = scene.cameras.iter().map(|c| c.node_name.as_str()).collect();
            format!("no camera named '{name}' (cameras: {})", known.join(", "))
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn placed(text: &str) -> Result<Camera> {
        let value: toml::Table = toml::from_str(text).unwrap();
        match parse_camera(&toml::Value::Table(value))? {
            CameraChoice::Placed(c) => Ok(c),
            CameraChoice::Named(_) => unreachable!(),
        }
    }

    #[test]
    fn a_placed_camera_looks_at_its_point() {
        let c = placed("position = [0, 1, 2]\nlook_at = [0, 1, 0]\nyfov_deg = 45").unwrap();
        let forward = c.world_from_camera.transform_vector3(Vec3::NEG_Z);
        assert!(forward.abs_diff_eq(Vec3::NEG_Z, 1e-6), "{forward}");
        assert!(c.world_from_camera.transform_point3(Vec3::ZERO).abs_diff_eq(Vec3::new(0.0, 1.0, 2.0), 1e-6));
        assert!((c.yfov - 45f32.to_radians()).abs() < 1e-6);
        let err = |t: &str| format!("{:#}", placed(t).err().unwrap());
        assert!(err("position = [0, 1, 2]\nlook_at = [0, 1, 2]\nyfov = 1").contains("differ"));
        assert!(err("position = [0, 2, 0]\nlook_at = [0, 0, 0]\nyfov = 1").contains("parallel"));
        assert!(err("position = [0, 1, 2]\nlook_at = [0, 1, 0]").contains("missing"));
        assert!(err("position = [0, 1, 2]\nlook_at = [0, 1, 0]\nyfov_deg = 200").contains("180"));
        assert!(err("position = [0, 1, 2]\nlookat = [0, 1, 0]\nyfov = 1").contains("lookat"));
    }
}
