//! The binary's command line on its own (the runs themselves are tested end
//! to end in `tests/`). Also makes `cargo test --workspace` build the binary.

use std::path::PathBuf;
use std::process::Command;

use gridswarm::agreement::{Agreement, ScenarioId};
use gridswarm::outcome::RunConfig;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;
use gridswarm::setup;

fn agent() -> Command {
    Command::new(env!("CARGO_BIN_EXE_robot-agent"))
}

/// A setup file of robot 0 on the paper scenario; removed on drop.
struct SetupFile(PathBuf);

impl Drop for SetupFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

fn setup_file(name: &str, text: Option<&str>) -> SetupFile {
    let path = std::env::temp_dir().join(format!("robot-agent-cli-{}-{name}.json", std::process::id()));
    let body = match text {
        Some(t) => t.to_string(),
        None => {
            let sc = Scenario::builtin("paper").unwrap();
            let world = sc.world();
            let cfg = RunConfig::new(Policy::Repulsive, 1, Situation::Two);
            let agreement = Agreement::new("k", ScenarioId::of(&sc), 1, cfg.policy, cfg.situation, world.params);
            serde_json::to_string(&setup::SetupFile { setup: cfg.robot_setup(&world, 0), agreement }).unwrap()
        }
    };
    std::fs::write(&path, body).unwrap();
    SetupFile(path)
}

#[test]
fn bad_arguments_are_a_usage_error() {
    let out = agent().arg("--world-pid").arg("x").output().unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn without_a_world_it_fails_at_once() {
    // A prefix no world ever created: the services cannot be opened.
    let prefix = format!("gs{}x{:06x}_", std::process::id(), 0xbad);
    let setup = setup_file("noworld", None);
    let out = agent().args(["--prefix", &prefix, "--world-pid", "1", "--setup"]).arg(&setup.0).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("robot-agent 0: error: cannot open service"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    // Its node left iceoryx2's small management file: what the run's owner removes.
    gridswarm::ipc::cleanup_run(&prefix).unwrap();
    assert!(gridswarm::ipc::run_files(&prefix).is_empty());
}

#[test]
fn a_bad_setup_is_refused_in_one_line() {
    for (name, text, want) in [
        ("garbage", Some("{not json"), "robot-agent: error:"),
        ("unknown-field", Some(r#"{"id": 0, "obstacles": []}"#), "robot-agent: error:"),
        ("missing", None, "cannot read"),
    ] {
        let setup = setup_file(name, text);
        let path = if text.is_none() { PathBuf::from("/nonexistent/setup.json") } else { setup.0.clone() };
        let out = agent().args(["--prefix", "gs1x1_", "--world-pid", "1", "--setup"]).arg(&path).output().unwrap();
        assert_eq!(out.status.code(), Some(1), "{name}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(want), "{name}: {err}");
        assert_eq!(err.lines().count(), 1, "{name}: {err}");
    }
}
