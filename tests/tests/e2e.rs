//! End-to-end tests of `gridswarm run`: the real orchestrator, world-server
//! and robot-agent binaries, one OS process per robot, on the same
//! simulated world as the in-process engine. After every run: no file of
//! it in /dev/shm, iceoryx2's root or the temporary directory, and no
//! process of it left.

use std::fs;
use std::path::Path;
use std::process::Stdio;

use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::sim::{schedule, Radio};
use gridswarm_e2e::*;
use gridswarm_orchestrator::run::{self, RunOptions};
use gridswarm_orchestrator::rundir::{self, RunRecord};
use serde_json::Value;

fn num(v: &Value) -> u64 {
    v.as_u64().unwrap_or_else(|| panic!("not a count: {v}"))
}

/// Trajectory lines of robot `r`.
fn robot_lines(traj: &str, r: usize) -> Vec<String> {
    let key = format!("\"robot\":{r},");
    traj.lines().filter(|l| l.contains(&key)).map(|l| l.split(",\"robot\"").nth(1).unwrap().to_string()).collect()
}

#[test]
fn thirteen_robots_complete_a_search() {
    let _s = serial();
    let v = run_json(&["--robots", "13", "--seed", "7"]);
    assert_eq!(v["engine"], "distributed");
    let local = serde_json::json!({"mode": "local"});
    let transport = serde_json::json!({"name": "iceoryx2", "endpoints": [], "remote_agents": false, "security": local});
    assert_eq!(v["transport"], transport);
    // `paper` is searched in situation 1.
    let a = &v["agreement"];
    assert_eq!(
        (&a["key"], &a["seed"], &a["scenario"]["name"]),
        (&v["ipc_prefix"], &serde_json::json!(7), &v["scenario"])
    );
    assert_eq!(
        (&a["protocol"], &a["algorithm"], &a["situation"]),
        (&serde_json::json!(gridswarm::agreement::PROTOCOL_VERSION), &v["algorithm"], &serde_json::json!(1))
    );
    assert_eq!(a["scenario"]["sha3_256"].as_str().map(str::len), Some(64), "{a}");
    assert_eq!(a["params"]["retries"], v["retries"]);
    assert_eq!(v["robots"], 13);
    assert_eq!(v["complete"], true);
    assert_eq!(v["targets_found"], v["targets_total"]);
    assert_eq!(num(&v["collisions"]), 0);
    assert_eq!(num(&v["refused_moves"]), 0);
    assert_eq!(num(&v["dropped_messages"]["total"]), 0);
    assert_eq!(num(&v["protocol"]["malformed"]), 0);
    assert_eq!(v["failures_detected"], serde_json::json!([]));
    assert_eq!(v["died"], serde_json::json!([]));
    assert_eq!(num(&v["agents_killed_at_end"]), 0, "every agent ends by itself on End");
    assert!(v["round_wall_ms"]["p50"].as_f64().unwrap() > 0.0);
    assert!(v["agent_peak_rss_kib"]["max"].as_f64().unwrap() > 0.0);
    let msgs = v["messages_per_robot_round"].as_f64().unwrap();
    let wakes = v["wakeups_per_robot_round"].as_f64().unwrap();
    assert!(msgs >= 1.0 && wakes >= 1.0, "every robot sends its map and is woken each round: {msgs} {wakes}");
}

/// Runs `gridswarm run --json --out DIR ARGS`; checks nothing is left.
fn run_into(dir: &Path, args: &[&str]) -> Value {
    let all = [&["run", "--json", "--out", dir.to_str().unwrap()][..], args].concat();
    let v = finished(&gridswarm().args(&all).output().unwrap(), &all);
    assert_no_leftovers(v["ipc_prefix"].as_str().unwrap());
    v
}

/// `simulate`'s summary and `run`'s say what was run, alike but for the
/// key only a distributed run has, and how: their transports tell them apart.
fn assert_same_agreement(tag: &str, run_summary: &Value, sim: &Path) {
    let sim: Value = serde_json::from_slice(&fs::read(sim.join("summary.json")).unwrap()).unwrap();
    let (mut agreed, simulated) = (run_summary["agreement"].clone(), &sim["agreement"]);
    assert_eq!(agreed["key"], run_summary["ipc_prefix"], "{tag}");
    assert!(simulated["key"].is_null(), "{tag}: {simulated}");
    agreed["key"] = Value::Null;
    assert_eq!(&agreed, simulated, "{tag}: agreement");
    assert_eq!(run_summary["transport"]["name"], "iceoryx2", "{tag}");
    assert_eq!(sim["transport"]["name"], "in-process", "{tag}");
}

/// The files that must be byte-identical between the engines, and the
/// summary numbers that must be equal.
fn assert_same_run(tag: &str, run: &Path, sim: &Path, run_summary: &Value) {
    for file in ["trajectories.jsonl", "rounds.csv"] {
        let (a, b) = (fs::read(run.join(file)).unwrap(), fs::read(sim.join(file)).unwrap());
        assert!(a == b, "{tag}: {file} differs between run and the in-process engine");
    }
    let sim: Value = serde_json::from_slice(&fs::read(sim.join("summary.json")).unwrap()).unwrap();
    for key in ["rounds", "search_time_s", "collisions", "complete", "targets_found", "coverage", "robot_rounds"] {
        assert_eq!(run_summary[key], sim[key], "{tag}: {key}");
    }
}

#[test]
fn same_trajectories_as_simulate_for_every_grid_policy() {
    let _s = serial();
    let dir = scratch("equivalence");
    let cases: &[(&str, &str, &str, &str)] = &[
        // (scenario, robots, seed, situations)
        ("paper", "5", "3", "12"),
        ("paper", "13", "11", "12"),
        ("open", "8", "2", "1"),
    ];
    let mut compared = 0;
    for &(scenario, robots, seed, situations) in cases {
        for policy in gridswarm::vopr::POLICIES {
            for sit in situations.chars().map(|c| c.to_string()) {
                let args = [
                    "--scenario",
                    scenario,
                    "--algorithm",
                    policy,
                    "--robots",
                    robots,
                    "--seed",
                    seed,
                    "--situation",
                    &sit,
                ];
                let tag = format!("{scenario}-{policy}-{robots}-{seed}-{sit}");
                let (d, s) = (dir.join(format!("run-{tag}")), dir.join(format!("sim-{tag}")));
                let summary = run_into(&d, &args);
                search(&[&["simulate", "--out", s.to_str().unwrap()][..], &args[..]].concat());
                assert_same_run(&tag, &d, &s, &summary);
                assert_same_agreement(&tag, &summary, &s);
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 40);
}

/// With `--starts random` the world-server draws the layout from the seed
/// as `simulate` does: the same layout, the same run, and not the fixed one.
#[test]
fn same_trajectories_as_simulate_with_random_starts() {
    let _s = serial();
    let dir = scratch("random-starts");
    for (policy, seed) in [("repulsive", "4"), ("escape", "9")] {
        let args = ["--algorithm", policy, "--robots", "6", "--seed", seed, "--starts", "random"];
        let tag = format!("random starts, {policy}, seed {seed}");
        let (d, s, f) = (dir.join(format!("run-{policy}")), dir.join(format!("sim-{policy}")), dir.join(policy));
        let summary = run_into(&d, &args);
        search(&[&["simulate", "--out", s.to_str().unwrap()][..], &args[..]].concat());
        assert_same_run(&tag, &d, &s, &summary);
        let sim: Value = serde_json::from_slice(&fs::read(s.join("summary.json")).unwrap()).unwrap();
        assert_eq!(summary["starts"], sim["starts"], "{tag}");
        assert_eq!(summary["start_rule"], "random", "{tag}");
        search(&["simulate", "--out", f.to_str().unwrap(), "--algorithm", policy, "--robots", "6", "--seed", seed]);
        let fixed: Value = serde_json::from_slice(&fs::read(f.join("summary.json")).unwrap()).unwrap();
        assert_ne!(fixed["starts"], sim["starts"], "{tag}: drawn, not the scenario's layout");
    }
}

/// Under the fixed slot rule the world closes every slot at the robots'
/// clocks' time, commanded or not: both engines still make the same run,
/// with faults too (a robot slow by 5 s misses its slots' ends).
#[test]
fn same_trajectories_as_simulate_under_the_fixed_slot() {
    let _s = serial();
    let dir = scratch("fixed-slot");
    let mut cases: Vec<Vec<&str>> = ["repulsive", "sequential", "ru", "escape", "frontier"]
        .iter()
        .map(|&p| vec!["--algorithm", p, "--robots", "6", "--seed", "5", "--situation", "2"])
        .collect();
    cases.push(vec!["--robots", "9", "--seed", "4", "--kill", "3@4+0.3", "--slow", "2@2:5000"]);
    cases.push(vec!["--algorithm", "escape", "--robots", "9", "--seed", "8", "--freeze", "5@2:6", "--loss", "0.05"]);
    for (k, case) in cases.iter().enumerate() {
        let args = [&["--scenario", "paper", "--slot", "fixed"][..], case].concat();
        let tag = format!("fixed {args:?}");
        let (d, s) = (dir.join(format!("run-{k}")), dir.join(format!("sim-{k}")));
        let summary = run_into(&d, &args);
        search(&[&["simulate", "--out", s.to_str().unwrap()][..], &args[..]].concat());
        assert_same_run(&tag, &d, &s, &summary);
        assert_same_agreement(&tag, &summary, &s);
        assert_eq!(summary["params"]["slot"], "fixed", "{tag}");
        assert_eq!(num(&summary["protocol"]["forced_slots"]), 0, "{tag}: a fixed slot is never forced");
        assert_eq!(num(&summary["protocol"]["late_motors"]), 0, "{tag}: no robot commands past a slot's end");
    }
}

/// Past a stated bound (a lone robot slow by 4 s under the fixed slot,
/// issue 37) both engines end the run's record `past_bound` at the same
/// round, naming the bound, with exit status 5 (`finished` checks it).
#[test]
fn a_run_past_a_bound_ends_past_bound_in_both_engines() {
    let _s = serial();
    let dir = scratch("past-bound");
    let args = [
        "--scenario",
        "paper",
        "--robots",
        "1",
        "--algorithm",
        "frontier",
        "--seed",
        "5",
        "--situation",
        "2",
        "--slot",
        "fixed",
        "--max-rounds",
        "1500",
        "--slow",
        "0@5:4000",
    ];
    let (d, s) = (dir.join("run"), dir.join("sim"));
    let summary = run_into(&d, &args);
    search(&[&["simulate", "--out", s.to_str().unwrap()][..], &args[..]].concat());
    assert_same_run("past bound", &d, &s, &summary);
    let sim: Value = serde_json::from_slice(&fs::read(s.join("summary.json")).unwrap()).unwrap();
    let why = "no robot moved for 50 rounds, robot 0 slow by 4 s, past the fixed slot's bound of 3.502 s";
    for v in [&summary, &sim] {
        assert_eq!((v["ended_by"].as_str(), v["past_bound"].as_str()), (Some("past_bound"), Some(why)), "{v}");
        assert_eq!(num(&v["rounds"]), 55);
    }
}

/// Under the local choice order, and with robots waiting on a frozen
/// neighbour past half a `t_wait` (so they send `Wait` frames, which
/// their neighbours hold in their radio buffers), both engines make the
/// same run.
#[test]
fn same_trajectories_as_simulate_under_the_local_order_and_long_waits() {
    let _s = serial();
    let dir = scratch("local-order");
    let cases: [&[&str]; 3] = [
        &["--order", "local", "--robots", "9", "--seed", "4"],
        &["--order", "local", "--algorithm", "sequential", "--robots", "9", "--seed", "8", "--freeze", "1@2+0.02:6"],
        &["--robots", "9", "--seed", "8", "--freeze", "5@2+0.02:6", "--kill", "2@4+0.05"],
    ];
    for (k, case) in cases.iter().enumerate() {
        let args = [&["--scenario", "paper"][..], case].concat();
        let tag = format!("order {args:?}");
        let (d, s) = (dir.join(format!("run-{k}")), dir.join(format!("sim-{k}")));
        let summary = run_into(&d, &args);
        search(&[&["simulate", "--out", s.to_str().unwrap()][..], &args[..]].concat());
        assert_same_run(&tag, &d, &s, &summary);
        assert_same_agreement(&tag, &summary, &s);
        let order = if case.contains(&"local") { "local" } else { "paper" };
        assert_eq!(summary["params"]["order"], order, "{tag}");
        if k > 0 {
            // Robots gave up on the frozen one after a `t_wait`: they told
            // theirs they waited half-way.
            assert!(num(&summary["protocol"]["timeouts"]) > 0, "{tag}: nobody waited on the frozen robot");
        }
    }
}

/// Options of `gridswarm run` on the paper scenario, 13 robots.
fn options(seed: u64, situation: Situation) -> RunOptions {
    let mut o = RunOptions::for_experiment("paper".into(), Policy::Repulsive, 13, seed, situation, 0, 100_000);
    o.json = true;
    o
}

/// The in-process engine on the same plan `gridswarm run` makes from
/// `opts`, its run directory written into `dir`.
fn in_process(opts: &RunOptions, dir: &Path) {
    let plan = run::plan(opts).unwrap();
    let result = gridswarm::engine::run(&plan.world, &plan.starts, &plan.cfg);
    let record = RunRecord {
        scenario: &plan.scenario,
        world: &plan.world,
        starts: &plan.starts,
        lfp: &plan.scenario.lfp,
        result: &result,
        extra: Value::Null,
    };
    rundir::write_run_dir(dir, &record).unwrap();
}

#[test]
fn faults_and_radio_impairments_give_the_in_process_run() {
    let _s = serial();
    let dir = scratch("fault-equivalence");
    let kill = |s| schedule::parse_kill(s).unwrap();
    let freeze = |s| schedule::parse_freeze(s).unwrap();
    let lossy = Radio { loss: 0.1, ..Radio::default() };
    let noisy = Radio { loss: 0.05, delay: 3000, jitter: 2000, dup: 0.1 };
    type Case<'a> = (&'a [&'a str], Vec<gridswarm::sim::Fault>, Radio, Option<u32>, usize);
    let cases: Vec<Case> = vec![
        (&["--kill", "3@4+0.3"], vec![kill("3@4+0.3")], Radio::default(), None, 0),
        (&["--freeze", "2@3:6"], freeze("2@3:6"), Radio::default(), None, 0),
        (&["--freeze", "5@2"], freeze("5@2"), Radio::default(), None, 0),
        (&["--loss", "0.1", "--retries", "1"], vec![], lossy, Some(1), 0),
        (&["--kill-random", "3", "--loss", "0.05", "--delay", "3:2", "--dup", "0.1"], vec![], noisy, None, 3),
    ];
    for (situation, sit) in [(Situation::One, "1"), (Situation::Two, "2")] {
        for (k, (args, faults, radio, retries, kill_random)) in cases.iter().enumerate() {
            let tag = format!("case {k} {args:?} situation {sit}");
            let mut opts = options(9, situation);
            opts.faults = faults.clone();
            opts.radio = *radio;
            opts.retries = *retries;
            opts.kill_random = *kill_random;
            let (d, s) = (dir.join(format!("run-{k}-{sit}")), dir.join(format!("sim-{k}-{sit}")));
            let base = ["--robots", "13", "--seed", "9", "--situation", sit];
            let summary = run_into(&d, &[&base[..], args].concat());
            in_process(&opts, &s);
            assert_same_run(&tag, &d, &s, &summary);
            if radio.is_perfect() || radio.loss == 0.1 {
                // (With delay, jitter and duplicates the protocol does
                // collide; the two engines agree on how often.)
                assert_eq!(num(&summary["collisions"]), 0, "{tag}");
            }
            let injected = summary["failures_injected"].as_array().unwrap();
            assert_eq!(injected.len(), faults.len() + kill_random, "{tag}");
        }
    }
}

#[test]
fn wake_ups_bigger_than_a_sample_cross_in_chunks_unchanged() {
    let _s = serial();
    let dir = scratch("chunks");
    // `large`: maps of about 10 KB; a robot hearing two at one instant gets
    // a wake-up bigger than one 16 KiB sample.
    let mut opts = RunOptions::for_experiment("large".into(), Policy::Repulsive, 30, 4, Situation::Two, 0, 25);
    opts.radio = Radio { loss: 0.05, ..Radio::default() };
    let (d, s) = (dir.join("run"), dir.join("sim"));
    let summary = run_into(
        &d,
        &[
            "--scenario",
            "large",
            "--robots",
            "30",
            "--seed",
            "4",
            "--situation",
            "2",
            "--max-rounds",
            "25",
            "--loss",
            "0.05",
        ],
    );
    in_process(&opts, &s);
    assert_same_run("large, 30 robots", &d, &s, &summary);
    let largest = num(&summary["largest_wake_bytes"]);
    assert!(largest > gridswarm::ipc::CHUNK_BYTES as u64, "no wake-up needed chunks: {largest} bytes");
    assert_eq!(num(&summary["dropped_messages"]["total"]), 0);
}

#[test]
fn killed_robots_are_declared_by_the_robots_and_the_search_completes() {
    let _s = serial();
    let dir = scratch("kill");
    for sit in ["1", "2"] {
        let out = dir.join(format!("sit{sit}"));
        let v = run_into(
            &out,
            &["--robots", "13", "--seed", "7", "--situation", sit, "--kill", "3@5", "--kill", "6@8+0.02"],
        );
        assert_eq!(v["complete"], true, "situation {sit}: {v}");
        assert_eq!(num(&v["collisions"]), 0);
        assert_eq!(num(&v["refused_moves"]), 0);
        let injected = v["failures_injected"].as_array().unwrap();
        assert!(injected.iter().all(|i| i["applied"] == true), "{injected:?}");
        let failures = v["protocol"]["failures"].as_array().unwrap();
        assert_eq!(failures.len(), 2, "{failures:?}");
        for (f, (robot, round)) in failures.iter().zip([(3u64, 5u64), (6, 8)]) {
            assert_eq!(f["robot"], robot);
            assert_eq!(f["kind"], "crash");
            // A fault late in a slot may fall after the slot closed.
            assert!((round..=round + 1).contains(&num(&f["round"])), "{f}");
            // Only robots tell: the world records who declared it.
            let by = f["declared_by"].as_array().unwrap();
            assert!(!by.is_empty(), "nobody declared robot {robot}: {f}");
            assert!(by.iter().all(|b| b != robot));
            assert!(num(&f["detected_round"]) >= num(&f["round"]));
        }
        // The dead robot never moves again: its vertex stays blocked.
        let traj = fs::read_to_string(out.join("trajectories.jsonl")).unwrap();
        let lines = robot_lines(&traj, 3);
        assert!(lines[5..].iter().all(|l| *l == lines[5]), "robot 3 moved after its death");
    }
}

#[test]
fn random_kills_are_reproducible_from_the_seed() {
    let _s = serial();
    let dir = scratch("kill-random");
    let mut seen = Vec::new();
    for n in 0..2 {
        let out = dir.join(format!("r{n}"));
        let v = run_into(&out, &["--robots", "13", "--seed", "5", "--kill-random", "3"]);
        assert_eq!(num(&v["collisions"]), 0);
        assert_eq!(num(&v["refused_moves"]), 0);
        let injected = v["failures_injected"].clone();
        assert_eq!(injected.as_array().unwrap().len(), 3);
        seen.push((injected, fs::read(out.join("trajectories.jsonl")).unwrap()));
    }
    assert_eq!(seen[0].0, seen[1].0, "same schedule");
    assert!(seen[0].1 == seen[1].1, "same trajectories");
}

#[test]
fn a_frozen_robot_is_declared_and_a_thawed_one_ends_by_itself() {
    let _s = serial();
    let v = run_json(&["--robots", "13", "--seed", "7", "--freeze", "4@3:8"]);
    assert_eq!(num(&v["collisions"]), 0);
    assert_eq!(num(&v["refused_moves"]), 0);
    let f = &v["protocol"]["failures"][0];
    assert_eq!(f["robot"], 4);
    assert_eq!(f["kind"], "freeze");
    assert!(f["thawed_s"].as_f64().is_some(), "{f}");
    assert_eq!(num(&v["agents_killed_at_end"]), 0, "thawed, it reads End and exits");
    // One frozen for good is killed at the end, at once.
    let v = run_json(&["--robots", "13", "--seed", "7", "--freeze", "5@2"]);
    assert_eq!(v["failures_injected"][0]["applied"], true);
    let f = &v["protocol"]["failures"][0];
    assert_eq!(f["robot"], 5);
    assert!(!f["declared_by"].as_array().unwrap().is_empty(), "{f}");
    assert_eq!(f["unaware"], serde_json::json!([]));
    assert!(v["run_wall_ms"].as_f64().unwrap() < 60_000.0);
}

#[test]
fn a_world_server_crash_ends_the_run_with_one_line() {
    let _s = serial();
    let (child, world, agents, prefix) = stalled_run();
    signal(world, libc::SIGKILL);
    let out = child.wait_with_output().unwrap();
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert_eq!(err.trim_end(), "error: world-server died (signal 9) in round 2");
    let mut pids = agents;
    pids.push(world);
    assert_all_gone(&pids, &prefix);
}

#[test]
fn an_agent_that_dies_unscheduled_is_found_dead_and_the_run_goes_on() {
    let _s = serial();
    let child = spawn_hanging(&["run", "--json", "--robots", "13", "--seed", "7"], "2@2");
    let hung = stopped_agent(child.id(), 2);
    // The world waits for its answer; its process vanishes instead.
    signal(hung, libc::SIGKILL);
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_no_leftovers(v["ipc_prefix"].as_str().unwrap());
    assert_eq!(v["died"], serde_json::json!([2]));
    let f = &v["protocol"]["failures"][0];
    assert_eq!((f["robot"].as_u64(), f["kind"].as_str(), f["round"].as_u64()), (Some(2), Some("died"), Some(2)), "{f}");
    assert_eq!(num(&v["collisions"]), 0);
    assert!(text(&out.stderr).contains("robot-agent(s) [2] did not end cleanly"), "{}", text(&out.stderr));
}

#[test]
fn a_live_robot_silent_too_long_ends_the_run_naming_it() {
    let _s = serial();
    // The world-server with a 1 s patience, through a wrapper the
    // orchestrator finds in GRIDSWARM_BIN_DIR.
    let bin = scratch("silence-bin");
    let real = bin_dir();
    std::os::unix::fs::symlink(real.join("robot-agent"), bin.join("robot-agent")).unwrap();
    let script = format!("#!/bin/sh\nexec {} --silence-s 1 \"$@\"\n", real.join("world-server").display());
    fs::write(bin.join("world-server"), script).unwrap();
    fs::set_permissions(bin.join("world-server"), std::os::unix::fs::PermissionsExt::from_mode(0o755)).unwrap();
    let child = std::process::Command::new(real.join("gridswarm"))
        .args(["run", "--robots", "5", "--seed", "3"])
        .env("GRIDSWARM_BIN_DIR", &*bin)
        .env("GRIDSWARM_AGENT_HANG", "2@2")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Every prefix of this orchestrator's runs starts so.
    let prefixes = format!("gs{}x", child.id());
    let out = child.wait_with_output().unwrap();
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    let (head, why) = err.trim_end().split_once(": robot 2 (pid ").unwrap_or_else(|| panic!("{err}"));
    assert_eq!(head, "error: world-server failed (exit status 1) in round 2");
    assert!(why.ends_with("is alive but has not answered for 1 s"), "{err}");
    assert_no_leftovers(&prefixes);
}

#[test]
fn two_runs_at_once_do_not_see_each_other() {
    let _s = serial();
    let dir = scratch("concurrent");
    let specs = [("13", "21"), ("9", "22")];
    let kids: Vec<_> = specs
        .iter()
        .map(|&(robots, seed)| {
            gridswarm()
                .args(["run", "--json", "--robots", robots, "--seed", seed, "--out"])
                .arg(dir.join(format!("run-{seed}")))
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    let outs: Vec<_> = kids.into_iter().map(|k| k.wait_with_output().unwrap()).collect();
    let mut prefixes = Vec::new();
    for (o, &(robots, seed)) in outs.iter().zip(&specs) {
        assert!(o.status.success(), "{}", text(&o.stderr));
        let v: Value = serde_json::from_slice(&o.stdout).unwrap();
        prefixes.push(v["ipc_prefix"].as_str().unwrap().to_string());
        let sim = dir.join(format!("sim-{seed}"));
        search(&["simulate", "--robots", robots, "--seed", seed, "--out", sim.to_str().unwrap()]);
        assert_same_run(&format!("seed {seed}"), &dir.join(format!("run-{seed}")), &sim, &v);
    }
    assert_ne!(prefixes[0], prefixes[1]);
    for p in &prefixes {
        assert_no_leftovers(p);
    }
}

#[test]
fn lfp_and_bad_failure_arguments_are_refused_with_one_error() {
    for (args, want) in [
        (&["run", "--algorithm", "lfp"][..], "lfp"),
        (&["run", "--robots", "3", "--kill", "5@2"][..], "robot 5 does not exist"),
        (&["run", "--freeze", "1@4:2"][..], "the wake must come after the freeze"),
        (&["run", "--kill", "1@x"][..], "not a whole number"),
        (&["run", "--robots", "3", "--kill-random", "4"][..], "--kill-random"),
        (&["run", "--loss", "1.5"][..], "probability"),
        (&["run", "--kill", "1@2", "--freeze", "1@3"][..], "more than one failure"),
    ] {
        let out = gridswarm().args(args).output().unwrap();
        assert!(!out.status.success(), "{args:?}");
        let err = text(&out.stderr);
        // One line of ours, or clap's message: the error and a pointer to --help.
        assert!(err.lines().count() == 1 || err.trim_end().ends_with("try '--help'."), "{args:?}: {err}");
        assert_eq!(err.matches("error: ").count(), 1, "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
    }
}
