//! glTF features the loader must honour.

mod common;

use common::load;

use glam::{Mat4, Vec3};
use mrshade_core::flags::Realness;
use mrshade_scene::gltf::{load_gltf, load_gltf_bytes};
use mrshade_scene::{AssetSource, LightKind};
use mrshade_testkit::gltf::{GltfBuilder, cuboid, lambert, quad, quat};
use serde_json::json;

#[test]
fn hierarchy_composes_trs_and_matrices() {
    let mut b = GltfBuilder::new();
    let mesh = b.mesh(&quad(1.0), None, true);
    let parent = b.node(json!({"name": "parent", "translation": [1.0, 0.0, 0.0], "scale": [2.0, 2.0, 2.0]}));
    // Column-major matrix: translate by (0, 3, 0).
    b.child(parent, json!({"name": "child", "mesh": mesh, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,3,0,1]}));
    let scene = load(&b);
    assert_eq!(scene.instances.len(), 1);
    let m = scene.instances[0].world_from_object;
    // Parent scale applies to the child's translation: (1, 0, 0) + 2·(0, 3, 0).
    assert!(m.transform_point3(Vec3::ZERO).abs_diff_eq(Vec3::new(1.0, 6.0, 0.0), 1e-6));
    assert!(m.transform_vector3(Vec3::X).abs_diff_eq(Vec3::new(2.0, 0.0, 0.0), 1e-6));
}

#[test]
fn realness_is_inherited_and_can_be_overridden() {
    let mut b = GltfBuilder::new();
    let mesh = b.mesh(&quad(1.0), None, true);
    let room = b.node(json!({"name": "room", "extras": {"real": true}}));
    b.child(room, json!({"name": "wall", "mesh": mesh}));
    b.child(room, json!({"name": "inserted", "mesh": mesh, "extras": {"real": false}}));
    b.node(json!({"name": "loose", "mesh": mesh}));
    let scene = load(&b);
    let realness = |name: &str| scene.instances.iter().find(|i| i.node_name == name).unwrap().realness;
    assert_eq!(realness("wall"), Realness::Real);
    assert_eq!(realness("inserted"), Realness::Virtual);
    assert_eq!(realness("loose"), Realness::Virtual);
}

#[test]
fn non_indexed_meshes_and_missing_normals_get_flat_normals() {
    let mut b = GltfBuilder::new();
    let mut tri = quad(1.0);
    tri.indices.clear();
    tri.positions.truncate(3);
    tri.uvs.truncate(3);
    let mesh = b.mesh(&tri, None, false);
    b.node(json!({"mesh": mesh}));
    let scene = load(&b);
    let p = &scene.primitives[0];
    assert_eq!(p.indices, vec![0, 1, 2]);
    // Winding (−1,0,−1) → (−1,0,1) → (1,0,1) faces +Y.
    assert!(p.normals.iter().all(|n| n.abs_diff_eq(Vec3::Y, 1e-6)), "{:?}", p.normals);
}

#[test]
fn materials_and_their_extensions() {
    let mut b = GltfBuilder::new();
    for e in [
        "KHR_materials_specular",
        "KHR_materials_transmission",
        "KHR_materials_ior",
        "KHR_materials_volume",
        "KHR_materials_emissive_strength",
    ] {
        b.use_extension(e, true);
    }
    let glass = b.material(json!({
        "name": "glass",
        "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0, "roughnessFactor": 0.1},
        "emissiveFactor": [0.5, 0.0, 0.0],
        "extensions": {
            "KHR_materials_transmission": {"transmissionFactor": 1.0},
            "KHR_materials_ior": {"ior": 1.33},
            "KHR_materials_volume": {"thicknessFactor": 0.05, "attenuationColor": [0.5, 0.8, 0.5], "attenuationDistance": 0.1},
            "KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [1.0, 0.5, 0.5]},
            "KHR_materials_emissive_strength": {"emissiveStrength": 4.0}
        }
    }));
    let diffuse = b.material(lambert("desk", [0.4, 0.25, 0.15]));
    let m1 = b.mesh(&quad(1.0), Some(glass), true);
    let m2 = b.mesh(&quad(1.0), Some(diffuse), true);
    b.node(json!({"mesh": m1}));
    b.node(json!({"mesh": m2}));
    let scene = load(&b);
    let g = &scene.materials[0];
    assert_eq!((g.transmission, g.ior, g.thickness, g.attenuation_distance), (1.0, 1.33, 0.05, 0.1));
    assert_eq!(g.attenuation_color, Vec3::new(0.5, 0.8, 0.5));
    assert_eq!(g.emissive, Vec3::new(2.0, 0.0, 0.0));
    let f0 = ((1.33f32 - 1.0) / 2.33).powi(2);
    assert!(g.dielectric_f0().abs_diff_eq(Vec3::new(f0, f0 * 0.5, f0 * 0.5) * 0.5, 1e-6));
    let d = &scene.materials[1];
    assert_eq!(d.specular, 0.0);
    assert_eq!(d.dielectric_f0(), Vec3::ZERO, "specularFactor 0 is a pure Lambertian surface");
    assert_eq!(d.metallic, 0.0);
    // The default material is appended for primitives without one.
    assert_eq!(scene.materials.len(), 3);
}

#[test]
fn textures_from_a_glb_buffer_view_are_decoded() {
    // A 2×2 PNG embedded as a data URI image, used as base color (sRGB) and metallic-roughness (linear).
    let mut png = Vec::new();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([255, 128, 0, 255]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let mut b = GltfBuilder::new();
    let m = b.material(
        json!({"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 0}}}),
    );
    let mesh = b.mesh(&quad(1.0), Some(m), true);
    b.node(json!({"mesh": mesh}));
    let mut doc: serde_json::Value = serde_json::from_slice(&b.embedded_json()).unwrap();
    use base64::Engine;
    doc["images"] =
        json!([{"uri": format!("data:image/png;base64,{}", base64::engine::general_purpose::STANDARD.encode(&png))}]);
    doc["textures"] = json!([{"source": 0}]);
    let scene =
        load_gltf_bytes(&serde_json::to_vec(&doc).unwrap(), &AssetSource::dir("/nonexistent"), &Default::default())
            .unwrap();
    assert_eq!(scene.textures.len(), 2, "one texture per colour space");
    assert!(scene.textures[0].srgb && !scene.textures[1].srgb);
    assert_eq!(&scene.textures[0].rgba8[..4], &[255, 128, 0, 255]);
}

#[test]
fn lights_of_every_kind_with_flags_and_radiometric_intensity() {
    let mut b = GltfBuilder::new();
    let spot = b.light(json!({"type": "spot", "color": [1.0, 0.5, 0.25], "intensity": 2.0, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.4}}));
    let point = b.light(json!({"type": "point", "intensity": 3.0}));
    let sun = b.light(json!({"type": "directional", "intensity": 1.5}));
    let rot = quat([1.0, 0.0, 0.0], -std::f32::consts::FRAC_PI_2);
    b.node(json!({"name": "lamp", "translation": [0, 2, 0], "rotation": rot, "extensions": {"KHR_lights_punctual": {"light": spot}}, "extras": {"real": true}}));
    b.node(json!({"name": "bulb", "translation": [1, 1, 1], "extensions": {"KHR_lights_punctual": {"light": point}}}));
    b.node(json!({"name": "sun", "extensions": {"KHR_lights_punctual": {"light": sun}}, "extras": {"real": true}}));
    let scene = load(&b);
    assert_eq!(scene.lights.len(), 3);
    let lamp = &scene.lights[0];
    assert_eq!(lamp.kind, LightKind::Spot { inner_cone: 0.2, outer_cone: 0.4 });
    assert_eq!(lamp.intensity, Vec3::new(2.0, 1.0, 0.5));
    assert_eq!(lamp.realness, Realness::Real);
    assert!(lamp.direction().abs_diff_eq(Vec3::NEG_Y, 1e-5));
    assert!(lamp.position().abs_diff_eq(Vec3::new(0.0, 2.0, 0.0), 1e-6));
    assert_eq!(scene.lights[1].kind, LightKind::Point);
    assert_eq!(scene.lights[1].realness, Realness::Virtual);
    assert_eq!(scene.lights[2].kind, LightKind::Directional);
    assert!(scene.lights[2].direction().abs_diff_eq(Vec3::NEG_Z, 1e-6));
}

#[test]
fn perspective_cameras_are_collected_without_scale() {
    let mut b = GltfBuilder::new();
    let cam = b.camera(json!({"name": "main-cam", "type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 1.5, "znear": 0.05}}));
    let rig = b.node(json!({"name": "rig", "scale": [3.0, 3.0, 3.0], "translation": [0, 1, 0]}));
    b.child(rig, json!({"name": "eye", "camera": cam, "translation": [0, 0, 1]}));
    let scene = load(&b);
    let c = &scene.cameras[0];
    assert!(c.is_named("eye") && c.is_named("main-cam"));
    assert_eq!((c.yfov, c.aspect_ratio, c.znear), (0.8, Some(1.5), 0.05));
    assert!(c.world_from_camera.transform_point3(Vec3::ZERO).abs_diff_eq(Vec3::new(0.0, 1.0, 3.0), 1e-5));
    assert!(c.world_from_camera.transform_vector3(Vec3::X).abs_diff_eq(Vec3::X, 1e-5), "scale removed");
}

#[test]
fn glb_and_data_uris_load_like_separate_files() {
    let mut b = GltfBuilder::new();
    let mesh = b.mesh(&cuboid([0.5, 0.5, 0.5]), None, true);
    b.node(json!({"mesh": mesh, "translation": [0, 0.5, 0]}));
    let nowhere = AssetSource::dir("/nonexistent");
    let glb = load_gltf_bytes(&b.glb(), &nowhere, &Default::default()).unwrap();
    let embedded = load_gltf_bytes(&b.embedded_json(), &nowhere, &Default::default()).unwrap();
    let files = load(&b);
    for s in [&glb, &embedded] {
        assert_eq!(s.primitives[0].positions, files.primitives[0].positions);
        assert_eq!(s.primitives[0].indices, files.primitives[0].indices);
    }
    let (lo, hi) = files.bounds().unwrap();
    assert!(lo.abs_diff_eq(Vec3::new(-0.5, 0.0, -0.5), 1e-6) && hi.abs_diff_eq(Vec3::new(0.5, 1.0, 0.5), 1e-6));
}

#[test]
fn unsupported_extensions_warn_by_name_and_required_ones_fail() {
    let mut b = GltfBuilder::new();
    let mesh = b.mesh(&quad(1.0), None, true);
    b.node(json!({"mesh": mesh}));
    b.use_extension("KHR_materials_sheen", false);
    let scene = load(&b);
    assert!(scene.warnings.iter().any(|w| w.contains("KHR_materials_sheen")), "{:?}", scene.warnings);

    b.use_extension("KHR_texture_transform", true);
    let dir = tempfile::tempdir().unwrap();
    b.write_gltf(dir.path(), "scene");
    let err = load_gltf(&AssetSource::dir(dir.path()), "scene.gltf", &Default::default()).unwrap_err();
    let msg = format!("{err:#}");
    assert!(msg.contains("requires KHR_texture_transform") && msg.contains("scene.gltf"), "{msg}");
}

#[test]
fn the_benchmark_style_scene_round_trips() {
    // Real desk, virtual box, real lamp, camera: the shape of every benchmark scene.
    let mut b = GltfBuilder::new();
    let desk = b.material(lambert("desk", [0.38, 0.24, 0.14]));
    let blue = b.material(lambert("blue", [0.2, 0.35, 0.75]));
    let m_desk = b.mesh(&quad(0.5), Some(desk), true);
    let m_box = b.mesh(&cuboid([0.05; 3]), Some(blue), true);
    b.node(json!({"name": "desk", "mesh": m_desk, "extras": {"real": true}}));
    b.node(json!({"name": "cube", "mesh": m_box, "translation": [0, 0.05, 0], "extras": {"real": false}}));
    let scene = load(&b);
    assert!(scene.has_virtual_content());
    assert_eq!(scene.instances[1].world_from_object, Mat4::from_translation(Vec3::new(0.0, 0.05, 0.0)));
}
