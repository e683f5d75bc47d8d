//! `mrshade render` of a posed image sequence (`assets/sequence/desk-orbit-mini`, 12 frames of
//! 80×60): one image per frame, one frame as a still, a range that matches the whole run (how
//! a sequence is sharded), ffmpeg missing, and misuse. Kept short for lavapipe.

mod common;

use common::{assert_one_line_error, copy_mini, mini, mrshade, stderr};
use std::path::Path;

fn session() -> String {
    format!("{}/session.toml", mini())
}

fn rgb(path: &Path) -> Vec<u8> {
    image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).to_rgb8().into_raw()
}

#[test]
fn a_sequence_renders_one_image_per_frame_numbered_as_its_input() {
    let out = tempfile::tempdir().unwrap();
    let (folder, aovs) = (out.path().join("frames"), out.path().join("aovs"));
    let o = mrshade(&[
        "render",
        &session(),
        "--method",
        "direct",
        "--set",
        "sequence.samples=2",
        "-o",
        folder.to_str().unwrap(),
        "--aov-dir",
        aovs.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for file in ["0000/l_rv.exr", "0022/side_by_side.png"] {
        assert!(aovs.join(file).is_file(), "no AOV {file} per frame");
    }
    let mut names: Vec<String> =
        std::fs::read_dir(&folder).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    let expected: Vec<String> = (0..12).map(|k| format!("{:04}.png", 2 * k)).collect();
    assert_eq!(names, expected);
    // Every frame differs from its photo (the virtual objects are in it) and has the photo's size.
    for name in ["0000.png", "0022.png"] {
        let (ours, photo) = (rgb(&folder.join(name)), rgb(&Path::new(&mini()).join("frames").join(name)));
        assert_eq!(ours.len(), photo.len());
        assert!(ours != photo, "{name} is the photo");
    }
    // One frame alone, converged as a still.
    let still = out.path().join("still.png");
    let o = mrshade(&["render", &session(), "--method", "direct", "--frame", "5", "-o", still.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(rgb(&still).len(), 80 * 60 * 3);
}

/// A range rendered on its own (after a few unwritten frames, numbered as in the whole run)
/// matches the whole run's frames: the way to shard a long sequence across machines.
#[test]
fn a_range_matches_the_whole_runs_frames() {
    let out = tempfile::tempdir().unwrap();
    let (whole, part) = (out.path().join("whole"), out.path().join("part"));
    let fast = ["--set", "output.frames=8", "--set", "sequence.samples=2"];
    let o = mrshade(&[&["render", &session(), "-o", whole.to_str().unwrap()][..], &fast].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let o = mrshade(
        &[&["render", &session(), "--frames", "8..12", "--warmup", "6", "-o", part.to_str().unwrap()][..], &fast]
            .concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let written: Vec<_> = std::fs::read_dir(&part).unwrap().collect();
    assert_eq!(written.len(), 4, "only the range is written");
    for k in [16, 18, 20, 22] {
        let name = format!("{k:04}.png");
        let (a, b) = (rgb(&whole.join(&name)), rgb(&part.join(&name)));
        let worst = a.iter().zip(&b).map(|(x, y)| x.abs_diff(*y)).max().unwrap();
        let mean = a.iter().zip(&b).map(|(x, y)| x.abs_diff(*y) as f64).sum::<f64>() / a.len() as f64;
        let off = a.iter().zip(&b).filter(|(x, y)| x.abs_diff(**y) > 4).count() as f64 / a.len() as f64;
        eprintln!(
            "{name}: range vs whole run: mean {mean:.3}/255, {:.2} % off by > 4/255, worst {worst}/255",
            off * 100.0
        );
        // The histories differ only by what the warm-up has not yet forgotten: a few values
        // (the temporal noise of this 8-frame test setting), no visible change.
        assert!(mean < 0.25 && off < 0.01, "{name}: mean {mean}, {off} off by more than 4/255");
    }
}

#[test]
fn misuse_and_bad_sequences_are_one_line_errors() {
    let out = tempfile::tempdir().unwrap();
    let png = out.path().join("x.png");
    let png = png.to_str().unwrap();
    // A sequence renders into a folder; a still session has no frames.
    assert_one_line_error(&mrshade(&["-q", "render", &session(), "-o", png]), "into a folder");
    assert_one_line_error(&mrshade(&["-q", "render", &session(), "--frame", "12", "-o", png]), "12 frames");
    assert_one_line_error(&mrshade(&["-q", "render", &session(), "--frames", "5..3", "-o", "dir/"]), "empty");
    let demo = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/demo/session.toml");
    assert_one_line_error(&mrshade(&["-q", "render", demo, "--frames", "0..2", "-o", png]), "still session");
    // ffmpeg not on the PATH: say how to install it, before rendering anything.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_mrshade"))
        .args(["-q", "render", &session(), "--method", "direct", "--video", out.path().join("v.mp4").to_str().unwrap()])
        .env("PATH", out.path())
        .env("XDG_RUNTIME_DIR", out.path())
        .output()
        .unwrap();
    assert_one_line_error(&o, "apt install ffmpeg");
    // A pose that is not a rigid transform, naming the file and the frame.
    let copy = copy_mini(out.path());
    let transforms = copy.join("transforms.json");
    let mut json: serde_json::Value = serde_json::from_slice(&std::fs::read(&transforms).unwrap()).unwrap();
    json["frames"][3]["transform_matrix"][0][0] = serde_json::json!(2.0);
    std::fs::write(&transforms, serde_json::to_vec(&json).unwrap()).unwrap();
    let o = mrshade(&["-q", "render", copy.join("session.toml").to_str().unwrap(), "-o", "unused/"]);
    assert_one_line_error(&o, "transforms.json");
    assert!(stderr(&o).contains("frame 3"), "{}", stderr(&o));
}

/// `info` names the sequence and its camera; its output piped into a reader that stops early
/// (`mrshade info … | head -1`) ends quietly, not with an internal-error report.
#[test]
fn info_describes_a_sequence_and_stops_quietly_on_a_closed_pipe() {
    let o = mrshade(&["-q", "info", &session()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("sequence   12 frames at 15 fps, 32 samples per frame, posed by transforms.json"), "{out}");
    let runtime = tempfile::tempdir().unwrap();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_mrshade"))
        .args(["-q", "info", &session()])
        .env("XDG_RUNTIME_DIR", runtime.path())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    assert!(!stderr(&o).contains("internal error"), "{}", stderr(&o));
}
