//! `mrshade reference` and `mrshade eval` from the command line.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn mrshade(args: &[&str]) -> Output {
    let runtime = std::env::temp_dir().join("mrshade-xdg-runtime");
    std::fs::create_dir_all(&runtime).unwrap();
    Command::new(env!("CARGO_BIN_EXE_mrshade")).args(args).env("XDG_RUNTIME_DIR", runtime).output().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn assets(rel: &str) -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/").to_string() + rel
}

#[test]
fn reference_renders_an_image_and_its_aovs() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("ref.png");
    let aovs = dir.path().join("aovs");
    let session = assets("demo/session.toml");
    let o = mrshade(&[
        "reference",
        &session,
        "--width",
        "48",
        "--spp",
        "4",
        "-o",
        png.to_str().unwrap(),
        "--aov-dir",
        aovs.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("4 spp"), "progress says what it does");
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (48, 36));
    for f in ["l_rv.exr", "l_r.exr", "alpha.exr", "virtual_mask.png", "side_by_side.png"] {
        assert!(aovs.join(f).is_file(), "AOV {f}");
    }
    let o = mrshade(&["reference", "-q", &session, "--spp", "0", "-o", png.to_str().unwrap()]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.trim().lines().count() == 1 && err.contains("reference.spp"), "{err}");
}

#[test]
fn eval_scores_methods_and_writes_a_report() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report");
    let dataset = assets("benchmark/desk-bunny");
    let o = mrshade(&[
        "eval",
        &dataset,
        "--method",
        "direct,reference",
        "--spp",
        "4",
        "--report",
        report.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        table.contains("| desk-bunny | direct |") && table.contains("| desk-bunny | reference | 4 spp |"),
        "{table}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("report.json")).unwrap()).unwrap();
    let rows = json["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    for row in rows {
        let flip = row["flip_region"].as_f64().unwrap();
        assert!(flip > 0.0 && flip < 0.5, "{row}");
        for key in ["result", "heatmap", "photo", "answer"] {
            let rel = row["images"][key].as_str().unwrap();
            assert!(report.join(rel).is_file(), "{rel}");
        }
    }
    // The path tracer is closer to the answer than direct light alone.
    assert!(rows[1]["flip_region"].as_f64() < rows[0]["flip_region"].as_f64());
    assert!(report.join("report.md").is_file() && report.join("index.html").is_file());
}

#[test]
fn eval_names_what_a_dataset_lacks() {
    let dir = tempfile::tempdir().unwrap();
    let dataset: PathBuf = dir.path().join("scene");
    std::fs::create_dir_all(&dataset).unwrap();
    std::fs::copy(assets("benchmark/desk-bunny/session.toml"), dataset.join("session.toml")).unwrap();
    let o = mrshade(&["eval", "-q", dataset.to_str().unwrap(), "--method", "reference"]);
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.trim().lines().count() == 1 && err.contains("background.png"), "{err}");
    assert!(!Path::new(&dataset.join("report.md")).exists());
}

#[test]
fn eval_rejects_misfit_answers_and_unknown_methods() {
    let dir = tempfile::tempdir().unwrap();
    let dataset = dir.path().join("scene");
    std::fs::create_dir_all(&dataset).unwrap();
    for f in ["session.toml", "scene.glb", "environment.exr", "background.png", "ground_truth.png"] {
        std::fs::copy(assets(&format!("benchmark/desk-bunny/{f}")), dataset.join(f)).unwrap();
    }
    let one_line = |o: &Output, needle: &str| {
        assert!(!o.status.success());
        let err = stderr(o);
        assert!(err.trim().lines().count() == 1 && err.contains(needle), "{err}");
    };
    let args = ["eval", "-q", dataset.to_str().unwrap(), "--method", "reference", "--spp", "1"];
    // An answer that is not an image.
    std::fs::write(dataset.join("ground_truth.png"), b"not a png").unwrap();
    one_line(&mrshade(&args), "ground_truth.png");
    // An answer of another size than the photo.
    image::RgbImage::new(40, 30).save(dataset.join("ground_truth.png")).unwrap();
    one_line(&mrshade(&args), "differ in size");
    // clap rejects an unknown method, naming the known ones.
    let o = mrshade(&["eval", dataset.to_str().unwrap(), "--method", "magic"]);
    assert!(!o.status.success() && stderr(&o).contains("reference"), "{}", stderr(&o));
}

#[test]
fn eval_times_methods_on_the_gpu_and_gives_them_equal_budgets() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report");
    let dataset = assets("benchmark/desk-bunny");
    // dir's still is 256 frames; a budget of a few milliseconds of lavapipe fits fewer.
    let o = mrshade(&[
        "eval",
        &dataset,
        "--method",
        "direct,dir",
        "--set",
        "output.frames=6",
        "--budget-ms",
        "1,1000000",
        "--report",
        report.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("report.json")).unwrap()).unwrap();
    let rows = json["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 4, "one row per method and budget");
    for row in rows {
        let total = row["gpu_ms"].as_f64().unwrap();
        let per_frame = row["gpu_ms_frame"].as_f64().unwrap();
        assert!(total > 0.0 && per_frame > 0.0 && per_frame <= total, "{row}");
    }
    // 1 ms fits one frame at least; a huge budget fits the whole still.
    assert_eq!(rows[0]["setting"], "1 frame in 1 GPU ms");
    assert_eq!(rows[3]["setting"], "6 frames in 1000000 GPU ms");
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(html.contains("Error against GPU time") && html.contains("<svg"), "the chart");
    // A budget must be a positive number of milliseconds: one line naming it.
    let o = mrshade(&["eval", "-q", &dataset, "--method", "direct", "--budget-ms", "0"]);
    assert!(!o.status.success() && stderr(&o).contains("budget"), "{}", stderr(&o));
}
