//! End-to-end tests of `gridswarm run` (issue "One process per robot over
//! iceoryx2, with failure injection"): the real orchestrator, world-server
//! and robot-agent binaries, one OS process per robot. After every run: no
//! file of it in /dev/shm or iceoryx2's root, no process of it left.

use std::fs;
use std::path::PathBuf;
use std::process::Stdio;
use std::time::Duration;

use gridswarm_e2e::*;
use serde_json::Value;

fn num(v: &Value) -> u64 {
    v.as_u64().unwrap_or_else(|| panic!("not a count: {v}"))
}

/// Trajectory lines of robot `r`.
fn robot_lines(traj: &str, r: usize) -> Vec<String> {
    let key = format!("\"robot\":{r},");
    traj.lines()
        .filter(|l| l.contains(&key))
        .map(|l| l.split(",\"robot\"").nth(1).unwrap().to_string())
        .collect()
}

#[test]
fn thirteen_robots_complete_a_search() {
    let _s = serial();
    let v = run_json(&["--robots", "13", "--seed", "7"]);
    assert_eq!(v["engine"], "distributed");
    assert_eq!(v["robots"], 13);
    assert_eq!(v["complete"], true);
    assert_eq!(v["targets_found"], v["targets_total"]);
    assert_eq!(num(&v["collisions"]), 0);
    assert_eq!(num(&v["refused_moves"]), 0);
    assert_eq!(num(&v["dropped_messages"]["total"]), 0);
    assert_eq!(v["failures_detected"], serde_json::json!([]));
    assert_eq!(
        num(&v["agents_killed_at_end"]),
        0,
        "every agent ends by itself on End"
    );
    assert!(v["round_wall_ms"]["p50"].as_f64().unwrap() > 0.0);
    assert!(v["agent_peak_rss_kib"]["max"].as_f64().unwrap() > 0.0);
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
        for policy in ["repulsive", "sequential", "ru", "escape"] {
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
                let (d, s) = (
                    dir.join(format!("run-{tag}")),
                    dir.join(format!("sim-{tag}")),
                );
                let out = ok(&[
                    &["run", "--json", "--out", d.to_str().unwrap()][..],
                    &args[..],
                ]
                .concat());
                let summary: Value = serde_json::from_slice(&out.stdout).unwrap();
                assert_no_leftovers(summary["ipc_prefix"].as_str().unwrap());
                ok(&[&["simulate", "--out", s.to_str().unwrap()][..], &args[..]].concat());
                for file in ["trajectories.jsonl", "rounds.csv"] {
                    let (a, b) = (
                        fs::read(d.join(file)).unwrap(),
                        fs::read(s.join(file)).unwrap(),
                    );
                    assert!(a == b, "{tag}: {file} differs between run and simulate");
                }
                let sim: Value =
                    serde_json::from_slice(&fs::read(s.join("summary.json")).unwrap()).unwrap();
                for key in [
                    "rounds",
                    "search_time_s",
                    "collisions",
                    "complete",
                    "targets_found",
                    "coverage",
                    "robot_rounds",
                ] {
                    assert_eq!(summary[key], sim[key], "{tag}: {key}");
                }
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 20);
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn killed_robots_are_declared_failed_and_the_search_completes() {
    let _s = serial();
    let dir = scratch("kill");
    for sit in ["1", "2"] {
        let out = dir.join(format!("sit{sit}"));
        let v = run_json(&[
            "--robots",
            "13",
            "--seed",
            "7",
            "--situation",
            sit,
            "--kill",
            "3@5",
            "--kill",
            "8@10",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(v["complete"], true, "situation {sit}: {v}");
        assert_eq!(num(&v["collisions"]), 0);
        assert_eq!(num(&v["refused_moves"]), 0);
        let detected = v["failures_detected"].as_array().unwrap();
        assert_eq!(detected.len(), 2, "{detected:?}");
        for (d, (robot, round)) in detected.iter().zip([(3, 5), (8, 10)]) {
            assert_eq!(d["robot"], robot);
            assert_eq!(
                d["cause"], "death",
                "primary detection is the process's death"
            );
            assert_eq!(d["round"], round);
            assert_eq!(d["delay_rounds"], 0);
            assert!(d["delay_ms"].as_f64().unwrap() < 1000.0, "{d}");
        }
        // The dead robot never moves again: its vertex stays blocked.
        let traj = fs::read_to_string(out.join("trajectories.jsonl")).unwrap();
        let lines = robot_lines(&traj, 3);
        assert!(
            lines[5..].iter().all(|l| *l == lines[5]),
            "robot 3 moved after its death"
        );
    }
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn random_kills_are_reproducible_from_the_seed() {
    let _s = serial();
    let dir = scratch("kill-random");
    let mut seen = Vec::new();
    for n in 0..2 {
        let out = dir.join(format!("r{n}"));
        let v = run_json(&[
            "--robots",
            "13",
            "--seed",
            "5",
            "--kill-random",
            "3",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(num(&v["collisions"]), 0);
        assert_eq!(num(&v["refused_moves"]), 0);
        let injected = v["failures_injected"].clone();
        assert_eq!(injected.as_array().unwrap().len(), 3);
        seen.push((injected, fs::read(out.join("trajectories.jsonl")).unwrap()));
    }
    assert_eq!(seen[0].0, seen[1].0, "same schedule");
    assert!(seen[0].1 == seen[1].1, "same trajectories");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn a_frozen_robot_is_declared_by_deadline_and_wakes_harmlessly() {
    let _s = serial();
    let v = run_json(&[
        "--robots",
        "13",
        "--seed",
        "7",
        "--freeze",
        "4@3:8",
        "--suspect-ms",
        "200",
    ]);
    assert_eq!(v["complete"], true);
    assert_eq!(num(&v["collisions"]), 0);
    assert_eq!(num(&v["refused_moves"]), 0);
    let d = &v["failures_detected"][0];
    assert_eq!(d["robot"], 4);
    assert_eq!(
        d["cause"], "deadline",
        "a stopped process is alive: only the deadline finds it"
    );
    assert_eq!(d["round"], 3);
    assert!(d["delay_ms"].as_f64().unwrap() >= 200.0);
    // Woken in round 8 it reads `Deposed` and exits by itself.
    assert_eq!(num(&v["agents_killed_at_end"]), 0);
}

#[test]
fn a_slow_robot_wrongly_suspected_stops_and_its_stale_messages_are_dropped() {
    let _s = serial();
    // Robot 5 takes 300 ms over its sensing; the world suspects it after 100.
    let v = run_json(&[
        "--scenario",
        "large",
        "--robots",
        "13",
        "--seed",
        "7",
        "--slow",
        "5@300",
        "--suspect-ms",
        "100",
    ]);
    assert_eq!(v["complete"], true);
    assert_eq!(num(&v["collisions"]), 0);
    assert_eq!(num(&v["refused_moves"]), 0);
    assert_eq!(v["failures_detected"][0]["robot"], 5);
    assert_eq!(v["failures_detected"][0]["cause"], "deadline");
    assert!(
        num(&v["dropped_messages"]["stale"]) >= 1,
        "its late map was dropped: {}",
        v["dropped_messages"]
    );
}

/// Starts a run that stalls in round 2 (robot 2 frozen, suspected only
/// after a minute) and returns it with its world pid, agent pids and prefix.
fn stalled_run() -> (std::process::Child, u32, Vec<u32>, String) {
    let child = gridswarm()
        .args([
            "run",
            "--robots",
            "13",
            "--seed",
            "7",
            "--freeze",
            "2@2",
            "--suspect-ms",
            "60000",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pid = child.id();
    let mut world = 0;
    let mut agents = Vec::new();
    let mut prefix = String::new();
    let found = wait_until(Duration::from_secs(20), || {
        let kids = children(pid);
        let (w, a): (Vec<u32>, Vec<u32>) = kids.iter().partition(|&&k| {
            cmdline(k)
                .first()
                .is_some_and(|c| c.ends_with("world-server"))
        });
        if w.len() == 1 && a.len() == 13 {
            world = w[0];
            agents = a;
            prefix = arg_of(&cmdline(world), "--prefix").unwrap_or_default();
            // Robot 2 frozen: the world is in round 2, waiting.
            agents
                .iter()
                .any(|&p| arg_of(&cmdline(p), "--robot").as_deref() == Some("2") && stopped(p))
        } else {
            false
        }
    });
    assert!(found, "the run did not reach its stall");
    assert!(!prefix.is_empty());
    (child, world, agents, prefix)
}

fn assert_all_gone(pids: &[u32], prefix: &str) {
    assert!(
        wait_until(Duration::from_secs(5), || pids.iter().all(|&p| !alive(p))),
        "a process of the run outlived it"
    );
    assert_no_leftovers(prefix);
    assert_eq!(temp_files(prefix), Vec::<PathBuf>::new());
}

/// The orchestrator's temporary files of a run (its report, the agents' log).
fn temp_files(prefix: &str) -> Vec<PathBuf> {
    let head = format!("gridswarm-{prefix}");
    fs::read_dir(std::env::temp_dir())
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with(&head))
        .map(|e| e.path())
        .collect()
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
    assert_eq!(
        err.trim_end(),
        "error: world-server died (signal 9) in round 2"
    );
    let mut pids = agents;
    pids.push(world);
    assert_all_gone(&pids, &prefix);
}

#[test]
fn sigint_and_sigterm_end_every_child() {
    let _s = serial();
    for (sig, name) in [(libc::SIGINT, "SIGINT"), (libc::SIGTERM, "SIGTERM")] {
        let (child, world, agents, prefix) = stalled_run();
        signal(child.id(), sig);
        let out = child.wait_with_output().unwrap();
        assert!(!out.status.success());
        let err = text(&out.stderr);
        assert_eq!(err.lines().count(), 1, "one line: {err}");
        assert!(
            err.starts_with(&format!("error: interrupted by {name}")),
            "{err}"
        );
        let mut pids = agents;
        pids.push(world);
        assert_all_gone(&pids, &prefix);
    }
}

#[test]
fn children_die_with_a_killed_orchestrator_and_the_next_run_sweeps_its_files() {
    let _s = serial();
    let (mut child, world, agents, prefix) = stalled_run();
    signal(child.id(), libc::SIGKILL);
    let _ = child.wait();
    let mut pids = agents;
    pids.push(world);
    // PR_SET_PDEATHSIG: the children die with it.
    assert!(
        wait_until(Duration::from_secs(5), || pids.iter().all(|&p| !alive(p))),
        "children outlived the orchestrator"
    );
    // Its files stay (nobody removed them)...
    assert!(!leftover_files(&prefix).is_empty());
    // ...until the next run sweeps runs whose owner is dead.
    run_json(&["--robots", "3", "--seed", "1"]);
    assert_no_leftovers(&prefix);
    assert_eq!(temp_files(&prefix), Vec::<PathBuf>::new());
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
    let outs: Vec<_> = kids
        .into_iter()
        .map(|k| k.wait_with_output().unwrap())
        .collect();
    let mut prefixes = Vec::new();
    for (o, &(robots, seed)) in outs.iter().zip(&specs) {
        assert!(o.status.success(), "{}", text(&o.stderr));
        let v: Value = serde_json::from_slice(&o.stdout).unwrap();
        prefixes.push(v["ipc_prefix"].as_str().unwrap().to_string());
        let sim = dir.join(format!("sim-{seed}"));
        ok(&[
            "simulate",
            "--robots",
            robots,
            "--seed",
            seed,
            "--out",
            sim.to_str().unwrap(),
        ]);
        let a = fs::read(dir.join(format!("run-{seed}/trajectories.jsonl"))).unwrap();
        assert!(
            a == fs::read(sim.join("trajectories.jsonl")).unwrap(),
            "seed {seed}: trajectories differ"
        );
    }
    assert_ne!(prefixes[0], prefixes[1]);
    for p in &prefixes {
        assert_no_leftovers(p);
    }
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn lfp_and_bad_failure_arguments_are_refused_in_one_line() {
    for (args, want) in [
        (&["run", "--algorithm", "lfp"][..], "lfp"),
        (
            &["run", "--robots", "3", "--kill", "5@2"][..],
            "robot 5 does not exist",
        ),
        (&["run", "--freeze", "1@4:2"][..], "wake round"),
        (
            &["run", "--robots", "3", "--kill-random", "4"][..],
            "--kill-random",
        ),
    ] {
        let out = gridswarm().args(args).output().unwrap();
        assert!(!out.status.success(), "{args:?}");
        let err = text(&out.stderr);
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
    }
}
