//! The binary's command line on its own (the runs themselves are tested end
//! to end in `tests/`). Also makes `cargo test --workspace` build the binary.

use std::process::Command;

fn agent() -> Command {
    Command::new(env!("CARGO_BIN_EXE_robot-agent"))
}

#[test]
fn bad_arguments_are_a_usage_error() {
    let out = agent().arg("--robot").arg("x").output().unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn without_a_world_it_fails_at_once() {
    // A prefix no world ever created: the services cannot be opened.
    let prefix = format!("gs{}x{:06x}_", std::process::id(), 0xbad);
    let out = agent()
        .args(["--prefix", &prefix, "--robot", "0"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("cannot open service"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    // Its node left iceoryx2's small management file: what the run's owner removes.
    let root = gridswarm::ipc::root_dir(&gridswarm::ipc::config(&prefix).unwrap());
    gridswarm::ipc::cleanup_run(&prefix, &root).unwrap();
    assert!(gridswarm::ipc::run_files(&prefix, &root).is_empty());
}

#[test]
fn a_robot_outside_the_run_is_refused() {
    let out = agent()
        .args(["--prefix", "gs1x1_", "--robot", "3", "--robots", "3"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("does not exist"));
}
