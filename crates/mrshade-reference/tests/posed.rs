//! The path tracer renders a scene in a pose: skinned and morphing instances deformed and
//! the BVH built for that pose (what `mrshade_reference::render_pose` does per frame).

mod common;

use common::{Builder, lambert};
use glam::{Quat, Vec3};
use mrshade_core::flags::Realness;
use mrshade_core::settings::ReferenceSettings;
use mrshade_scene::{AssetSource, Placement, Trs};
use mrshade_testkit::deform::morph_box;
use mrshade_testkit::gltf::GltfBuilder;

#[test]
fn a_morphing_insert_is_traced_where_its_pose_puts_it() {
    // A camera 1.6 m above a floor looking down at a 0.5 m morphing box, which grows 0.5 m
    // upward and shifts 0.25 m toward +x between t = 0 and t = 1.
    let mut b = Builder::new(Vec3::new(0.0, 1.6, 0.0), Vec3::NEG_Y);
    b.floor(3.0, 0.0, lambert(0.5), Realness::Real).uniform_probe(1.0);
    let mut model = GltfBuilder::new();
    morph_box(&mut model, [0.0, 0.5, 0.0]);
    let dir = tempfile::tempdir().unwrap();
    model.write_gltf(dir.path(), "box");
    let model = mrshade_scene::gltf::load_gltf(&AssetSource::dir(dir.path()), "box.gltf", &Default::default()).unwrap();
    let local = Trs { translation: Vec3::ZERO, rotation: Quat::IDENTITY, scale: Vec3::splat(0.5) };
    let placement = Placement {
        name: "box".into(),
        local,
        parent: None,
        realness: Realness::Virtual,
        animation: None,
        time_offset: 0.0,
    };
    b.scene.insert(model, &placement).unwrap();
    let session = b.session(32, 32, ReferenceSettings { spp: 4, ..Default::default() });
    let coverage = |t: f32| {
        let pose = session.scene.pose_at(t).unwrap();
        let image = mrshade_reference::render_pose(&session, &pose, &|_, _| {});
        // Mean column of the pixels that see the box, and how many there are.
        let seen: Vec<usize> = (0..32 * 32).filter(|&i| image.coverage[i] > 0.5).collect();
        let mean_x = seen.iter().map(|&i| (i % 32) as f32).sum::<f32>() / seen.len().max(1) as f32;
        (seen.len(), mean_x)
    };
    let (before, x0) = coverage(0.0);
    let (after, x1) = coverage(1.0);
    // Nearer the camera and larger: more pixels; shifted toward +x: the centroid moves right.
    assert!(before > 10 && after > before, "{before} → {after} pixels");
    assert!(x1 > x0 + 2.0, "the box's centroid stayed at column {x0} → {x1}");
}
