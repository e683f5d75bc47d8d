//! glTF animations of node transforms: sampled poses against values computed by hand from
//! glTF 2.0 Appendix C, and broken animations refused with one line naming the animation,
//! the channel and the field.

mod common;

use common::{error_of, load};

use glam::{Mat4, Quat, Vec3};
use mrshade_scene::{Scene, ScenePose};
use mrshade_testkit::gltf::{GltfBuilder, quad, quat};
use serde_json::{Value, json};
use std::f32::consts::{FRAC_1_SQRT_2, FRAC_PI_2, FRAC_PI_4};

/// One sampler and the channel that uses it.
struct Track<'a> {
    node: usize,
    path: &'a str,
    interpolation: &'a str,
    times: &'a [f32],
    values: &'a [f32],
}

impl<'a> Track<'a> {
    fn new(node: usize, path: &'a str, interpolation: &'a str, times: &'a [f32], values: &'a [f32]) -> Self {
        Self { node, path, interpolation, times, values }
    }
}

/// Adds an animation named `name` of `tracks` (VEC4 outputs for rotations, VEC3 otherwise).
fn animate(b: &mut GltfBuilder, name: &str, tracks: &[Track]) {
    let (mut samplers, mut channels) = (Vec::new(), Vec::new());
    for (i, t) in tracks.iter().enumerate() {
        let input = b.accessor_f32(t.times, "SCALAR", true);
        let ty = match t.path {
            "rotation" => "VEC4",
            "weights" => "SCALAR",
            _ => "VEC3",
        };
        let output = b.accessor_f32(t.values, ty, false);
        samplers.push(json!({"input": input, "output": output, "interpolation": t.interpolation}));
        channels.push(json!({"sampler": i, "target": {"node": t.node, "path": t.path}}));
    }
    b.animation(json!({"name": name, "samplers": samplers, "channels": channels}));
}

/// A document with one quad mesh on node 0 ("box"); returns it and the mesh.
fn one_box(node: Value) -> (GltfBuilder, usize) {
    let mut b = GltfBuilder::new();
    let mesh = b.mesh(&quad(1.0), None, true);
    let mut node = node;
    node["name"] = json!("box");
    node["mesh"] = json!(mesh);
    b.node(node);
    (b, mesh)
}

fn origin(m: Mat4) -> Vec3 {
    m.transform_point3(Vec3::ZERO)
}

fn close(a: Vec3, b: Vec3) -> bool {
    a.abs_diff_eq(b, 1e-5)
}

fn pose(scene: &Scene, t: f32) -> ScenePose {
    scene.pose_at(t).unwrap()
}

#[test]
fn linear_translation_at_mid_interval_keeps_the_rest_rotation_and_scale() {
    let (mut b, _) = one_box(json!({"translation": [9.0, 9.0, 9.0], "scale": [2.0, 2.0, 2.0]}));
    animate(&mut b, "slide", &[Track::new(0, "translation", "LINEAR", &[0.0, 2.0], &[0.0, 0.0, 0.0, 4.0, 2.0, 0.0])]);
    let scene = load(&b);
    assert!(scene.is_animated());
    assert_eq!(scene.time_range(), Some((0.0, 2.0)));
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // The loaded transform is the rest pose, the node's own TRS.
    assert!(close(origin(scene.instances[0].world_from_object), Vec3::splat(9.0)));
    // t = 0.5 is a quarter of the way from (0, 0, 0) to (4, 2, 0).
    let m = pose(&scene, 0.5).instances[0];
    assert!(close(origin(m), Vec3::new(1.0, 0.5, 0.0)), "{m}");
    assert!(close(m.transform_vector3(Vec3::X), Vec3::new(2.0, 0.0, 0.0)), "{m}");
}

#[test]
fn step_holds_the_previous_key() {
    let (mut b, _) = one_box(json!({}));
    let values = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 2.0, 0.0, 0.0];
    animate(&mut b, "hop", &[Track::new(0, "translation", "STEP", &[0.0, 1.0, 2.0], &values)]);
    let scene = load(&b);
    let x = |t: f32| origin(pose(&scene, t).instances[0]).x;
    assert_eq!((x(0.999), x(1.0), x(1.5), x(2.0), x(7.0)), (0.0, 1.0, 1.0, 2.0, 2.0));
}

#[test]
fn cubic_spline_follows_the_hermite_formula() {
    let (mut b, _) = one_box(json!({}));
    // Keys at 1 s and 3 s, each [in-tangent, value, out-tangent]:
    // key 0: in (9, 0, 0), value (0, 1, 0), out (1, 0, 0); key 1: in (2, 0, 0), value (4, 1, 0), out (9, 0, 0).
    #[rustfmt::skip]
    let values = [
        9.0, 0.0, 0.0,  0.0, 1.0, 0.0,  1.0, 0.0, 0.0,
        2.0, 0.0, 0.0,  4.0, 1.0, 0.0,  9.0, 0.0, 0.0,
    ];
    animate(&mut b, "ease", &[Track::new(0, "translation", "CUBICSPLINE", &[1.0, 3.0], &values)]);
    let scene = load(&b);
    let at = |t: f32| origin(pose(&scene, t).instances[0]);
    // t = 2 s: s = 0.5, t_d = 2. Basis: 2s³−3s²+1 = 0.5, s³−2s²+s = 0.125, −2s³+3s² = 0.5, s³−s² = −0.125.
    // x = 0.5·0 + 2·0.125·1 + 0.5·4 + 2·(−0.125)·2 = 0.25 + 2 − 0.5 = 1.75; y = 0.5·1 + 0.5·1 = 1.
    assert!(close(at(2.0), Vec3::new(1.75, 1.0, 0.0)), "{}", at(2.0));
    // t = 1.5 s: s = 0.25. Basis: 0.84375, 0.140625, 0.15625, −0.046875.
    // x = 2·0.140625·1 + 0.15625·4 + 2·(−0.046875)·2 = 0.28125 + 0.625 − 0.1875 = 0.71875.
    assert!(close(at(1.5), Vec3::new(0.71875, 1.0, 0.0)), "{}", at(1.5));
    // At and beyond the keys: the values, never the tangents.
    assert!(close(at(0.0), Vec3::new(0.0, 1.0, 0.0)) && close(at(3.0), Vec3::new(4.0, 1.0, 0.0)));
    assert!(close(at(10.0), Vec3::new(4.0, 1.0, 0.0)));
}

#[test]
fn linear_rotation_is_a_slerp() {
    let (mut b, _) = one_box(json!({}));
    let values: Vec<f32> = [[0.0, 0.0, 0.0, 1.0], quat([0.0, 1.0, 0.0], FRAC_PI_2)].concat();
    animate(&mut b, "turn", &[Track::new(0, "rotation", "LINEAR", &[0.0, 1.0], &values)]);
    let scene = load(&b);
    // Halfway from 0° to 90° about +Y is 45°: +X turns to (cos 45°, 0, −sin 45°).
    let m = pose(&scene, 0.5).instances[0];
    assert!(close(m.transform_vector3(Vec3::X), Vec3::new(FRAC_1_SQRT_2, 0.0, -FRAC_1_SQRT_2)), "{m}");
    assert!(close(pose(&scene, 1.0).instances[0].transform_vector3(Vec3::X), Vec3::new(0.0, 0.0, -1.0)));
}

#[test]
fn normalized_integer_rotations_are_read() {
    let (mut b, _) = one_box(json!({}));
    let input = b.accessor_f32(&[0.0, 1.0], "SCALAR", true);
    // Identity, then 90° about +Y: (0, sin 45°, 0, cos 45°) as SHORT / 32767.
    let shorts: [i16; 8] = [0, 0, 0, 32767, 0, 23170, 0, 23170];
    let bytes: Vec<u8> = shorts.iter().flat_map(|v| v.to_le_bytes()).collect();
    let output = b.accessor_bytes(&bytes, 5122, "VEC4", 2, true);
    b.animation(json!({"samplers": [{"input": input, "output": output}],
        "channels": [{"sampler": 0, "target": {"node": 0, "path": "rotation"}}]}));
    let scene = load(&b);
    let x = pose(&scene, 1.0).instances[0].transform_vector3(Vec3::X);
    assert!(x.abs_diff_eq(Vec3::new(0.0, 0.0, -1.0), 1e-4), "{x}");
    // The same integers not normalized are refused.
    b.patch_accessor(output, |a| a["normalized"] = json!(false));
    let msg = error_of(&b);
    assert!(msg.contains("animation #0 channel 0") && msg.contains("not normalized"), "{msg}");
}

#[test]
fn scale_and_clamping_outside_the_keys() {
    let (mut b, _) = one_box(json!({}));
    animate(&mut b, "grow", &[Track::new(0, "scale", "LINEAR", &[1.0, 2.0], &[1.0, 1.0, 1.0, 3.0, 1.0, 1.0])]);
    let scene = load(&b);
    let sx = |t: f32| pose(&scene, t).instances[0].transform_vector3(Vec3::X).x;
    assert_eq!((sx(0.0), sx(1.0), sx(1.5), sx(2.0), sx(100.0)), (1.0, 1.0, 2.0, 3.0, 3.0));
}

#[test]
fn an_animated_parent_carries_its_static_child() {
    let mut b = GltfBuilder::new();
    let mesh = b.mesh(&quad(1.0), None, true);
    let parent = b.node(json!({"name": "arm", "scale": [2.0, 2.0, 2.0]}));
    let rot = quat([0.0, 0.0, 1.0], FRAC_PI_2);
    b.child(parent, json!({"name": "hand", "mesh": mesh, "translation": [0.0, 1.0, 0.0], "rotation": rot}));
    let values = [0.0, 0.0, 0.0, 10.0, 0.0, 0.0];
    animate(&mut b, "swing", &[Track::new(parent, "translation", "LINEAR", &[0.0, 1.0], &values)]);
    let scene = load(&b);
    assert_eq!(scene.nodes.len(), 2);
    assert_eq!(scene.nodes[scene.node_of.instances[0]].parent, Some(0));
    // world(t) = parent(t) · child local, with parent(0.3) = T(3, 0, 0) · S(2).
    let child = Mat4::from_rotation_translation(Quat::from_array(rot), Vec3::Y);
    let expected = Mat4::from_translation(Vec3::new(3.0, 0.0, 0.0)) * Mat4::from_scale(Vec3::splat(2.0)) * child;
    let m = pose(&scene, 0.3).instances[0];
    assert!(m.abs_diff_eq(expected, 1e-5), "{m} vs {expected}");
    assert!(close(origin(m), Vec3::new(3.0, 2.0, 0.0)));
}

#[test]
fn an_animated_camera_stays_rigid() {
    let mut b = GltfBuilder::new();
    let rig = b.node(json!({"name": "rig", "scale": [3.0, 3.0, 3.0]}));
    let cam = b.camera(json!({"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}));
    let node = b.child(rig, json!({"name": "cam", "camera": cam}));
    let turn: Vec<f32> = [[0.0, 0.0, 0.0, 1.0], quat([0.0, 1.0, 0.0], FRAC_PI_2)].concat();
    animate(
        &mut b,
        "dolly",
        &[
            Track::new(node, "translation", "LINEAR", &[0.0, 1.0], &[0.0, 0.0, 0.0, 0.0, 0.0, 2.0]),
            Track::new(node, "rotation", "LINEAR", &[0.0, 1.0], &turn),
            Track::new(node, "scale", "LINEAR", &[0.0, 1.0], &[1.0, 1.0, 1.0, 5.0, 5.0, 5.0]),
        ],
    );
    let scene = load(&b);
    let m = pose(&scene, 0.5).cameras[0];
    // The rig's scale 3 moves the camera to 3·(0, 0, 1); the rotation is 45° about +Y; no scale.
    let expected = Mat4::from_rotation_translation(Quat::from_rotation_y(FRAC_PI_4), Vec3::new(0.0, 0.0, 3.0));
    assert!(m.abs_diff_eq(expected, 1e-5), "{m} vs {expected}");
    assert!(pose(&scene, 0.0).cameras[0].abs_diff_eq(scene.cameras[0].world_from_camera, 1e-6));
}

#[test]
fn an_animated_spot_light_turns() {
    let mut b = GltfBuilder::new();
    let light = b.light(json!({"type": "spot", "intensity": 10.0, "spot": {"outerConeAngle": 0.5}}));
    let lamp = b.node(json!({"name": "lamp", "translation": [0.0, 2.0, 0.0],
        "extensions": {"KHR_lights_punctual": {"light": light}}}));
    // From shining down −Z to shining down −Y (−90° about +X).
    let down: Vec<f32> = [[0.0, 0.0, 0.0, 1.0], quat([1.0, 0.0, 0.0], -FRAC_PI_2)].concat();
    animate(&mut b, "tilt", &[Track::new(lamp, "rotation", "LINEAR", &[0.0, 2.0], &down)]);
    let scene = load(&b);
    let m = pose(&scene, 2.0).lights[0];
    assert!(close(m.transform_vector3(Vec3::NEG_Z), Vec3::NEG_Y) && close(origin(m), Vec3::new(0.0, 2.0, 0.0)));
    let half = pose(&scene, 1.0).lights[0].transform_vector3(Vec3::NEG_Z);
    assert!(close(half, Vec3::new(0.0, -FRAC_1_SQRT_2, -FRAC_1_SQRT_2)), "{half}");
}

#[test]
fn without_animations_poses_are_the_loaded_transforms() {
    let mut b = GltfBuilder::new();
    let mesh = b.mesh(&quad(1.0), None, true);
    let parent = b.node(json!({"name": "p", "translation": [1.0, 2.0, 3.0], "rotation": quat([0.0, 1.0, 0.0], 0.3)}));
    b.child(parent, json!({"mesh": mesh, "matrix": [1,0,0,0, 0,2,0,0, 0,0,1,0, 0,3,0,1]}));
    b.camera_node("cam", 0.7, None, [0.0, 1.0, 5.0], quat([1.0, 0.0, 0.0], -0.2));
    let light = b.light(json!({"type": "point", "intensity": 1.0}));
    b.node(json!({"translation": [0.0, 3.0, 0.0], "extensions": {"KHR_lights_punctual": {"light": light}}}));
    let scene = load(&b);
    assert!(!scene.is_animated() && scene.time_range().is_none());
    let loaded = ScenePose {
        instances: scene.instances.iter().map(|i| i.world_from_object).collect(),
        lights: scene.lights.iter().map(|l| l.world_from_light).collect(),
        cameras: scene.cameras.iter().map(|c| c.world_from_camera).collect(),
        deformations: Vec::new(),
    };
    for t in [0.0, 1.5, 1e6] {
        assert_eq!(pose(&scene, t), loaded);
    }
    assert!(scene.pose_at(f32::NAN).is_err());
    // The hierarchy is kept: the matrix node's rest TRS is its decomposition.
    assert_eq!(scene.nodes.len(), 4);
    let child = &scene.nodes[scene.node_of.instances[0]];
    assert!(child.rest.scale.abs_diff_eq(Vec3::new(1.0, 2.0, 1.0), 1e-6) && child.parent == Some(0));
}

#[test]
fn the_later_animation_wins_and_all_play_at_once() {
    let mut b = GltfBuilder::new();
    let mesh = b.mesh(&quad(1.0), None, true);
    let a = b.node(json!({"name": "a", "mesh": mesh}));
    let c = b.node(json!({"name": "c", "mesh": mesh}));
    let up = [0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let right = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0];
    animate(&mut b, "first", &[Track::new(a, "translation", "LINEAR", &[0.0, 1.0], &up)]);
    animate(
        &mut b,
        "second",
        &[
            Track::new(a, "translation", "LINEAR", &[0.0, 1.0], &right),
            Track::new(c, "translation", "LINEAR", &[0.0, 1.0], &up),
        ],
    );
    let scene = load(&b);
    let p = pose(&scene, 1.0);
    assert!(close(origin(p.instances[0]), Vec3::X) && close(origin(p.instances[1]), Vec3::Y));
}

#[test]
fn zero_scales_hide_meshes_but_leave_cameras_without_orientation() {
    // A mesh that pops in from scale 0 is kept (its rest scale is zero), singular at the start.
    let (mut b, _) = one_box(json!({"scale": [0.0, 0.0, 0.0]}));
    animate(&mut b, "pop", &[Track::new(0, "scale", "LINEAR", &[0.0, 1.0], &[0.0, 0.0, 0.0, 1.0, 1.0, 1.0])]);
    let scene = load(&b);
    assert_eq!(scene.instances.len(), 1, "{:?}", scene.warnings);
    assert_eq!(pose(&scene, 0.0).instances[0].determinant(), 0.0);
    assert_eq!(pose(&scene, 1.0).instances[0], Mat4::IDENTITY);

    let mut b = GltfBuilder::new();
    let cam = b.camera_node("cam", 0.7, None, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]);
    let values = [1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0];
    animate(&mut b, "blink", &[Track::new(cam, "scale", "LINEAR", &[0.0, 1.0, 2.0], &values)]);
    let scene = load(&b);
    let msg = format!("{:#}", scene.pose_at(1.0).unwrap_err());
    assert!(
        msg.contains("node 'cam'")
            && msg.contains("animation 'blink'")
            && msg.contains("t = 1 s")
            && msg.contains("singular"),
        "{msg}"
    );
    assert!(scene.pose_at(0.5).is_ok());
    // At an end of the animations, the load refuses it.
    let values = [1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
    let mut b = GltfBuilder::new();
    let cam = b.camera_node("cam", 0.7, None, [0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]);
    animate(&mut b, "shrink", &[Track::new(cam, "scale", "LINEAR", &[0.0, 1.0], &values)]);
    let msg = error_of(&b);
    assert!(msg.contains("node 'cam'") && msg.contains("t = 1 s") && msg.contains("singular"), "{msg}");
}

#[test]
fn morph_weights_of_a_mesh_without_targets_are_refused() {
    let (mut b, _) = one_box(json!({}));
    animate(&mut b, "smile", &[Track::new(0, "weights", "LINEAR", &[0.0, 1.0], &[0.0, 1.0])]);
    let msg = error_of(&b);
    assert!(msg.contains("animation 'smile' channel 0") && msg.contains("no morph targets"), "{msg}");
}

/// The error of one broken track on node 0 of a one-box document.
fn track_error(node: Value, track: Track) -> String {
    let (mut b, _) = one_box(node);
    animate(&mut b, "walk", &[track]);
    error_of(&b)
}

#[test]
fn keys_must_be_finite_increasing_and_as_many_as_the_values() {
    let t3 = [0.0; 9];
    let msg = track_error(json!({}), Track::new(0, "translation", "LINEAR", &[0.0, 1.0, 1.0], &t3));
    assert!(msg.contains("animation 'walk' channel 0 (translation of node 'box', sampler 0)"), "{msg}");
    assert!(msg.contains("sampler.input") && msg.contains("key 2") && msg.contains("increase strictly"), "{msg}");
    let msg = track_error(json!({}), Track::new(0, "translation", "LINEAR", &[-1.0, 1.0], &t3[..6]));
    assert!(msg.contains("key 0 is -1 s, before 0"), "{msg}");
    let msg = track_error(json!({}), Track::new(0, "translation", "LINEAR", &[0.0, f32::NAN], &t3[..6]));
    assert!(msg.contains("sampler.input") && msg.contains("key 1 is NaN"), "{msg}");
    let msg = track_error(json!({}), Track::new(0, "translation", "LINEAR", &[0.0, 1.0], &t3));
    assert!(msg.contains("sampler.output") && msg.contains("3 elements") && msg.contains("2 keys"), "{msg}");
    let msg = track_error(json!({}), Track::new(0, "scale", "CUBICSPLINE", &[0.0, 1.0], &t3[..6]));
    assert!(msg.contains("channel 0 (scale") && msg.contains("CUBICSPLINE needs 3 per key"), "{msg}");
}

#[test]
fn values_must_be_finite_and_rotations_non_zero() {
    let nan = [0.0, 0.0, 0.0, 1.0, f32::NAN, 0.0];
    let msg = track_error(json!({}), Track::new(0, "translation", "LINEAR", &[0.0, 1.0], &nan));
    assert!(
        msg.contains("channel 0") && msg.contains("sampler.output") && msg.contains("element 1 holds NaN"),
        "{msg}"
    );
    let zero = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0];
    let msg = track_error(json!({}), Track::new(0, "rotation", "STEP", &[0.0, 1.0], &zero));
    assert!(msg.contains("element 1 is a zero quaternion"), "{msg}");
}

#[test]
fn accessor_types_must_fit_the_path() {
    // A rotation with three components per key.
    let (mut b, _) = one_box(json!({}));
    let input = b.accessor_f32(&[0.0, 1.0], "SCALAR", true);
    let output = b.accessor_f32(&[0.0; 6], "VEC3", false);
    b.animation(json!({"name": "walk", "samplers": [{"input": input, "output": output}],
        "channels": [{"sampler": 0, "target": {"node": 0, "path": "rotation"}}]}));
    let msg = error_of(&b);
    assert!(msg.contains("animation 'walk' channel 0 (rotation") && msg.contains("sampler.output accessor"), "{msg}");
    assert!(msg.contains("Vec3 F32, expected Vec4 F32"), "{msg}");
    // Times that are not scalars.
    b.patch_accessor(input, |a| {
        a["type"] = json!("VEC2");
        a["count"] = json!(1);
    });
    assert!(error_of(&b).contains("sampler.input accessor"));
}

/// The error of a one-box document whose animation JSON is `animation(times, translations)`,
/// given two accessors: two times and two translations.
fn json_error(node: Value, animation: impl FnOnce(usize, usize) -> Value) -> String {
    let (mut b, _) = one_box(node);
    let times = b.accessor_f32(&[0.0, 1.0], "SCALAR", true);
    let values = b.accessor_f32(&[0.0; 6], "VEC3", false);
    b.animation(animation(times, values));
    error_of(&b)
}

#[test]
fn references_paths_and_interpolations_are_checked() {
    let channel = |target: Value| move |i: usize, o: usize| json!({"name": "walk", "samplers": [{"input": i, "output": o}], "channels": [{"sampler": 0, "target": target}]});
    let msg = json_error(json!({}), channel(json!({"node": 99, "path": "translation"})));
    assert!(msg.contains("animations[0].channels[0].target.node is 99") && msg.contains("'walk'"), "{msg}");
    let identity = json!({"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]});
    let msg = json_error(identity, channel(json!({"node": 0, "path": "translation"})));
    assert!(msg.contains("animations[0].channels[0]") && msg.contains("has a matrix"), "{msg}");
    let msg = json_error(json!({}), channel(json!({"node": 0, "path": "position"})));
    assert!(msg.contains("channels[0].target.path"), "{msg}");
    let msg = json_error(
        json!({}),
        |i, o| json!({"samplers": [{"input": i, "output": o}], "channels": [{"sampler": 5, "target": {"node": 0, "path": "scale"}}]}),
    );
    assert!(msg.contains("animations[0].channels[0].sampler is 5"), "{msg}");
    let msg = json_error(json!({}), |i, _| json!({"samplers": [{"input": i, "output": 40}], "channels": []}));
    assert!(msg.contains("samplers[0].output is accessor 40"), "{msg}");
    let msg = json_error(
        json!({}),
        |i, o| json!({"samplers": [{"input": i, "output": o, "interpolation": "SMOOTH"}], "channels": []}),
    );
    assert!(msg.contains("samplers[0].interpolation"), "{msg}");
    let msg = json_error(json!({}), |i, o| {
        let target = json!({"node": 0, "path": "translation"});
        json!({"name": "walk", "samplers": [{"input": i, "output": o}],
            "channels": [{"sampler": 0, "target": target}, {"sampler": 0, "target": target}]})
    });
    assert!(msg.contains("animation 'walk' channel 1") && msg.contains("channel 0 animates the same"), "{msg}");
}

#[test]
fn ten_thousand_nodes_pose_in_milliseconds() {
    let mut b = GltfBuilder::new();
    let mesh = b.mesh(&quad(0.1), None, true);
    let mut parent = b.node(json!({"name": "root"}));
    let mut animated = Vec::new();
    for i in 0..10_000 {
        let node = json!({"mesh": mesh, "translation": [0.0, 0.0001, 0.0]});
        // Chains of 100, each hanging off the root.
        parent = if i % 100 == 0 { b.child(0, node) } else { b.child(parent, node) };
        if i % 10 == 0 {
            animated.push(parent);
        }
    }
    let times = [0.0, 1.0];
    let values = [0.0, 0.0, 0.0, 0.001, 0.0, 0.0];
    let tracks: Vec<Track> =
        animated.iter().map(|&n| Track::new(n, "translation", "LINEAR", &times, &values)).collect();
    animate(&mut b, "drift", &tracks);
    let scene = load(&b);
    assert_eq!(scene.instances.len(), 10_000);
    let start = std::time::Instant::now();
    for frame in 0..24 {
        pose(&scene, frame as f32 / 24.0);
    }
    let each = start.elapsed() / 24;
    assert!(each < std::time::Duration::from_millis(20), "{each:?} per pose");
    // The deepest node of the first chain moved by the ten animated nodes above it.
    let last = pose(&scene, 1.0).instances[99];
    // Ten of its hundred nodes are animated: their y steps are replaced by x steps.
    assert!(close(origin(last), Vec3::new(0.01, 0.009, 0.0)), "{}", origin(last));
}
