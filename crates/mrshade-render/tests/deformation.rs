//! Skinned and morphing inserts on the GPU: the deformation pass against the CPU's known
//! answer (`mrshade_scene::deform_vertices`, itself tested against hand math), and the
//! shadow of a bending skinned strip on a real floor moving with it.

mod common;

use common::Setup;
use glam::{Quat, Vec2, Vec3};
use mrshade_core::HdrImage;
use mrshade_render::methods::dir::{DirMethod, GpuPoint};
use mrshade_render::{FrameInputs, Renderer};
use mrshade_scene::{Session, deform_vertices};
use mrshade_testkit::deform::{morph_box, simple_skin};
use mrshade_testkit::gltf::GltfBuilder;
use serde_json::json;

/// A real floor under a real spot (low, to +x), a skinned strip lying 0.1 m above it (its tip swings
/// toward −x as it bends) and a small morphing box.
fn setup() -> Setup {
    let mut s = Setup::top_down(64);
    s.plane(1.0, 0.0, 0.5, true);
    // Low and off to +x, so that the top-down camera sees the shadow beside the strip.
    let spot = s.gltf.light(json!({"type": "spot", "intensity": 4.0, "spot": {"outerConeAngle": 0.9}}));
    let toward = Quat::from_rotation_arc(Vec3::NEG_Z, Vec3::new(-1.7, -1.0, 0.0).normalize());
    s.gltf.node(json!({"name": "spot", "translation": [1.5, 1.0, 0.0], "rotation": toward.to_array(),
        "extensions": {"KHR_lights_punctual": {"light": spot}}, "extras": {"real": true}}));
    let mut strip = GltfBuilder::new();
    simple_skin(&mut strip, std::f32::consts::FRAC_PI_2, [0.0; 3], [0.0, 0.0, 0.0, 1.0]);
    let mut cube = GltfBuilder::new();
    morph_box(&mut cube, [0.0; 3]);
    s.models = vec![("strip".into(), strip), ("cube".into(), cube)];
    s.extra_toml += "[[insert]]\nmodel = \"strip.gltf\"\ntranslation = [-0.1, 0.1, 0.25]\nrotation_deg = [-90, 0, 0]\n\
                     scale = 0.25\n[[insert]]\nmodel = \"cube.gltf\"\ntranslation = [0.35, 0.05, -0.35]\nscale = 0.1\n";
    s
}

/// Renders one frame with the scene posed at `time`; returns the radiance pair's darkening.
fn render_at(ctx: &mrshade_gpu::GpuContext, renderer: &mut Renderer, session: &Session, time: f32) -> HdrImage {
    let pose = session.scene.pose_at(time).unwrap();
    let inputs = FrameInputs {
        camera: session.view_at(0),
        jitter: Vec2::ZERO,
        photo: None,
        instances: Some(&pose.instances),
        lights: Some(&pose.lights),
        deformations: Some(&pose.deformations),
    };
    let mut profiler = mrshade_gpu::timing::profiler(ctx, false).unwrap();
    renderer.render_untimed(ctx, &mut profiler, &inputs).unwrap();
    let radiance = renderer.read_radiance(ctx).unwrap();
    let pixels = radiance.rv.pixels.iter().zip(&radiance.r.pixels).map(|(a, b)| [a[0] / b[0].max(1e-6), 0.0, 0.0]);
    HdrImage { width: radiance.rv.width, height: radiance.rv.height, pixels: pixels.collect() }
}

#[test]
fn the_gpu_deforms_as_the_cpu_computes() {
    let (_dir, session) = setup().session();
    let ctx = mrshade_testkit::gpu();
    let mut renderer = Renderer::new(&ctx, &session).unwrap();
    let scene = &session.scene;
    let deformed: Vec<usize> = (0..scene.instances.len())
        .filter(|&i| scene.primitives[scene.instances[i].primitive].is_deformable())
        .collect();
    assert_eq!(deformed.len(), 2, "the strip and the box deform");
    for time in [0.0, 0.4, 1.0] {
        render_at(&ctx, &mut renderer, &session, time);
        let pose = scene.pose_at(time).unwrap();
        for &i in &deformed {
            let (positions, normals) =
                deform_vertices(&scene.primitives[scene.instances[i].primitive], &pose.deformations[i]);
            let gpu = renderer.read_instance_vertices(&ctx, i).unwrap();
            assert_eq!(gpu.len(), positions.len());
            for (v, ((p, n), (gp, gn))) in positions.iter().zip(&normals).zip(&gpu).enumerate() {
                assert!(p.abs_diff_eq(*gp, 1e-5), "t = {time}, instance {i}, vertex {v}: GPU {gp} != CPU {p}");
                assert!(n.abs_diff_eq(*gn, 1e-4), "t = {time}, instance {i}, vertex {v}: GPU normal {gn} != CPU {n}");
            }
        }
    }
}

#[test]
fn a_bending_skinned_insert_moves_its_shadow_on_the_real_floor() {
    let (_dir, session) = setup().session();
    let ctx = mrshade_testkit::gpu();
    let mut renderer = Renderer::new(&ctx, &session).unwrap();
    // Shadowed floor pixels: L_rv clearly below L_r (the strip seen directly is virtual and
    // has no L_r difference of this kind: its pixels are excluded by their flags below).
    let flags = |r: &Renderer| r.read_flags(&ctx).unwrap();
    let shadow = |ratio: &HdrImage, flags: &[u32]| -> Vec<(u32, u32)> {
        let real = mrshade_core::flags::SURFACE_REAL;
        (0..ratio.height)
            .flat_map(|y| (0..ratio.width).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let i = (y * ratio.width + x) as usize;
                flags[i] & real != 0 && ratio.pixels[i][0] < 0.6
            })
            .collect()
    };
    let straight = render_at(&ctx, &mut renderer, &session, 0.0);
    // The strip's shadow (rows below the morphing box's, whose shadow grows as it morphs).
    let strip_rows = |s: Vec<(u32, u32)>| -> Vec<(u32, u32)> { s.into_iter().filter(|&(_, y)| y >= 16).collect() };
    let straight = strip_rows(shadow(&straight, &flags(&renderer)));
    let bent = render_at(&ctx, &mut renderer, &session, 1.0);
    let bent = strip_rows(shadow(&bent, &flags(&renderer)));
    let centroid = |s: &[(u32, u32)]| {
        let sum = s.iter().fold(Vec2::ZERO, |a, &(x, y)| a + Vec2::new(x as f32, y as f32));
        sum / s.len().max(1) as f32
    };
    assert!(straight.len() > 20 && bent.len() > 20, "shadows of {} and {} pixels", straight.len(), bent.len());
    let (a, b) = (centroid(&straight), centroid(&bent));
    // The tip swings 0.25 m toward −x (≈ 15 pixels): the shadow's centroid follows.
    assert!(a.x - b.x > 4.0, "the shadow's centroid moved from {a} to {b}");
    // Where the tip's shadow was (toward −z: the top of the image), there is none now.
    let tip_before = straight.iter().filter(|&&(_, y)| y < 24).count();
    let tip_after = bent.iter().filter(|&&(x, y)| y < 24 && x > 12).count();
    assert!(tip_before > 10 && tip_after * 4 < tip_before, "tip shadow {tip_before} → {tip_after} pixels");
}

#[test]
fn ism_points_follow_a_skinned_insert() {
    let mut setup = setup();
    setup.top_toml = "method = \"dir\"\n[dir]\nvpl_count = 16\n".into();
    let (_dir, session) = setup.session();
    let ctx = mrshade_testkit::gpu();
    let mut renderer = Renderer::new(&ctx, &session).unwrap();
    render_at(&ctx, &mut renderer, &session, 1.0);
    let strip = session.scene.instances.iter().position(|i| i.skin.is_some()).unwrap();
    let pose = session.scene.pose_at(1.0).unwrap();
    let primitive = &session.scene.primitives[session.scene.instances[strip].primitive];
    let (lo, hi) = mrshade_core::math::bounding_box(&deform_vertices(primitive, &pose.deformations[strip]).0);
    let dir = renderer.method_as::<DirMethod>().unwrap();
    let bytes = mrshade_gpu::readback::read_buffer(&ctx, &dir.ism_resources.points_virtual).unwrap();
    let points: &[GpuPoint] = bytemuck::cast_slice(&bytes);
    let on_strip: Vec<Vec3> =
        points.iter().filter(|p| p.instance as usize == strip).map(|p| Vec3::from(p.position)).collect();
    assert!(on_strip.len() > 20, "{} points on the strip", on_strip.len());
    for p in &on_strip {
        assert!(p.cmpge(lo - 1e-4).all() && p.cmple(hi + 1e-4).all(), "point {p} outside the bent strip {lo}–{hi}");
    }
    // Some lie on the tip, which only the bend brings to x < −0.15.
    assert!(on_strip.iter().any(|p| p.x < -0.15), "no point followed the tip");
}
