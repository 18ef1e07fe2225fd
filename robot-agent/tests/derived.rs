//! An agent started by hand (zenoh, another host) has no setup file: it
//! derives its setup from the scenario, seed and robot number, and that
//! must be exactly the setup the orchestrator writes for the same run, and
//! present the agreement the orchestrator's world holds.

use std::process::Command;

use gridswarm::params::{Order, Situation, SlotRule};
use gridswarm::policy::Policy;
use gridswarm_orchestrator::run::{self, RunOptions};
use robot_agent::Overrides;

fn agent() -> Command {
    Command::new(env!("CARGO_BIN_EXE_robot-agent"))
}

#[test]
fn a_derived_setup_is_the_one_the_orchestrator_writes() {
    let cases = [
        ("paper", Policy::Repulsive, Situation::Two, None, None, None, 7),
        ("paper", Policy::Sequential, Situation::One, Some(2), None, Some(Order::Local), 12),
        ("random:3", Policy::Escape, Situation::One, None, Some(SlotRule::Fixed), None, 0),
    ];
    for (scenario, policy, situation, retries, slot, order, robot) in cases {
        let mut o = RunOptions::for_experiment(scenario.into(), policy, 13, 41, situation, 0, 100);
        o.retries = retries;
        o.slot = slot;
        o.order = order;
        let retries = Overrides { retries, slot, order };
        let plan = run::plan(&o).unwrap();
        let written = plan.cfg.robot_setup(&plan.world, robot);
        let sit = if situation == Situation::One { 1 } else { 2 };
        let derived = robot_agent::derived_setup(scenario, robot, 41, policy.name(), Some(sit), retries).unwrap();
        assert_eq!(derived, written, "{scenario} {policy} robot {robot}");
        // And the agreement it presents is the one the world holds.
        let (_, agreement) =
            robot_agent::derived("key", scenario, robot, 41, policy.name(), Some(sit), retries).unwrap();
        assert_eq!(agreement, plan.agreement("key"), "{scenario} {policy} robot {robot}");
    }
    let err = robot_agent::derived_setup("paper", 0, 1, "lfp", None, Overrides::default()).unwrap_err();
    assert!(err.contains("lfp"), "{err}");
    assert!(robot_agent::derived_setup("nowhere", 0, 1, "repulsive", None, Overrides::default()).is_err());
    assert!(robot_agent::derived_setup("paper", 0, 1, "repulsive", Some(3), Overrides::default()).is_err());
}

#[test]
fn without_a_setup_or_a_scenario_it_is_a_usage_error() {
    let out = agent().args(["--prefix", "k", "--transport", "zenoh"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn a_zenoh_agent_with_no_world_gives_up_in_one_line() {
    let port = std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
    let out = agent()
        .args([
            "--transport",
            "zenoh",
            "--prefix",
            "noworld",
            "--insecure",
            "--connect",
            &format!("tcp/127.0.0.1:{port}"),
        ])
        .args(["--connect-timeout-ms", "300", "--scenario", "paper", "--seed", "1", "--robot", "0"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("robot-agent 0: error: "), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}

#[test]
fn over_zenoh_it_needs_credentials_or_insecure_and_plain_tcp_stays_on_loopback() {
    let run = ["--transport", "zenoh", "--prefix", "k", "--scenario", "paper", "--seed", "1", "--robot", "0"];
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
