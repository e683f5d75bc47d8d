//! Inserting models from their own glTF files into a benchmark scene's photo, from the
//! command line: conformance samples of assimp's glTF 2.0 test models render (a few, small,
//! on lavapipe; `scripts/gltf-conformance.sh` runs all of them), invalid ones and bad
//! `[[insert]]` tables are one-line errors naming the file and the field, and a session
//! without a glTF camera places its own.

mod common;

use common::{assert_one_line_error, mrshade, stderr};
use std::path::{Path, PathBuf};

/// The repository's folder `rel`.
fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").join(rel)
}

/// A copy of `desk-spot-real` in `dir` with the conformance samples beside it, and its
/// session file with `tables` appended.
fn desk_with(dir: &Path, tables: &str) -> PathBuf {
    for entry in std::fs::read_dir(repo("assets/benchmark/desk-spot-real")).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), dir.join(entry.file_name())).unwrap();
    }
    for entry in std::fs::read_dir(repo("tests/assets/gltf2")).unwrap() {
        let entry = entry.unwrap();
        if entry.path().is_file() {
            std::fs::copy(entry.path(), dir.join(entry.file_name())).unwrap();
        }
    }
    std::fs::create_dir(dir.join("draco")).unwrap();
    for file in ["2CylinderEngine.gltf", "2CylinderEngine.bin"] {
        std::fs::copy(repo("tests/assets/gltf2/draco").join(file), dir.join("draco").join(file)).unwrap();
    }
    let session = dir.join("session.toml");
    let text = std::fs::read_to_string(&session).unwrap();
    std::fs::write(&session, format!("{text}\n{tables}")).unwrap();
    session
}

/// An `[[insert]]` of `model`, 12 cm tall on the desk in front of the torus.
fn insert(model: &str, extra: &str) -> String {
    format!("[[insert]]\nmodel = \"{model}\"\ntranslation = [0.05, 0.0, 0.2]\nfit = 0.12\n{extra}\n")
}

fn render(session: &Path, out: &Path) -> std::process::Output {
    let (s, o) = (session.to_str().unwrap(), out.to_str().unwrap());
    mrshade(&["render", s, "-q", "-o", o, "--method", "direct", "--width", "160", "--height", "120"])
}

fn mean_abs_difference(a: &Path, b: &Path) -> f64 {
    let (a, b) = (image::open(a).unwrap().to_rgb8(), image::open(b).unwrap().to_rgb8());
    let sum: u64 = a.as_raw().iter().zip(b.as_raw()).map(|(x, y)| x.abs_diff(*y) as u64).sum();
    sum as f64 / a.as_raw().len() as f64
}

#[test]
fn conformance_samples_render_on_the_desk() {
    let dir = tempfile::tempdir().unwrap();
    let plain = desk_with(dir.path(), "");
    let without = dir.path().join("without.png");
    assert!(render(&plain, &without).status.success());
    for (model, extra) in [
        ("BoxTextured.glb", ""),
        ("simple_skin.gltf", "time_offset = 0.5"),
        ("AnimatedMorphCube.gltf", "rotation_deg = [0, 30, 0]"),
        ("Mesh_PrimitiveMode_15.gltf", ""),
        ("draco/2CylinderEngine.gltf", ""),
    ] {
        let sub = tempfile::tempdir().unwrap();
        let session = desk_with(sub.path(), &insert(model, extra));
        let out = sub.path().join("with.png");
        let o = render(&session, &out);
        assert!(o.status.success(), "{model}: {}", stderr(&o));
        // The model is there: the image differs from the scene without it.
        let change = mean_abs_difference(&without, &out);
        assert!(change > 0.05, "{model}: the insert changed the image by only {change}");
    }
    // Lines are valid glTF but have no surface: the photo renders, with a warning.
    let sub = tempfile::tempdir().unwrap();
    let session = desk_with(sub.path(), &insert("Mesh_PrimitiveMode_01.gltf", ""));
    let (s, out) = (session.to_str().unwrap(), sub.path().join("lines.png"));
    let o = mrshade(&["render", s, "-o", out.to_str().unwrap(), "--method", "direct", "--width", "160"]);
    let err = stderr(&o);
    assert!(
        o.status.success() && err.contains("Lines primitives are not rendered") && err.contains("no triangles to fit"),
        "{err}"
    );
}

#[test]
fn invalid_models_and_bad_inserts_are_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (insert("IndexOutOfRange.gltf", ""), "IndexOutOfRange.gltf"),
        (insert("RecursiveNodes.gltf", ""), "cycle"),
        (insert("missing.glb", ""), "insert[0].model"),
        (insert("background.png", ""), "not valid glTF"),
        (insert("BoxTextured.glb", "rotation = [0, 1, 0, 1]"), "not a unit quaternion"),
        (insert("BoxTextured.glb", "rotation = [0, 0, 0, 1]\nrotation_deg = [0, 90, 0]"), "insert[0].rotation"),
        (insert("BoxTextured.glb", "scale = 2"), "not both"),
        (insert("BoxTextured.glb", "parent = \"shelf\""), "no node named 'shelf'"),
        (insert("simple_skin.gltf", "animation = \"dance\""), "no animation 'dance'"),
        (insert("BoxTextured.glb", "colour = 3"), "colour"),
        (insert("BoxTextured.glb", "name = \"desk\""), "already has a node"),
    ];
    for (i, (table, needle)) in cases.iter().enumerate() {
        let sub = dir.path().join(format!("case{i}"));
        std::fs::create_dir(&sub).unwrap();
        let session = desk_with(&sub, table);
        let o = render(&session, &sub.join("out.png"));
        assert_one_line_error(&o, needle);
    }
    // A damaged Draco bitstream (its bytes scrambled past the header).
    let sub = dir.path().join("draco");
    std::fs::create_dir(&sub).unwrap();
    let session = desk_with(&sub, &insert("draco/2CylinderEngine.gltf", ""));
    let bin = sub.join("draco/2CylinderEngine.bin");
    let mut bytes = std::fs::read(&bin).unwrap();
    for (i, b) in bytes.iter_mut().enumerate().skip(16).take(4000) {
        *b = (i as u8).wrapping_mul(31);
    }
    std::fs::write(&bin, bytes).unwrap();
    assert_one_line_error(&render(&session, &sub.join("out.png")), "KHR_draco_mesh_compression");
}

#[test]
fn a_session_places_its_own_camera() {
    let dir = tempfile::tempdir().unwrap();
    // The desk's own camera, and the same pose given by a [camera] table: the same image.
    let session = desk_with(dir.path(), "");
    let own = dir.path().join("own.png");
    assert!(render(&session, &own).status.success());
    let text = std::fs::read_to_string(&session).unwrap();
    // camera node: at (0.1, 0.4, 0.72), turned down by 2·asin(0.2149…) about an axis near +X.
    let placed = format!(
        "camera = {{ position = [0.1, 0.4, 0.72], look_at = [{}, {}, {}], up = [{}, {}, {}], yfov_deg = 45.0 }}\n{text}",
        0.1 + LOOK[0],
        0.4 + LOOK[1],
        0.72 + LOOK[2],
        UP[0],
        UP[1],
        UP[2]
    );
    std::fs::write(&session, placed).unwrap();
    let table = dir.path().join("table.png");
    let o = render(&session, &table);
    assert!(o.status.success(), "{}", stderr(&o));
    let change = mean_abs_difference(&own, &table);
    assert!(change < 1.0, "the placed camera sees another image (mean difference {change})");
    // A table without a field of view is refused.
    std::fs::write(&session, format!("camera = {{ position = [0, 1, 1], look_at = [0, 0, 0] }}\n{text}")).unwrap();
    assert_one_line_error(&render(&session, &table), "field of view is missing");
}

/// −Z and +Y of the desk camera's rotation (x, y, z, w) = (−0.21491945669802462,
/// 0.06301447451297766, 0.013897454415555403, 0.9744976469418727).
const LOOK: [f64; 3] = look_and_up().0;
const UP: [f64; 3] = look_and_up().1;

const fn look_and_up() -> ([f64; 3], [f64; 3]) {
    let (x, y, z, w) = (-0.21491945669802462, 0.06301447451297766, 0.013897454415555403, 0.9744976469418727);
    // Columns of the rotation matrix: R·(0,0,−1) = −column 2, R·(0,1,0) = column 1.
    let col1 = [2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x)];
    let col2 = [2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y)];
    ([-col2[0], -col2[1], -col2[2]], col1)
}
