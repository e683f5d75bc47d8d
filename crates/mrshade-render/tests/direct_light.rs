//! Known answers for the direct method on lavapipe: punctual lights on a Lambertian plane
//! against CPU math, and Knecht's visibility rules (Eq. 5.1–5.3) for real and virtual
//! occluders and lights.

mod common;

use common::{Blocker, Setup, ShadowClass, classify, lambert_point, rel, segment_hits_box};
use glam::Vec3;
use serde_json::json;

const SIZE: u32 = 24;

#[test]
fn spot_light_on_a_plane_matches_cpu_math() {
    let (inner, outer) = (0.3f32, 0.6f32);
    let mut s = Setup::top_down(SIZE);
    s.plane(2.0, 0.0, 0.5, true).light(
        json!({"type": "spot", "intensity": 2.0, "spot": {"innerConeAngle": inner, "outerConeAngle": outer}}),
        [0.1, 0.8, -0.05],
        true,
    );
    let r = s.render();
    let light = Vec3::new(0.1, 0.8, -0.05);
    let mut checked = 0;
    for (x, y) in [(12, 12), (4, 9), (20, 18), (15, 2), (2, 22)] {
        let p = r.world_on_plane(x, y, 0.0);
        let cos_angle = (p - light).normalize().dot(Vec3::NEG_Y);
        let t = ((cos_angle - outer.cos()) / (inner.cos() - outer.cos())).clamp(0.0, 1.0);
        let expected = lambert_point(0.5, 2.0, light, p, t * t);
        let got = r.l_rv(x, y);
        assert_eq!(got, r.l_r(x, y), "real light on a real plane: both buffers agree");
        if expected > 0.01 {
            assert!(rel(got.x, expected) < 0.015, "pixel ({x},{y}): {} vs {expected}", got.x);
            checked += 1;
        } else {
            assert!(got.x < 0.01 + expected, "pixel ({x},{y}) outside the cone: {}", got.x);
        }
    }
    assert!(checked >= 3, "the test must look at lit pixels");
}

#[test]
fn point_light_falls_off_with_the_inverse_square() {
    let mut s = Setup::top_down(SIZE);
    s.plane(2.0, 0.0, 0.8, true).light(
        json!({"type": "point", "intensity": 0.5, "color": [1.0, 0.5, 0.25]}),
        [0.2, 0.4, 0.1],
        true,
    );
    let r = s.render();
    for (x, y) in [(12, 12), (3, 3), (20, 6), (8, 21)] {
        let p = r.world_on_plane(x, y, 0.0);
        let expected = lambert_point(0.8, 0.5, Vec3::new(0.2, 0.4, 0.1), p, 1.0);
        let got = r.l_rv(x, y);
        assert!(rel(got.x, expected) < 0.015, "({x},{y}) {} vs {expected}", got.x);
        assert!(
            rel(got.y, 0.5 * expected) < 0.015 && rel(got.z, 0.25 * expected) < 0.015,
            "colour scales the intensity"
        );
    }
}

#[test]
fn directional_light_gives_uniform_irradiance() {
    let mut s = Setup::top_down(SIZE);
    let l = s.gltf.light(json!({"type": "directional", "intensity": 3.0}));
    // Tilted 30° from vertical.
    let rot = mrshade_testkit::gltf::quat([1.0, 0.0, 0.0], -std::f32::consts::FRAC_PI_3);
    s.gltf.node(json!({"translation": [0, 2, 0], "rotation": rot, "extensions": {"KHR_lights_punctual": {"light": l}}, "extras": {"real": true}}));
    s.plane(2.0, 0.0, 0.5, true);
    let r = s.render();
    let expected = 0.5 / std::f32::consts::PI * 3.0 * (std::f32::consts::FRAC_PI_3).sin();
    for (x, y) in [(1, 1), (12, 12), (22, 5)] {
        assert!(rel(r.l_rv(x, y).x, expected) < 0.015, "({x},{y}) {} vs {expected}", r.l_rv(x, y).x);
    }
}

const LAMP: Vec3 = Vec3::new(0.35, 0.9, 0.0);
const CAMERA: Vec3 = Vec3::new(0.0, 1.0, 0.0);
const BLOCKER: Blocker = Blocker { center: Vec3::new(0.1, 0.35, 0.0), half: 0.08 };

/// A real spot above a real plane, shining straight down.
fn lamp_over_plane() -> Setup {
    let mut s = Setup::top_down(SIZE);
    s.plane(2.0, 0.0, 0.5, true).light(
        json!({"type": "spot", "intensity": 1.0, "spot": {"innerConeAngle": 1.0, "outerConeAngle": 1.2}}),
        LAMP.to_array(),
        true,
    );
    s
}

fn add(s: &mut Setup, b: Blocker, real: bool) {
    s.cube(b.center.to_array(), b.half, real);
}

/// Plane pixels classified against `blockers`, with the unshadowed Lambert answer.
fn plane_pixels(r: &common::Rendered, blockers: &[Blocker]) -> Vec<(u32, u32, ShadowClass, f32)> {
    (0..SIZE * SIZE)
        .map(|i| (i % SIZE, i / SIZE))
        .map(|(x, y)| {
            let p = r.world_on_plane(x, y, 0.0);
            (x, y, classify(CAMERA, p, LAMP, blockers, 0.02), lambert_point(0.5, 1.0, LAMP, p, 1.0))
        })
        .collect()
}

#[test]
fn a_virtual_occluder_shadows_l_rv_only() {
    let mut s = lamp_over_plane();
    add(&mut s, BLOCKER, false);
    let r = s.render();
    let (mut shadowed, mut lit) = (0, 0);
    for (x, y, class, unshadowed) in plane_pixels(&r, &[BLOCKER]) {
        match class {
            ShadowClass::Shadowed => {
                assert!(r.l_rv(x, y).x < 0.05 * unshadowed, "({x},{y}) L_rv {} in the virtual shadow", r.l_rv(x, y).x);
                assert!(rel(r.l_r(x, y).x, unshadowed) < 0.015, "({x},{y}) L_r keeps the real light");
                shadowed += 1;
            }
            ShadowClass::Lit => {
                assert_eq!(r.l_rv(x, y), r.l_r(x, y), "({x},{y}) outside the shadow nothing changes");
                lit += 1;
            }
            ShadowClass::Unknown => {}
        }
    }
    assert!(shadowed >= 3 && lit >= 100, "{shadowed} shadowed, {lit} lit pixels checked");
}

#[test]
fn a_real_occluder_shadows_both_buffers() {
    let mut s = lamp_over_plane();
    add(&mut s, BLOCKER, true);
    let r = s.render();
    for y in 0..SIZE {
        for x in 0..SIZE {
            assert_eq!(r.l_rv(x, y), r.l_r(x, y), "everything is real: L_rv == L_r at ({x},{y})");
        }
    }
    let mut shadowed = 0;
    for (x, y, class, unshadowed) in plane_pixels(&r, &[BLOCKER]) {
        if class == ShadowClass::Shadowed {
            assert!(r.l_r(x, y).x < 0.05 * unshadowed, "({x},{y}) in the real shadow");
            shadowed += 1;
        }
    }
    assert!(shadowed >= 3, "{shadowed}");
}

#[test]
fn shadows_are_never_doubled() {
    // A small virtual cube inside the shadow volume of a real one (Knecht Fig. 5.5/5.6): where
    // both would shadow the plane, the photo is already dark, so L_rv − L_r must stay 0.
    let small = Blocker { center: LAMP + (BLOCKER.center - LAMP) * 1.45, half: 0.02 };
    let mut s = lamp_over_plane();
    add(&mut s, BLOCKER, true);
    add(&mut s, small, false);
    let r = s.render();
    let mut both = 0;
    for (x, y, class, _) in plane_pixels(&r, &[BLOCKER]) {
        let p = r.world_on_plane(x, y, 0.0);
        if class == ShadowClass::Shadowed {
            assert!((r.l_rv(x, y) - r.l_r(x, y)).abs().max_element() < 1e-6, "doubled shadow at ({x},{y})");
            if segment_hits_box(p, LAMP, small.center, small.half) {
                both += 1;
            }
        }
    }
    assert!(both > 0, "some plane pixels lie in both shadows");
}

#[test]
fn a_virtual_light_relights_only_l_rv() {
    let mut s = Setup::top_down(SIZE);
    s.plane(2.0, 0.0, 0.5, true).light(json!({"type": "point", "intensity": 0.4}), [0.0, 0.5, 0.0], false);
    let r = s.render();
    for (x, y) in [(12, 12), (3, 20)] {
        let p = r.world_on_plane(x, y, 0.0);
        assert!(rel(r.l_rv(x, y).x, lambert_point(0.5, 0.4, Vec3::new(0.0, 0.5, 0.0), p, 1.0)) < 0.015);
        assert_eq!(r.l_r(x, y), Vec3::ZERO, "a virtual light is not in L_r (Eq. 5.2, r(pl) = 0)");
    }
}

#[test]
fn point_light_shadows_use_the_right_cube_face() {
    let mut s = Setup::top_down(SIZE);
    s.plane(2.0, 0.0, 0.5, true)
        .light(json!({"type": "point", "intensity": 0.3}), [0.0, 0.3, 0.0], true)
        // Virtual blockers toward +X and −Z: their shadows fall further out on those sides.
        .cube([0.15, 0.15, 0.0], 0.03, false)
        .cube([0.0, 0.15, -0.15], 0.03, false);
    let r = s.render();
    let shadowed_at = |target: Vec3| {
        let (x, y) = (0..SIZE * SIZE)
            .map(|i| (i % SIZE, i / SIZE))
            .min_by(|a, b| {
                let da = (r.world_on_plane(a.0, a.1, 0.0) - target).length();
                let db = (r.world_on_plane(b.0, b.1, 0.0) - target).length();
                da.total_cmp(&db)
            })
            .unwrap();
        r.l_rv(x, y).x < 0.3 * r.l_r(x, y).x
    };
    assert!(shadowed_at(Vec3::new(0.3, 0.0, 0.0)), "shadow of the +X blocker");
    assert!(shadowed_at(Vec3::new(0.0, 0.0, -0.3)), "shadow of the −Z blocker");
    assert!(!shadowed_at(Vec3::new(-0.3, 0.0, 0.0)), "nothing toward −X");
    assert!(!shadowed_at(Vec3::new(0.0, 0.0, 0.3)), "nothing toward +Z");
}

#[test]
fn a_uniform_probe_lights_an_upward_plane_by_its_radiance_times_albedo() {
    let mut s = Setup::top_down(SIZE);
    s.plane(20.0, 0.0, 0.5, true).probe = Some([0.8, 0.4, 0.2]);
    let r = s.render();
    // E = π·L over the upper hemisphere, L_o = albedo·E/π = albedo·L (unshadowed probe light).
    let got = r.l_rv(12, 12);
    for (g, e) in got.to_array().iter().zip([0.4, 0.2, 0.1]) {
        assert!(rel(*g, e) < 0.02, "{got} vs 0.5·probe");
    }
    assert_eq!(got, r.l_r(12, 12), "the probe is real light");
}
