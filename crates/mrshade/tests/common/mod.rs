//! What the command-line tests share: running the binary, reading its errors, the small
//! sequence of `assets/sequence`.
#![allow(dead_code, reason = "each test file uses a part")]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `mrshade args…`.
pub fn mrshade(args: &[&str]) -> Output {
    let runtime = tempfile::tempdir().unwrap();
    Command::new(env!("CARGO_BIN_EXE_mrshade"))
        .args(args)
        // Mesa's WSI complains on stderr when this is unset; keep stderr to our own lines.
        .env("XDG_RUNTIME_DIR", runtime.path())
        .output()
        .expect("run mrshade")
}

/// Its standard error.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The command failed with exactly one line on stderr, which names `needle`.
pub fn assert_one_line_error(o: &Output, needle: &str) {
    assert!(!o.status.success(), "expected failure");
    let err = stderr(o);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "one line on stderr, got: {err}");
    assert!(lines[0].starts_with("error: ") && lines[0].contains(needle), "{err}");
}

/// The small posed sequence (12 frames of 80×60).
pub fn mini() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/sequence/desk-orbit-mini").to_string()
}

/// A copy of the mini sequence in `dir`, to break.
pub fn copy_mini(dir: &Path) -> PathBuf {
    let to = dir.join("orbit");
    for sub in ["frames", "ground_truth"] {
        std::fs::create_dir_all(to.join(sub)).unwrap();
        for entry in std::fs::read_dir(Path::new(&mini()).join(sub)).unwrap() {
            let entry = entry.unwrap();
            std::fs::copy(entry.path(), to.join(sub).join(entry.file_name())).unwrap();
        }
    }
    for f in ["session.toml", "scene.glb", "environment.exr", "transforms.json"] {
        std::fs::copy(Path::new(&mini()).join(f), to.join(f)).unwrap();
    }
    to
}
