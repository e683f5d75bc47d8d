//! Known answers of the `dir` method's passes on lavapipe.

mod common;

use common::{Rendered, Setup};
use glam::Vec3;
use mrshade_render::methods::dir::DirMethod;
use serde_json::json;

/// A virtual sphere (radius `r`, centre height `h`) over a real plane, under a probe that is
/// `plus_x` toward +x and white elsewhere.
fn floating_sphere(r: f32, h: f32, plus_x: [f32; 3], extra: &str) -> Rendered {
    let mut s = Setup::top_down(32);
    s.probe = Some([1.0, 1.0, 1.0]);
    s.probe_plus_x = Some(plus_x);
    s.top_toml = "method = \"dir\"\n".into();
    s.extra_toml = format!("[output]\nframes = 16\n{}{extra}", s.extra_toml);
    s.plane(2.0, 0.0, 0.5, true);
    let sphere = mrshade_testkit::gltf::sphere(r, 48);
    let m = s.gltf.material(mrshade_testkit::gltf::lambert("ball", [0.5; 3]));
    let mesh = s.gltf.mesh(&sphere, Some(m), true);
    s.gltf.node(json!({"name": "ball", "mesh": mesh, "translation": [0.15, h, 0.0], "extras": {"real": false}}));
    let (_dir, session) = s.session();
    Rendered::new(session)
}

#[test]
fn environment_shadow_of_a_floating_sphere_matches_its_form_factor() {
    check_sphere_shadow(0.08, 0.25, [1.0; 3]);
}

#[test]
fn environment_shadow_of_a_resting_sphere_matches_its_form_factor() {
    check_sphere_shadow(0.08, 0.08, [1.0; 3]);
}

/// Under a probe whose half toward +x is red (and white elsewhere), a sphere on the +x side of
/// a point hides only red light from it: the point's shadow is cyan, with a red ratio of
/// 1 − FF and green and blue ratios of 1. One luminance-weighted ratio for all channels would
/// make the shadow gray.
#[test]
fn environment_shadow_has_the_color_of_the_light_it_blocks() {
    check_sphere_shadow(0.08, 0.08, [1.0, 0.0, 0.0]);
}

fn check_sphere_shadow(radius: f32, height: f32, plus_x: [f32; 3]) {
    let centre = Vec3::new(0.15, height, 0.0);
    // Interleaving off: at 32×32 pixels a 4×4 block spans 14 cm of the plane, and its
    // merge would blur the contact shadow being checked.
    let r = floating_sphere(radius, height, plus_x, "[dir]\ninterleave = 1\n");
    let vis = r.renderer.method_as::<DirMethod>().expect("dir method").read_probe_visibility(&r.ctx).unwrap();
    // The share of each channel's irradiance that comes from the +x half.
    let half_share = plus_x.map(|c| c / (c + 1.0));
    let uniform = plus_x == [1.0; 3];
    let mut worst = 0.0f32;
    let mut checked = 0;
    let mut bias = 0.0f32;
    for y in 0..32 {
        for x in 0..32 {
            let p = r.world_on_plane(x, y, 0.0);
            // Skip pixels where the camera sees the sphere.
            if common::segment_hits_box(Vec3::new(0.0, 1.0, 0.0), p, centre, radius * 1.05) {
                continue;
            }
            // With a colored half, only points that see the whole sphere in the +x half.
            if !uniform && p.x > centre.x - radius - 0.02 {
                continue;
            }
            let to = centre - p;
            let d = to.length();
            // Point-to-sphere form factor: cos β (r/d)² (the sphere is above the horizon).
            let form_factor = (to.y / d) * (radius / d).powi(2);
            let i = (y * 32 + x) as usize;
            for (c, share) in half_share.iter().enumerate() {
                // The share of channel c's light that the sphere's directions carry, relative to
                // a uniform probe: 2 · half_share (1 for a uniform probe).
                let expected = 1.0 - form_factor * 2.0 * share;
                let got = vis.rv[i][c];
                assert!((vis.r[i][c] - 1.0).abs() < 0.05, "open plane: ratio_r {:?}", vis.r[i]);
                if (got - expected).abs() > worst {
                    eprintln!("({x},{y}) channel {c} p={p} expected {expected:.3} got {got:.3}");
                }
                worst = worst.max((got - expected).abs());
                bias += got - expected;
                checked += 1;
            }
        }
    }
    eprintln!("worst |ratio_rv − exact| = {worst:.3}, mean error {:.4}, over {checked} values", bias / checked as f32);
    assert!(checked >= 30, "only {checked} values checked");
    assert!(worst < 0.06, "worst error {worst}");
}

/// A virtual chrome ball (F0 = 0.9) resting on a real plane (albedo ρ = 0.5) under a white
/// probe hides the same sky as a black ball, but shows the plane, where it hides the sky, half
/// of the plane's surroundings mirrored (vpl_light.wgsl): with every other path off (no bounce
/// VPLs, no near field, no photons), L_rv(chrome) − L_rv(black) = ρ · F0 · ½ · FF · L_rv(chrome),
/// FF the point-to-sphere form factor. Without the term the two balls' shadows are the same.
#[test]
fn a_virtual_mirror_shows_the_plane_its_surroundings_where_it_hides_the_sky() {
    let (radius, height, rho, f0) = (0.08f32, 0.08f32, 0.5f32, 0.9f32);
    let render = |chrome: bool| {
        let mut s = Setup::top_down(32);
        s.probe = Some([1.0, 1.0, 1.0]);
        s.top_toml = "method = \"dir\"\n".into();
        s.extra_toml = format!(
            "[output]\nframes = 24\n{}[dir]\ninterleave = 1\nnear_field_samples = 0\nbounce = \"off\"\n\
             distribution = \"weighted\"\nweights = {{ environment_bounce = 0.0 }}\n[caustics]\nenabled = false\n",
            s.extra_toml
        );
        s.plane(2.0, 0.0, rho, true);
        let sphere = mrshade_testkit::gltf::sphere(radius, 48);
        let material = if chrome {
            json!({"name": "chrome", "pbrMetallicRoughness": {"baseColorFactor": [f0, f0, f0, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.0}})
        } else {
            mrshade_testkit::gltf::lambert("black", [0.0; 3])
        };
        let m = s.gltf.material(material);
        let mesh = s.gltf.mesh(&sphere, Some(m), true);
        s.gltf
            .node(json!({"name": "ball", "mesh": mesh, "translation": [0.15, height, 0.0], "extras": {"real": false}}));
        let (_dir, session) = s.session();
        Rendered::new(session)
    };
    let (chrome, black) = (render(true), render(false));
    let centre = Vec3::new(0.15, height, 0.0);
    let (mut checked, mut worst, mut largest) = (0, 0.0f32, 0.0f32);
    for y in 0..32 {
        for x in 0..32 {
            let p = chrome.world_on_plane(x, y, 0.0);
            if common::segment_hits_box(Vec3::new(0.0, 1.0, 0.0), p, centre, radius * 1.05) {
                continue;
            }
            let to = centre - p;
            let d = to.length();
            let form_factor = (to.y / d) * (radius / d).powi(2);
            if form_factor < 0.05 {
                continue;
            }
            let (lit, dark) = (chrome.l_rv(x, y), black.l_rv(x, y));
            let got = (lit.y - dark.y) / lit.y;
            let expected = rho * f0 * 0.5 * form_factor;
            eprintln!("({x},{y}) FF {form_factor:.3}: expected {expected:.4} got {got:.4}");
            worst = worst.max((got - expected).abs());
            largest = largest.max(expected);
            checked += 1;
        }
    }
    eprintln!("worst error {worst:.4} over {checked} points, largest expected {largest:.3}");
    assert!(checked >= 8 && largest > 0.03, "only {checked} points, largest expected {largest}");
    assert!(worst < 0.25 * largest, "worst error {worst} against a largest effect of {largest}");
}

/// One bounce from a spot light: a floor lit from straight above reflects onto a wall.
/// The wall's indirect radiance is ρ_w/π ∫ L_floor cos θ_w cos θ_f / r² dA over the lit floor,
/// with L_floor = ρ_f/π · I cos³θ / h² (inverse square and cosine).
#[test]
fn one_bounce_from_a_spot_matches_the_integral() {
    let (h, intensity, rho_f, rho_w, wall_x) = (0.6f32, 1.0f32, 0.8f32, 0.5f32, 0.25f32);
    let mut s = Setup::top_down(32);
    s.gltf = mrshade_testkit::gltf::GltfBuilder::new();
    // Camera looking at the wall from −x, slightly above the floor.
    s.gltf.camera_node(
        "camera",
        0.9,
        None,
        [-0.3, 0.2, 0.0],
        mrshade_testkit::gltf::quat([0.0, 1.0, 0.0], -std::f32::consts::FRAC_PI_2),
    );
    s.top_toml = "method = \"dir\"\n".into();
    s.extra_toml =
        "[output]\nframes = 24\n[dir]\nbounce = \"off\"\nclamp_distance = 0.005\n[shadows]\nresolution = 512\n".into();
    s.plane(1.5, 0.0, rho_f, true);
    let wall = s.gltf.material(mrshade_testkit::gltf::lambert("wall", [rho_w; 3]));
    let quad = mrshade_testkit::gltf::quad(0.3);
    let mesh = s.gltf.mesh(&quad, Some(wall), true);
    // Quad in XZ facing +Y, turned to face −X, standing at x = wall_x.
    let rot = mrshade_testkit::gltf::quat([0.0, 0.0, 1.0], std::f32::consts::FRAC_PI_2);
    s.gltf.node(json!({"name": "wall", "mesh": mesh, "translation": [wall_x, 0.3, 0.0], "rotation": rot, "extras": {"real": true}}));
    s.light(
        json!({"type": "spot", "intensity": intensity, "spot": {"innerConeAngle": 1.2, "outerConeAngle": 1.3}}),
        [0.0, h, 0.0],
        true,
    );
    let (_dir, session) = s.session();
    let r = Rendered::new(session);
    let indirect = r.renderer.method_as::<DirMethod>().expect("dir method").read_indirect(&r.ctx).unwrap();
    // CPU integral over the floor in front of the wall.
    let wall_radiance = |q: Vec3| {
        let n = 300;
        let (lo, hi) = (-1.5f32, wall_x);
        let step_x = (hi - lo) / n as f32;
        let step_z = 3.0 / n as f32;
        let mut sum = 0.0f64;
        for i in 0..n {
            for k in 0..n {
                let x = Vec3::new(lo + (i as f32 + 0.5) * step_x, 0.0, -1.5 + (k as f32 + 0.5) * step_z);
                let to_light = Vec3::new(0.0, h, 0.0) - x;
                let cos_l = (to_light.y / to_light.length()).max(0.0);
                // Inside the spot's full-intensity cone (1.2 rad) everywhere on this floor.
                let e = intensity * cos_l / to_light.length_squared();
                let l_floor = rho_f / std::f32::consts::PI * e;
                let d = q - x;
                let cos_f = (d.y / d.length()).max(0.0);
                let cos_w = (d.x / d.length()).max(0.0);
                sum += (l_floor * cos_f * cos_w / d.length_squared() * step_x * step_z) as f64;
            }
        }
        rho_w / std::f32::consts::PI * sum as f32
    };
    let mut checked = 0;
    for (x, y) in [(16, 10), (12, 14), (20, 18), (16, 22)] {
        let got = indirect.rv.get(x, y)[0];
        // The wall point under this pixel.
        let q = r.world_on_plane_x(x, y, wall_x);
        let expected = wall_radiance(q);
        eprintln!("pixel ({x},{y}) q={q} indirect {got:.4} expected {expected:.4}");
        assert!((got / expected - 1.0).abs() < 0.15, "({x},{y}): {got} vs {expected}");
        assert_eq!(indirect.r.get(x, y), indirect.rv.get(x, y), "all real: both buffers agree");
        checked += 1;
    }
    assert_eq!(checked, 4);
}

/// A wall standing on a floor under a sky that is black below the horizon: nothing blocks any
/// sky light the wall receives, so its probe visibility is 1 (no self-shadowing by the floor's
/// splats or its own).
#[test]
fn a_wall_on_a_floor_sees_all_of_the_sky() {
    let mut s = Setup::top_down(32);
    s.gltf = mrshade_testkit::gltf::GltfBuilder::new();
    s.gltf.camera_node(
        "camera",
        0.9,
        None,
        [-0.3, 0.15, 0.0],
        mrshade_testkit::gltf::quat([0.0, 1.0, 0.0], -std::f32::consts::FRAC_PI_2),
    );
    s.top_toml = "method = \"dir\"\n".into();
    s.extra_toml = "[output]\nframes = 16\n[shadows]\nresolution = 512\n".into();
    s.sky_only = true;
    s.probe = Some([1.0; 3]);
    s.plane(1.0, 0.0, 0.5, true);
    let wall = s.gltf.material(mrshade_testkit::gltf::lambert("wall", [0.5; 3]));
    let mesh = s.gltf.mesh(&mrshade_testkit::gltf::quad(0.3), Some(wall), true);
    let rot = mrshade_testkit::gltf::quat([0.0, 0.0, 1.0], std::f32::consts::FRAC_PI_2);
    s.gltf.node(json!({"name": "wall", "mesh": mesh, "translation": [0.2, 0.3, 0.0], "rotation": rot, "extras": {"real": true}}));
    let (_dir, session) = s.session();
    let r = Rendered::new(session);
    let vis = r.renderer.method_as::<DirMethod>().expect("dir method").read_probe_visibility(&r.ctx).unwrap();
    let mut worst = 1.0f32;
    for y in 0..32 {
        for x in 8..24 {
            let q = r.world_on_plane_x(x, y, 0.2);
            if q.y > 0.005 && q.y < 0.55 && q.z.abs() < 0.25 {
                let v = vis.r[(y * 32 + x) as usize][1];
                if v < worst {
                    eprintln!("({x},{y}) height {:.3}: ratio_r {v:.3}", q.y);
                }
                worst = worst.min(v);
            }
        }
    }
    assert!(worst > 0.9, "the wall loses {:.0} % of its sky", 100.0 * (1.0 - worst));
}
