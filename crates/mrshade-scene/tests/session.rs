//! Session files: strict parsing and clear errors naming the file and the field.

use mrshade_core::settings::{CompositeMode, Method};
use mrshade_scene::{Session, SessionOverrides};
use mrshade_testkit::gltf::{GltfBuilder, cuboid, lambert, quad, quat, write_exr, write_png};
use serde_json::json;
use std::path::{Path, PathBuf};

const SESSION: &str = r#"
scene = "scene.gltf"
background = "background.png"
exposure = 1.5
[environment]
image = "environment.exr"
rotation_deg = 30.0
intensity = 0.5
"#;

/// A complete small session (32×24 photo, 4:3 camera) in a temp dir.
fn session_dir(camera_aspect: Option<f32>, photo: (u32, u32)) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let mut b = GltfBuilder::new();
    let desk = b.material(lambert("desk", [0.4, 0.3, 0.2]));
    let m1 = b.mesh(&quad(1.0), Some(desk), true);
    let m2 = b.mesh(&cuboid([0.1; 3]), None, true);
    b.node(json!({"name": "desk", "mesh": m1, "extras": {"real": true}}));
    b.node(json!({"name": "cube", "mesh": m2}));
    b.camera_node("camera", 0.8, camera_aspect, [0.0, 0.5, 1.0], quat([1.0, 0.0, 0.0], -0.4));
    b.write_gltf(dir.path(), "scene");
    write_png(&dir.path().join("background.png"), photo.0, photo.1, |x, y| [x as u8 * 4, y as u8 * 4, 90]);
    write_exr(&dir.path().join("environment.exr"), 16, 8, |_, y| [1.0, 1.0, if y < 4 { 2.0 } else { 0.2 }]);
    let path = dir.path().join("session.toml");
    std::fs::write(&path, SESSION).unwrap();
    (dir, path)
}

fn edit(path: &Path, from: &str, to: &str) {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains(from), "{from} not in session");
    std::fs::write(path, text.replacen(from, to, 1)).unwrap();
}

fn error(path: &Path, overrides: &SessionOverrides) -> String {
    let msg = format!("{:#}", Session::load(path, overrides).expect_err("must fail"));
    assert!(msg.contains("session.toml"), "the error names the session file: {msg}");
    msg
}

#[test]
fn a_complete_session_loads_with_defaults() {
    let (_dir, path) = session_dir(Some(4.0 / 3.0), (32, 24));
    let s = Session::load(&path, &SessionOverrides::default()).unwrap();
    assert_eq!((s.output.width, s.output.height, s.output.supersample), (32, 24, 1));
    assert_eq!(s.exposure, 1.5);
    let env = s.environment.as_ref().unwrap();
    assert_eq!((env.rotation_deg, env.intensity), (30.0, 0.5));
    assert_eq!(s.settings.method, Method::Dir);
    assert_eq!(s.settings.composite.mode, CompositeMode::AlphaScaled);
    assert_eq!(s.scene.cameras[s.camera].node_name, "camera");
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn unknown_keys_are_errors() {
    let (_dir, path) = session_dir(Some(4.0 / 3.0), (32, 24));
    edit(&path, "exposure = 1.5", "exposure = 1.5\nexposur = 2");
    let msg = error(&path, &SessionOverrides::default());
    assert!(msg.contains("unknown field `exposur`"), "{msg}");
    let (_dir, path) = session_dir(Some(4.0 / 3.0), (32, 24));
    edit(&path, "intensity = 0.5", "intensity = 0.5\nblur = 1");
    assert!(error(&path, &SessionOverrides::default()).contains("unknown field `blur`"));
}

#[test]
fn a_weight_for_an_unknown_source_is_an_error() {
    let (_dir, path) = session_dir(Some(4.0 / 3.0), (32, 24));
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, text + "\n[dir]\ndistribution = \"weighted\"\nweights = { lamp-typo = 2.0 }\n").unwrap();
    let msg = error(&path, &SessionOverrides::default());
    assert!(msg.contains("dir.weights") && msg.contains("lamp-typo") && msg.contains("environment"), "{msg}");
}

#[test]
fn wrong_types_name_the_key() {
    let (_dir, path) = session_dir(Some(4.0 / 3.0), (32, 24));
    edit(&path, "exposure = 1.5", "exposure = \"bright\"");
    let msg = error(&path, &SessionOverrides::default());
    assert!(msg.contains("exposure") && msg.contains("invalid type"), "{msg}");
}

#[test]
fn missing_files_name_the_field_and_the_path() {
    for (file, field) in
        [("background.png", "background"), ("environment.exr", "environment.image"), ("scene.gltf", "scene")]
    {
        let (dir, path) = session_dir(Some(4.0 / 3.0), (32, 24));
        std::fs::remove_file(dir.path().join(file)).unwrap();
        let msg = error(&path, &SessionOverrides::default());
        assert!(msg.contains(&format!("field `{field}`")) && msg.contains(file) && msg.contains("not found"), "{msg}");
    }
    let msg = format!(
        "{:#}",
        Session::load(Path::new("/nonexistent/session.toml"), &SessionOverrides::default()).unwrap_err()
    );
    assert!(msg.contains("/nonexistent/session.toml"), "{msg}");
}

#[test]
fn a_photo_with_another_aspect_than_the_camera_is_an_error() {
    let (_dir, path) = session_dir(Some(4.0 / 3.0), (32, 32));
    let msg = error(&path, &SessionOverrides::default());
    assert!(msg.contains("field `background`") && msg.contains("32×32") && msg.contains("camera 'camera'"), "{msg}");
    // Without a fixed camera aspect the photo decides.
    let (_dir, path) = session_dir(None, (32, 32));
    assert_eq!(Session::load(&path, &SessionOverrides::default()).unwrap().output.width, 32);
}

#[test]
fn output_size_follows_the_photo_aspect() {
    let (_dir, path) = session_dir(Some(4.0 / 3.0), (64, 48));
    let s = Session::load(&path, &SessionOverrides { width: Some(32), ..Default::default() }).unwrap();
    assert_eq!((s.output.width, s.output.height), (32, 24));
    assert_eq!((s.background.width, s.background.height), (32, 24), "the photo is resampled");
    let msg = error(&path, &SessionOverrides { width: Some(32), height: Some(32), ..Default::default() });
    assert!(msg.contains("field `output`") && msg.contains("aspect"), "{msg}");
}

#[test]
fn output_sizes_are_checked_as_given_then_as_derived() {
    let (_dir, path) = session_dir(Some(4.0 / 3.0), (64, 48));
    let size = |width, height| SessionOverrides { width, height, ..Default::default() };
    for (given, named) in [(size(Some(0), None), "width"), (size(None, Some(100_000)), "height")] {
        let msg = error(&path, &given);
        assert!(msg.contains(&format!("{named} must be between 16 and 16384")), "{msg}");
    }
    // A 1×1 render shows whatever lies at the centre of the frame: refused.
    let msg = error(&path, &size(Some(16), None));
    assert!(msg.contains("width 16 gives a height of 12"), "{msg}");
    let msg = error(&path, &size(None, Some(16000)));
    assert!(msg.contains("height 16000 gives a width of 21333"), "{msg}");
    // Within the side limits but past the pixel budget.
    let big =
        SessionOverrides { width: Some(16384), set: vec!["limits.image_pixels=1000000".into()], ..Default::default() };
    let msg = error(&path, &big);
    assert!(msg.contains("16384×12288") && msg.contains("limits.image_pixels"), "{msg}");
}

#[test]
fn set_overrides_are_as_strict_as_the_file() {
    let (_dir, path) = session_dir(Some(4.0 / 3.0), (32, 24));
    let set =
        |pairs: &[&str]| SessionOverrides { set: pairs.iter().map(|s| s.to_string()).collect(), ..Default::default() };
    let s =
        Session::load(&path, &set(&["shadows.resolution=512", "composite.mode=\"additive\"", "output.supersample=2"]))
            .unwrap();
    assert_eq!(s.settings.shadows.resolution, 512);
    assert_eq!(s.settings.composite.mode, CompositeMode::Additive);
    assert_eq!(s.output.supersample, 2);
    assert!(error(&path, &set(&["shadows.resolutoin=512"])).contains("resolutoin"));
    assert!(error(&path, &set(&["shadows.resolution=5"])).contains("shadows.resolution"));
    assert!(error(&path, &set(&["no-equals-sign"])).contains("KEY=VALUE"));
    assert!(error(&path, &set(&["composite.mode=\"multiply\""])).contains("multiply"));
    assert!(error(&path, &set(&["dvct.resolution=100"])).contains("`dvct.resolution` must be a power of two"));
    assert!(error(&path, &set(&["dvct.voxels=64"])).contains("voxels"));
    assert!(error(&path, &set(&["dvct.virtual_rays=300"])).contains("`dvct.virtual_rays` must be at most 256 rays"));
    assert!(error(&path, &set(&["dlpv.probe_lights=6"])).contains("`dlpv.probe_lights` must be 0 or a power of two"));
    assert!(error(&path, &set(&["dlpv.cells=32"])).contains("cells"));
    assert!(error(&path, &set(&["dlpv.probe_rsm_resolution=100"])).contains("`dlpv.probe_rsm_resolution`"));
    assert!(error(&path, &set(&["dlpv.sharp_probe_shadows_deg=-1"])).contains("`dlpv.sharp_probe_shadows_deg`"));
    assert!(error(&path, &set(&["dlpv.virtual_light=\"volume\""])).contains("expected `gathered` or `propagated`"));
    assert!(error(&path, &set(&["dlpv.photo_bounce=3"])).contains("expected a boolean"));
    assert!(error(&path, &set(&["dlpv.soft_probe_shadows=3"])).contains("expected a boolean"));
    assert!(Session::load(&path, &set(&["dlpv.soft_probe_shadows=true"])).unwrap().settings.dlpv.soft_probe_shadows);
    assert!(error(&path, &set(&["dlpv.soft_virtual_probe_shadows=soft"])).contains("expected a boolean"));
    assert!(error(&path, &set(&["dlpv.bounce_visibility=1"])).contains("expected a boolean"));
    assert!(error(&path, &set(&["dlpv.virtual_bounce=yes"])).contains("expected a boolean"));
    assert!(
        error(&path, &set(&["dlpv.virtual_bounce=false", "dlpv.bounce_visibility=true"]))
            .contains("needs `dlpv.virtual_bounce`")
    );
    assert!(
        !Session::load(&path, &set(&["dlpv.soft_virtual_probe_shadows=false"]))
            .unwrap()
            .settings
            .dlpv
            .soft_virtual_probe_shadows
    );
    assert!(error(&path, &set(&["dlpv.bounce_light=\"volume\""])).contains("expected `gathered` or `propagated`"));
    assert!(error(&path, &set(&["dlpv.gather_block=12"])).contains("`dlpv.gather_block` must be a power of two"));
    assert!(error(&path, &set(&["ibl.virtual=\"prt9\""])).contains("prt9"));
    assert!(error(&path, &set(&["ibl.samples=0"])).contains("`ibl.samples` must be between 1 and 256"));
    assert!(error(&path, &set(&["ibl.prt_samples=8"])).contains("`ibl.prt_samples`"));
    assert!(error(&path, &set(&["ibl.prt_coefficients=25"])).contains("`ibl.prt_coefficients` must be 9 or 16"));
    assert!(error(&path, &set(&["ibl.prt_specular=\"gauss\""])).contains("gauss"));
    let fis = Session::load(&path, &set(&["ibl.prt_specular=\"fis\""])).unwrap();
    assert_eq!(fis.settings.ibl.prt_specular, mrshade_core::settings::PrtSpecular::Fis);
    assert_eq!(Session::load(&path, &set(&["dlpv.resolution=64"])).unwrap().settings.dlpv.resolution, 64);
    // A still's frame count (default 256 for dir) is bounded like the file's.
    assert!(error(&path, &set(&["output.frames=0"])).contains("frames must be between 1 and 10000, got 0"));
    assert!(error(&path, &set(&["output.frames=10001"])).contains("got 10001"));
    assert_eq!(Session::load(&path, &set(&["output.frames=12"])).unwrap().output.frames, 12);
}

#[test]
fn camera_override_by_name() {
    let (_dir, path) = session_dir(Some(4.0 / 3.0), (32, 24));
    edit(&path, "exposure = 1.5", "exposure = 1.5\ncamera = \"camera\"");
    assert!(Session::load(&path, &SessionOverrides::default()).is_ok());
    edit(&path, "camera = \"camera\"", "camera = \"drone\"");
    let msg = error(&path, &SessionOverrides::default());
    assert!(msg.contains("field `camera`") && msg.contains("'drone'") && msg.contains("cameras: camera"), "{msg}");
}

#[test]
fn bad_values_are_errors() {
    for (from, to, field) in [
        ("exposure = 1.5", "exposure = -1.0", "exposure"),
        ("intensity = 0.5", "intensity = -2.0", "environment.intensity"),
        ("exposure = 1.5", "exposure = 1.5\n[composite]\nalpha_max = 0.5", "composite.alpha_max"),
        ("exposure = 1.5", "exposure = 1.5\n[reference]\nspp = 0", "reference.spp"),
        ("exposure = 1.5", "exposure = 1.5\n[reference]\nmax_bounces = 0", "reference.max_bounces"),
        ("exposure = 1.5", "exposure = 1.5\n[reference]\nsamples = 4", "unknown field `samples`"),
        ("exposure = 1.5", "exposure = 1.5\n[reference]\nspp = -4", "spp"),
    ] {
        let (_dir, path) = session_dir(Some(4.0 / 3.0), (32, 24));
        edit(&path, from, to);
        let msg = error(&path, &SessionOverrides::default());
        assert!(msg.contains(field), "{msg}");
    }
}

#[test]
fn a_scene_without_camera_is_an_error() {
    let (dir, path) = session_dir(Some(4.0 / 3.0), (32, 24));
    let mut b = GltfBuilder::new();
    let m = b.mesh(&quad(1.0), None, true);
    b.node(json!({"mesh": m}));
    b.write_gltf(dir.path(), "scene");
    let msg = error(&path, &SessionOverrides::default());
    assert!(msg.contains("no perspective camera"), "{msg}");
}
