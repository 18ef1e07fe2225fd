//! Open-file limits: a distributed run needs about 9 descriptors a robot
//! in the world-server (15 before outboxes and wake-ups were shared).
//! Under a limit too low for it, a run used to go wrong in the middle
//! (with 256 and 15 a robot: healthy robots declared dead at 17 robots,
//! 1.5 s rounds at 18, a 32 s wait for hellos at 19-24); now it is refused
//! before anything starts, with the number needed, the limits and the fix,
//! every run the limit admits runs correctly, and the number needed is
//! not below what a run opens. A wake-up that still fails ends the run
//! with a message.

use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use gridswarm::nofile::needed;
use gridswarm_e2e::*;

/// `gridswarm ARGS` with open-file limits `soft:hard`, as `prlimit
/// --nofile=soft:hard` would start it.
fn limited(soft: u64, hard: u64, args: &[&str]) -> Command {
    let mut c = gridswarm();
    c.args(args);
    // SAFETY: setrlimit is async-signal-safe.
    unsafe {
        c.pre_exec(move || {
            let l = libc::rlimit { rlim_cur: soft as libc::rlim_t, rlim_max: hard as libc::rlim_t };
            if libc::setrlimit(libc::RLIMIT_NOFILE, &l) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    c
}

/// Runs it, with how long it took and the prefix head of its runs.
fn timed(mut c: Command) -> (Output, Duration, String) {
    let t = Instant::now();
    let child = c.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let prefixes = format!("gs{}x", child.id());
    let out = child.wait_with_output().unwrap();
    (out, t.elapsed(), prefixes)
}

/// The refusal's one line, for `what` needing `needed` under `limit:limit`.
fn assert_refused(out: &Output, took: Duration, what: &str, needed: u64, limit: u64) {
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    let err = text(&out.stderr);
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with(&format!("error: {what} needs {needed} open files")), "{err}");
    assert!(err.contains(&format!("open-file limit is {limit} (hard limit {limit})")), "{err}");
    assert!(err.contains(&format!("`ulimit -n {needed}`")), "{err}");
    assert!(took < Duration::from_secs(10), "took {took:?}");
}

#[test]
fn runs_a_limit_of_256_cannot_hold_are_refused_at_once() {
    let _s = serial();
    // The first count past the limit, and one further.
    let first = largest_admitted(256) + 1;
    for n in [first, first + 7] {
        let robots = n.to_string();
        let (out, took, prefixes) = timed(limited(256, 256, &["run", "--robots", &robots, "--seed", "3"]));
        assert_refused(&out, took, &format!("a distributed run of {n} robots"), needed(n), 256);
        assert_no_leftovers(&prefixes);
    }
}

#[test]
fn the_largest_run_a_limit_of_256_admits_runs_correctly() {
    let _s = serial();
    let n = largest_admitted(256);
    // 17-23 were the reproducers when a robot cost 15 descriptors.
    assert!(n >= 23, "{n}");
    let robots = n.to_string();
    let args = ["run", "--json", "--robots", &robots, "--seed", "3"];
    let (out, _, _) = timed(limited(256, 256, &args));
    let v = finished(&out, &args);
    assert_no_leftovers(v["ipc_prefix"].as_str().unwrap());
    assert_eq!(v["complete"], true, "{v}");
    assert_eq!(v["died"], serde_json::json!([]), "healthy robots taken for dead");
    assert_eq!(v["failures_detected"], serde_json::json!([]), "healthy robots declared");
    assert!(v["world_fds"].as_u64().unwrap() <= needed(n), "{} open, {} needed", v["world_fds"], needed(n));
    assert!(v["round_wall_ms"]["max"].as_f64().unwrap() < 1000.0, "a slow path: {}", v["round_wall_ms"]);
    // The same search as in-process.
    let sim = finished(&search(&["simulate", "--json", "--robots", &robots, "--seed", "3"]), &[]);
    for k in ["rounds", "search_time_s", "collisions", "targets_found"] {
        assert_eq!(v[k], sim[k], "{k}");
    }
}

/// The most robots a limit of `limit` descriptors admits.
fn largest_admitted(limit: u64) -> usize {
    let n = (0..).find(|&n| needed(n + 1) > limit).unwrap();
    assert!(needed(n) <= limit);
    n
}

/// What the world of a run of many robots really opens, measured in the
/// middle of the run (the report counts before `End`): never more than
/// the number the run asks for, and not much less either (the number
/// would refuse runs that fit).
#[test]
fn the_number_needed_covers_what_a_run_opens() {
    let _s = serial();
    let n = 200;
    let args = ["run", "--json", "--scenario", "large", "--robots", "200", "--seed", "3", "--max-rounds", "3"];
    let (out, _, _) = timed(limited(needed(n), needed(n), &args));
    let v = finished(&out, &args);
    assert_no_leftovers(v["ipc_prefix"].as_str().unwrap());
    assert_eq!(v["died"], serde_json::json!([]), "{v}");
    let open = v["world_fds"].as_u64().unwrap();
    assert!(open <= needed(n), "{open} open, {} needed", needed(n));
    assert!(open + 60 >= needed(n), "{open} open, {} needed: the number is far too high", needed(n));
}

#[test]
fn a_soft_limit_below_the_need_is_raised_to_the_hard_one() {
    let _s = serial();
    let args = ["run", "--json", "--robots", "13", "--seed", "3"];
    let (out, _, _) = timed(limited(64, 4096, &args));
    let v = finished(&out, &args);
    assert_no_leftovers(v["ipc_prefix"].as_str().unwrap());
    assert_eq!(v["complete"], true);
    assert!(v["world_fds"].as_u64().unwrap() > 64, "the world ran with more than the soft limit: {}", v["world_fds"]);
}

#[test]
fn experiments_are_refused_before_their_first_run() {
    let _s = serial();
    let dir = scratch("limits-experiments");
    let out_dir = dir.join("out");
    let o = out_dir.to_str().unwrap();
    let cases: [(&[&str], usize); 2] = [
        (&["experiment", "scale", "--robots", "5,100", "--runs", "1", "--out", o], 100),
        (
            &[
                "experiment",
                "failures",
                "--engine",
                "distributed",
                "--scenario",
                "large",
                "--robots",
                "30",
                "--killed",
                "0",
                "--runs",
                "1",
                "--out",
                o,
            ],
            30,
        ),
    ];
    for (args, n) in cases {
        let (out, took, prefixes) = timed(limited(256, 256, args));
        assert_refused(&out, took, &format!("a distributed run of {n} robots"), needed(n), 256);
        assert!(!Path::new(&out_dir).exists(), "{args:?} wrote results");
        assert_no_leftovers(&prefixes);
    }
}

/// The open-file count of process `pid`.
fn fds(pid: u32) -> u64 {
    std::fs::read_dir(format!("/proc/{pid}/fd")).map(|d| d.count() as u64).unwrap_or(0)
}

#[test]
fn a_wake_up_that_cannot_be_delivered_ends_the_run_with_a_message() {
    let _s = serial();
    // Admission keeps the world within its limit; to see a wake-up fail,
    // lower the world's limit behind its back: stopped as soon as the
    // first agent exists (its services and ports made, no robot heard
    // yet), it gets room to hear every robot (a data segment and a
    // connection each) but not to reach their listeners (two more each).
    let n = 100u64;
    let robots = n.to_string();
    let mut seen = Vec::new();
    for _attempt in 0..3 {
        let t = Instant::now();
        let child = gridswarm()
            .args(["run", "--json", "--scenario", "large", "--robots", &robots, "--seed", "3"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let prefixes = format!("gs{}x", child.id());
        let mut world = 0;
        let started = wait_until(Duration::from_secs(60), || {
            let kids = children(child.id());
            world = kids
                .iter()
                .copied()
                .find(|&k| cmdline(k).first().is_some_and(|c| c.ends_with("world-server")))
                .unwrap_or(0);
            world != 0 && kids.len() > 1
        });
        assert!(started, "no agent started");
        signal(world, libc::SIGSTOP);
        assert!(wait_until(Duration::from_secs(5), || stopped(world)));
        let room = fds(world) + 2 * n + 6;
        let lim = libc::rlimit { rlim_cur: room as libc::rlim_t, rlim_max: room as libc::rlim_t };
        // SAFETY: prlimit on a process of this user, with a valid struct.
        let rc = unsafe { libc::prlimit(world as libc::pid_t, libc::RLIMIT_NOFILE, &lim, std::ptr::null_mut()) };
        assert_eq!(rc, 0, "prlimit: {}", std::io::Error::last_os_error());
        signal(world, libc::SIGCONT);
        let out = child.wait_with_output().unwrap();
        let took = t.elapsed();
        assert_no_leftovers(&prefixes);
        let err = text(&out.stderr);
        if out.status.code() == Some(1) {
            assert_eq!(err.lines().count(), 1, "one line: {err}");
            assert!(
                err.starts_with("error: world-server failed (exit status 1) in round 0: cannot wake robot "),
                "{err}"
            );
            assert!(err.contains("its listener cannot be reached (out of open files? the limit is"), "{err}");
            assert!(took < Duration::from_secs(60), "took {took:?}");
            return;
        }
        // Too late: the world had already heard its robots.
        seen.push(format!("{:?}: {err}", out.status));
    }
    panic!("the world never ran short of descriptors: {seen:?}");
}

/// Issue 23: a full `/dev/shm` killed the world with SIGBUS, and the run's
/// error did not mention shared memory. In a mount namespace of its own
/// (root, as CI), the run gets a `/dev/shm` of 16 KiB (the world's first
/// pages do not fit: SIGBUS) or 256 KiB (a service's file does not fit);
/// either way the one error line says that `/dev/shm` ran out, and the
/// machine's own `/dev/shm` is never touched.
#[test]
fn a_full_dev_shm_is_named_in_the_error() {
    if !as_root("a_full_dev_shm_is_named_in_the_error", "no mount namespace with a small /dev/shm") {
        return;
    }
    let _s = serial();
    for (size, robots, says) in
        [("16k", "13", "SIGBUS: the run's shared memory in /dev/shm"), ("256k", "200", "/dev/shm")]
    {
        let script = format!(
            "mount -t tmpfs -o size={size} tmpfs /dev/shm && exec \"$0\" run --scenario large --seed 1 --robots {robots}"
        );
        let child = Command::new("unshare")
            .args(["--mount", "--propagation", "private", "sh", "-c", &script])
            .arg(bin_dir().join("gridswarm"))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("unshare runs");
        // unshare and sh exec: the pid is gridswarm's.
        let prefixes = format!("gs{}x", child.id());
        let out = child.wait_with_output().unwrap();
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{size}: {err}");
        assert_eq!(err.lines().count(), 1, "{size}: one line: {err}");
        assert!(err.starts_with("error: world-server ") && err.contains(says), "{size}: {err}");
        assert!(err.contains(&format!("free of {} KiB", size.trim_end_matches('k'))), "{size}: {err}");
        assert_no_leftovers(&prefixes);
    }
}
