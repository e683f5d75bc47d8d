//! Broken glTF files give clear errors naming the file and the element, never a panic.

use mrshade_scene::AssetSource;
use mrshade_scene::gltf::load_gltf;
use mrshade_testkit::gltf::{GltfBuilder, quad};
use serde_json::json;

/// Writes `b` to a temp dir, lets `tamper` change the files, loads, returns the error text.
fn error_of(b: &GltfBuilder, tamper: impl FnOnce(&std::path::Path)) -> String {
    let dir = tempfile::tempdir().unwrap();
    b.write_gltf(dir.path(), "scene");
    tamper(dir.path());
    let err = load_gltf(&AssetSource::dir(dir.path()), "scene.gltf", &Default::default()).expect_err("must fail");
    let msg = format!("{err:#}");
    assert!(msg.contains("scene.gltf"), "the error names the file: {msg}");
    msg
}

fn simple() -> GltfBuilder {
    let mut b = GltfBuilder::new();
    let mesh = b.mesh(&quad(1.0), None, true);
    b.node(json!({"name": "desk", "mesh": mesh}));
    b
}

#[test]
fn truncated_bin() {
    let msg = error_of(&simple(), |d| {
        let bin = std::fs::read(d.join("scene.bin")).unwrap();
        std::fs::write(d.join("scene.bin"), &bin[..bin.len() / 2]).unwrap();
    });
    assert!(msg.contains("truncated"), "{msg}");
}

#[test]
fn missing_bin() {
    let msg = error_of(&simple(), |d| std::fs::remove_file(d.join("scene.bin")).unwrap());
    assert!(msg.contains("scene.bin") && msg.contains("not found"), "{msg}");
}

#[test]
fn wrong_accessor_type_for_position() {
    let mut b = simple();
    b.patch_accessor(0, |a| a["type"] = json!("VEC2"));
    let msg = error_of(&b, |_| {});
    assert!(msg.contains("POSITION") && msg.contains("Vec2") && msg.contains("expected Vec3"), "{msg}");
}

#[test]
fn wrong_component_type_for_indices() {
    let mut b = simple();
    let indices = 3; // POSITION, NORMAL, TEXCOORD_0, then indices
    b.patch_accessor(indices, |a| a["componentType"] = json!(5126));
    let msg = error_of(&b, |_| {});
    assert!(msg.contains("indices") && msg.contains("F32"), "{msg}");
}

#[test]
fn accessor_count_past_its_buffer_view() {
    let mut b = simple();
    b.patch_accessor(1, |a| a["count"] = json!(1000));
    let msg = error_of(&b, |_| {});
    assert!(msg.contains("do not fit") || msg.contains("NORMAL has 1000"), "{msg}");
}

#[test]
fn index_out_of_range() {
    let mut b = GltfBuilder::new();
    let mut shape = quad(1.0);
    shape.indices[2] = 99;
    let mesh = b.mesh(&shape, None, true);
    b.node(json!({"mesh": mesh}));
    let msg = error_of(&b, |_| {});
    // The position of the bad index, not its value: values are bytes of a file that may not
    // be the scene's.
    assert!(msg.contains("index 2 of the index list is out of range for 4 vertices") && !msg.contains("99"), "{msg}");
}

#[test]
fn nan_positions() {
    let mut b = GltfBuilder::new();
    let mut shape = quad(1.0);
    shape.positions[1][1] = f32::NAN;
    let mesh = b.mesh(&shape, None, true);
    b.node(json!({"mesh": mesh}));
    let msg = error_of(&b, |_| {});
    assert!(msg.contains("NaN"), "{msg}");
}

#[test]
fn not_json_and_empty_files() {
    for contents in [&b""[..], b"{ not json", b"glTF\x02\x00\x00\x00"] {
        let msg = error_of(&simple(), |d| std::fs::write(d.join("scene.gltf"), contents).unwrap());
        assert!(msg.contains("empty") || msg.contains("not valid glTF") || msg.contains("truncated"), "{msg}");
    }
}

#[test]
fn dangling_indices_fail_validation() {
    let mut b = simple();
    b.node(json!({"name": "ghost", "mesh": 42}));
    let msg = error_of(&b, |_| {});
    assert!(msg.contains("invalid glTF") && msg.contains("mesh"), "{msg}");
}

#[test]
fn real_flag_of_the_wrong_type() {
    let mut b = GltfBuilder::new();
    let mesh = b.mesh(&quad(1.0), None, true);
    b.node(json!({"name": "desk", "mesh": mesh, "extras": {"real": "yes"}}));
    let msg = error_of(&b, |_| {});
    assert!(msg.contains("'desk'") && msg.contains("extras.real must be true or false"), "{msg}");
}

#[test]
fn impossible_spot_cone() {
    let mut b = simple();
    let l = b.light(json!({"type": "spot", "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.2}}));
    b.node(json!({"name": "lamp", "extensions": {"KHR_lights_punctual": {"light": l}}}));
    let msg = error_of(&b, |_| {});
    assert!(msg.contains("cone"), "{msg}");
}

#[test]
fn material_factor_out_of_range() {
    let mut b = GltfBuilder::new();
    let m = b.material(json!({"name": "shiny", "pbrMetallicRoughness": {"metallicFactor": 1.5}}));
    let mesh = b.mesh(&quad(1.0), Some(m), true);
    b.node(json!({"mesh": mesh}));
    let msg = error_of(&b, |_| {});
    assert!(msg.contains("'shiny'") && msg.contains("metallicFactor 1.5"), "{msg}");
}

#[test]
fn remote_buffer_uris_are_refused() {
    let b = simple();
    let msg = error_of(&b, |d| {
        let text = std::fs::read_to_string(d.join("scene.gltf"))
            .unwrap()
            .replace("\"scene.bin\"", "\"https://example.com/x.bin\"");
        std::fs::write(d.join("scene.gltf"), text).unwrap();
    });
    assert!(msg.contains("not a relative path"), "{msg}");
}
