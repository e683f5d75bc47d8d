//! Skins and morph targets against hand math (the testkit's `SimpleSkin` and
//! `AnimatedMorphCube`-style models), the glTF conformance models of that kind, and broken
//! skins refused with one line naming the file and the field.

mod common;

use common::{error_of, load};

use glam::{Mat4, Quat, Vec3};
use mrshade_scene::gltf::load_gltf;
use mrshade_scene::{AssetSource, Scene, deform_vertices};
use mrshade_testkit::deform::{morph_box, simple_skin};
use mrshade_testkit::gltf::GltfBuilder;
use serde_json::json;

/// World positions of instance 0 at `time`, deformed on the CPU.
fn world_positions(scene: &Scene, time: f32) -> Vec<Vec3> {
    let pose = scene.pose_at(time).unwrap();
    let (positions, _) = deform_vertices(&scene.primitives[scene.instances[0].primitive], &pose.deformations[0]);
    positions.iter().map(|&p| pose.instances[0].transform_point3(p)).collect()
}

fn assert_close(got: &[Vec3], want: &[Vec3]) {
    assert_eq!(got.len(), want.len());
    for (v, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(g.abs_diff_eq(*w, 1e-5), "vertex {v}: {g} != {w}");
    }
}

#[test]
fn a_skinned_strip_bends_as_hand_math_says() {
    let mut b = GltfBuilder::new();
    let rotation = Quat::from_rotation_x(-0.3);
    let skin = simple_skin(&mut b, std::f32::consts::FRAC_PI_2, [0.2, 0.1, -0.3], rotation.to_array());
    let scene = load(&b);
    assert_eq!(scene.skins.len(), 1);
    assert_eq!(scene.instances[0].skin, Some(0));
    let world_from_root = Mat4::from_rotation_translation(rotation, Vec3::new(0.2, 0.1, -0.3));
    for t in [0.0, 0.25, 0.5, 1.0, 2.0] {
        assert_close(&world_positions(&scene, t), &skin.expected(t, world_from_root));
    }
    // The top of the strip swings by the bend: at 90° it points along −X from the joint.
    let top = world_positions(&scene, 1.0)[8];
    let joint = world_from_root.transform_point3(Vec3::Y);
    assert!((world_from_root.inverse().transform_vector3(top - joint)).abs_diff_eq(Vec3::new(-1.0, 0.0, 0.0), 1e-5));
    // Normals follow the joints: the bent rows still face the rotated +Z.
    let pose = scene.pose_at(1.0).unwrap();
    let (_, normals) = deform_vertices(&scene.primitives[0], &pose.deformations[0]);
    assert!(normals[9].abs_diff_eq(rotation * Vec3::Z, 1e-5), "{}", normals[9]);
    // The rest pose (what a still renders) is the pose with the joints where the nodes are.
    assert_close(
        &deform_vertices(&scene.primitives[0], &scene.rest_pose().deformations[0]).0,
        &skin.expected(0.0, world_from_root),
    );
}

#[test]
fn a_morphing_box_follows_its_weights() {
    let mut b = GltfBuilder::new();
    let morph = morph_box(&mut b, [1.0, 2.0, 3.0]);
    let scene = load(&b);
    assert_eq!(scene.primitives[0].targets.len(), 2);
    for t in [0.0, 0.3, 1.0, 5.0] {
        let want: Vec<Vec3> = morph.expected(t).iter().map(|p| *p + Vec3::new(1.0, 2.0, 3.0)).collect();
        assert_close(&world_positions(&scene, t), &want);
    }
    assert_eq!(scene.pose_at(0.5).unwrap().deformations[0].morph_weights, vec![0.5, 0.25]);
    // Rest weights come from the node (or the mesh): here none, zeros.
    assert_eq!(scene.rest_pose().deformations[0].morph_weights, vec![0.0, 0.0]);
}

#[test]
fn a_mesh_used_twice_is_deformed_per_instance() {
    let mut b = GltfBuilder::new();
    let morph = morph_box(&mut b, [0.0; 3]);
    let mesh = b.json(None)["nodes"][morph.node]["mesh"].clone();
    b.node(json!({"name": "second", "mesh": mesh, "weights": [0.0, 1.0]}));
    let scene = load(&b);
    assert_eq!(scene.instances.len(), 2);
    assert_ne!(scene.instances[0].primitive, scene.instances[1].primitive);
    assert_eq!(scene.rest_pose().deformations[1].morph_weights, vec![0.0, 1.0]);
}

#[test]
fn broken_skins_are_one_line_errors() {
    let mut b = GltfBuilder::new();
    simple_skin(&mut b, 1.0, [0.0; 3], [0.0, 0.0, 0.0, 1.0]);
    // Weights that do not sum to one (vertex 0's first weight doubled).
    let msg = edited_error(&b, |doc, bin| {
        let accessor = doc["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"].as_u64().unwrap() as usize;
        let view = doc["accessors"][accessor]["bufferView"].as_u64().unwrap() as usize;
        let offset = doc["bufferViews"][view]["byteOffset"].as_u64().unwrap() as usize;
        bin[offset..offset + 4].copy_from_slice(&2.0f32.to_le_bytes());
    });
    assert!(msg.contains("WEIGHTS_0") && msg.contains("vertex 0") && msg.contains("sum to 2"), "{msg}");
    // A joint that is not a node of the scene: `bend` unhooked from `root`.
    let msg = edited_error(&b, |doc, _| doc["nodes"][0]["children"] = json!([]));
    assert!(msg.contains("skin 'strip'") && msg.contains("'bend'") && msg.contains("not in the scene"), "{msg}");
    // A joint index past the skin's joints: the skin cut to its first joint.
    let msg = edited_error(&b, |doc, _| {
        doc["skins"][0]["joints"] = json!([0]);
        let ibm = doc["skins"][0]["inverseBindMatrices"].as_u64().unwrap() as usize;
        doc["accessors"][ibm]["count"] = json!(1);
    });
    assert!(msg.contains("JOINTS_0") && msg.contains("joint 1") && msg.contains("1 joints"), "{msg}");
    // Inverse bind matrices that cannot be inverted.
    let msg = edited_error(&b, |doc, bin| {
        let ibm = doc["skins"][0]["inverseBindMatrices"].as_u64().unwrap() as usize;
        let view = doc["accessors"][ibm]["bufferView"].as_u64().unwrap() as usize;
        let offset = doc["bufferViews"][view]["byteOffset"].as_u64().unwrap() as usize;
        bin[offset..offset + 64].fill(0);
    });
    assert!(msg.contains("inverse bind matrix 0"), "{msg}");
    // JOINTS_0 without WEIGHTS_0.
    let msg = edited_error(&b, |doc, _| {
        doc["meshes"][0]["primitives"][0]["attributes"].as_object_mut().unwrap().remove("WEIGHTS_0");
    });
    assert!(msg.contains("JOINTS_0 without WEIGHTS_0"), "{msg}");
}

/// The one-line error of loading `b` after `edit` changed its JSON and binary buffer.
fn edited_error(b: &GltfBuilder, edit: impl FnOnce(&mut serde_json::Value, &mut Vec<u8>)) -> String {
    let dir = tempfile::tempdir().unwrap();
    let mut doc = b.json(Some("scene.bin"));
    let mut bin = b.bin().to_vec();
    edit(&mut doc, &mut bin);
    std::fs::write(dir.path().join("scene.bin"), &bin).unwrap();
    std::fs::write(dir.path().join("scene.gltf"), serde_json::to_vec(&doc).unwrap()).unwrap();
    let source = AssetSource::dir(dir.path());
    let msg = format!("{:#}", load_gltf(&source, "scene.gltf", &Default::default()).expect_err("must fail"));
    assert!(msg.contains("scene.gltf") && !msg.contains('\n'), "one line naming the file: {msg}");
    msg
}

#[test]
fn morph_weights_must_be_finite() {
    let mut b = GltfBuilder::new();
    let morph = morph_box(&mut b, [0.0; 3]);
    b.patch_node(morph.node, |n| n["weights"] = json!([1e39, 0.0]));
    let msg = error_of(&b);
    assert!(msg.contains("weight") && msg.contains("node 'morph'"), "{msg}");
    // Finite, but displacing the box 4·10⁹ m (found by the fuzzer: the path tracer's BVH
    // builder panicked on it).
    let mut b = GltfBuilder::new();
    let morph = morph_box(&mut b, [0.0; 3]);
    b.patch_node(morph.node, |n| n["weights"] = json!([4294967300.0, 0.0]));
    let msg = error_of(&b);
    assert!(msg.contains("node 'morph' in its rest pose") && msg.contains("beyond"), "{msg}");
}
