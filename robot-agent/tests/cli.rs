//! The binary's command line on its own (the runs themselves are tested end
//! to end in `tests/`). Also makes `cargo test --workspace` build the binary.

use std::path::PathBuf;
use std::process::Command;

use gridswarm_orchestrator::cli::setup::{setup_file as setup_of, SetupArgs};
use gridswarm_robot::policy::Policy;

fn agent() -> Command {
    Command::new(env!("CARGO_BIN_EXE_robot-agent"))
}

/// A setup file of robot 0 of run `k` on the paper scenario, as `gridswarm
/// setup` writes it (or `text`); removed on drop.
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
            let args = SetupArgs {
                key: "k".into(),
                robot: 0,
                robots: None,
                scenario: "paper".into(),
                algorithm: Policy::Repulsive,
                seed: 1,
                situation: None,
                retries: None,
                slot: None,
                order: None,
                agent_bin: None,
                out: path.clone(),
            };
            serde_json::to_string(&setup_of(&args).unwrap()).unwrap()
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
    gridswarm_transport::ipc::cleanup_run(&prefix).unwrap();
    assert!(gridswarm_transport::ipc::run_files(&prefix).is_empty());
}

#[test]
fn a_bad_setup_is_refused_in_one_line() {
    for (name, text, want) in [
        ("garbage", Some("{not json"), "robot-agent: error:"),
        ("unknown-field", Some(r#"{"id": 0, "obstacles": []}"#), "robot-agent: error:"),
        // The old form: an agreement declared beside the setup, which could differ from it.
        ("old-form", Some(r#"{"setup": {}, "agreement": {"seed": 7}}"#), "`agreement` section beside its `setup`"),
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

#[test]
fn without_a_setup_it_is_a_usage_error() {
    // An agent never derives a setup from a scenario: `gridswarm setup` writes one.
    for extra in [&[][..], &["--scenario", "paper", "--seed", "1", "--robot", "0"][..]] {
        let out = agent().args(["--prefix", "k", "--transport", "zenoh"]).args(extra).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {}", String::from_utf8_lossy(&out.stderr));
    }
}

#[test]
fn a_zenoh_agent_with_no_world_gives_up_in_one_line() {
    let port = std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
    let setup = setup_file("zenoh-noworld", None);
    let out = agent()
        .args(["--transport", "zenoh", "--prefix", "k", "--insecure", "--connect", &format!("tcp/127.0.0.1:{port}")])
        .args(["--connect-timeout-ms", "300", "--setup"])
        .arg(&setup.0)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("robot-agent 0: error: "), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}

#[test]
fn over_zenoh_it_needs_credentials_or_insecure_and_plain_tcp_stays_on_loopback() {
    let setup = setup_file("zenoh-flags", None);
    let run = ["--transport", "zenoh", "--prefix", "k", "--setup", setup.0.to_str().unwrap()];
    for (extra, words) in [
        (&["--connect", "tls/10.0.0.1:7447"][..], "needs --credentials DIR"),
        (&["--insecure", "--connect", "tcp/10.0.0.1:7447"][..], "not loopback"),
        (&["--insecure"][..], "scouting"),
        (&["--insecure", "--connect", "tls/127.0.0.1:7447"][..], "needs --credentials"),
        (&["--credentials", "/nowhere", "--connect", "tcp/127.0.0.1:7447"][..], "plain TCP"),
    ] {
        let out = agent().args(run).args(extra).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {err}");
        assert!(err.starts_with("robot-agent: error: ") && err.contains(words), "{extra:?}: {err}");
    }
    let out =
        agent().args(run).args(["--credentials", "/nowhere", "--connect", "tls/127.0.0.1:7447"]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("/nowhere/ca.pem") && err.contains("gridswarm credentials"), "{err}");
}
