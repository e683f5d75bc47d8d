//! The command line: help everywhere, one-line errors with a non-zero exit, and the commands
//! doing their work on the test GPU.

mod common;

use common::{assert_one_line_error, mrshade, stderr};
use std::path::Path;
use std::process::Command;

fn demo_session() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/demo/session.toml").to_string()
}

#[test]
fn help_everywhere() {
    for args in [
        &["--help"][..],
        &["render", "--help"],
        &["demo", "--help"],
        &["bench", "--help"],
        &["info", "--help"],
        &["adapters", "--help"],
        &["compare", "--help"],
        &["reference", "--help"],
        &["eval", "--help"],
        &["stream", "--help"],
    ] {
        let o = mrshade(args);
        assert!(o.status.success(), "{args:?}");
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(out.contains("Usage: mrshade"), "{args:?}: {out}");
    }
    let out = String::from_utf8_lossy(&mrshade(&["render", "--help"]).stdout).into_owned();
    for flag in ["--width", "--height", "--aov-dir", "--method", "--composite", "--set", "--supersample"] {
        assert!(out.contains(flag), "render --help lists {flag}");
    }
}

#[test]
fn failures_are_one_line_and_non_zero() {
    assert_one_line_error(
        &mrshade(&["render", "-q", "/nonexistent/session.toml", "-o", "/tmp/x.png"]),
        "/nonexistent/session.toml",
    );
    assert_one_line_error(&mrshade(&["render", "-q", &demo_session(), "-o", "/tmp/x.bmp"]), "unknown image extension");
    assert_one_line_error(
        &mrshade(&["render", "-q", &demo_session(), "-o", "/tmp/x.png", "--set", "shadows.resolutoin=1"]),
        "resolutoin",
    );
    assert_one_line_error(
        &mrshade(&["render", "-q", &demo_session(), "-o", "/tmp/x.png", "--width", "100", "--height", "100"]),
        "aspect",
    );
    assert_one_line_error(&mrshade(&["bench", "-q", &demo_session(), "--frames", "0"]), "--frames");
    // clap rejects unknown values itself, also with a non-zero exit.
    assert!(!mrshade(&["render", &demo_session(), "-o", "x.png", "--method", "magic"]).status.success());
}

#[test]
fn render_writes_png_exr_and_aovs() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("out.png");
    let exr = dir.path().join("out.exr");
    let aovs = dir.path().join("aovs");
    let o = mrshade(&[
        "render",
        &demo_session(),
        "--width",
        "64",
        "-o",
        png.to_str().unwrap(),
        "--aov-dir",
        aovs.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("adapter:"), "progress names the adapter");
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (64, 48));
    for f in [
        "l_rv.exr",
        "l_r.exr",
        "alpha.exr",
        "difference.exr",
        "difference_signed.png",
        "virtual_mask.png",
        "normals.png",
        "flags.png",
        "side_by_side.png",
    ] {
        assert!(aovs.join(f).is_file(), "AOV {f}");
    }
    let o = mrshade(&[
        "render",
        "-q",
        &demo_session(),
        "--width",
        "64",
        "--composite",
        "additive",
        "-o",
        exr.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let linear = image::open(&exr).unwrap().to_rgb32f();
    assert!(linear.pixels().any(|p| p.0[0] > 0.0));
}

#[test]
fn demo_needs_no_input() {
    let dir = tempfile::tempdir().unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_mrshade"))
        .args(["demo", "--width", "80"])
        .current_dir(dir.path())
        .env("XDG_RUNTIME_DIR", dir.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(Path::new(&dir.path().join("demo.png")).is_file());
}

#[test]
fn bench_reports_per_pass_gpu_time() {
    let dir = tempfile::tempdir().unwrap();
    let json = dir.path().join("bench.json");
    let session = demo_session();
    let bench = |extra: &[&str]| {
        let mut args = vec!["bench", "-q", "--frames", "3", "--warmup", "1", "--width", "64", "--json"];
        args.push(json.to_str().unwrap());
        args.extend_from_slice(extra);
        args.push(&session);
        let o = mrshade(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let report: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
        (o, report)
    };
    // A still scene keeps its shadow maps after the warm-up; a moving insert redraws them.
    let (_, still) = bench(&[]);
    assert!(still["passes"]["shadows"].is_null(), "{}", still["passes"]);
    let (o, report) = bench(&["--moving"]);
    assert_eq!(report["frames"], 3);
    assert!(!report["adapter"].as_str().unwrap().is_empty());
    for pass in ["shadows", "gbuffer", "direct", "composite"] {
        assert!(report["passes"][pass]["mean_ms"].as_f64().unwrap() > 0.0, "{pass}");
    }
    assert!(report["frame"]["p95_ms"].as_f64().unwrap() >= report["frame"]["mean_ms"].as_f64().unwrap() * 0.5);
    let table = String::from_utf8_lossy(&o.stdout);
    assert!(table.contains("frame") && table.contains("direct"), "{table}");
}

#[test]
fn info_lists_objects_and_flags() {
    let o = mrshade(&["info", "-q", &demo_session()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("virtual  torus")
            && out.contains("real     desk")
            && out.contains("light      real     desk-lamp"),
        "{out}"
    );
}

/// Writes a `w × h` RGB8 PNG whose pixel (x, y) is `f(x, y)`.
fn png(path: &Path, w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 3]) {
    let img = image::RgbImage::from_fn(w, h, |x, y| image::Rgb(f(x, y)));
    img.save(path).unwrap();
}

#[test]
fn compare_scores_images_and_names_misfits() {
    let dir = tempfile::tempdir().unwrap();
    let p = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    png(Path::new(&p("a.png")), 32, 16, |x, y| [(x * 8) as u8, (y * 16) as u8, 90]);
    png(Path::new(&p("b.png")), 32, 16, |x, y| [(x * 8) as u8, (y * 16) as u8, if x < 16 { 90 } else { 100 }]);
    png(Path::new(&p("left.png")), 32, 16, |x, _| if x < 16 { [255; 3] } else { [0; 3] });
    png(Path::new(&p("small.png")), 16, 16, |_, _| [0; 3]);
    // Identical images.
    let o = mrshade(&["compare", &p("a.png"), &p("a.png")]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("FLIP 0.0000"), "{}", String::from_utf8_lossy(&o.stdout));
    // Blue differs by 10 on the right half only: RMSE over the left half is 0, over all > 0.
    let o = mrshade(&["compare", &p("a.png"), &p("b.png"), "--json", "--heatmap", &p("heat.png")]);
    assert!(o.status.success(), "{}", stderr(&o));
    let all: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(all["rmse"].as_f64().unwrap() > 0.0 && all["flip"].as_f64().unwrap() > 0.0, "{all}");
    assert_eq!(image::open(p("heat.png")).unwrap().to_rgb8().dimensions(), (32, 16));
    let o = mrshade(&["compare", &p("a.png"), &p("b.png"), "--json", "--mask", &p("left.png")]);
    let left: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!((left["rmse"].as_f64(), left["pixels"].as_u64()), (Some(0.0), Some(256)), "{left}");
    // Misfits: one line each, naming the cause.
    assert_one_line_error(&mrshade(&["compare", &p("a.png"), &p("small.png")]), "32×16 and 16×16");
    assert_one_line_error(&mrshade(&["compare", &p("a.png"), &p("a.png"), "--mask", &p("small.png")]), "mask");
    assert_one_line_error(&mrshade(&["compare", &p("a.png"), &p("missing.png")]), "missing.png");
}
