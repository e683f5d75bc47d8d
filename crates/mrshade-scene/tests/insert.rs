//! `Scene::insert`: a model's meshes, lights, skins and animations placed under a new node,
//! with its indices offset and its flags set by the insert.

mod common;

use common::load;

use glam::{Mat4, Quat, Vec3};
use mrshade_core::flags::Realness;
use mrshade_scene::{Placement, Trs};
use mrshade_testkit::deform::morph_box;
use mrshade_testkit::gltf::{GltfBuilder, cuboid, lambert};
use serde_json::json;

#[test]
fn an_insert_brings_its_meshes_lights_and_animations_under_its_node() {
    // The scene: a real table node at (1, 0, 0), turned 90° about +Y.
    let mut s = GltfBuilder::new();
    let m = s.material(lambert("table", [0.5; 3]));
    let mesh = s.mesh(&cuboid([0.5, 0.05, 0.5]), Some(m), true);
    let turned = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
    s.node(json!({"name": "table", "mesh": mesh, "translation": [1.0, 0.0, 0.0], "rotation": turned.to_array(),
        "extras": {"real": true}}));
    let mut scene = load(&s);
    // The model: a textured-less box with a point light 1 m above it, and a morphing box.
    let mut b = GltfBuilder::new();
    let m = b.material(lambert("red", [0.8, 0.1, 0.1]));
    let mesh = b.mesh(&cuboid([0.1; 3]), Some(m), true);
    let light = b.light(json!({"type": "point", "intensity": 2.0}));
    let holder = b.node(json!({"name": "holder", "mesh": mesh}));
    b.child(
        holder,
        json!({"name": "bulb", "translation": [0.0, 1.0, 0.0],
        "extensions": {"KHR_lights_punctual": {"light": light}}}),
    );
    morph_box(&mut b, [0.0, 0.0, 0.5]);
    let model = load(&b);
    let (materials, primitives) = (scene.materials.len(), scene.primitives.len());
    let placement = Placement {
        name: "lamp".into(),
        local: Trs { translation: Vec3::new(0.0, 0.1, 0.0), rotation: Quat::IDENTITY, scale: Vec3::splat(2.0) },
        parent: scene.node_named("table"),
        realness: Realness::Virtual,
        animation: Some("morph".into()),
        time_offset: 0.5,
    };
    let node = scene.insert(model, &placement).unwrap();
    assert_eq!(scene.nodes[node].name, "lamp");
    assert_eq!(scene.instances.len(), 3);
    let world_from_lamp = Mat4::from_rotation_translation(turned, Vec3::X) * placement.local.matrix();
    // The box: under the table's transform and the insert's, its material offset.
    let box_instance = &scene.instances[1];
    assert!(box_instance.world_from_object.abs_diff_eq(world_from_lamp, 1e-6));
    assert_eq!(scene.primitives[box_instance.primitive].material, materials, "its first material, after the scene's");
    assert!(box_instance.primitive >= primitives);
    assert_eq!(box_instance.realness, Realness::Virtual);
    assert_eq!(scene.instances[0].realness, Realness::Real);
    // The light: 1 m above the box in the model, 2 m once scaled, rigid, virtual.
    let light = &scene.lights[0];
    assert!(light.position().abs_diff_eq(world_from_lamp.transform_point3(Vec3::Y), 1e-5), "{}", light.position());
    assert_eq!(light.realness, Realness::Virtual);
    // The animation plays with the offset: scene time 0 is the model's 0.5 s.
    assert_eq!(scene.animations.len(), 1);
    let morph = scene.instances.iter().position(|i| !scene.primitives[i.primitive].targets.is_empty()).unwrap();
    assert_eq!(scene.pose_at(0.0).unwrap().deformations[morph].morph_weights, vec![0.5, 0.25]);
    assert_eq!(scene.time_range(), Some((-0.5, 0.5)));
    // Moving the insert node moves everything it holds.
    let moved = Trs { translation: Vec3::new(0.0, 0.5, 0.0), ..placement.local };
    let pose = scene.pose_with(0.0, &[(node, moved)]).unwrap();
    let world_moved = Mat4::from_rotation_translation(turned, Vec3::X) * moved.matrix();
    assert!(pose.instances[1].abs_diff_eq(world_moved, 1e-6));
    assert!(pose.lights[0].transform_point3(Vec3::ZERO).abs_diff_eq(world_moved.transform_point3(Vec3::Y), 1e-5));
    // A second insert of the same name is refused.
    let again = scene.insert(load(&b), &placement).unwrap_err().to_string();
    assert!(again.contains("already has a node"), "{again}");
}
