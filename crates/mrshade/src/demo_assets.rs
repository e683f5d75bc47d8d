//! The demo session, compiled into the binary (made from the benchmark scene
//! `desk-spot-real`; see assets/demo/README.md for its origin and licence).

use mrshade_scene::AssetSource;

/// The session file's name inside the embedded set.
pub const SESSION: &str = "session.toml";

static FILES: mrshade_scene::assets::EmbeddedFiles = &[
    ("session.toml", include_bytes!("../../../assets/demo/session.toml")),
    ("scene.glb", include_bytes!("../../../assets/demo/scene.glb")),
    ("background.jpg", include_bytes!("../../../assets/demo/background.jpg")),
    ("environment.exr", include_bytes!("../../../assets/demo/environment.exr")),
];

/// The embedded files.
pub fn source() -> AssetSource {
    AssetSource::embedded(FILES)
}
