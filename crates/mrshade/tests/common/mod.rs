//! What the command-line tests share: running the binary, reading its errors, the small
//! sequence of `assets/sequence`.
#![allow(dead_code, reason = "each test file uses a part")]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// `mrshade args…`, its runtime folder in `runtime`.
fn command(args: &[&str], runtime: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_mrshade"));
    // Mesa's WSI complains on stderr when this is unset; keep stderr to our own lines.
    command.args(args).env("XDG_RUNTIME_DIR", runtime);
    command
}

/// Runs `mrshade args…`.
pub fn mrshade(args: &[&str]) -> Output {
    let runtime = tempfile::tempdir().unwrap();
    command(args, runtime.path()).output().expect("run mrshade")
}

/// Runs `mrshade args…` with `input` on its standard input (written by a thread while it
/// runs; a command that stops reading early is not an error here).
pub fn mrshade_with_input(args: &[&str], input: Vec<u8>) -> Output {
    piped(args, input, false)
}

/// [`mrshade_with_input`] with its standard output closed before it writes anything (a
/// reader that went away).
pub fn mrshade_into_closed_pipe(args: &[&str], input: Vec<u8>) -> Output {
    piped(args, input, true)
}

fn piped(args: &[&str], input: Vec<u8>, close_stdout: bool) -> Output {
    let runtime = tempfile::tempdir().unwrap();
    let mut child = command(args, runtime.path())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run mrshade");
    if close_stdout {
        drop(child.stdout.take());
    }
    let mut stdin = child.stdin.take().unwrap();
    let feeder = std::thread::spawn(move || {
        let _ = stdin.write_all(&input);
    });
    let output = child.wait_with_output().expect("wait for mrshade");
    feeder.join().unwrap();
    output
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
