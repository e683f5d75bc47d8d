//! The path tracer against answers known in closed form, and the exact invariant of
//! differential rendering.

mod common;

use common::{Builder, lambert, point_on_plane};
use glam::Vec3;
use mrshade_core::flags::Realness::{Real, Virtual};
use mrshade_core::settings::ReferenceSettings;
use mrshade_reference::environment::EnvironmentLight;
use mrshade_reference::geometry::Geometry;
use mrshade_reference::integrator::Tracer;
use mrshade_reference::sampler::PathSampler;
use mrshade_reference::{ReferenceImage, render};
use std::f32::consts::PI;

fn settings(spp: u32) -> ReferenceSettings {
    ReferenceSettings { spp, ..ReferenceSettings::default() }
}

fn rgb(img: &mrshade_core::HdrImage, x: u32, y: u32) -> Vec3 {
    Vec3::from(img.get(x, y))
}

#[test]
fn furnace_a_white_lambert_sphere_under_a_uniform_probe_has_radiance_one() {
    // Every path off a convex white sphere escapes to the probe: radiance 1 exactly in
    // expectation, whatever the bounce count. The sphere is virtual, so L_r sees the probe only.
    let mut b = Builder::new(Vec3::new(0.0, 0.0, 3.0), Vec3::NEG_Z);
    b.uniform_probe(1.0).sphere(Vec3::ZERO, 1.0, lambert(1.0), Virtual);
    let session = b.session(40, 30, settings(64));
    let out = render(&session, &|_, _| {});
    let (mut sum, mut count, mut worst) = (0.0f64, 0, 0.0f32);
    for (i, p) in out.l_rv.pixels.iter().enumerate() {
        assert_eq!(out.l_r.pixels[i], [1.0; 3], "L_r sees the uniform probe");
        if out.coverage[i] == 1.0 {
            let v = Vec3::from(*p);
            sum += v.element_sum() as f64 / 3.0;
            count += 1;
            worst = worst.max((v - Vec3::ONE).abs().max_element());
        }
    }
    let mean = sum / count as f64;
    assert!(count > 300, "the sphere covers {count} pixels");
    assert!((mean - 1.0).abs() < 0.01, "mean radiance on the sphere {mean}");
    assert!(worst < 0.1, "worst pixel off by {worst}");
}

#[test]
fn spot_on_a_lambert_plane_matches_the_closed_form() {
    // L = ρ/π · I · t² · cos θ / d² (contract falloff), for a virtual spot: L_r stays dark.
    let (albedo, intensity, height) = (0.5, 3.0, 1.5);
    let cones = (0.3f32, 0.6f32);
    let mut b = Builder::new(Vec3::new(0.0, 2.5, 0.0), Vec3::NEG_Y);
    b.floor(5.0, 0.0, lambert(albedo), Real).spot_down(Vec3::new(0.0, height, 0.0), intensity, cones, Virtual);
    let session = b.session(48, 36, settings(16));
    let out = render(&session, &|_, _| {});
    let expected = |px: f32, py: f32| {
        // The pixel's mean over a 4×4 grid of positions (the render box-filters the pixel).
        let mut sum = 0.0;
        for j in 0..4 {
            for i in 0..4 {
                let p = point_on_plane(&session, px + (i as f32 + 0.5) / 4.0, py + (j as f32 + 0.5) / 4.0, 0.0);
                let to_light = Vec3::new(0.0, height, 0.0) - p;
                let d = to_light.length();
                let cos = height / d;
                let t = ((cos - cones.1.cos()) / (cones.0.cos() - cones.1.cos())).clamp(0.0, 1.0);
                sum += albedo / PI * intensity * t * t * cos / (d * d);
            }
        }
        sum / 16.0
    };
    let mut checked = 0;
    for y in 0..36 {
        for x in 0..48 {
            let want = expected(x as f32, y as f32);
            let got = rgb(&out.l_rv, x, y);
            assert!((got.x - want).abs() <= 0.02 * want + 1e-4, "pixel ({x}, {y}): {got} vs {want}");
            assert_eq!(rgb(&out.l_r, x, y), Vec3::ZERO);
            checked += usize::from(want > 0.0);
        }
    }
    assert!(checked > 200, "{checked} lit pixels");
}

#[test]
fn glass_absorbs_by_beer_lambert_along_the_path_inside() {
    // A virtual cube of clear glass with ior 1 (no reflection, no bending) and attenuation
    // 0.5 per 0.1 m: the 0.2 m crossing transmits 0.5² = 0.25 of the uniform probe.
    let glass = mrshade_scene::Material {
        name: "glass".into(),
        metallic: 0.0,
        roughness: 0.0,
        transmission: 1.0,
        ior: 1.0,
        thickness: 0.2,
        attenuation_color: Vec3::splat(0.5),
        attenuation_distance: 0.1,
        ..mrshade_scene::Material::default()
    };
    let mut b = Builder::new(Vec3::new(0.0, 0.0, 2.0), Vec3::NEG_Z);
    b.uniform_probe(1.0).cuboid(Vec3::ZERO, Vec3::splat(0.1), glass, Virtual);
    let session = b.session(32, 24, settings(4));
    let out = render(&session, &|_, _| {});
    let centre = rgb(&out.l_rv, 16, 12);
    assert!((centre - Vec3::splat(0.25)).abs().max_element() < 1e-3, "{centre}");
    assert_eq!(rgb(&out.l_r, 16, 12), Vec3::ONE);
}

fn real_only_scene() -> Builder {
    let mut b = Builder::new(Vec3::new(0.3, 1.2, 2.0), Vec3::new(-0.1, -0.5, -1.0).normalize());
    b.uniform_probe(0.7)
        .floor(2.0, 0.0, lambert(0.6), Real)
        .cuboid(Vec3::new(0.0, 0.2, 0.0), Vec3::splat(0.2), lambert(0.8), Real)
        .spot_down(Vec3::new(0.2, 1.5, 0.1), 2.0, (0.4, 0.7), Real);
    b
}

#[test]
fn without_virtual_content_l_rv_and_l_r_are_the_same_number_for_every_path() {
    let b = real_only_scene();
    let session = b.session(24, 18, settings(8));
    let geometry = Geometry::new(&session.scene);
    let env = EnvironmentLight::new(session.environment.as_ref().unwrap());
    let tracer = Tracer { scene: &session.scene, geometry: &geometry, environment: Some(&env), settings: settings(8) };
    let eye = session.scene.cameras[0].world_from_camera.transform_point3(Vec3::ZERO);
    let mut lit = 0;
    for i in 0..2000u32 {
        let sampler = PathSampler::new(i, i % 64, 1);
        let [u, v] = sampler.pixel();
        let dir =
            session.scene.cameras[0].world_from_camera.transform_vector3(Vec3::new(u - 0.5, v - 0.8, -1.0)).normalize();
        let path = tracer.trace_camera(eye, dir, &sampler);
        assert_eq!(path.radiance.rv.to_array(), path.radiance.r.to_array(), "path {i}");
        lit += usize::from(path.radiance.rv != Vec3::ZERO);
    }
    assert!(lit > 1000);
    // And so the composite is the photo, bit for bit.
    let out: ReferenceImage = render(&session, &|_, _| {});
    assert_eq!(out.composite.pixels, session.background.pixels);
}

#[test]
fn a_virtual_object_shadows_the_real_floor_and_is_seen_through_coverage() {
    let mut b = real_only_scene();
    b.cuboid(Vec3::new(0.5, 0.15, 0.4), Vec3::splat(0.15), lambert(0.5), Virtual);
    let session = b.session(48, 36, settings(16));
    let out = render(&session, &|_, _| {});
    let (mut darker, mut covered) = (0, 0);
    for i in 0..out.l_rv.pixels.len() {
        let (rv, r) = (Vec3::from(out.l_rv.pixels[i]), Vec3::from(out.l_r.pixels[i]));
        if out.coverage[i] == 0.0 && rv.x < 0.97 * r.x {
            darker += 1;
        }
        covered += usize::from(out.coverage[i] > 0.5);
    }
    assert!(darker > 20, "{darker} floor pixels in the virtual cube's shadow");
    assert!(covered > 20, "{covered} pixels show the cube");
    // Determinism: the same seed gives the same image.
    assert_eq!(render(&session, &|_, _| {}).composite.pixels, out.composite.pixels);
}

#[test]
fn rough_glass_is_reported_as_rendered_smooth() {
    let mut b = Builder::new(Vec3::Z, Vec3::NEG_Z);
    let glass = |roughness| mrshade_scene::Material {
        name: format!("glass {roughness}"),
        transmission: 1.0,
        roughness,
        ..mrshade_scene::Material::default()
    };
    b.sphere(Vec3::ZERO, 0.5, glass(0.0), Virtual).sphere(Vec3::X, 0.5, glass(0.4), Virtual);
    let warnings = mrshade_reference::warnings(&b.scene);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("glass 0.4") && warnings[0].contains("smooth glass"));
}

#[test]
fn a_directional_light_shades_a_normal_mapped_plane_by_the_mapped_normal() {
    // A 1×1 normal map tilts the floor's normal toward +u (+x): n' = t·m.x + b·m.y + n·m.z.
    // L = ρ/π · E · (n'·l) for a directional light of irradiance E from l.
    let texel = [204u8, 160, 220, 255];
    let m = Vec3::new(texel[0] as f32, texel[1] as f32, texel[2] as f32) / 255.0 * 2.0 - Vec3::ONE;
    let m = m.normalize();
    let mut floor = lambert(0.5);
    floor.normal_texture = Some((mrshade_scene::TextureRef { texture: 0 }, 1.0));
    let mut b = Builder::new(Vec3::new(0.0, 2.0, 0.0), Vec3::NEG_Y);
    b.floor(3.0, 0.0, floor, Real);
    b.scene.textures.push(mrshade_scene::Texture {
        name: "normals".into(),
        width: 1,
        height: 1,
        rgba8: texel.to_vec(),
        srgb: false,
        repeat_u: true,
        repeat_v: true,
    });
    // The floor's u grows along +x, v along +z (so the map's +y, up the image, is −z).
    let l = Vec3::new(-0.5, 1.0, 0.3).normalize();
    b.scene.lights.push(mrshade_scene::Light {
        name: "sun".into(),
        kind: mrshade_scene::LightKind::Directional,
        intensity: Vec3::splat(2.0),
        world_from_light: glam::Mat4::from_quat(glam::Quat::from_rotation_arc(Vec3::NEG_Z, -l)),
        realness: Real,
    });
    let session = b.session(16, 12, ReferenceSettings { max_bounces: 1, ..settings(4) });
    let out = render(&session, &|_, _| {});
    let n = Vec3::new(m.x, m.z, -m.y).normalize();
    let want = 0.5 / PI * 2.0 * n.dot(l);
    let flat = 0.5 / PI * 2.0 * l.y;
    let got = rgb(&out.l_rv, 8, 6).x;
    assert!((got - want).abs() < 1e-3 * want, "{got} vs {want} (unmapped: {flat})");
    assert!((want - flat).abs() > 0.05 * flat, "the map changes the answer");
}
