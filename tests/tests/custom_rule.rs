//! A choice rule defined in one file outside the workspace's crates
//! (`robot-agent/examples/my_rule.rs`) runs in both engines by name, with
//! the same trajectories: in-process through the example itself, and one
//! process per robot through `gridswarm run --agent-bin`.

use std::fs;
use std::process::Command;

use gridswarm_e2e::*;
use serde_json::Value;

#[test]
fn a_rule_of_ones_own_runs_in_both_engines_alike() {
    let _s = serial();
    let example = bin_dir().join("examples").join("my_rule");
    assert!(example.is_file(), "{} is missing: `cargo test --release --workspace` builds it", example.display());
    let dir = scratch("custom-rule");
    let (run_dir, sim_dir) = (dir.join("run"), dir.join("sim"));
    let args = ["--scenario", "paper", "--robots", "5", "--seed", "3"];

    let listed = Command::new(&example).arg("--list-rules").output().unwrap();
    assert!(text(&listed.stdout).lines().any(|l| l == "sweep"), "the agent lists its rule: {}", text(&listed.stdout));

    let mut sim = Command::new(&example);
    sim.args(["simulate", "--algorithm", "sweep", "--json"]).args(args).arg("--out").arg(&sim_dir);
    let sim = sim.output().unwrap();
    assert!(sim.status.success(), "in-process run failed: {}", text(&sim.stderr));
    let sim: Value = serde_json::from_slice(&sim.stdout).unwrap();
    assert_eq!(sim["algorithm"], "sweep");

    let ex = example.to_str().unwrap();
    let run = run_json(
        &[&["--agent-bin", ex, "--algorithm", "sweep", "--out", run_dir.to_str().unwrap()][..], &args[..]].concat(),
    );
    assert_eq!(run["algorithm"], "sweep");
    assert_eq!(run["complete"], true);
    for key in ["rounds", "search_time_s", "collisions", "targets_found"] {
        assert_eq!(run[key], sim[key], "{key}");
    }
    for file in ["trajectories.jsonl", "rounds.csv"] {
        assert!(
            fs::read(run_dir.join(file)).unwrap() == fs::read(sim_dir.join(file)).unwrap(),
            "{file} differs between the engines"
        );
    }

    // Without the agent program, gridswarm does not know the name.
    let plain = gridswarm().args(["simulate", "--algorithm", "sweep"]).output().unwrap();
    assert_eq!(plain.status.code(), Some(2));
    assert!(text(&plain.stderr).contains("unknown algorithm `sweep`"), "{}", text(&plain.stderr));
}

#[test]
fn the_examples_binary_is_the_whole_tool_plus_its_rule() {
    let example = bin_dir().join("examples").join("my_rule");
    // Held to the end: the scratch removes its folder when dropped, and
    // the sweep would recreate `out` inside a folder no one removes.
    let dir = scratch("custom-rule-sweep");
    let out = dir.join("out");
    let sweep = Command::new(&example)
        .args(["experiment", "--algorithms", "sweep,sequential", "--robots", "2,3", "--runs", "2"])
        .args(["--set", "t_trans=4.5,6", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(sweep.status.success(), "{}", text(&sweep.stderr));
    let results = fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(results.lines().filter(|l| l.starts_with("sweep,")).count(), 4, "{results}");
    let rerun = Command::new(&example).arg("rerun").arg(&out).output().unwrap();
    assert!(rerun.status.success(), "the recorded command reruns with the rule: {}", text(&rerun.stderr));

    // simulate's fault and radio flags, with the rule.
    let sim = Command::new(&example)
        .args(["simulate", "--algorithm", "sweep", "--robots", "4", "--loss", "0.2", "--kill", "2@5", "--json"])
        .output()
        .unwrap();
    assert!(sim.status.code() != Some(2), "{}", text(&sim.stderr));
    let sim: Value = serde_json::from_slice(&sim.stdout).unwrap();
    assert_eq!(sim["algorithm"], "sweep");
    assert!(sim["lost"].as_u64().unwrap() > 0, "frames lost to --loss: {sim}");
    assert_eq!(sim["failures"][0]["robot"], 2, "--kill 2@5");
}
