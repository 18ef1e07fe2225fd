//! The binary's command line on its own (the runs themselves are tested end
//! to end in `tests/`). Also makes `cargo test --workspace` build the binary.

use std::path::PathBuf;
use std::process::Command;

fn world_server() -> Command {
    Command::new(env!("CARGO_BIN_EXE_world-server"))
}

/// A run file; removed on drop.
struct RunFile(PathBuf);

impl Drop for RunFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

fn run_file(name: &str, algorithm: &str) -> RunFile {
    let path = std::env::temp_dir().join(format!("world-server-cli-{}-{name}.json", std::process::id()));
    let text = format!(
        r#"{{"scenario": "paper", "robots": 3, "config": {{"policy": "{algorithm}", "seed": 1, "situation": "Two",
            "max_rounds": 10, "measure_coverage": true, "record_trajectories": true,
            "radio": {{"loss": 0.0, "delay": 0, "jitter": 0, "dup": 0.0}}, "faults": []}}}}"#
    );
    std::fs::write(&path, text).unwrap();
    RunFile(path)
}

#[test]
fn bad_arguments_are_a_usage_error() {
    let out = world_server().arg("--no-such-flag").output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: unexpected argument '--no-such-flag'"), "{err}");
    assert!(err.contains("Usage:"), "clap's whole message: {err}");
}

#[test]
fn a_prefix_that_is_not_a_run_prefix_is_refused() {
    // A typo must never reach iceoryx2 (or the cleanup, which removes by prefix).
    let run = run_file("prefix", "repulsive");
    let out =
        world_server().args(["--prefix", "iox2_", "--report", "/dev/null", "--run"]).arg(&run.0).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: `iox2_` is not a run prefix"), "{err}");
}

#[test]
fn lfp_is_not_a_grid_policy() {
    let run = run_file("lfp", "lfp");
    let out =
        world_server().args(["--prefix", "gs1x1_", "--report", "/dev/null", "--run"]).arg(&run.0).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("grid policies only"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}

#[test]
fn a_bad_run_file_is_one_error_line() {
    // An ill-formed name: a well-formed unknown one may be a rule another
    // agent program runs, which the world cannot tell (it would start and
    // wait for hellos).
    let run = run_file("bad", "No Such Policy");
    let out =
        world_server().args(["--prefix", "gs1x1_", "--report", "/dev/null", "--run"]).arg(&run.0).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: ") && err.contains("bad algorithm name"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}
