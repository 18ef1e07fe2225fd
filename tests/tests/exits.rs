//! Exit statuses of `gridswarm`, through the binary: 0 a search that
//! completed, 3 one that ended incomplete (every robot failed, or the round
//! limit), 5 one past a stated bound that stalled, 1 an error, 2 a usage
//! error; and an agent that fails at start
//! ends the run at once with its own words.

use std::fs;
use std::os::unix::fs::PermissionsExt;
use std::process::Output;
use std::time::{Duration, Instant};

use gridswarm_e2e::*;

fn status(args: &[&str]) -> (Option<i32>, Output) {
    let out = gridswarm().args(args).output().expect("gridswarm runs");
    (out.status.code(), out)
}

#[test]
fn a_search_exits_0_complete_and_3_incomplete_in_both_engines() {
    let _s = serial();
    let all_killed = ["--robots", "3", "--seed", "2", "--kill", "0@1", "--kill", "1@1", "--kill", "2@1+0.5"];
    let cut_off = ["--robots", "3", "--seed", "2", "--max-rounds", "2"];
    let complete = ["--robots", "3", "--seed", "2"];
    for cmd in ["simulate", "run"] {
        for (args, want, ended_by) in
            [(&complete[..], 0, "stop"), (&all_killed[..], 3, "no_robots"), (&cut_off[..], 3, "max_rounds")]
        {
            let all = [&[cmd, "--json"][..], args].concat();
            let (code, out) = status(&all);
            assert_eq!(code, Some(want), "{all:?}: {}", text(&out.stderr));
            let v = finished(&out, &all);
            assert_eq!(v["ended_by"], ended_by, "{all:?}");
            if cmd == "run" {
                assert_no_leftovers(v["ipc_prefix"].as_str().unwrap());
            }
        }
    }
}

/// Every documented case of the README's exit-status table, each with the
/// words of the table's row it stands for (which the row must hold), run
/// against the binary. Signals (exit 1) are in `signals.rs`, a too low
/// open-file limit in `limits.rs`, a failing agent below.
#[test]
fn every_documented_exit_status_case_exits_as_the_readme_s_table_says() {
    let _s = serial();
    let readme = fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md")).expect("README.md");
    let row = |code: i32| {
        let head = format!("| {code} | ");
        readme.lines().find(|l| l.starts_with(&head)).unwrap_or_else(|| panic!("no row {code} in README's table"))
    };
    let unwritable = "/proc/gridswarm-unwritable";
    // Adjacent vertices exactly 2 r_safe apart: S0 fails.
    let dir = scratch("exits-s0");
    let tight = dir.join("tight.toml");
    fs::write(
        &tight,
        "targets = [[3.0, 3.0]]\n[area]\npolygon = [[0, 0], [8, 0], [8, 8], [0, 8]]\n\
         [params]\na = 0.5\nr_rob = 0.2\nr_safe = 0.25\n",
    )
    .unwrap();
    let tight = tight.to_str().unwrap();
    let cases: &[(&[&str], i32, &str)] = &[
        (&["simulate", "--robots", "3", "--seed", "2"], 0, "the search completed"),
        (&["check", "paper"], 0, "the command did its work"),
        (&["simulate", "--scenario", "no-such-scenario"], 1, "a bad scenario"),
        (&["run", "--scenario", "no-such-scenario"], 1, "a bad scenario"),
        (&["simulate", "--robots", "2", "--out", unwritable], 1, "unwritable output"),
        (&["run", "--no-such-flag"], 2, "an unknown flag"),
        (&["simulate", "--algorithm", "no-such-algorithm"], 2, "algorithm"),
        (&["run", "--algorithm", "lfp"], 2, "an algorithm `run` cannot run"),
        (&["run", "--robots", "0"], 2, "a value out of range"),
        (&["experiment", "scale", "--robots", "4097"], 2, "a value out of range"),
        (&["run", "--loss", "1.5"], 2, "a value out of range"),
        (&["simulate", "--robots", "3", "--kill", "3@2"], 2, "faults that do not fit the run"),
        (&["run", "--transport", "zenoh", "--remote-agents", "k", "--kill", "1@2"], 2, "faults with `--remote-agents`"),
        (&["run", "--listen", "tcp/127.0.0.1:7447"], 2, "zenoh's flags without `--transport zenoh`"),
        (&["run", "--transport", "zenoh", "--remote-agents", "a/b"], 2, "a bad run key or endpoint"),
        (&["run", "--transport", "zenoh", "--listen", "garbage"], 2, "a bad run key or endpoint"),
        (
            &["run", "--transport", "zenoh", "--remote-agents", "k", "--listen", "tls/0.0.0.0:7447"],
            2,
            "without `--credentials` or `--insecure`",
        ),
        (
            &["run", "--transport", "zenoh", "--insecure", "--listen", "tcp/0.0.0.0:7447"],
            2,
            "plain TCP off loopback without `--insecure-network`",
        ),
        (
            &["run", "--transport", "zenoh", "--credentials", "k", "--listen", "tcp/127.0.0.1:7447"],
            2,
            "an endpoint whose link does not fit",
        ),
        (&["credentials", "--out", "/tmp", "--robots", "2"], 1, "unwritable output"),
        (&["simulate", "--robots", "3", "--seed", "2", "--max-rounds", "2"], 3, "the search ended incomplete"),
        (&["check", "random:5,break=3.1.2"], 3, "`check` found a failing assumption"),
        (&["simulate", "--robots", "13", "--seed", "1", "--loss", "0.5", "--max-rounds", "400"], 4, "robots collided"),
        (&["simulate", "--scenario", tight], 4, "the run was refused"),
        (
            &["simulate", "--robots", "1", "--seed", "5", "--slot", "fixed", "--slow", "0@5:4000"],
            5,
            "past a stated bound",
        ),
        (&["run", "--robots", "1", "--seed", "5", "--slot", "fixed", "--slow", "0@5:4000"], 5, "no robot moved for 50"),
        (&["run", "--scenario", tight], 4, "`check`'s S0 fails"),
    ];
    for &(args, want, words) in cases {
        assert!(row(want).contains(words), "README's row {want} does not say {words:?}: {}", row(want));
        let (code, out) = status(args);
        let err = text(&out.stderr);
        assert_eq!(code, Some(want), "{args:?}: {err}");
        if want == 1 || want == 2 {
            assert!(err.starts_with("error: "), "{args:?}: {err}");
            // No debug dump of a library's error, naming its source files.
            assert!(!err.contains(".cargo/registry") && !err.contains("Err("), "{args:?}: {err}");
        }
    }
}

#[test]
fn the_help_lists_the_exit_statuses() {
    let (code, out) = status(&["--help"]);
    assert_eq!(code, Some(0));
    let help = text(&out.stdout);
    let table = &help[help.find("Exit status:").expect("an exit status section")..];
    for line in [
        "0  success",
        "1  error",
        "2  usage error",
        "3  the search ended incomplete",
        "4  robots collided",
        "5  the search went past a stated bound",
    ] {
        assert!(table.contains(line), "no {line:?} in {table}");
    }
}

#[test]
fn an_agent_that_fails_at_start_ends_the_run_at_once_with_its_error() {
    let _s = serial();
    // An agent program that lists its rules, then cannot start.
    let bin = scratch("failing-agent");
    let agent = bin.join("agent");
    fs::write(
        &agent,
        "#!/bin/sh\nif [ \"$1\" = --list-rules ]; then echo repulsive; exit 0; fi\n\
         echo \"my-agent: cannot start: no licence\" >&2\nexit 1\n",
    )
    .unwrap();
    fs::set_permissions(&agent, fs::Permissions::from_mode(0o755)).unwrap();
    let (out, took, prefixes) = run_with_agent("5", &agent);
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    let (head, tail) =
        err.trim_end().split_once(" failed at start (exit status 1): ").unwrap_or_else(|| panic!("{err}"));
    assert!(head.starts_with("error: robot-agent "), "{err}");
    assert_eq!(tail, "my-agent: cannot start: no licence");
    // Not the world's hello time-out (30 s).
    assert!(took < Duration::from_secs(10), "took {took:?}");
    assert_no_leftovers(&prefixes);
}

/// Issue 23: an agent that exits, even with status 0, or dies before its
/// hello ended the run only at the world's hello time-out (30 s). It ends
/// the run at once, with its exit status.
#[test]
fn an_agent_that_dies_before_its_hello_ends_the_run_at_once_with_its_status() {
    let _s = serial();
    let bin = scratch("dying-agent");
    let agent = bin.join("agent");
    fs::write(&agent, "#!/bin/sh\nif [ \"$1\" = --list-rules ]; then echo repulsive; exit 0; fi\nkill -9 $$\n")
        .unwrap();
    fs::set_permissions(&agent, fs::Permissions::from_mode(0o755)).unwrap();
    for (program, status) in [(agent.as_path(), "(signal 9)"), (std::path::Path::new("/bin/true"), "(exit status 0)")] {
        let (out, took, prefixes) = run_with_agent("3", program);
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{program:?}: {err}");
        assert_eq!(err.lines().count(), 1, "one line: {err}");
        assert!(err.starts_with("error: robot-agent ") && err.contains(&format!("failed at start {status}")), "{err}");
        // Well before the world's hello time-out (30 s), on a busy machine.
        assert!(took < Duration::from_secs(20), "{program:?}: took {took:?}");
        assert_no_leftovers(&prefixes);
    }
}

/// `gridswarm run --robots ROBOTS --agent-bin AGENT`: its output, how long
/// it took, and the prefix of its shared-memory files.
fn run_with_agent(robots: &str, agent: &std::path::Path) -> (std::process::Output, Duration, String) {
    let t = Instant::now();
    let child = gridswarm()
        .args(["run", "--robots", robots, "--agent-bin"])
        .arg(agent)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let prefixes = format!("gs{}x", child.id());
    (child.wait_with_output().unwrap(), t.elapsed(), prefixes)
}
