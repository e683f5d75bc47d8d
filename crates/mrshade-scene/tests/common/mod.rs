//! What the glTF tests share: a document written to a temporary folder and loaded, or its
//! one-line error.
#![allow(dead_code, reason = "each test file uses a part")]

use mrshade_scene::gltf::load_gltf;
use mrshade_scene::{AssetSource, Scene};
use mrshade_testkit::gltf::GltfBuilder;

/// `b` loaded from `scene.gltf` + `scene.bin` in a temporary folder.
pub fn load(b: &GltfBuilder) -> Scene {
    let dir = tempfile::tempdir().unwrap();
    b.write_gltf(dir.path(), "scene");
    load_gltf(&AssetSource::dir(dir.path()), "scene.gltf", &Default::default()).unwrap()
}

/// The one-line error of loading `b`, which names the file.
pub fn error_of(b: &GltfBuilder) -> String {
    let dir = tempfile::tempdir().unwrap();
    b.write_gltf(dir.path(), "scene");
    let loaded = load_gltf(&AssetSource::dir(dir.path()), "scene.gltf", &Default::default());
    let msg = format!("{:#}", loaded.expect_err("must fail"));
    assert!(msg.contains("scene.gltf") && !msg.contains('\n'), "one line naming the file: {msg}");
    msg
}
