//! The fuzzing harness under the test suite: a fixed range of cases (the same every run, so a
//! failure is reproducible with `mrshade-fuzz show N DIR`), each in the worker under the
//! 4 GiB allocation cap and a 30 s limit. `./dev fuzz SECONDS` runs more, from a random first
//! case.

use std::process::Command;

#[test]
fn a_thousand_mutated_sessions_are_loaded_or_refused_never_worse() {
    let failures = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_mrshade-fuzz"))
        .args(["run", "--count", "1000", "--first", "0", "--failures"])
        .arg(failures.path())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n(failing cases were written to {})", failures.path().display());
    assert!(stdout.contains("1000 cases") && stdout.contains("0 failures"), "{stdout}");
}

#[test]
fn a_hang_and_a_crash_are_caught_and_written_down() {
    // The worker's own misbehaviour stands in for a case's: an allocation cap of 1 MiB makes
    // it abort on the first case.
    let failures = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_mrshade-fuzz"))
        .args(["run", "--count", "2", "--memory-mib", "1", "--failures"])
        .arg(failures.path())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(!out.status.success() && stdout.contains("crash"), "{stdout}");
    let written = failures.path().join("case-0");
    assert!(written.join("session.toml").is_file() && written.join("failure.txt").is_file());
}
