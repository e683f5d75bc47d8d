//! Golden images: committed renders on lavapipe, compared by mean FLIP under an explicit
//! threshold. `MRSHADE_BLESS=1` (re)writes them. A missing golden is a failure; outside CI
//! the failing test also writes the candidate so it can be reviewed and committed.

use std::path::{Path, PathBuf};

/// Folder of the goldens: `tests/golden` at the workspace root.
pub fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/golden")
}

/// Compares `rgb` with golden `name`.png; panics above `threshold` mean FLIP, writing
/// `target/golden-failures/<name>.{png,flip.png}` for inspection.
pub fn check(name: &str, rgb: &[u8], width: u32, height: u32, threshold: f32) {
    let path = dir().join(format!("{name}.png"));
    if std::env::var("MRSHADE_BLESS").is_ok_and(|v| v == "1") {
        save(&path, rgb, width, height);
        eprintln!("blessed {}", path.display());
        return;
    }
    let Ok(golden) = image::open(&path) else {
        if !crate::is_ci() {
            save(&path, rgb, width, height);
        }
        panic!(
            "golden image {} is missing{}; review it and commit it (or run with MRSHADE_BLESS=1)",
            path.display(),
            if crate::is_ci() { "" } else { " (a candidate was written there)" }
        );
    };
    let golden = golden.to_rgb8();
    assert_eq!((golden.width(), golden.height()), (width, height), "golden {name} has another size");
    let flip = crate::flip::mean(golden.as_raw(), rgb, width, height);
    eprintln!("golden {name}: mean FLIP {flip:.4} (threshold {threshold})");
    if flip > threshold {
        let out = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/golden-failures");
        save(&out.join(format!("{name}.png")), rgb, width, height);
        let heat = crate::flip::heatmap(golden.as_raw(), rgb, width, height);
        save(&out.join(format!("{name}.flip.png")), &heat, width, height);
        panic!("golden {name}: mean FLIP {flip:.4} > {threshold}; see {}", out.display());
    }
}

fn save(path: &Path, rgb: &[u8], width: u32, height: u32) {
    if let Some(p) = path.parent() {
        std::fs::create_dir_all(p).expect("create golden folder");
    }
    image::save_buffer(path, rgb, width, height, image::ExtendedColorType::Rgb8).expect("write png");
}
