//! Helpers for the end-to-end tests in `tests/tests/`: they drive the real
//! binaries (`gridswarm`, `world-server`, `robot-agent`) from the build
//! directory next to the test executable, and check after every run that no
//! file and no process of it is left.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::{Mutex, MutexGuard};
use std::time::{Duration, Instant};

use serde_json::Value;

/// The build directory holding the binaries: the test executable lives in
/// its `deps/`. `cargo test --workspace` builds every binary first (each
/// binary crate has an integration test of its own, which makes cargo build it).
pub fn bin_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable");
    let dir = exe.parent().and_then(Path::parent).expect("target/<profile>/deps/<test>").to_path_buf();
    for b in ["gridswarm", "world-server", "robot-agent"] {
        assert!(
            dir.join(b).is_file(),
            "{} is missing: run `cargo test --release --workspace` (or `cargo build --release --workspace` first)",
            dir.join(b).display()
        );
    }
    dir
}

pub fn gridswarm() -> Command {
    let mut c = Command::new(bin_dir().join("gridswarm"));
    c.env_remove("GRIDSWARM_BIN_DIR");
    c
}

/// One test at a time: the machine has two cores and the deadline tests
/// must not be starved by other runs.
pub fn serial() -> MutexGuard<'static, ()> {
    static LOCK: Mutex<()> = Mutex::new(());
    LOCK.lock().unwrap_or_else(|e| e.into_inner())
}

pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Runs `gridswarm run --json ARGS`, expects the search to finish
/// ([`finished`]), returns the summary.
pub fn run_json(args: &[&str]) -> Value {
    let out = gridswarm().arg("run").arg("--json").args(args).output().expect("gridswarm runs");
    let v = finished(&out, args);
    assert_no_leftovers(v["ipc_prefix"].as_str().expect("the run names its prefix"));
    v
}

/// The JSON summary of a `simulate` or `run` whose search finished: exit
/// status 4 if robots collided under an algorithm that promises they never
/// do, else 5 if it ended past a stated bound, 0 if it completed, 3 if it
/// ended incomplete otherwise, as it says.
pub fn finished(out: &Output, args: &[&str]) -> Value {
    let code = out.status.code();
    assert!(matches!(code, Some(0 | 3 | 4 | 5)), "gridswarm {args:?} failed ({:?}): {}", out.status, text(&out.stderr));
    let v: Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    assert_eq!(code, Some(search_status(&v)), "exit status for {v}");
    v
}

/// The exit status a search's summary calls for (README "Exit status").
pub fn search_status(v: &Value) -> i32 {
    let promises_none = !matches!(v["algorithm"].as_str(), Some("ru" | "lfp" | "oracle"));
    if promises_none && v["collisions"].as_u64().unwrap_or(0) > 0 {
        4
    } else if v["ended_by"] == "past_bound" {
        5
    } else if v["complete"] == true {
        0
    } else {
        3
    }
}

/// Runs `gridswarm simulate` or `run` with ARGS; expects the search to
/// finish, complete (exit status 0) or not (3), with robots collided (4),
/// or past a stated bound (5).
pub fn search(args: &[&str]) -> Output {
    let out = gridswarm().args(args).output().expect("gridswarm runs");
    assert!(matches!(out.status.code(), Some(0 | 3 | 4 | 5)), "gridswarm {args:?} failed: {}", text(&out.stderr));
    out
}

/// Runs a gridswarm subcommand, expects success.
pub fn ok(args: &[&str]) -> Output {
    let out = gridswarm().args(args).output().expect("gridswarm runs");
    assert!(out.status.success(), "gridswarm {args:?} failed: {}", text(&out.stderr));
    out
}

/// Every file of the run with this prefix in /dev/shm and its iceoryx2 root.
pub fn leftover_files(prefix: &str) -> Vec<PathBuf> {
    gridswarm::ipc::run_files(prefix)
}

/// No file in /dev/shm or iceoryx2's root, no temporary file and no
/// process of the run with this prefix is left.
pub fn assert_no_leftovers(prefix: &str) {
    let files = leftover_files(prefix);
    assert!(files.is_empty(), "files of run {prefix} left: {files:?}");
    assert_eq!(temp_files(prefix), Vec::<PathBuf>::new(), "temporary files of run {prefix} left");
    assert!(
        wait_until(Duration::from_secs(5), || processes_of(prefix).is_empty()),
        "processes of run {prefix} left: {:?}",
        processes_of(prefix)
    );
}

/// Starts a run that stalls in round 2 (robot 2 stops its own process
/// there, unscheduled: the world waits for its answer) and returns it with
/// its world pid, agent pids and prefix.
pub fn stalled_run() -> (std::process::Child, u32, Vec<u32>, String) {
    let child = spawn_hanging(&["run", "--robots", "13", "--seed", "7"], "2@2");
    let pid = child.id();
    // Robot 2 has read slot 2: the world and every agent are up by then.
    stopped_agent(pid, 2);
    let (world, agents): (Vec<u32>, Vec<u32>) =
        children(pid).into_iter().partition(|&k| cmdline(k).first().is_some_and(|c| c.ends_with("world-server")));
    assert_eq!((world.len(), agents.len()), (1, 13), "the run's processes");
    let prefix = arg_of(&cmdline(world[0]), "--prefix").unwrap_or_default();
    assert!(!prefix.is_empty());
    (child, world[0], agents, prefix)
}

/// `gridswarm ARGS`, its output piped, with `GRIDSWARM_AGENT_HANG=hang`:
/// the robots it names stop their own processes at those slots.
pub fn spawn_hanging(args: &[&str], hang: &str) -> std::process::Child {
    gridswarm()
        .args(args)
        .env("GRIDSWARM_AGENT_HANG", hang)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap()
}

/// The agent of robot `r` among `pid`'s children, once it has stopped itself.
pub fn stopped_agent(pid: u32, r: usize) -> u32 {
    let setup = format!("robot-{r}.json");
    let mut found = 0;
    let stopped_itself = wait_until(Duration::from_secs(60), || {
        found = children(pid)
            .into_iter()
            .find(|&p| arg_of(&cmdline(p), "--setup").is_some_and(|s| s.ends_with(&setup)) && stopped(p))
            .unwrap_or(0);
        found != 0
    });
    assert!(stopped_itself, "robot {r} did not stop itself");
    found
}

/// Every process in `pids` ends within 5 s, and nothing of the run is left.
pub fn assert_all_gone(pids: &[u32], prefix: &str) {
    assert!(wait_until(Duration::from_secs(5), || pids.iter().all(|&p| !alive(p))), "a process of the run outlived it");
    assert_no_leftovers(prefix);
}

/// Child processes of `pid`.
pub fn children(pid: u32) -> Vec<u32> {
    let mut out = Vec::new();
    if let Ok(tasks) = std::fs::read_dir(format!("/proc/{pid}/task")) {
        for t in tasks.flatten() {
            if let Ok(s) = std::fs::read_to_string(t.path().join("children")) {
                out.extend(s.split_whitespace().filter_map(|p| p.parse::<u32>().ok()));
            }
        }
    }
    out
}

pub fn cmdline(pid: u32) -> Vec<String> {
    std::fs::read(format!("/proc/{pid}/cmdline"))
        .map(|b| b.split(|&c| c == 0).filter(|a| !a.is_empty()).map(text).collect())
        .unwrap_or_default()
}

/// The value following `flag` in a command line.
pub fn arg_of(cmd: &[String], flag: &str) -> Option<String> {
    cmd.iter().position(|a| a == flag).and_then(|k| cmd.get(k + 1).cloned())
}

/// Whether this test process is root. A test that needs root and lacks it
/// says so (`test`: not root, so `lacking`) and checks nothing; CI is root.
pub fn as_root(test: &str, lacking: &str) -> bool {
    // SAFETY: geteuid has no preconditions.
    let root = unsafe { libc::geteuid() == 0 };
    if !root {
        eprintln!("{test}: not root, so {lacking}; nothing checked");
    }
    root
}

pub fn alive(pid: u32) -> bool {
    gridswarm::ipc::pid_alive(pid)
}

pub fn stopped(pid: u32) -> bool {
    gridswarm::ipc::pid_stopped(pid)
}

/// Polls `cond` every 10 ms until it holds or `timeout` passes.
pub fn wait_until(timeout: Duration, mut cond: impl FnMut() -> bool) -> bool {
    let end = Instant::now() + timeout;
    while Instant::now() < end {
        if cond() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    cond()
}

pub fn signal(pid: u32, sig: i32) {
    // SAFETY: kill(2) on a process this test started (or its child).
    unsafe {
        libc::kill(pid as libc::pid_t, sig);
    }
}

/// A scratch directory for one test, removed when dropped (also when
/// the test fails and unwinds).
pub struct Scratch(PathBuf);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A fresh scratch directory for one test.
pub fn scratch(name: &str) -> Scratch {
    let d = std::env::temp_dir().join(format!("gridswarm-e2e-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    Scratch(d)
}

/// Processes whose command line mentions `prefix` (a run's iceoryx2
/// prefix: the world-server and every robot-agent of that run carry it).
pub fn processes_of(prefix: &str) -> Vec<u32> {
    let Ok(dir) = std::fs::read_dir("/proc") else { return Vec::new() };
    dir.flatten()
        .filter_map(|e| e.file_name().to_str()?.parse::<u32>().ok())
        .filter(|&p| alive(p) && cmdline(p).iter().any(|a| a.contains(prefix)))
        .collect()
}

/// The orchestrator's temporary files of a run (its run directory).
pub fn temp_files(prefix: &str) -> Vec<PathBuf> {
    let head = format!("gridswarm-{prefix}");
    std::fs::read_dir(std::env::temp_dir())
        .map(|d| d.flatten().filter(|e| e.file_name().to_string_lossy().starts_with(&head)).map(|e| e.path()).collect())
        .unwrap_or_default()
}

/// `gridswarm setup --key KEY RUN --robot K --out DIR/robot-K.json`: the
/// setup file of an agent started by hand (README, "Running on several
/// machines"); returns its path.
pub fn setup_file(dir: &Path, key: &str, run: &[&str], robot: usize) -> PathBuf {
    let out = dir.join(format!("robot-{robot}.json"));
    let k = robot.to_string();
    let args = [&["setup", "--key", key][..], run, &["--robot", &k, "--out", out.to_str().unwrap()]].concat();
    ok(&args);
    out
}
