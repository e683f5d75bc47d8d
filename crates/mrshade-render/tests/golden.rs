//! Golden frames on lavapipe, compared with FLIP under explicit thresholds. Regenerate with
//! `MRSHADE_BLESS=1 cargo test --release -p mrshade-render --test golden` and review the
//! images in tests/golden/ before committing them.

mod common;

use common::{Rendered, Setup};
use mrshade_core::settings::Method;
use mrshade_scene::{AssetSource, Session, SessionOverrides};
use serde_json::json;

/// Mean FLIP allowed against the golden. Renders on the same software driver differ only in
/// float rounding; 0.01 is far below a visible change (a missing shadow scores > 0.05).
const THRESHOLD: f32 = 0.01;

fn check(name: &str, r: &Rendered) {
    let c = r.renderer.read_composite(&r.ctx).unwrap();
    let rgb = c.image.to_srgb8();
    mrshade_testkit::golden::check(name, &rgb, c.image.width, c.image.height, THRESHOLD);
}

/// The demo session with every method (`demo_160x120` is the default method's).
#[test]
fn demo_session() {
    let demo = AssetSource::dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/demo"));
    for method in Method::ALL {
        // 48 frames, not the still's default 256, keep the suite fast.
        let overrides = SessionOverrides {
            width: Some(160),
            method: Some(*method),
            set: vec![format!("output.frames={}", method.default_still_frames().min(48))],
            ..Default::default()
        };
        let session = Session::load_from(&demo, "session.toml", &overrides).unwrap();
        let name = match method {
            Method::Dir => "demo_160x120".to_string(),
            other => format!("demo_160x120_{}", other.name()),
        };
        check(&name, &Rendered::new(session));
    }
}

#[test]
fn lights_of_every_kind_with_real_and_virtual_shadows() {
    let mut s = Setup::top_down(96);
    s.photo = Box::new(|x, y| if (x / 12 + y / 12) % 2 == 0 { [150, 120, 90] } else { [120, 95, 70] });
    s.probe = Some([0.3, 0.35, 0.45]);
    s.plane(2.0, 0.0, 0.45, true)
        .cube([-0.2, 0.08, 0.15], 0.08, true)
        .cube([0.12, 0.1, -0.1], 0.07, false)
        .light(json!({"type": "spot", "intensity": 1.2, "color": [1.0, 0.9, 0.7], "spot": {"innerConeAngle": 0.4, "outerConeAngle": 0.7}}), [0.3, 0.8, 0.2], true)
        .light(json!({"type": "point", "intensity": 0.08, "color": [0.3, 0.6, 1.0]}), [-0.25, 0.3, -0.25], false);
    let sphere = mrshade_testkit::gltf::sphere(0.08, 24);
    let metal = s.gltf.material(json!({"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.7, 0.4, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.3}}));
    let mesh = s.gltf.mesh(&sphere, Some(metal), true);
    s.gltf.node(json!({"name": "ball", "mesh": mesh, "translation": [0.25, 0.08, -0.3]}));
    check("synthetic_lights_96", &s.render());
}
