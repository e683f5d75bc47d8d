//! `mrshade eval` on a sequence dataset (`assets/sequence/desk-orbit-mini`: 12 frames of
//! 80×60) from the command line. The renders are kept short for lavapipe: `direct` (one frame
//! per still), and `dir` with `output.frames=2`.

mod common;

use common::{copy_mini, mini, mrshade, stderr};
use std::path::Path;
use std::process::Output;

fn finite(v: &serde_json::Value) -> bool {
    v.as_f64().is_some_and(f64::is_finite)
}

#[test]
fn eval_scores_every_frame_of_a_sequence_and_its_stills() {
    let dir = tempfile::tempdir().unwrap();
    let report = dir.path().join("report");
    let o = mrshade(&[
        "eval",
        &mini(),
        "--method",
        "direct,reference",
        "--spp",
        "1",
        "--stills",
        "--set",
        "sequence.samples=2",
        "--report",
        report.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout).into_owned();
    for row in ["| desk-orbit-mini | photo |", "| desk-orbit-mini | direct |", "| desk-orbit-mini | direct-stills |"] {
        assert!(table.contains(row), "{table}");
    }
    assert!(table.contains("| desk-orbit-mini | reference | 1 spp per frame |"), "{table}");
    // The quality bar, footage against stills over frames 4.., in the log and the report.
    let bar = "desk-orbit-mini direct: mean FLIP region over frames 4..11: sequence ";
    assert!(stderr(&o).contains(bar) && table.contains(&format!("- {bar}")), "{table}");

    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("report.json")).unwrap()).unwrap();
    let seq = &json["sequences"][0];
    assert_eq!(seq["frames"].as_array().unwrap().len(), 12);
    let runs = seq["runs"].as_array().unwrap();
    let methods: Vec<&str> = runs.iter().map(|r| r["method"].as_str().unwrap()).collect();
    assert_eq!(methods, ["direct", "direct-stills", "reference"]);
    for run in runs.iter().chain([&seq["photo"]]) {
        let frames = run["frames"].as_array().unwrap();
        assert_eq!(frames.len(), 12, "{}", run["method"]);
        for f in frames {
            assert!(finite(&f["flip_region"]) && finite(&f["flip_frame"]) && finite(&f["psnr_frame"]), "{f}");
            for key in ["result", "heatmap"] {
                assert!(report.join(f[key].as_str().unwrap()).is_file(), "{f}");
            }
        }
        let s = &run["summary"];
        assert!(finite(&s["flip_region"]) && finite(&s["flip_region_from4"]) && s["worst_frame"].is_string());
    }
    // Inserting the objects beats inserting nothing on every frame.
    assert_eq!(runs[0]["summary"]["beats_photo"], 12);
    assert!(seq["photo"]["summary"]["beats_photo"].is_null());
    let bar = &seq["quality_bars"][0];
    assert_eq!(bar["method"], "direct");
    let ratio = bar["sequence"].as_f64().unwrap() / bar["stills"].as_f64().unwrap();
    assert!((bar["ratio"].as_f64().unwrap() - ratio).abs() < 1e-9 && bar["met"] == (ratio <= 1.3), "{bar}");
    assert!(report.join("desk-orbit-mini/answer/0022.png").is_file());

    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(html.contains("<svg") && html.matches("<polyline").count() == 4, "photo and three runs plotted");
    assert!(html.contains("type=\"range\"") && html.contains("<select") && html.contains("oninput"));
    assert!(report.join("report.md").is_file());
}

#[test]
fn eval_plays_a_temporal_method_through_the_sequence() {
    let o = mrshade(&["eval", &mini(), "--method", "dir", "--set", "output.frames=2", "--set", "sequence.samples=2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let table = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        table.contains("| desk-orbit-mini | dir | footage, 2 samples per frame, settles over 1 frame |"),
        "{table}"
    );
    assert!(table.contains("12/12"), "dir beats the photo on every frame: {table}");
}

#[test]
fn eval_names_the_frame_a_sequence_lacks() {
    let dir = tempfile::tempdir().unwrap();
    let orbit = copy_mini(dir.path());
    let one_line = |o: &Output, needles: &[&str]| {
        assert!(!o.status.success());
        let err = stderr(o);
        assert!(err.trim().lines().count() == 1 && needles.iter().all(|n| err.contains(n)), "{err}");
    };
    let args = ["eval", "-q", orbit.to_str().unwrap(), "--method", "direct"];

    std::fs::remove_file(orbit.join("ground_truth/0006.png")).unwrap();
    one_line(&mrshade(&args), &["orbit", "frame 0006", "ground_truth/0006.png"]);

    std::fs::copy(orbit.join("ground_truth/0004.png"), orbit.join("ground_truth/0006.png")).unwrap();
    image::RgbImage::new(40, 30).save(orbit.join("ground_truth/0010.png")).unwrap();
    one_line(&mrshade(&args), &["frame 0010", "40×30"]);

    // The path tracer renders centred pinholes only: refused before anything renders.
    std::fs::copy(Path::new(&mini()).join("ground_truth/0010.png"), orbit.join("ground_truth/0010.png")).unwrap();
    let transforms = std::fs::read_to_string(orbit.join("transforms.json")).unwrap();
    let shifted = transforms.replacen("\"cx\": 40.0", "\"cx\": 30.0", 1);
    assert_ne!(shifted, transforms, "the test edits the principal point");
    std::fs::write(orbit.join("transforms.json"), shifted).unwrap();
    one_line(&mrshade(&["eval", "-q", orbit.to_str().unwrap(), "--method", "reference"]), &["reference", "off-centre"]);
}
