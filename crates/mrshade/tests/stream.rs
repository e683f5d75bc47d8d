//! `mrshade stream`: raw RGB frames through the small sequence's session (80×60,
//! `assets/sequence/desk-orbit-mini`), with and without poses, ended cleanly, truncated, or
//! into a closed pipe, and misuse. Kept short for lavapipe: a few frames, mostly `direct`.

mod common;

use common::{assert_one_line_error, copy_mini, mini, mrshade, mrshade_into_closed_pipe, mrshade_with_input, stderr};
use std::path::Path;

/// Bytes of one 80×60 RGB frame.
const FRAME: usize = 80 * 60 * 3;

fn session() -> String {
    format!("{}/session.toml", mini())
}

fn rgb(path: &Path) -> Vec<u8> {
    image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).to_rgb8().into_raw()
}

/// Frames `ks` of the sequence's photos, raw.
fn photos(ks: &[usize]) -> Vec<u8> {
    ks.iter().flat_map(|k| rgb(&Path::new(&mini()).join(format!("frames/{:04}.png", 2 * k)))).collect()
}

/// The summary line on stderr.
fn summary(err: &str) -> &str {
    err.lines().find(|l| l.starts_with("mrshade: stream: ")).unwrap_or_else(|| panic!("no summary in: {err}"))
}

/// A streamed frame is the frame rendered from its PNG with the same inputs (`render
/// --frame K` of one unjittered frame): the session's camera for frame 0, the poses file's
/// for frames 1 and 2 (the poses of `transforms.json`). A line that is not JSON is skipped
/// with a warning.
#[test]
fn a_streamed_frame_is_the_frame_rendered_from_its_png() {
    let dir = tempfile::tempdir().unwrap();
    let transforms: serde_json::Value =
        serde_json::from_slice(&std::fs::read(Path::new(&mini()).join("transforms.json")).unwrap()).unwrap();
    let pose = |k: usize| transforms["frames"][k]["transform_matrix"].clone();
    let lines = [
        "this is not JSON".to_string(),
        serde_json::json!({"frame": 1, "transform_matrix": pose(1)}).to_string(),
        serde_json::json!({"frame": 2, "transform_matrix": pose(2), "fl_x": 72.42640687119285, "w": 80, "h": 60})
            .to_string(),
    ];
    let poses = dir.path().join("poses.jsonl");
    std::fs::write(&poses, lines.join("\n")).unwrap();
    let args = ["stream", &session(), "--size", "80x60", "--method", "direct", "--poses", poses.to_str().unwrap()];
    let o = mrshade_with_input(&args, photos(&[0, 1, 2]));
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("warning: poses line 1: not JSON") && err.contains("keeping the last good pose"), "{err}");
    assert!(summary(&err).contains("3 frames in, 3 out, 0 dropped"), "{err}");
    assert_eq!(o.stdout.len(), 3 * FRAME, "three frames and nothing else on stdout");
    for k in 0..3 {
        let png = dir.path().join(format!("{k}.png"));
        let args = ["-q", "render", &session(), "--method", "direct", "--set", "output.frames=1", "--frame"];
        let r = mrshade(&[&args[..], &[&k.to_string(), "-o", png.to_str().unwrap()]].concat());
        assert!(r.status.success(), "{}", stderr(&r));
        let streamed = &o.stdout[k * FRAME..(k + 1) * FRAME];
        assert!(streamed == rgb(&png), "frame {k} differs from render --frame {k}");
        assert!(streamed != &photos(&[k])[..], "frame {k} is its photo: no virtual objects");
    }
}

/// `inserts` in the poses move a session's `[[insert]]` per frame and hold until moved again;
/// an unknown insert name is a warning.
#[test]
fn poses_move_inserts() {
    let dir = tempfile::tempdir().unwrap();
    let orbit = copy_mini(dir.path());
    let mut model = mrshade_testkit::gltf::GltfBuilder::new();
    let red = model.material(serde_json::json!({"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.1, 0.1, 1]}}));
    let mesh = model.mesh(&mrshade_testkit::gltf::cuboid([0.5; 3]), Some(red), true);
    model.node(serde_json::json!({"mesh": mesh}));
    model.write_gltf(&orbit, "box");
    let toml = std::fs::read_to_string(orbit.join("session.toml")).unwrap();
    let insert = "[[insert]]\nmodel = \"box.gltf\"\nname = \"box\"\ntranslation = [-0.1, 0.05, 0.15]\nscale = 0.08\n";
    std::fs::write(orbit.join("session.toml"), format!("{toml}\n{insert}")).unwrap();
    let poses = dir.path().join("poses.jsonl");
    let lines = [
        r#"{"frame": 1, "inserts": {"box": {"translation": [0.1, 0.05, 0.2]}}}"#,
        r#"{"frame": 2, "inserts": {"duck": {"translation": [0, 0, 0]}}}"#,
    ];
    std::fs::write(&poses, lines.join("\n")).unwrap();
    let session = orbit.join("session.toml");
    let args = ["stream", session.to_str().unwrap(), "--size", "80x60", "--method", "direct"];
    let o = mrshade_with_input(&[&args[..], &["--poses", poses.to_str().unwrap()]].concat(), photos(&[0, 0, 0]));
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("no insert named 'duck' (its inserts: 'box')"), "{err}");
    let frame = |k: usize| &o.stdout[k * FRAME..(k + 1) * FRAME];
    assert!(frame(1) != frame(0), "the box moved at frame 1");
    assert!(frame(2) == frame(1), "and stays where it was moved");
}

/// The default method (`dir`, temporal) streams too; every frame is kept.
#[test]
fn the_default_method_streams_every_frame() {
    let o = mrshade_with_input(&["stream", &session(), "--size", "80x60"], photos(&[0, 1]));
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert_eq!(o.stdout.len(), 2 * FRAME);
    assert!(o.stdout[..FRAME] != photos(&[0])[..]);
    let line = summary(&err);
    assert!(line.contains("2 frames in, 2 out, 0 dropped") && line.contains("latency p50"), "{line}");
}

/// `--drop-late` renders the newest frame: every frame read is written or dropped.
#[test]
fn drop_late_keeps_the_newest_frame() {
    let input: Vec<u8> = photos(&[0]).repeat(12);
    let o = mrshade_with_input(&["stream", &session(), "--size", "80x60", "--method", "direct", "--drop-late"], input);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    let line = summary(&err);
    let number = |after: &str| -> usize {
        let at = line.find(after).unwrap_or_else(|| panic!("{line}")) + after.len();
        line[at..].split(|c: char| !c.is_ascii_digit()).next().unwrap().parse().unwrap()
    };
    let (read, out, dropped) = (number("stream: "), number("in, "), number("out, "));
    assert_eq!((read, out + dropped), (12, 12), "{line}");
    assert!(out >= 1 && o.stdout.len() == out * FRAME, "{line}");
}

/// Input that ends inside a frame: the frames before it are written, then one error.
#[test]
fn a_truncated_frame_is_an_error_after_the_whole_ones() {
    let mut input = photos(&[0, 1]);
    input.extend_from_slice(&[0; 100]);
    let o = mrshade_with_input(&["-q", "stream", &session(), "--size", "80x60", "--method", "direct"], input);
    assert_one_line_error(&o, "stdin: truncated frame 2: got 100 of 14400 bytes");
    assert_eq!(o.stdout.len(), 2 * FRAME);
    // Frames of another size than --size: the first frame is already short.
    let o = mrshade_with_input(&["-q", "stream", &session(), "--size", "160x120"], photos(&[0, 1, 2]));
    assert_one_line_error(&o, "stdin: truncated frame 0: got 43200 of 57600 bytes");
    assert!(o.stdout.is_empty());
}

/// End of input at a frame boundary ends the stream cleanly, even with no frame at all.
#[test]
fn no_frames_is_a_clean_end() {
    let o = mrshade_with_input(&["stream", &session(), "--size", "80x60"], Vec::new());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(o.stdout.is_empty());
    assert!(summary(&stderr(&o)).contains("0 frames in, 0 out"));
}

/// A reader that went away ends the stream quietly, as SIGPIPE ends a Unix tool.
#[test]
fn a_closed_stdout_exits_quietly() {
    let args = ["-q", "stream", &session(), "--size", "80x60", "--method", "direct"];
    let o = mrshade_into_closed_pipe(&args, photos(&[0, 1, 2]));
    assert_eq!(o.status.code(), Some(141), "{}", stderr(&o));
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
}

#[test]
fn misuse_is_one_line() {
    for (size, needle) in [
        ("abc", "--size abc: expected WIDTHxHEIGHT"),
        ("0x0", "--size 0x0: the width must be between 16"),
        ("160x90", "--size 160x90 (frames of another aspect ratio need --stretch)"),
    ] {
        assert_one_line_error(&mrshade(&["-q", "stream", &session(), "--size", size]), needle);
    }
    let o = mrshade(&["-q", "stream", &session(), "--size", "80x60", "--width", "80"]);
    assert_one_line_error(&o, "--width/--height: mrshade stream takes the frame size as --size WxH");
    let o = mrshade(&["-q", "stream", &session(), "--size", "80x60", "--poses", "/nonexistent/poses.jsonl"]);
    assert_one_line_error(&o, "--poses /nonexistent/poses.jsonl");
    assert_one_line_error(&mrshade(&["-q", "stream", &session(), "--size", "80x60", "--fps", "0"]), "--fps 0");
}
