//! Punctual lights as the data contract defines them: radiant intensity `intensity × color`
//! (W/sr in linear RGB units, no 683 lm/W), inverse-square falloff with no range, and the glTF
//! spot cone `t = clamp((cos a − cos outer)/(cos inner − cos outer), 0, 1)`, factor `t²`.

use glam::Vec3;
use mrshade_scene::{Light, LightKind};

/// Light arriving at a point from one punctual light.
#[derive(Clone, Copy, Debug)]
pub struct Incident {
    /// Unit direction from the point toward the light.
    pub dir: Vec3,
    /// Distance to the light (infinite for directional lights).
    pub distance: f32,
    /// Irradiance on a surface facing the light.
    pub irradiance: Vec3,
}

/// The spot factor of the contract for the angle whose cosine is `cos_a`.
pub fn spot_factor(cos_a: f32, inner: f32, outer: f32) -> f32 {
    let (cos_inner, cos_outer) = (inner.cos(), outer.cos());
    let t = ((cos_a - cos_outer) / (cos_inner - cos_outer).max(1e-6)).clamp(0.0, 1.0);
    t * t
}

/// What `light` sends to point `p`, or `None` where it sends nothing (outside a spot's cone).
pub fn incident(light: &Light, p: Vec3) -> Option<Incident> {
    if let LightKind::Directional = light.kind {
        return Some(Incident { dir: -light.direction(), distance: f32::INFINITY, irradiance: light.intensity });
    }
    let to_light = light.position() - p;
    let distance = to_light.length();
    if distance <= 0.0 {
        return None;
    }
    let dir = to_light / distance;
    let factor = match light.kind {
        LightKind::Spot { inner_cone, outer_cone } => {
            spot_factor((-dir).dot(light.direction()), inner_cone, outer_cone)
        }
        _ => 1.0,
    };
    (factor > 0.0).then(|| Incident { dir, distance, irradiance: light.intensity * factor / (distance * distance) })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spot_factor_is_full_inside_zero_outside_and_squared_between() {
        assert_eq!(spot_factor(1.0, 0.3, 0.5), 1.0);
        assert_eq!(spot_factor(0.6f32.cos(), 0.3, 0.5), 0.0);
        let mid = 0.5 * (0.3f32.cos() + 0.5f32.cos());
        assert!((spot_factor(mid, 0.3, 0.5) - 0.25).abs() < 1e-5);
    }
}
