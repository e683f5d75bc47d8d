//! The specular stage (reflections spec §2.5–§2.16) on the test GPU: the exact invariant with
//! real mirrors and glass, and known answers of the back-projection.

mod common;

use common::{Setup, glass, mirror};
use glam::Vec3;
use mrshade_core::settings::Method;
use mrshade_render::uniforms::FrameUniforms;
use mrshade_testkit::gltf::{cuboid, quad, quat};
use serde_json::json;

/// A unique colour per photo pixel (red and green vary, blue constant).
fn textured(x: u32, y: u32) -> [u8; 3] {
    [(x * 4 + 20) as u8, (y * 4 + 20) as u8, 140]
}

#[test]
fn real_mirrors_and_glass_without_virtual_content_return_the_photo() {
    // Every method, and every intersection technique with the default method.
    let cases =
        Method::ALL.iter().map(|&m| (m, "impostor")).chain(INTERSECTIONS[1..].iter().map(|&i| (Method::default(), i)));
    for (method, intersection) in cases {
        let mut s = Setup::top_down(32);
        s.photo = Box::new(textured);
        s.probe = Some([0.6, 0.7, 0.9]);
        s.top_toml = format!("method = \"{}\"\n", method.name());
        // Caustics too: the real spot's photons through the real glass land alike in L_rv and L_r.
        s.extra_toml += &format!(
            "[output]\nframes = 2\n[caustics]\nenabled = true\nphoton_resolution = 32\n\
             [specular]\nintersection = \"{intersection}\"\n"
        );
        s.plane(2.0, 0.0, 0.4, true).light(
            json!({"type": "spot", "intensity": 1.5, "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.9}}),
            [0.2, 0.8, 0.0],
            true,
        );
        let m = s.gltf.material(mirror());
        let mesh = s.gltf.mesh(&cuboid([0.08; 3]), Some(m), true);
        s.gltf.node(
            json!({"name": "real-mirror", "mesh": mesh, "translation": [-0.15, 0.1, 0.0], "extras": {"real": true}}),
        );
        let g = s.gltf.material(glass());
        let mesh = s.gltf.mesh(&cuboid([0.08; 3]), Some(g), true);
        s.gltf.node(
            json!({"name": "real-glass", "mesh": mesh, "translation": [0.15, 0.1, 0.05], "extras": {"real": true}}),
        );
        let r = s.render();
        assert!(r.renderer.specular_traced(), "the stage runs for real mirrors and glass");
        let photo: Vec<u8> = (0..32 * 32).flat_map(|i| textured(i % 32, i / 32)).collect();
        let out = r.renderer.read_composite(&r.ctx).unwrap().image.to_srgb8();
        assert_eq!(photo, out, "bit-exact photo with {} and {intersection}", method.name());
    }
}

/// Where `ndc` (a world point projected by the camera) lands in a `size`² image, how far
/// `got` is from a grey multiple of the photo pixel there or at one of its four neighbours
/// (the smallest relative channel spread: a wrong pixel of the textured photo is not grey),
/// and that multiple at the pixel itself (blue channel).
fn photo_pixel_match(got: [f32; 3], ndc: Vec3, size: u32) -> ((f32, f32), f32, f32) {
    let photo = |x: u32, y: u32| textured(x, y).map(srgb_to_linear);
    let q = ((ndc.x * 0.5 + 0.5) * size as f32, (0.5 - ndc.y * 0.5) * size as f32);
    let spread = |px: u32, py: u32| {
        let c = photo(px, py);
        let k: Vec<f32> = (0..3).map(|i| got[i] / c[i]).collect();
        (k[0] - k[2]).abs().max((k[1] - k[2]).abs()) / k[2]
    };
    let (qx, qy) = (q.0 as u32, q.1 as u32);
    let best = [(0i32, 0i32), (-1, 0), (1, 0), (0, -1), (0, 1)]
        .iter()
        .map(|(dx, dy)| spread((qx as i32 + dx) as u32, (qy as i32 + dy) as u32))
        .fold(f32::INFINITY, f32::min);
    (q, best, got[2] / photo(qx, qy)[2])
}

fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// Every `specular.intersection`.
const INTERSECTIONS: [&str; 4] = ["impostor", "cube", "layered-cube", "planar"];

#[test]
fn a_virtual_planar_mirror_shows_the_photo_where_its_reflection_lands() {
    for intersection in INTERSECTIONS {
        planar_mirror(intersection);
    }
}

fn planar_mirror(intersection: &str) {
    const SIZE: u32 = 48;
    // A virtual mirror tilted 60° about z above a real floor, seen from straight above: the
    // reflected rays go down to the right and meet the floor at a point the photo shows.
    let mut s = Setup::top_down(SIZE);
    s.photo = Box::new(textured);
    s.probe = Some([0.5, 0.5, 0.5]);
    s.extra_toml += &format!("[specular]\nintersection = \"{intersection}\"\n");
    s.plane(2.0, 0.0, 0.5, true);
    let m = s.gltf.material(mirror());
    let mesh = s.gltf.mesh(&quad(0.05), Some(m), true);
    let tilt = -60f32.to_radians();
    let centre = [-0.2, 0.15, 0.0];
    s.gltf.node(json!({"name": "mirror", "mesh": mesh, "translation": centre, "rotation": quat([0.0, 0.0, 1.0], tilt),
        "extras": {"real": false}}));
    let r = s.render();
    let normal = Vec3::new(-tilt.sin(), tilt.cos(), 0.0);
    let clip_from_world = FrameUniforms::new(&r.session, &r.session.view_at(0), 0, 1).clip_from_world;
    let composite = r.renderer.read_composite(&r.ctx).unwrap().image;
    let mut checked = 0;
    // Mirror pixels: around the mirror's centre in the image.
    for y in SIZE / 2 - 2..SIZE / 2 + 3 {
        for x in 0..SIZE {
            // The camera ray meets the mirror's plane…
            let eye = Vec3::new(0.0, 1.0, 0.0);
            let on_floor = r.world_on_plane(x, y, 0.0);
            let d = (on_floor - eye).normalize();
            let t = (Vec3::from(centre) - eye).dot(normal) / d.dot(normal);
            let p = eye + d * t;
            if (p - Vec3::from(centre)).length() > 0.03 {
                continue; // not well inside the 10 cm mirror
            }
            // …and its reflection meets the floor where the photo is looked up.
            let reflected = d - 2.0 * d.dot(normal) * normal;
            let hit = p + reflected * (-p.y / reflected.y);
            let got = composite.get(x, y);
            // The mirror's weight (split-sum albedo ≈ 1) is the same in every channel.
            let (q, best, k) = photo_pixel_match(got, clip_from_world.project_point3(hit), SIZE);
            assert!(
                best < 0.02,
                "{intersection}: pixel ({x}, {y}): composite {got:?} is not photo pixel {q:?} scaled (spread {best})"
            );
            assert!((0.8..=1.05).contains(&k), "{intersection}: pixel ({x}, {y}): mirror weight {k}");
            checked += 1;
        }
    }
    assert!(checked >= 5, "{intersection}: only {checked} mirror pixels checked");
}

#[test]
fn a_virtual_glass_slab_shifts_the_photo_by_the_analytic_amount() {
    for (refraction, intersection) in
        [("traced", "impostor"), ("two-interfaces", "impostor"), ("traced", "cube"), ("traced", "layered-cube")]
    {
        slab_shift(refraction, intersection);
    }
}

fn slab_shift(refraction: &str, intersection: &str) {
    const SIZE: u32 = 48;
    // A 30 cm glass slab (ior 1.5, no absorption) 5 cm above a real floor, seen from straight
    // above: a view ray at angle θ leaves the slab parallel to itself, shifted sideways by
    // d·sin θ·(1 − cos θ / √(n² − sin² θ)), and meets the floor there. No probe and no lights:
    // only the refracted photo is left on the slab's pixels.
    let (ior, thickness, centre_y) = (1.5f32, 0.3f32, 0.2f32);
    let mut s = Setup::top_down(SIZE);
    s.photo = Box::new(textured);
    // One frame (`direct`): internal reflections dropped, so that every ray leaves through the
    // bottom face (sampled, a few would leave through the top in any one frame).
    s.extra_toml += &format!(
        "[specular]\nrefraction = \"{refraction}\"\ninternal_reflections = \"dropped\"\nintersection = \"{intersection}\"\n"
    );
    s.plane(2.0, 0.0, 0.5, true);
    let m = s
        .gltf
        .material(json!({"name": "glass", "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.0},
        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": ior}}}));
    let mesh = s.gltf.mesh(&cuboid([0.5, thickness / 2.0, 0.5]), Some(m), true);
    s.gltf.node(json!({"name": "slab", "mesh": mesh, "translation": [0.0, centre_y, 0.0], "extras": {"real": false}}));
    let r = s.render();
    let clip_from_world = FrameUniforms::new(&r.session, &r.session.view_at(0), 0, 1).clip_from_world;
    let composite = r.renderer.read_composite(&r.ctx).unwrap().image;
    let eye = Vec3::new(0.0, 1.0, 0.0);
    let mut shifted = 0;
    for (x, y) in [(6, 24), (10, 10), (24, 40), (40, 30), (36, 8), (24, 24)] {
        let d = (r.world_on_plane(x, y, 0.0) - eye).normalize();
        let top = eye + d * ((centre_y + thickness / 2.0 - eye.y) / d.y);
        let sin_t = (1.0 - d.y * d.y).sqrt();
        let cos_t = -d.y;
        let shift = thickness * sin_t * (1.0 - cos_t / (ior * ior - sin_t * sin_t).sqrt());
        let straight = eye + d * (-eye.y / d.y);
        let toward_axis = Vec3::new(-d.x, 0.0, -d.z).normalize_or_zero();
        let hit = straight + toward_axis * shift;
        assert!(top.x.abs() < 0.5 && top.z.abs() < 0.5, "pixel ({x}, {y}) sees the slab");
        let got = composite.get(x, y);
        let (q, best, k) = photo_pixel_match(got, clip_from_world.project_point3(hit), SIZE);
        assert!(
            best < 0.02,
            "{refraction}, {intersection}: pixel ({x}, {y}): composite {got:?} is not photo pixel {q:?} (spread {best})"
        );
        // Two interfaces of (1 − F) each at these angles: 0.85–0.93 of the photo.
        assert!((0.8..=0.95).contains(&k), "{refraction}, {intersection}: pixel ({x}, {y}): slab transmittance {k}");
        // The floor seen by one pixel: 2·tan(0.5 rad) m over SIZE pixels.
        if shift / (2.0 * 0.5f32.tan() / SIZE as f32) > 1.0 {
            shifted += 1;
        }
    }
    assert!(shifted >= 3, "the shift is large enough to tell apart at {shifted} of the pixels");
}

/// A right glass prism along z (`half` deep): its cross-section has the top face at height
/// `top` from x = −w to w, a vertical face at x = w down to `top − 2w`, and the hypotenuse
/// between them, at 45°. Flat-shaded, faces wound outward.
fn prism(w: f32, top: f32, half: f32) -> mrshade_testkit::gltf::Shape {
    let (a, b, c) = ([-w, top], [w, top], [w, top - 2.0 * w]);
    let v = |p: [f32; 2], z: f32| Vec3::new(p[0], p[1], z);
    let faces: [(Vec<Vec3>, Vec3); 5] = [
        (vec![v(a, -half), v(b, -half), v(b, half), v(a, half)], Vec3::Y),
        (vec![v(b, -half), v(c, -half), v(c, half), v(b, half)], Vec3::X),
        (vec![v(a, -half), v(a, half), v(c, half), v(c, -half)], Vec3::new(-1.0, -1.0, 0.0).normalize()),
        (vec![v(a, -half), v(b, -half), v(c, -half)], Vec3::NEG_Z),
        (vec![v(a, half), v(b, half), v(c, half)], Vec3::Z),
    ];
    let mut s = mrshade_testkit::gltf::Shape::default();
    for (corners, normal) in faces {
        let first = s.positions.len() as u32;
        for p in &corners {
            s.positions.push(p.to_array());
            s.normals.push(normal.to_array());
            s.uvs.push([0.0, 0.0]);
        }
        for k in 1..corners.len() as u32 - 1 {
            let (i, j) = (first + k, first + k + 1);
            let outward =
                (corners[k as usize] - corners[0]).cross(corners[k as usize + 1] - corners[0]).dot(normal) > 0.0;
            s.indices.extend(if outward { [first, i, j] } else { [first, j, i] });
        }
    }
    s
}

#[test]
fn total_internal_reflection_is_followed_or_takes_the_fallback() {
    // Seen from straight above, a view ray enters the prism's top face, meets the hypotenuse at
    // 45° (beyond the critical angle of n = 1.5, 41.8°) and is totally reflected toward +x;
    // traced, it leaves the vertical face along +x and the scene with it. Wyman's two
    // interfaces neglect total internal reflection (spec §2.12, [T]): the fallback leaves
    // along the hypotenuse, (1, −1, 0)/√2, and meets the floor at x = top − w.
    const SIZE: u32 = 32;
    let (w, top) = (0.1f32, 0.3f32);
    for refraction in ["traced", "two-interfaces"] {
        let mut s = Setup::top_down(SIZE);
        s.extra_toml += &format!("[specular]\nrefraction = \"{refraction}\"\ninternal_reflections = \"dropped\"\n");
        s.plane(2.0, 0.0, 0.5, true);
        let m = s.gltf.material(json!({"name": "glass", "pbrMetallicRoughness": {"metallicFactor": 0.0,
            "roughnessFactor": 0.0}, "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
            "KHR_materials_ior": {"ior": 1.5}}}));
        let mesh = s.gltf.mesh(&prism(w, top, 0.1), Some(m), true);
        s.gltf.node(json!({"name": "prism", "mesh": mesh, "extras": {"real": false}}));
        let r = s.render();
        let aovs = r.renderer.read_aovs(&r.ctx).unwrap();
        let hit = aovs.iter().find(|a| a.name == "refraction_hit").expect("refraction_hit AOV");
        let mrshade_render::outputs::AovImage::Linear(image) = &hit.image else { panic!("linear AOV") };
        let (x, y) = (SIZE / 2, SIZE / 2);
        let got = Vec3::from(image.get(x, y));
        let entry = r.world_on_plane(x, y, top);
        if refraction == "traced" {
            assert!((got - Vec3::X).length() < 0.05, "traced: the ray leaves along +x, not {got}");
        } else {
            // From the entry, straight down to the hypotenuse (y = top − (x + w)), then along
            // (1, −1, 0) to the floor.
            let on_hypotenuse = Vec3::new(entry.x, top - (entry.x + w), entry.z);
            let floor = on_hypotenuse + Vec3::new(on_hypotenuse.y, -on_hypotenuse.y, 0.0);
            assert!((got - floor).length() < 0.02, "two interfaces: the fallback lands at {floor}, not {got}");
        }
    }
}

/// A virtual metal quad of `roughness` tilted 60° above a real textured floor, seen from
/// above, with the specular light smoothed at `temporal_weight`; no frames rendered yet.
fn tilted_metal(roughness: f32, temporal_weight: f32) -> common::Rendered {
    const SIZE: u32 = 48;
    let mut s = Setup::top_down(SIZE);
    s.photo = Box::new(textured);
    s.probe = Some([0.5, 0.5, 0.5]);
    s.extra_toml += &format!("[output]\nframes = 1\n[specular]\ntemporal_weight = {temporal_weight}\n");
    s.plane(2.0, 0.0, 0.5, true);
    let m = s.gltf.material(json!({"name": "metal",
        "pbrMetallicRoughness": {"metallicFactor": 1.0, "roughnessFactor": roughness}}));
    let mesh = s.gltf.mesh(&quad(0.15), Some(m), true);
    s.gltf.node(json!({"name": "metal", "mesh": mesh, "translation": [-0.2, 0.15, 0.0],
        "rotation": quat([0.0, 0.0, 1.0], -60f32.to_radians()), "extras": {"real": false}}));
    s.render()
}

/// One frame with `photo` uploaded (a live stream's frame: everything counts as changed).
fn stream_frame(r: &mut common::Rendered, photo: &dyn Fn(u32, u32) -> [u8; 3]) -> Vec<f32> {
    r.render_with_photo(photo);
    r.renderer.read_composite(&r.ctx).unwrap().image.pixels.iter().map(|p| p[0] + p[1] + p[2]).collect()
}

/// Temporal smoothing of the specular light (spec §2.19, the filter ours): in a live stream a
/// glossy metal's one ray per pixel and frame flickers less with the default weight than
/// without, and a new photo shows in a smooth mirror at once (the history is clamped to the
/// new frame's values around each pixel), not after many frames.
#[test]
fn the_specular_light_is_smoothed_in_a_stream_and_a_new_photo_shows_at_once() {
    let flicker = |weight: f32| {
        let mut r = tilted_metal(0.3, weight);
        let frames: Vec<Vec<f32>> = (0..10).map(|_| stream_frame(&mut r, &textured)).collect();
        let change: f32 =
            frames[4..].windows(2).map(|f| f[0].iter().zip(&f[1]).map(|(a, b)| (a - b).abs()).sum::<f32>()).sum();
        change / 5.0
    };
    let (rough, smooth) = (flicker(0.0), flicker(0.8));
    assert!(rough > 0.0, "a glossy reflection changes from frame to frame without smoothing");
    assert!(smooth < 0.4 * rough, "smoothed flicker {smooth} is not well below {rough}");

    let inverted = |x: u32, y: u32| [(235 - x * 4) as u8, (235 - y * 4) as u8, 60];
    let switch = |weight: f32| {
        let mut r = tilted_metal(0.0, weight);
        for _ in 0..6 {
            stream_frame(&mut r, &textured);
        }
        stream_frame(&mut r, &inverted)
    };
    let (plain, smoothed) = (switch(0.0), switch(0.8));
    let before = {
        let mut r = tilted_metal(0.0, 0.0);
        stream_frame(&mut r, &textured)
    };
    // Where the mirror's reflection changed with the photo, the smoothed frame is the new one:
    // without the clip it would trail by the history's weight (80 % of the change).
    let (mut trail, mut change, mut checked) = (0.0, 0.0, 0);
    for ((&p, &s), &b) in plain.iter().zip(&smoothed).zip(&before) {
        if (p - b).abs() > 0.3 * p.max(b) {
            checked += 1;
            trail += (s - p).abs();
            change += (b - p).abs();
        }
    }
    assert!(checked >= 100, "only {checked} pixels changed with the photo");
    assert!(
        trail <= 0.1 * change,
        "the smoothed frame keeps {:.1} % of the old photo's reflection",
        100.0 * trail / change
    );
}
