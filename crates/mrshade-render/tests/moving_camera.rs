//! Temporal reuse under a moving camera (Knecht §2.10 assumes a tracked camera): the history
//! is reprojected through the camera's motion, newly seen surfaces do not inherit what was in
//! front of them (no ghosting), and a static scene seen while the camera moves converges to
//! the still of the final pose.

mod common;

use common::{Rendered, Setup};
use glam::{Mat4, Vec3};
use mrshade_core::camera::CameraView;
use mrshade_render::FrameInputs;
use mrshade_render::methods::dir::DirMethod;
use serde_json::json;

const SIZE: u32 = 64;

/// A real floor and box, a tall virtual box standing on the floor, a real spot and a probe
/// with a sun (whose shadows come from the environment VPLs' ISMs and so pass through the
/// temporal reuse); the `dir` method with the temporal `extra` settings.
fn scene(extra: &str) -> Setup {
    let mut s = Setup::top_down(SIZE);
    s.photo = Box::new(|x, y| [(100 + x % 7 * 3) as u8, (90 + y % 5 * 4) as u8, 80]);
    s.probe = Some([0.3, 0.3, 0.3]);
    s.sun = Some([150.0, 140.0, 120.0]);
    s.top_toml = "method = \"dir\"\n".into();
    s.extra_toml = format!("[output]\nframes = 1\n[shadows]\nresolution = 512\n{extra}");
    s.plane(2.0, 0.0, 0.5, true).cube([-0.25, 0.06, 0.2], 0.06, true).cube([0.0, 0.15, 0.0], 0.15, false);
    s.light(
        json!({"type": "spot", "intensity": 1.5, "spot": {"innerConeAngle": 0.6, "outerConeAngle": 0.9}}),
        [0.1, 0.9, 0.1],
        true,
    );
    s
}

/// `camera` moved sideways by `dx` metres.
fn shifted(camera: CameraView, dx: f32) -> CameraView {
    CameraView {
        world_from_camera: Mat4::from_translation(Vec3::new(dx, 0.0, 0.0)) * camera.world_from_camera,
        ..camera
    }
}

fn render(r: &mut Rendered, camera: CameraView, frames: u32) {
    let mut profiler = mrshade_gpu::timing::profiler(&r.ctx, false).unwrap();
    for _ in 0..frames {
        r.renderer.render_untimed(&r.ctx, &mut profiler, &FrameInputs::camera(camera)).unwrap();
    }
}

fn srgb(r: &Rendered) -> Vec<u8> {
    r.renderer.read_composite(&r.ctx).unwrap().image.to_srgb8()
}

/// The camera slides 0.3 m over 12 frames and then holds for 36: the frame equals (mean FLIP)
/// the 48th frame of a camera that never moved.
#[test]
fn a_moving_camera_converges_to_the_still_of_its_final_pose() {
    let (_dir, session) = scene("").session();
    let mut moving = Rendered::new(session.clone());
    let end = moving.renderer.session_camera();
    for i in 0..12 {
        render(&mut moving, shifted(end, 0.3 * (1.0 - i as f32 / 11.0)), 1);
    }
    render(&mut moving, end, 35);
    let mut still = Rendered::new(session);
    render(&mut still, end, 47);
    let flip = mrshade_testkit::flip::mean(&srgb(&still), &srgb(&moving), SIZE, SIZE);
    eprintln!("moved then held vs still: mean FLIP {flip:.4}");
    assert!(flip < 0.01, "mean FLIP {flip} between the moved camera's frame and the still's");
}

/// A camera low over the floor looking at the virtual box, which hides much floor behind it.
fn low_camera() -> CameraView {
    let eye = Vec3::new(0.0, 0.3, 0.9);
    CameraView {
        world_from_camera: glam::camera::rh::view::look_to_mat4(eye, Vec3::new(0.0, 0.1, 0.0) - eye, Vec3::Y).inverse(),
        intrinsics: mrshade_core::camera::Intrinsics::from_yfov(0.9, SIZE, SIZE),
        znear: 0.01,
    }
}

/// How far the probe's visibility (the `dir` method's smoothed environment shadows, where a
/// ghost would show) of a camera that jumped sideways, so that floor hidden behind the virtual
/// box comes into view, is from that of a camera that was at the new place all along, eight
/// frames after the jump, with the temporal settings `extra`: the mean absolute difference
/// over the pixels and the rgb channels of both solutions.
fn after_a_jump(extra: &str) -> f32 {
    let (_dir, session) = scene(extra).session();
    let mut jumped = Rendered::new(session.clone());
    let end = low_camera();
    render(&mut jumped, shifted(end, -0.3), 40);
    render(&mut jumped, end, 8);
    let mut still = Rendered::new(session);
    render(&mut still, end, 47);
    let visibility = |r: &Rendered| r.renderer.method_as::<DirMethod>().unwrap().read_probe_visibility(&r.ctx).unwrap();
    let (a, b) = (visibility(&jumped), visibility(&still));
    let pairs = a.rv.iter().zip(&b.rv).chain(a.r.iter().zip(&b.r));
    let (sum, count) =
        pairs.fold((0.0, 0), |(s, n), (p, q)| (s + (0..3).map(|c| (p[c] - q[c]).abs()).sum::<f32>(), n + 3));
    sum / count as f32
}

/// No ghosting: after the jump the reprojected history is rejected where it belonged to
/// another surface. Without the position and normal tests (the same renderer with their
/// weights at 0) the cube's light and shadow smear over the newly seen floor: the test can fail.
#[test]
fn newly_seen_surfaces_do_not_inherit_the_history_in_front_of_them() {
    let tested = after_a_jump("");
    let untested = after_a_jump(
        "[dir.temporal]\nposition_weights = [0.0, 0.0, 0.0]\nnormal_weight = 0.0\nillumination_weight = 0.0\n",
    );
    eprintln!(
        "eight frames after the jump vs a still there: probe visibility off by {tested:.4} (tests off: {untested:.4})"
    );
    assert!(tested < 0.5 * untested, "with the disocclusion tests {tested}, without {untested}");
}

/// A light moved through the frame's inputs (as an animation moves it) lights and shadows as a
/// light placed there from the start: its shadow maps, RSMs and VPLs follow it.
#[test]
fn a_moved_light_equals_one_placed_there() {
    let at = |x: f32| {
        let mut s = scene("");
        s.gltf = Setup::top_down(SIZE).gltf;
        s.plane(2.0, 0.0, 0.5, true).cube([0.0, 0.06, 0.0], 0.06, false);
        s.light(json!({"type": "point", "intensity": 0.4}), [x, 0.5, 0.1], true);
        s.session()
    };
    let ((_a, from), (_b, to)) = (at(-0.3), at(0.3));
    let lights: Vec<Mat4> = to.scene.lights.iter().map(|l| l.world_from_light).collect();
    let mut moved = Rendered::new(from);
    let camera = moved.renderer.session_camera();
    let mut profiler = mrshade_gpu::timing::profiler(&moved.ctx, false).unwrap();
    let inputs = FrameInputs { lights: Some(&lights), ..FrameInputs::camera(camera) };
    moved.renderer.render_untimed(&moved.ctx, &mut profiler, &inputs).unwrap();
    render(&mut moved, camera, 29);
    let mut placed = Rendered::new(to);
    render(&mut placed, camera, 30);
    let flip = mrshade_testkit::flip::mean(&srgb(&placed), &srgb(&moved), SIZE, SIZE);
    eprintln!("moved light vs placed light: mean FLIP {flip:.4}");
    // Without moving the shadow maps with the light this is 0.0048.
    assert!(flip < 0.003, "mean FLIP {flip}");
}

/// An object moved through the frame's inputs (as an animation moves it) lights and shadows
/// as one placed there from the start, real or virtual: the shadow layers and RSMs of the
/// kind of caster that moved are drawn again, those of the other kept (`direct`, `dlpv`: no
/// temporal reuse, so the two frames must match to the bit).
#[test]
fn a_moved_object_equals_one_placed_there() {
    for method in ["direct", "dlpv"] {
        for moving_real in [false, true] {
            // The virtual surfaces' bounce reads the V_ρ of the gather before: `dlpv` without it
            // here (the next test moves an object with it).
            let (moved, placed) = object_moved(method, moving_real, "virtual_bounce = false\n", 0);
            let (a, b) = (srgb(&placed), srgb(&moved));
            let differing = a.iter().zip(&b).filter(|(p, q)| p != q).count();
            assert_eq!(
                differing,
                0,
                "{method}, moving a {} cube: {differing} bytes differ",
                ["virtual", "real"][moving_real as usize]
            );
        }
    }
}

/// Two cubes on a floor under a probe and a spot (a `method` session with `dlpv` settings
/// `dlpv`), the real or the virtual one moved from x = −0.3 to 0.2 after a frame and then
/// `rest` frames more; and the same scene with it placed at 0.2, after three frames.
fn object_moved(method: &str, moving_real: bool, dlpv: &str, rest: u32) -> (Rendered, Rendered) {
    let at = |x: f32| {
        let mut s = Setup::top_down(SIZE);
        s.probe = Some([0.3, 0.3, 0.3]);
        s.top_toml = format!("method = \"{method}\"\n");
        s.extra_toml = format!("[shadows]\nresolution = 256\n[dlpv]\nresolution = 16\nrsm_resolution = 64\n{dlpv}");
        s.plane(2.0, 0.0, 0.5, true);
        s.cube([x, 0.08, 0.0], 0.08, moving_real).cube([0.0, 0.1, 0.3], 0.1, !moving_real);
        s.light(
            json!({"type": "spot", "intensity": 1.5, "spot": {"innerConeAngle": 0.6, "outerConeAngle": 0.9}}),
            [0.1, 0.9, 0.1],
            true,
        );
        s.session()
    };
    let ((_a, from), (_b, to)) = (at(-0.3), at(0.2));
    let instances: Vec<Mat4> = to.scene.instances.iter().map(|i| i.world_from_object).collect();
    let mut moved = Rendered::new(from);
    let camera = moved.renderer.session_camera();
    render(&mut moved, camera, 1);
    let mut profiler = mrshade_gpu::timing::profiler(&moved.ctx, false).unwrap();
    let inputs = FrameInputs { instances: Some(&instances), ..FrameInputs::camera(camera) };
    moved.renderer.render_untimed(&moved.ctx, &mut profiler, &inputs).unwrap();
    render(&mut moved, camera, rest);
    let mut placed = Rendered::new(to);
    render(&mut placed, camera, 2);
    (moved, placed)
}

#[test]
fn dlpv_gathers_the_virtual_surfaces_bounce_while_the_content_rests() {
    // `dlpv.virtual_bounce` leaves the frames in which an object moves without the virtual
    // surfaces' bounce (`virtual_bounce_moving` off): such a frame is, to the byte, the frame
    // without the option; two frames after the object came to rest the bounce is back, within
    // a level of one placed there from the start (the surfaces' light, which reads the gather
    // before, converges).
    let frame = |dlpv: &str, rest: u32| object_moved("dlpv", false, dlpv, rest);
    let (moving, _) = frame("", 0);
    let (without, _) = frame("virtual_bounce = false\n", 0);
    assert!(srgb(&moving) == srgb(&without), "a frame of a moving object gathered the virtual surfaces' bounce");
    let (rested, placed) = frame("", 2);
    let (a, b, c) = (srgb(&rested), srgb(&placed), srgb(&without));
    let differing = |x: &[u8], y: &[u8]| x.iter().zip(y).filter(|(p, q)| p != q).count();
    let most = a.iter().zip(&b).map(|(p, q)| p.abs_diff(*q)).max().unwrap_or(0);
    eprintln!(
        "at rest: {} bytes differ from the frame without the bounce, {} from the object placed there (at most {most})",
        differing(&a, &c),
        differing(&a, &b)
    );
    assert!(differing(&a, &c) > 0, "the bounce did not come back at rest");
    assert!(most <= 1, "at rest {most} levels from the object placed there");
}
