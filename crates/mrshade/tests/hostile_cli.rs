//! Hostile input at the command line, as users feel it: one line on stderr naming the cause,
//! a non-zero exit, no panic, no terminal injection, memory bounded by the operating system's
//! own limit (`prlimit`), and no hang on a FIFO.

use mrshade_testkit::gltf::push_root;
use serde_json::{Value, json};
use std::path::Path;
use std::process::{Command, Output};

/// `mrshade -q ARGS`: errors only on stderr.
fn mrshade(args: &[&str]) -> Output {
    let runtime = tempfile::tempdir().unwrap();
    Command::new(env!("CARGO_BIN_EXE_mrshade"))
        .arg("-q")
        .args(args)
        .env("XDG_RUNTIME_DIR", runtime.path())
        .output()
        .expect("run mrshade")
}

/// Exactly one line on stderr, starting `error: ` and holding every fragment; exit code 1 (not
/// 101, a panic, nor a signal).
fn one_line_error(o: &Output, fragments: &[&str]) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "exit code 1: {err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "one line: {err}");
    assert!(lines[0].starts_with("error: "), "{err}");
    for f in fragments {
        assert!(lines[0].contains(f), "expected {f:?} in {err}");
    }
    assert!(!err.contains('\u{1b}') && !err.contains('\r'), "no control characters: {err:?}");
}

const SEED: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/benchmark/desk-spot-real");

/// The seed session in a temporary folder with its glTF changed by `f`.
fn session_with(f: impl FnOnce(&mut Value)) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    mrshade_testkit::gltf::copy_session_with(Path::new(SEED), dir.path(), f);
    dir
}

fn session_path(dir: &tempfile::TempDir) -> String {
    dir.path().join("session.toml").display().to_string()
}

#[test]
fn names_with_control_characters_are_printed_escaped() {
    let dir = session_with(|d| d["nodes"][0]["name"] = json!("desk\r\u{1b}[31mEVIL\u{1b}[0m\nsecond"));
    let o = mrshade(&["info", &session_path(&dir)]);
    assert!(o.status.success());
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("desk\\r\\u{1b}[31mEVIL\\u{1b}[0m\\nsecond"), "{out}");
    assert!(!out.contains('\u{1b}') && !out.contains('\r'), "{out:?}");
    // The same in an error, and in a TOML line quoted by an error.
    let dir = session_with(|d| {
        d["nodes"][6]["name"] = json!("cam\u{1b}]0;owned\u{7}");
        d["cameras"][0]["perspective"]["yfov"] = json!(0);
    });
    one_line_error(&mrshade(&["info", &session_path(&dir)]), &["cam\\u{1b}]0;owned\\u{7}", "yfov 0"]);
    let dir = session_with(|_| {});
    std::fs::write(dir.path().join("session.toml"), "scene = \"scene.glb\"\nbogus\u{1b}[2J = 1\n").unwrap();
    one_line_error(&mrshade(&["info", &session_path(&dir)]), &["line 2", "bogus\\u{1b}[2J"]);
}

#[test]
fn paths_that_are_not_session_files() {
    one_line_error(&mrshade(&["info", "/"]), &["session /", "names no file"]);
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("session.toml")).unwrap();
    one_line_error(&mrshade(&["info", &session_path(&dir)]), &["session.toml", "is a directory"]);
    // A FIFO would block a reader for ever.
    let fifo = tempfile::tempdir().unwrap();
    assert!(Command::new("mkfifo").arg(fifo.path().join("session.toml")).status().unwrap().success());
    one_line_error(&mrshade(&["info", &session_path(&fifo)]), &["not a regular file"]);
}

#[test]
fn relative_paths_read_from_the_current_folder() {
    // `mrshade info session.toml` run inside the session's folder: its parent is "".
    let dir = session_with(|_| {});
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_mrshade")).args(args).current_dir(dir.path()).output().unwrap()
    };
    let o = run(&["info", "session.toml"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = run(&["compare", "background.png", "background.png"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn sizes_are_named_as_given() {
    let dir = session_with(|_| {});
    one_line_error(&mrshade(&["info", &session_path(&dir), "--height", "100000"]), &["height must be between"]);
    one_line_error(&mrshade(&["info", &session_path(&dir), "--width", "1"]), &["width must be between 16"]);
}

#[test]
fn a_loader_under_a_one_gib_address_space_refuses_instead_of_aborting() {
    // 2³¹ sparse-only positions: 24 GiB if allocated before checking.
    let dir = session_with(|d| {
        let n = d["accessors"].as_array().unwrap().len();
        d["accessors"].as_array_mut().unwrap().push(json!({"componentType": 5126, "count": 2147483648u64,
            "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1],
            "sparse": {"count": 1, "indices": {"bufferView": 0, "componentType": 5125}, "values": {"bufferView": 0}}}));
        d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(n);
    });
    let o = Command::new("prlimit")
        .args(["--as=1073741824", "--", env!("CARGO_BIN_EXE_mrshade"), "-q", "info", &session_path(&dir)])
        .output()
        .expect("prlimit (util-linux)");
    one_line_error(&o, &["2147483648 elements", "limits.scene_mib"]);
}

#[test]
fn compare_refuses_images_too_large_to_score() {
    // Two small files that claim 26000 × 19500 pixels: FLIP would need 60 GB.
    let dir = tempfile::tempdir().unwrap();
    let big = dir.path().join("big.png");
    let mut png = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut png, 26000, 19500);
        encoder.set_color(png::ColorType::Grayscale);
        encoder.set_depth(png::BitDepth::One);
        let mut writer = encoder.write_header().unwrap();
        let mut stream = writer.stream_writer().unwrap();
        let row = vec![0u8; 3250];
        for _ in 0..19500 {
            std::io::Write::write_all(&mut stream, &row).unwrap();
        }
        stream.finish().unwrap();
    }
    std::fs::write(&big, &png).unwrap();
    let big = big.display().to_string();
    one_line_error(&mrshade(&["compare", &big, &big]), &["big.png", "26000×19500", "--max-pixels"]);
}

#[test]
fn too_many_lights_for_the_device_is_an_error_not_a_bug_report() {
    let dir = session_with(|d| {
        for i in 0..10_000 {
            let lamp = json!({"name": format!("l{i}"), "translation": [0, 1, 0],
                "extensions": {"KHR_lights_punctual": {"light": 0}}});
            push_root(d, lamp);
        }
    });
    let out = dir.path().join("out.png").display().to_string();
    one_line_error(&mrshade(&["render", &session_path(&dir), "-o", &out]), &["10001 lights", "limits.lights"]);
    // Raised past what the device holds: the device's limit is named, not "a bug in mrshade".
    let o = mrshade(&["render", &session_path(&dir), "-o", &out, "--set", "limits.lights=20000", "--method", "direct"]);
    // (The device's binding limit or the GPU memory budget, whichever this device reaches.)
    one_line_error(&o, &["shadow"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("bug in mrshade"), "{err}");
}

#[test]
fn bench_moving_needs_a_virtual_object() {
    // Every node made real: nothing for --moving to turn.
    let dir = session_with(|d| {
        for node in d["nodes"].as_array_mut().unwrap() {
            node["extras"] = json!({"real": true});
        }
    });
    let path = session_path(&dir);
    one_line_error(
        &mrshade(&["bench", &path, "--moving", "--frames", "1", "--warmup", "0", "--width", "32"]),
        &["--moving", "no virtual object"],
    );
}
