//! Posed image sequences (`[sequence]`, nerfstudio / instant-ngp `transforms.json`): frames,
//! poses and intrinsics as given, and one-line errors naming the file, the frame and the key.

use mrshade_core::camera::Intrinsics;
use mrshade_scene::session::SEQUENCE_CAMERA;
use mrshade_scene::{Session, SessionOverrides};
use mrshade_testkit::gltf::{GltfBuilder, cuboid, quad, quat, write_exr, write_png};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

const SESSION: &str =
    "scene = \"scene.gltf\"\nexposure = 1.0\n[sequence]\ntransforms = \"transforms.json\"\nfps = 24\n";
const STILL: &str = "scene = \"scene.gltf\"\nbackground = \"frames/0000.png\"\nexposure = 1.0\n";
const FRAMES: usize = 3;

/// Frame `k`'s camera-to-world rows: turned about +Y, moved along +X.
fn rows(k: usize) -> [[f64; 4]; 4] {
    let (s, c) = (0.2 * k as f64).sin_cos();
    [[c, 0.0, s, 0.1 * k as f64], [0.0, 1.0, 0.0, 0.5], [-s, 0.0, c, 1.0], [0.0, 0.0, 0.0, 1.0]]
}

/// A good `transforms.json`, with keys nerfstudio writes that mrshade does not use.
fn good_json() -> Value {
    let frames: Vec<Value> = (0..FRAMES)
        .map(|k| {
            json!({"file_path": format!("frames/{k:04}.png"), "transform_matrix": rows(k), "colmap_im_id": k,
                   "mask_path": null, "depth_file_path": format!("depths/{k:04}.png")})
        })
        .collect();
    json!({"camera_model": "PINHOLE", "w": 32, "h": 24, "fl_x": 30.0, "fl_y": 31.0, "cx": 16.0, "cy": 12.0,
           "k1": 0.0, "p1": 0.0, "aabb_scale": 16, "ply_file_path": "sparse.ply",
           "applied_transform": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]], "frames": frames})
}

/// A sequence session of three 32×24 frames (frame k's photo is k·80 in red) in a temp dir;
/// the glTF camera, if any, has aspect ratio 1 (which a `transforms` session does not check).
fn sequence_dir(camera: bool) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let mut b = GltfBuilder::new();
    let m1 = b.mesh(&quad(1.0), None, true);
    let m2 = b.mesh(&cuboid([0.1; 3]), None, true);
    b.node(json!({"name": "desk", "mesh": m1, "extras": {"real": true}}));
    b.node(json!({"name": "cube", "mesh": m2}));
    if camera {
        b.camera_node("camera", 0.8, Some(1.0), [0.0, 0.5, 1.0], quat([1.0, 0.0, 0.0], -0.4));
    }
    b.write_gltf(dir.path(), "scene");
    std::fs::create_dir(dir.path().join("frames")).unwrap();
    for k in 0..FRAMES {
        write_png(&dir.path().join(format!("frames/{k:04}.png")), 32, 24, |_, _| [k as u8 * 80, 0, 0]);
    }
    write_json(dir.path(), &good_json());
    let path = dir.path().join("session.toml");
    std::fs::write(&path, SESSION).unwrap();
    (dir, path)
}

fn write_json(dir: &Path, json: &Value) {
    std::fs::write(dir.join("transforms.json"), serde_json::to_vec_pretty(json).unwrap()).unwrap();
}

fn load(path: &Path) -> Session {
    Session::load(path, &SessionOverrides::default()).unwrap()
}

/// The error of loading `path`, which must be one line naming the session file.
fn error(path: &Path, overrides: &SessionOverrides) -> String {
    let msg = format!("{:#}", Session::load(path, overrides).expect_err("must fail"));
    assert!(!msg.contains('\n'), "one line: {msg}");
    assert!(msg.contains("session.toml"), "the error names the session file: {msg}");
    msg
}

/// The error of the sequence with `edit` applied to its JSON: it names the transforms file.
fn json_error(edit: impl FnOnce(&mut Value)) -> String {
    let (dir, path) = sequence_dir(true);
    let mut json = good_json();
    edit(&mut json);
    write_json(dir.path(), &json);
    let msg = error(&path, &SessionOverrides::default());
    assert!(msg.contains("field `sequence.transforms`") && msg.contains("transforms.json"), "{msg}");
    msg
}

fn assert_has(msg: &str, parts: &[&str]) {
    for part in parts {
        assert!(msg.contains(part), "`{part}` not in: {msg}");
    }
}

#[test]
fn a_transforms_session_loads_every_frame_as_given() {
    let (dir, path) = sequence_dir(true);
    let s = load(&path);
    assert_eq!(s.frame_count(), FRAMES);
    assert_eq!((s.output.width, s.output.height), (32, 24), "the output takes frame 0's size");
    assert_eq!(s.scene.cameras[s.camera].node_name, "camera");
    let seq = s.sequence.as_ref().unwrap();
    assert!(seq.from_transforms);
    assert_eq!((seq.fps, seq.time(12)), (24.0, 0.5));
    let k = Intrinsics { fl_x: 30.0, fl_y: 31.0, cx: 16.0, cy: 12.0, width: 32, height: 24 };
    for (i, frame) in seq.frames.iter().enumerate() {
        assert_eq!(
            (frame.name.as_str(), frame.file.as_str()),
            (format!("{i:04}").as_str(), format!("frames/{i:04}.png").as_str())
        );
        assert_eq!(frame.intrinsics, k);
        for (r, row) in rows(i).iter().enumerate() {
            let got = frame.world_from_camera.row(r).to_array();
            assert!(got.iter().zip(row).all(|(a, b)| (*a as f64 - b).abs() < 1e-6), "frame {i} row {r}: {got:?}");
        }
        let view = s.view_at(i);
        assert_eq!((view.world_from_camera, view.intrinsics, view.znear), (frame.world_from_camera, k, 0.01));
    }
    // Photos: frame 0 is the background; each frame's is its own.
    assert_eq!(s.photo_at(0).unwrap().pixels, s.background.pixels);
    let second = s.photo_at(2).unwrap();
    assert!(second.pixels[0][0] > s.background.pixels[0][0] && (second.width, second.height) == (32, 24));
    assert!(format!("{:#}", s.photo_at(3).unwrap_err()).contains("no frame 3"));
    // A photo changed after loading is refused when it is read.
    write_png(&dir.path().join("frames/0001.png"), 16, 12, |_, _| [0, 0, 0]);
    let msg = format!("{:#}", s.photo_at(1).unwrap_err());
    assert_has(&msg, &["frame 1", "frames/0001.png", "16×12", "32×24"]);
}

#[test]
fn views_follow_the_output_size() {
    let (_dir, path) = sequence_dir(true);
    let s = Session::load(&path, &SessionOverrides { width: Some(64), ..Default::default() }).unwrap();
    let view = s.view_at(1);
    assert_eq!(view.intrinsics, Intrinsics { fl_x: 60.0, fl_y: 62.0, cx: 32.0, cy: 24.0, width: 64, height: 48 });
    assert_eq!((s.photo_at(1).unwrap().width, s.view_at(99)), (64, s.view_at(FRAMES - 1)));
    let msg = error(&path, &SessionOverrides { width: Some(32), height: Some(32), ..Default::default() });
    assert_has(&msg, &["field `output`", "aspect"]);
}

#[test]
fn per_frame_intrinsics_override_the_top_level() {
    let (dir, path) = sequence_dir(true);
    let mut json = good_json();
    json["frames"][1]["fl_x"] = json!(40.0);
    json["frames"][2]["camera_angle_x"] = json!(2.0 * (0.5f64).atan());
    json["frames"][2]["cx"] = json!(10.0);
    write_json(dir.path(), &json);
    let s = load(&path);
    let frames = &s.sequence.as_ref().unwrap().frames;
    assert_eq!((frames[0].intrinsics.fl_x, frames[1].intrinsics.fl_x, frames[1].intrinsics.fl_y), (30.0, 40.0, 31.0));
    // 2·atan(1/2) over 32 pixels: a focal length of 32 pixels.
    assert!((frames[2].intrinsics.fl_x - 32.0).abs() < 1e-4 && frames[2].intrinsics.cx == 10.0);
}

#[test]
fn camera_angle_alone_and_paths_without_extension() {
    let (dir, path) = sequence_dir(true);
    write_exr(&dir.path().join("frames/0002.exr"), 32, 24, |_, _| [0.5, 0.5, 0.5]);
    std::fs::remove_file(dir.path().join("frames/0002.png")).unwrap();
    // instant-ngp: a horizontal field of view, no size (the image's), no principal point.
    let frames: Vec<Value> =
        (0..FRAMES).map(|k| json!({"file_path": format!("frames/{k:04}"), "transform_matrix": rows(k)})).collect();
    write_json(dir.path(), &json!({"camera_angle_x": 2.0 * (0.5f64).atan(), "frames": frames}));
    let s = load(&path);
    let frames = &s.sequence.as_ref().unwrap().frames;
    assert_eq!((frames[0].file.as_str(), frames[2].file.as_str()), ("frames/0000.png", "frames/0002.exr"));
    assert_eq!((frames[2].name.as_str(), frames[2].intrinsics.cx, frames[2].intrinsics.cy), ("0002", 16.0, 12.0));
    assert!((frames[0].intrinsics.fl_x - 32.0).abs() < 1e-4 && frames[0].intrinsics.fl_x == frames[0].intrinsics.fl_y);
    assert!((s.photo_at(2).unwrap().pixels[0][0] - 0.5).abs() < 1e-6);
}

#[test]
fn intrinsics_of_a_larger_image_are_scaled_to_the_photos() {
    let (dir, path) = sequence_dir(true);
    let mut json = good_json();
    for (key, v) in [("w", 64.0), ("h", 48.0), ("fl_x", 60.0), ("fl_y", 62.0), ("cx", 32.0), ("cy", 24.0)] {
        json[key] = json!(v);
    }
    write_json(dir.path(), &json);
    let k = load(&path).sequence.unwrap().frames[1].intrinsics;
    assert_eq!(k, Intrinsics { fl_x: 30.0, fl_y: 31.0, cx: 16.0, cy: 12.0, width: 32, height: 24 });
}

#[test]
fn a_gltf_without_camera_takes_frame_0s() {
    let (_dir, path) = sequence_dir(false);
    let s = load(&path);
    let camera = &s.scene.cameras[s.camera];
    assert_eq!((camera.node_name.as_str(), camera.znear), (SEQUENCE_CAMERA, 0.01));
    assert_eq!(camera.world_from_camera, s.sequence.as_ref().unwrap().frames[0].world_from_camera);
    assert!((camera.yfov - 2.0 * (12.0f32 / 31.0).atan()).abs() < 1e-6);
    assert_eq!(s.view_at(1).znear, 0.01);
}

#[test]
fn the_view_of_a_still_session_is_the_gltf_camera() {
    let (_dir, path) = sequence_dir(true);
    std::fs::write(&path, STILL).unwrap();
    let s = Session::load(&path, &SessionOverrides { stretch_photo: true, ..Default::default() }).unwrap();
    assert!(s.sequence.is_none() && s.frame_count() == 1);
    let camera = &s.scene.cameras[s.camera];
    let view = s.view_at(0);
    assert_eq!(view.world_from_camera, camera.world_from_camera);
    assert_eq!(view.intrinsics, Intrinsics::from_yfov(camera.yfov, 32, 24));
    assert_eq!(view.znear, camera.znear);
    assert_eq!(s.photo_at(0).unwrap().pixels, s.background.pixels);
    assert!(s.photo_at(1).is_err());
}

#[test]
fn a_photo_repeated_for_some_frames() {
    let (_dir, path) = sequence_dir(false);
    let mut b = GltfBuilder::new();
    b.camera_node("camera", 0.8, None, [0.0, 0.5, 1.0], quat([1.0, 0.0, 0.0], -0.4));
    b.write_gltf(path.parent().unwrap(), "scene");
    std::fs::write(&path, format!("{STILL}[sequence]\nframes = 4\n")).unwrap();
    let s = load(&path);
    let seq = s.sequence.as_ref().unwrap();
    assert!(!seq.from_transforms && seq.fps == 30.0 && s.frame_count() == 4);
    let names: Vec<&str> = seq.frames.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["0000", "0001", "0002", "0003"]);
    assert!(seq.frames.iter().all(|f| f.file == "frames/0000.png"));
    assert_eq!(s.photo_at(3).unwrap().pixels, s.background.pixels);
    assert_eq!(s.view_at(3).world_from_camera, s.scene.cameras[s.camera].world_from_camera);
}

#[test]
fn the_sequence_table_is_checked() {
    let (_dir, path) = sequence_dir(true);
    for (toml, parts) in [
        (format!("background = \"frames/0000.png\"\n{SESSION}"), &["field `background`", "not both"][..]),
        ("scene = \"scene.gltf\"\n".to_string(), &["field `background`", "missing", "[sequence] transforms"]),
        (format!("{SESSION}frames = 3\n"), &["field `sequence.frames`", "not with `sequence.transforms`"]),
        (format!("{STILL}[sequence]\nfps = 30\n"), &["field `sequence.frames`", "missing"]),
        (
            format!("{STILL}[sequence]\nframes = 0\n"),
            &["field `sequence.frames`", "between 1 and `limits.sequence_frames`"],
        ),
        (SESSION.replace("fps = 24", "fps = 0"), &["field `sequence.fps`", "got 0"]),
        (SESSION.replace("fps = 24", "fps = inf"), &["field `sequence.fps`"]),
        (format!("{SESSION}speed = 2\n"), &["unknown field `speed`"]),
    ] {
        std::fs::write(&path, &toml).unwrap();
        assert_has(&error(&path, &SessionOverrides::default()), parts);
    }
}

/// The error for frame 1 (of `frames/0001.png`) names it, and the key.
fn frame_1(msg: &str, parts: &[&str]) {
    assert_has(msg, &["frame 1 (frames/0001.png)"]);
    assert_has(msg, parts);
}

#[test]
fn bad_poses_name_the_frame_and_the_key() {
    let matrix = |m: Value| move |j: &mut Value| j["frames"][1]["transform_matrix"] = m;
    let mut scaled = rows(1);
    (0..3).for_each(|r| (0..3).for_each(|c| scaled[r][c] *= 2.0));
    let mut mirrored = rows(1);
    (0..3).for_each(|r| mirrored[r][0] *= -1.0);
    let mut bottom = rows(1);
    bottom[3][2] = 1.0;
    let mut far = rows(1);
    far[0][3] = 1e7;
    let mut huge = rows(1);
    huge[1][3] = 1e39;
    let three_rows = json!(&rows(1)[..3]);
    let short_row = json!([[1, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]);
    frame_1(&json_error(matrix(three_rows)), &["`transform_matrix` must be 4×4", "3 rows"]);
    frame_1(&json_error(matrix(short_row)), &["`transform_matrix` must be 4×4", "row 0 has 3 numbers"]);
    frame_1(&json_error(matrix(json!(scaled))), &["`transform_matrix` is not a rigid transform", "scale", "2.0000"]);
    frame_1(&json_error(matrix(json!(mirrored))), &["`transform_matrix` is not a rigid transform", "determinant -1"]);
    frame_1(&json_error(matrix(json!(bottom))), &["`transform_matrix`", "bottom row is [0, 0, 1, 1]"]);
    frame_1(&json_error(matrix(json!(far))), &["`transform_matrix`", "farther than 1e6 m"]);
    frame_1(&json_error(matrix(json!(huge))), &["`transform_matrix` row 1 column 3", "not a finite single-precision"]);
    let msg = json_error(|j| j["frames"][1].as_object_mut().unwrap().retain(|k, _| k != "transform_matrix"));
    frame_1(&msg, &["`transform_matrix` is missing"]);
    // Wrong types are found while parsing, before the frame's file_path is known: the frame's
    // index, the key and the line.
    let msg = json_error(matrix(json!([[1, 0, 0, "0"], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])));
    assert_has(&msg, &["frame 1, `transform_matrix`: invalid type: string \"0\"", "line "]);
    assert_has(&json_error(matrix(json!(5))), &["frame 1, `transform_matrix`: invalid type: integer `5`"]);
}

#[test]
fn bad_intrinsics_name_the_frame_and_the_key() {
    let set = |key: &'static str, v: Value| move |j: &mut Value| j["frames"][1][key] = v;
    frame_1(&json_error(set("fl_x", json!(-5.0))), &["`fl_x`", "focal length above 0"]);
    frame_1(&json_error(set("camera_angle_x", json!(4.0))), &["`camera_angle_x`", "between 0 and π"]);
    frame_1(&json_error(set("w", json!(0))), &["`w`", "whole number of pixels"]);
    frame_1(&json_error(set("h", json!(24.5))), &["`h`", "whole number of pixels"]);
    frame_1(&json_error(set("cx", json!(100.0))), &["`cx` = 100", "principal point outside the image"]);
    frame_1(&json_error(set("cy", json!(-1.0))), &["`cy` = -1", "principal point outside the image"]);
    frame_1(&json_error(set("h", json!(32))), &["`w` × `h` is 32×32", "image is 32×24", "aspect ratio"]);
    frame_1(&json_error(set("k1", json!(0.1))), &["`k1` is 0.1", "undistort the images first"]);
    frame_1(&json_error(set("camera_model", json!("OPENCV_FISHEYE"))), &["`camera_model`", "pinhole"]);
    assert_has(&json_error(set("fl_y", json!("big"))), &["frame 1, `fl_y`: invalid type: string"]);
    // At the top level: named as such.
    let msg = json_error(|j| j["fl_x"] = json!(0.0));
    assert_has(&msg, &["frame 0 (frames/0000.png)", "`fl_x` (top level)", "above 0"]);
    let msg = json_error(|j| j["camera_model"] = json!("OPENCV"));
    assert_has(&msg, &["top level", "`camera_model` is \"OPENCV\"", "pinhole", "undistort"]);
    let msg = json_error(|j| {
        let top = j.as_object_mut().unwrap();
        top.remove("fl_x");
        top.remove("fl_y");
    });
    assert_has(&msg, &["frame 0 (frames/0000.png)", "intrinsics are missing", "`fl_x`", "`camera_angle_x`"]);
}

#[test]
fn bad_frame_lists_and_images_are_named() {
    let msg = json_error(|j| j["frames"][1].as_object_mut().unwrap().retain(|k, _| k != "file_path"));
    assert_has(&msg, &["frame 1: `file_path` is missing"]);
    assert_has(&json_error(|j| j["frames"] = json!([])), &["`frames` is empty"]);
    assert_has(&json_error(|j| j.as_object_mut().unwrap().retain(|k, _| k != "frames")), &["`frames` is missing"]);
    assert_has(&json_error(|j| j["frames"] = json!({})), &["`frames`: invalid type: map"]);
    // Two images of one name would write one output.
    let msg = json_error(|j| j["frames"][2]["file_path"] = json!("frames/../frames/0001.png"));
    assert_has(&msg, &["frame 2 (frames/../frames/0001.png)", "name `0001` of frame 1's"]);

    let (dir, path) = sequence_dir(true);
    std::fs::remove_file(dir.path().join("frames/0001.png")).unwrap();
    frame_1(&error(&path, &SessionOverrides::default()), &["transforms.json", "`file_path`", "not found"]);
    write_png(&dir.path().join("frames/0001.png"), 64, 48, |_, _| [0, 0, 0]);
    let msg = error(&path, &SessionOverrides::default());
    frame_1(&msg, &["the image is 64×48 but frame 0's (frames/0000.png) is 32×24", "transforms.json"]);
    std::fs::write(dir.path().join("frames/0001.png"), b"not an image").unwrap();
    frame_1(&error(&path, &SessionOverrides::default()), &["`file_path`", "unrecognised image format"]);
    // A missing transforms file names itself and the field.
    std::fs::remove_file(dir.path().join("transforms.json")).unwrap();
    assert_has(
        &error(&path, &SessionOverrides::default()),
        &["field `sequence.transforms`", "transforms.json", "not found"],
    );
}

#[test]
fn the_budgets_bound_the_transforms_file() {
    let (dir, path) = sequence_dir(true);
    let set =
        |pairs: &[&str]| SessionOverrides { set: pairs.iter().map(|s| s.to_string()).collect(), ..Default::default() };
    let msg = error(&path, &set(&["limits.sequence_frames=2"]));
    assert_has(&msg, &["transforms.json", "`frames`: more than `limits.sequence_frames` = 2 frames", "--set"]);
    assert!(Session::load(&path, &set(&["limits.sequence_frames=3"])).is_ok());
    assert_has(&error(&path, &set(&["limits.sequence_frames=0"])), &["limits.sequence_frames", "between 1"]);
    let mut json = good_json();
    json["notes"] = json!("x".repeat(3 << 20));
    write_json(dir.path(), &json);
    let msg = error(&path, &set(&["limits.file_mib=2"]));
    assert_has(&msg, &["field `sequence.transforms`", "transforms.json", "limits.file_mib"]);
    // Unused keys are skipped however large.
    assert_eq!(load(&path).frame_count(), FRAMES);
}
