//! Signals that end a distributed run: SIGINT, SIGTERM, SIGHUP (a closed
//! terminal) and SIGQUIT end every child and remove every file of the run;
//! a `kill -9` of `gridswarm`, which nothing can catch, still leaves
//! nothing behind: the children die with it (`PR_SET_PDEATHSIG`) and the
//! world-server removes the run's files on its way out.

use std::time::Duration;

use gridswarm_e2e::*;

#[test]
fn every_terminal_signal_ends_every_child_and_removes_the_runs_files() {
    let _s = serial();
    let cases =
        [(libc::SIGINT, "SIGINT"), (libc::SIGTERM, "SIGTERM"), (libc::SIGHUP, "SIGHUP"), (libc::SIGQUIT, "SIGQUIT")];
    for (sig, name) in cases {
        let (child, world, agents, prefix) = stalled_run();
        assert!(!leftover_files(&prefix).is_empty(), "a live run has files");
        signal(child.id(), sig);
        let out = child.wait_with_output().unwrap();
        assert_eq!(out.status.code(), Some(1), "{name}: {:?}", out.status);
        let err = text(&out.stderr);
        assert_eq!(err.lines().count(), 1, "one line: {err}");
        assert!(err.starts_with(&format!("error: interrupted by {name}: stopped the world-server")), "{err}");
        let mut pids = agents;
        pids.push(world);
        assert_all_gone(&pids, &prefix);
    }
}

#[test]
fn a_killed_orchestrator_leaves_no_process_and_no_file() {
    let _s = serial();
    let (mut child, world, agents, prefix) = stalled_run();
    assert!(!temp_files(&prefix).is_empty() && !leftover_files(&prefix).is_empty());
    signal(child.id(), libc::SIGKILL);
    let _ = child.wait();
    let mut pids = agents;
    pids.push(world);
    // PR_SET_PDEATHSIG: the agents die with it; the world gets SIGTERM and
    // removes the run's files, the agents' included, and the
    // orchestrator's temporary directory: no later run is needed.
    assert!(
        wait_until(Duration::from_secs(5), || pids.iter().all(|&p| !alive(p))),
        "children outlived the orchestrator"
    );
    assert!(
        wait_until(Duration::from_secs(5), || leftover_files(&prefix).is_empty() && temp_files(&prefix).is_empty()),
        "left: {:?} {:?}",
        leftover_files(&prefix),
        temp_files(&prefix)
    );
    assert_no_leftovers(&prefix);
}

/// Issue 23: a `kill -9`'d run leaves its hidden output folder (nothing
/// can catch SIGKILL); the next run into the same place removes it.
#[test]
fn the_next_run_removes_the_hidden_folder_a_killed_run_left() {
    let _s = serial();
    let dir = scratch("killed-out");
    let out = dir.join("out");
    let out_arg = out.to_str().unwrap();
    let mut child = spawn_hanging(&["run", "--robots", "3", "--seed", "7", "--out", out_arg], "1@2");
    stopped_agent(child.id(), 1);
    let hidden = |d: &std::path::Path| -> Vec<String> {
        let names = std::fs::read_dir(d).unwrap().flatten().map(|e| e.file_name().to_string_lossy().into_owned());
        names.filter(|n| n.starts_with(".out.tmp-")).collect()
    };
    assert_eq!(hidden(&dir).len(), 1, "the live run's hidden folder");
    signal(child.id(), libc::SIGKILL);
    let _ = child.wait();
    assert_eq!(hidden(&dir).len(), 1, "SIGKILL leaves it");
    let v = run_json(&["--robots", "2", "--seed", "1", "--out", out_arg]);
    assert_eq!(v["complete"], true);
    assert_eq!(hidden(&dir), Vec::<String>::new(), "the next run removed it");
    assert!(out.join("summary.json").is_file());
}

/// Issue 23: a world-server stopped with SIGSTOP hung `gridswarm run`
/// forever. The world says `alive` every second while it waits, so the
/// run notices its silence (10 s) and ends with a message naming it.
#[test]
fn a_stopped_world_ends_the_run_with_a_message() {
    let _s = serial();
    let (mut child, world, agents, prefix) = stalled_run();
    signal(world, libc::SIGSTOP);
    // 10 s of silence, with room for a busy machine; never forever.
    let ended = wait_until(Duration::from_secs(60), || child.try_wait().is_ok_and(|s| s.is_some()));
    if !ended {
        let _ = child.kill();
    }
    let out = child.wait_with_output().unwrap();
    assert!(ended, "the run still hangs 60 s after its world was stopped");
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    let last = err.lines().last().unwrap_or("");
    assert!(last.starts_with(&format!("error: world-server (pid {world}) is stopped")), "{err}");
    assert!(last.contains("has said nothing for 10 s"), "{err}");
    let mut pids = agents;
    pids.push(world);
    assert_all_gone(&pids, &prefix);
}

/// Issue 23: outside a run's loop (setup, the checks, an in-process sweep,
/// writing the outputs) the four signals killed `gridswarm` with no word,
/// exit 130 or 131, its hidden output folder left. They are handled from
/// the first line of `main`: one line naming the signal, exit 1, nothing
/// left. Here in the middle of an in-process sweep, which runs for many
/// seconds (500 runs a cell).
#[test]
fn a_signal_outside_a_run_ends_the_command_cleanly() {
    let _s = serial();
    let dir = scratch("signal-sweep");
    let out = dir.join("out");
    for (sig, name) in
        [(libc::SIGINT, "SIGINT"), (libc::SIGTERM, "SIGTERM"), (libc::SIGHUP, "SIGHUP"), (libc::SIGQUIT, "SIGQUIT")]
    {
        let child = gridswarm()
            .args(["experiment", "--runs", "500", "--out", out.to_str().unwrap()])
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let hidden = || std::fs::read_dir(&dir).unwrap().count();
        assert!(wait_until(Duration::from_secs(30), || hidden() == 1), "{name}: no staging folder appeared");
        signal(child.id(), sig);
        let o = child.wait_with_output().unwrap();
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {:?} {err}", o.status);
        assert_eq!(err.trim_end().lines().last(), Some(format!("error: interrupted by {name}").as_str()), "{err}");
        assert_eq!(hidden(), 0, "{name}: the unfinished output folder was left");
    }
}

/// The other side of the world's 10 s: a world that waits longer on a
/// robot that stopped itself (its patience is 30 s) keeps saying it is
/// alive, so the run ends with the world's own verdict on the robot, not
/// with a stuck world.
#[test]
fn a_world_waiting_on_a_silent_robot_is_not_taken_for_stuck() {
    let _s = serial();
    let (mut child, world, agents, prefix) = stalled_run();
    let ended = wait_until(Duration::from_secs(120), || child.try_wait().is_ok_and(|s| s.is_some()));
    if !ended {
        let _ = child.kill();
    }
    let out = child.wait_with_output().unwrap();
    assert!(ended, "the run still hangs 120 s after a robot stopped itself");
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(!err.contains("said nothing"), "a waiting world was taken for stuck: {err}");
    assert!(err.contains("robot 2") && err.contains("has not answered for 30 s"), "{err}");
    let mut pids = agents;
    pids.push(world);
    assert_all_gone(&pids, &prefix);
}
