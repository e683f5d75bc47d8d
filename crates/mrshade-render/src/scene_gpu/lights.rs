//! Punctual lights for the shaders and the shadow-map layers they own.
//!
//! Every light owns two sets of layers in one depth-texture array: casters of the real scene
//! only, and virtual casters only (Knecht §2.7: with one combined map a virtual object behind
//! a real one would darken `L_rv` twice, "double shadowing"). A set is one layer for spot and
//! directional lights, six cube faces for point lights and spots wider than a frustum holds.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, UVec4, Vec3, Vec4};
use mrshade_core::flags::Realness;
use mrshade_core::settings::ShadowSettings;
use mrshade_scene::{Light, LightKind};

/// Mirrors `struct Light` in shaders/lib/lights.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuLight {
    /// World position.
    pub position: Vec4,
    /// Direction the light shines along; w = r(pl).
    pub direction_real: Vec4,
    /// Intensity × color.
    pub intensity: Vec4,
    /// cos(outer), 1/(cos(inner) − cos(outer)), shadow texel size at unit distance, unused.
    pub cone: Vec4,
    /// Kind, first real-only layer, layers per set, first virtual-only layer.
    pub info: UVec4,
}

/// Matches `LIGHT_*` in lights.wgsl.
const LIGHT_POINT: u32 = 0;
const LIGHT_SPOT: u32 = 1;
const LIGHT_DIRECTIONAL: u32 = 2;

/// Spots wider than this (half angle) use six cube faces instead of one frustum.
pub(crate) const MAX_FRUSTUM_HALF_ANGLE: f32 = 65.0 * std::f32::consts::PI / 180.0;
/// Extra field of view so that a cone edge or a cube-face edge is inside the map.
pub const FOV_MARGIN: f32 = 2.0 * std::f32::consts::PI / 180.0;

/// One layer of the shadow-map array.
#[derive(Clone, Debug)]
pub struct ShadowLayer {
    /// World → clip of this layer (reversed depth).
    pub clip_from_world: Mat4,
    /// Which casters are drawn into it.
    pub casters: Realness,
    /// Near-plane distance of a perspective layer; 0 for orthographic ones.
    pub near: f32,
    /// Index of the light that owns it.
    pub light: u32,
}

/// The lights as the shaders see them, and the shadow layers they use; directional maps
/// cover `bounds` (the scene's box).
pub fn pack_lights(
    lights_in: &[Light],
    bounds: Option<(Vec3, Vec3)>,
    settings: &ShadowSettings,
) -> (Vec<GpuLight>, Vec<ShadowLayer>) {
    let (center, radius) = match bounds {
        Some((lo, hi)) => ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(1e-3)),
        None => (Vec3::ZERO, 1.0),
    };
    let near = (radius * 1e-3).clamp(1e-4, 0.05);
    let mut lights = Vec::new();
    let mut layers = Vec::new();
    for (light_index, light) in lights_in.iter().enumerate() {
        let (kind, cone) = match light.kind {
            LightKind::Point => (LIGHT_POINT, (-2.0, 1.0)),
            LightKind::Directional => (LIGHT_DIRECTIONAL, (-2.0, 1.0)),
            LightKind::Spot { inner_cone, outer_cone } => {
                let (ci, co) = (inner_cone.cos(), outer_cone.cos());
                (LIGHT_SPOT, (co, 1.0 / (ci - co).max(1e-4)))
            }
        };
        let faces = light_faces(light, center, radius, near);
        let texel_at_unit_distance = faces.texel_extent / settings.resolution as f32;
        let first_real = layers.len() as u32;
        let layer_near = if light.kind == LightKind::Directional { 0.0 } else { near };
        for casters in [Realness::Real, Realness::Virtual] {
            for &clip_from_world in &faces.clip_from_world {
                layers.push(ShadowLayer { clip_from_world, casters, near: layer_near, light: light_index as u32 });
            }
        }
        let per_set = faces.clip_from_world.len() as u32;
        lights.push(GpuLight {
            position: light.position().extend(1.0),
            direction_real: light.direction().extend(light.realness.r()),
            intensity: light.intensity.extend(0.0),
            cone: Vec4::new(cone.0, cone.1, texel_at_unit_distance, 0.0),
            info: UVec4::new(kind, first_real, per_set, first_real + per_set),
        });
    }
    (lights, layers)
}

/// The projections of one set of a light's layers.
struct Faces {
    clip_from_world: Vec<Mat4>,
    /// Width of the whole map: at unit distance for perspective maps, in metres for
    /// orthographic ones.
    texel_extent: f32,
}

fn light_faces(light: &Light, center: Vec3, radius: f32, near: f32) -> Faces {
    let position = light.position();
    let dir = light.direction();
    let perspective = |fov: f32| glam::camera::rh::proj::directx::perspective_infinite_reverse(fov, 1.0, near);
    match light.kind {
        LightKind::Spot { outer_cone, .. } if outer_cone <= MAX_FRUSTUM_HALF_ANGLE => {
            let fov = 2.0 * outer_cone + FOV_MARGIN;
            Faces {
                clip_from_world: vec![perspective(fov) * look_to(position, dir)],
                texel_extent: 2.0 * (fov * 0.5).tan(),
            }
        }
        LightKind::Directional => {
            // An orthographic box around the scene's bounding sphere; near/far are swapped
            // so that depth is reversed like every other map.
            let eye = center - dir * 2.0 * radius;
            let proj =
                glam::camera::rh::proj::directx::orthographic(-radius, radius, -radius, radius, 4.0 * radius, 0.0);
            Faces { clip_from_world: vec![proj * look_to(eye, dir)], texel_extent: 2.0 * radius }
        }
        _ => {
            let fov = std::f32::consts::FRAC_PI_2 + FOV_MARGIN;
            Faces { clip_from_world: cube_faces(position, fov, near).to_vec(), texel_extent: 2.0 * (fov * 0.5).tan() }
        }
    }
}

/// The six faces of a cube map at `eye` (+X, −X, +Y, −Y, +Z, −Z, `cube_face` in cube.wgsl),
/// each a square perspective of field of view `fov` (π/2 and a margin) with reversed depth
/// from `near` to infinity.
pub fn cube_faces(eye: Vec3, fov: f32, near: f32) -> [Mat4; 6] {
    let perspective = glam::camera::rh::proj::directx::perspective_infinite_reverse(fov, 1.0, near);
    [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z].map(|a| perspective * look_to(eye, a))
}

/// View matrix looking from `eye` along unit `dir`.
pub fn look_to(eye: Vec3, dir: Vec3) -> Mat4 {
    let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    glam::camera::rh::view::look_to_mat4(eye, dir, up)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrshade_scene::{Light, Scene};

    fn scene_with(kind: LightKind) -> Scene {
        let mut scene = Scene::default();
        scene.lights.push(Light {
            name: "l".into(),
            kind,
            intensity: Vec3::ONE,
            world_from_light: Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0))
                * Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2),
            realness: Realness::Real,
        });
        scene
    }

    fn pack(scene: &Scene) -> (Vec<GpuLight>, Vec<ShadowLayer>) {
        pack_lights(&scene.lights, scene.bounds(), &ShadowSettings::default())
    }

    #[test]
    fn each_light_owns_a_real_and_a_virtual_set() {
        let (lights, layers) = pack(&scene_with(LightKind::Point));
        assert_eq!(layers.len(), 12);
        assert_eq!(lights[0].info, UVec4::new(LIGHT_POINT, 0, 6, 6));
        assert!(layers[..6].iter().all(|l| l.casters == Realness::Real));
        assert!(layers[6..].iter().all(|l| l.casters == Realness::Virtual));
    }

    #[test]
    fn spot_map_sees_its_axis_at_the_centre_with_reversed_depth() {
        let spot = LightKind::Spot { inner_cone: 0.3, outer_cone: 0.5 };
        let (lights, layers) = pack(&scene_with(spot));
        assert_eq!(layers.len(), 2);
        // The light hangs at y = 2 looking down −Y.
        assert!(lights[0].direction_real.truncate().abs_diff_eq(Vec3::NEG_Y, 1e-5));
        let near_point = layers[0].clip_from_world.project_point3(Vec3::new(0.0, 1.0, 0.0));
        let far_point = layers[0].clip_from_world.project_point3(Vec3::new(0.0, 0.0, 0.0));
        assert!(near_point.truncate().abs_diff_eq(glam::Vec2::ZERO, 1e-5));
        assert!(near_point.z > far_point.z && far_point.z > 0.0);
    }

    #[test]
    fn directional_depth_is_reversed_too() {
        let (_, layers) = pack(&scene_with(LightKind::Directional));
        let m = layers[0].clip_from_world;
        // Scene bounds are empty (no instances): the box is around the origin, radius 1.
        let top = m.project_point3(Vec3::new(0.0, 0.5, 0.0));
        let bottom = m.project_point3(Vec3::new(0.0, -0.5, 0.0));
        assert!(top.z > bottom.z, "{top} {bottom}");
        assert!((0.0..=1.0).contains(&top.z) && (0.0..=1.0).contains(&bottom.z));
    }
}
