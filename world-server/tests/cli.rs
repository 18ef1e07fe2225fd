//! The binary's command line on its own (the runs themselves are tested end
//! to end in `tests/`). Also makes `cargo test --workspace` build the binary.

use std::process::Command;

fn world_server() -> Command {
    Command::new(env!("CARGO_BIN_EXE_world-server"))
}

#[test]
fn bad_arguments_are_a_usage_error() {
    let out = world_server().arg("--no-such-flag").output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
}

#[test]
fn a_prefix_that_is_not_a_run_prefix_is_refused() {
    // A typo must never reach iceoryx2 (or the cleanup, which removes by prefix).
    let out = world_server()
        .args(["--prefix", "iox2_", "--report", "/dev/null"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.starts_with("error: `iox2_` is not a run prefix"),
        "{err}"
    );
}

#[test]
fn lfp_is_not_a_grid_policy() {
    let out = world_server()
        .args([
            "--prefix",
            "gs1x1_",
            "--algorithm",
            "lfp",
            "--report",
            "/dev/null",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("grid policies only"));
}
