//! Other local users against a run (issue 11, item 4; SECURITY.md): a
//! hostile user who keeps overwriting and truncating every file of a live
//! run, a second user running beside the first, and a root folder that
//! belongs to someone else; and a zenoh run (issue 23, item 2), which the
//! other user can neither read, join nor disturb without the run's
//! credentials, while with `--insecure` it can read it all. The other user
//! is uid 65534 (`nobody`), reached with `setpriv`; that needs root, as in
//! CI.

mod intruder;

use std::fs;
use std::io::Read;
use std::os::unix::fs::{MetadataExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use gridswarm_e2e::*;
use serde_json::Value;

/// The other user: `nobody` on Debian and most distributions.
const OTHER_UID: u32 = 65534;

/// Set in the hostile writer's environment: the pid whose runs it attacks.
const HOSTILE: &str = "GRIDSWARM_TEST_HOSTILE_PID";

/// Becoming another user takes root. Without it these tests cannot make
/// the other user at all; they say so and check nothing.
fn can_switch_user(test: &str) -> bool {
    as_root(test, "no other uid to act as")
}

/// Whether the other user may run `program`: it and every folder above it
/// are open to others (a checkout under `/root` is not).
fn other_can_run(program: &Path) -> bool {
    let open = |p: &Path, bits: u32| fs::metadata(p).is_ok_and(|m| m.mode() & bits == bits);
    open(program, 0o005) && program.ancestors().skip(1).filter(|a| !a.as_os_str().is_empty()).all(|a| open(a, 0o001))
}

/// `programs`, where the other user can run them: in place if it can,
/// else copied into `dir` (which must be open to others), side by side.
fn runnable_by_other(programs: &[PathBuf], dir: &Path) -> Vec<PathBuf> {
    if programs.iter().all(|p| other_can_run(p)) {
        return programs.to_vec();
    }
    fs::set_permissions(dir, fs::Permissions::from_mode(0o755)).unwrap();
    let copies: Vec<PathBuf> = programs.iter().map(|p| dir.join(p.file_name().unwrap())).collect();
    for (p, c) in programs.iter().zip(&copies) {
        fs::copy(p, c).unwrap();
        fs::set_permissions(c, fs::Permissions::from_mode(0o755)).unwrap();
    }
    copies
}

/// `PROGRAM ARGS` run as the other user, with no supplementary groups.
fn as_other_user(program: &Path) -> Command {
    let mut c = Command::new("setpriv");
    c.args([format!("--reuid={OTHER_UID}"), format!("--regid={OTHER_UID}"), "--clear-groups".into()]);
    c.arg(program);
    c
}

/// Ends and reaps a child when dropped, so that a failing test leaves no
/// hostile writer or run behind: SIGTERM first, on which a run removes
/// its files, then SIGKILL.
struct Reaped(Option<Child>);

impl Reaped {
    fn take(&mut self) -> Child {
        self.0.take().expect("the child is still held")
    }
}

impl Drop for Reaped {
    fn drop(&mut self) {
        if let Some(mut c) = self.0.take() {
            signal(c.id(), libc::SIGTERM);
            if !wait_until(Duration::from_secs(5), || c.try_wait().is_ok_and(|s| s.is_some())) {
                let _ = c.kill();
            }
            let _ = c.wait();
        }
    }
}

/// What the hostile writer did, from the line it prints at the end.
#[derive(Debug, Default)]
struct Attack {
    /// Files of the run it found.
    seen: usize,
    /// Reads of them that succeeded.
    read: usize,
    /// Opens for writing, writes and truncations that succeeded.
    succeeded: usize,
    /// Whether it found the node counter file (the one iceoryx2 makes 0666).
    saw_counter: bool,
}

/// Every file under `dir` whose path (below `dir`) starts with `head`.
fn files_of(dir: &Path, head: &str, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else { return };
    for e in entries.flatten() {
        if !e.file_name().to_string_lossy().starts_with(head) {
            continue;
        }
        match e.file_type() {
            Ok(t) if t.is_dir() => files_of(&e.path(), "", out),
            Ok(t) if t.is_file() => out.push(e.path()),
            _ => {}
        }
    }
}

/// Whether `f` could be read.
fn peek(f: &Path) -> bool {
    fs::File::open(f).is_ok_and(|mut file| file.read(&mut [0u8; 64]).is_ok())
}

/// Overwrites the start of `f` with garbage, then truncates it; never
/// creates a file. Counts what succeeded.
fn attack(f: &Path) -> usize {
    use std::io::Write;
    let Ok(mut file) = fs::OpenOptions::new().write(true).open(f) else { return 0 };
    1 + usize::from(file.write_all(&[0xa5; 64]).is_ok()) + usize::from(file.set_len(0).is_ok())
}

/// The hostile writer (this test executable, run again as the other user):
/// until its stdin closes, it reads and attacks every file whose name starts with
/// the prefix of the runs of `pid`, in /dev/shm and the temporary folder,
/// then prints what it did.
fn hostile_writer(pid: &str) {
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = stop.clone();
    std::thread::spawn(move || {
        let _ = std::io::stdin().read_to_end(&mut Vec::new());
        flag.store(true, std::sync::atomic::Ordering::Relaxed);
    });
    let shm_head = format!("gs{pid}x");
    let tmp_head = format!("gridswarm-gs{pid}x");
    let (mut seen, mut read, mut succeeded, mut saw_counter) = (std::collections::BTreeSet::new(), 0, 0, false);
    while !stop.load(std::sync::atomic::Ordering::Relaxed) {
        let mut files = Vec::new();
        files_of(Path::new("/dev/shm"), &shm_head, &mut files);
        // The run's iceoryx2 root folder.
        files_of(Path::new("/dev/shm"), &tmp_head, &mut files);
        files_of(&std::env::temp_dir(), &tmp_head, &mut files);
        for f in files {
            saw_counter |= f.to_string_lossy().ends_with(".global_mgmt");
            read += usize::from(peek(&f));
            succeeded += attack(&f);
            seen.insert(f);
        }
    }
    println!("seen {} read {read} succeeded {succeeded} counter {saw_counter}", seen.len());
}

fn parse_attack(out: &str) -> Attack {
    let w: Vec<&str> = out.split_whitespace().collect();
    assert!(w.len() == 8 && w[0] == "seen", "the hostile writer's report: {out:?}");
    Attack {
        seen: w[1].parse().unwrap(),
        read: w[3].parse().unwrap(),
        succeeded: w[5].parse().unwrap(),
        saw_counter: w[7] == "true",
    }
}

#[test]
fn a_hostile_user_cannot_disturb_a_live_run() {
    if let Ok(pid) = std::env::var(HOSTILE) {
        return hostile_writer(&pid);
    }
    if !can_switch_user("a_hostile_user_cannot_disturb_a_live_run") {
        return;
    }
    let _s = serial();
    let dir = scratch("hostile");
    let (run_out, sim_out) = (dir.join("run"), dir.join("sim"));
    let args = ["--robots", "8", "--seed", "3"];
    // The run starts a moment late, so the writer is already at work when
    // the run's first file appears; `exec` keeps the pid the writer targets.
    let mut run = Reaped(Some(
        Command::new("sh")
            .args(["-c", "sleep 0.3; exec \"$0\" \"$@\""])
            .arg(bin_dir().join("gridswarm"))
            .args(["run", "--json", "--out", run_out.to_str().unwrap()])
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("gridswarm starts"),
    ));
    let run_pid = run.0.as_ref().unwrap().id();
    let mut writer = Reaped(Some(
        as_other_user(&runnable_by_other(&[std::env::current_exe().unwrap()], &dir)[0])
            .args(["--exact", "a_hostile_user_cannot_disturb_a_live_run", "--nocapture", "--test-threads=1"])
            .env(HOSTILE, run_pid.to_string())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("setpriv starts the hostile writer"),
    ));
    let started = Instant::now();
    let out = run.take().wait_with_output().unwrap();
    let took = started.elapsed();
    let mut w = writer.take();
    drop(w.stdin.take());
    let w_out = w.wait_with_output().unwrap();
    let report = text(&w_out.stdout);
    // The test harness prints its own words before it on the same line.
    let line = report.find("seen ").map(|k| report[k..].lines().next().unwrap_or("")).unwrap_or_else(|| {
        panic!("the hostile writer did not report ({}): {report}{}", w_out.status, text(&w_out.stderr))
    });
    let attack = parse_attack(line);
    assert!(out.status.success(), "the run failed after {took:?} under attack ({attack:?}): {}", text(&out.stderr));
    assert!(attack.seen > 0 && attack.saw_counter, "the writer never saw the run's node counter: {attack:?}");
    assert_eq!(attack.succeeded, 0, "another user wrote to a file of the run: {attack:?}");
    assert_eq!(attack.read, 0, "another user read a file of the run: {attack:?}");
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!((v["complete"].as_bool(), v["collisions"].as_u64()), (Some(true), Some(0)), "{v}");
    assert_no_leftovers(v["ipc_prefix"].as_str().unwrap());
    ok(&[&["simulate", "--out", sim_out.to_str().unwrap()][..], &args].concat());
    for file in ["trajectories.jsonl", "rounds.csv"] {
        let (a, b) = (fs::read(run_out.join(file)).unwrap(), fs::read(sim_out.join(file)).unwrap());
        assert!(a == b, "{file} differs from the in-process run's");
    }
}

/// iceoryx2's shared default root, `/tmp/iceoryx2`, as the first user of a
/// machine leaves it (mode 0750); made for the test if missing, and then
/// removed again.
struct SharedIox2Root {
    made: bool,
}

impl SharedIox2Root {
    const PATH: &'static str = "/tmp/iceoryx2";

    fn ensure() -> Self {
        let made = fs::create_dir(Self::PATH).is_ok();
        if made {
            fs::set_permissions(Self::PATH, fs::Permissions::from_mode(0o750)).unwrap();
        }
        SharedIox2Root { made }
    }
}

impl Drop for SharedIox2Root {
    fn drop(&mut self) {
        if self.made {
            let _ = fs::remove_dir(Self::PATH);
        }
    }
}

#[test]
fn a_second_user_runs_while_iceoryx2_s_shared_root_is_another_s() {
    if !can_switch_user("a_second_user_runs_while_iceoryx2_s_shared_root_is_another_s") {
        return;
    }
    let _s = serial();
    let dir = scratch("second-user");
    let bins = runnable_by_other(&["gridswarm", "world-server", "robot-agent"].map(|b| bin_dir().join(b)), &dir);
    let shared = SharedIox2Root::ensure();
    let owner = fs::metadata(SharedIox2Root::PATH).unwrap();
    assert!(owner.uid() != OTHER_UID && owner.mode() & 0o007 == 0, "/tmp/iceoryx2 is closed to the other user");
    let mut run = Reaped(Some(
        as_other_user(&bins[0])
            .args(["run", "--json", "--robots", "3", "--seed", "1"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("setpriv starts gridswarm"),
    ));
    let out = run.take().wait_with_output().unwrap();
    drop(shared);
    assert!(out.status.success(), "the other user's run failed: {}", text(&out.stderr));
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["complete"], true);
    assert_no_leftovers(v["ipc_prefix"].as_str().unwrap());
}

#[test]
fn a_root_folder_another_user_owns_is_refused_naming_folder_and_owner() {
    if !can_switch_user("a_root_folder_another_user_owns_is_refused_naming_folder_and_owner") {
        return;
    }
    let _s = serial();
    let dir = scratch("foreign-root");
    // The run's own root folder, made in advance by the other user.
    let prefix = format!("gs{}x{:06x}_", std::process::id(), 0xf0e);
    let root = gridswarm::ipc::run_root(&prefix);
    let _gone = RunGone(prefix.clone());
    fs::create_dir(&root).unwrap();
    chown(&root, OTHER_UID);
    let config = gridswarm::ipc::config(&prefix).unwrap();
    let err = gridswarm::ipc::create_node(&config, "world").expect_err("a foreign root is refused");
    assert!(err.contains(&root.display().to_string()) && err.contains(&format!("uid {OTHER_UID}")), "{err}");
    assert!(gridswarm::ipc::run_files(&prefix).is_empty(), "nothing was made in it");

    // A temporary folder of the other user's: the whole run stops at once,
    // naming it and its owner.
    let tmp = dir.join("tmp");
    fs::create_dir(&tmp).unwrap();
    chown(&tmp, OTHER_UID);
    let started = Instant::now();
    let out = gridswarm().args(["run", "--robots", "2", "--seed", "1"]).env("TMPDIR", &tmp).output().unwrap();
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains(&format!("{} above", tmp.display())) && err.contains(&format!("uid {OTHER_UID}")), "{err}");
    assert!(started.elapsed() < Duration::from_secs(10), "refused after {:?}", started.elapsed());
}

fn chown(path: &Path, uid: u32) {
    let c = std::ffi::CString::new(path.as_os_str().as_encoded_bytes()).unwrap();
    // SAFETY: chown(2) on a path this test made, with a valid C string.
    assert_eq!(unsafe { libc::chown(c.as_ptr(), uid, uid) }, 0, "chown {}", path.display());
}

/// `setpriv` as the other user, as an intruder's launcher.
fn other_user() -> Vec<String> {
    ["setpriv".into(), format!("--reuid={OTHER_UID}"), format!("--regid={OTHER_UID}"), "--clear-groups".into()].into()
}

/// Makes `dir` and its files readable by the other user (its own
/// certificates; the authority's certificate, which is no secret).
fn open_to_other(dir: &Path) {
    fs::set_permissions(dir, fs::Permissions::from_mode(0o755)).unwrap();
    for e in fs::read_dir(dir).unwrap() {
        fs::set_permissions(e.unwrap().path(), fs::Permissions::from_mode(0o644)).unwrap();
    }
}

#[test]
fn another_user_cannot_read_join_or_disturb_a_zenoh_run() {
    const TEST: &str = "another_user_cannot_read_join_or_disturb_a_zenoh_run";
    if let Ok(spec) = std::env::var(intruder::SPEC) {
        return intruder::act(&spec);
    }
    if !can_switch_user(TEST) {
        return;
    }
    let _s = serial();
    let dir = scratch("zenoh-other-user");
    let exe = runnable_by_other(&[std::env::current_exe().unwrap()], &dir)[0].clone();
    // The run's credentials, as README's commands make them (mode 0700).
    let keys = dir.join("keys");
    intruder::credentials(&keys, 4, &[]);
    // The other user's own: another authority's, with a `robot-0`
    // certificate, and a copy of the run's authority's certificate.
    let own = dir.join("own");
    intruder::credentials(&own, 1, &[]);
    fs::copy(keys.join("ca.pem"), own.join("run-ca.pem")).unwrap();
    open_to_other(&own);
    let port = intruder::free_port();
    let (tls, tcp) = (format!("tls/127.0.0.1:{port}"), format!("tcp/127.0.0.1:{port}"));
    let key = format!("other{}", std::process::id());
    let security = ["--credentials".to_string(), keys.display().to_string()];
    let run = ["--scenario", "paper", "--seed", "3", "--robots", "4"];
    let out = dir.join("run");
    let mut world = Reaped(Some(intruder::start_world(&key, &tls, &security, &run, &out)));
    let orders = intruder::Orders {
        endpoint: tls.clone(),
        key: key.clone(),
        ca: Some(own.join("run-ca.pem")),
        cert: Some((own.join("robot-0.pem"), own.join("robot-0.key"))),
        read: ["ca.pem", "world.key", "robot-0.key"].map(|f| keys.join(f)).into(),
        disturb: true,
    };
    let impostor = intruder::Intruder::start(&other_user(), &exe, TEST, &orders);
    let anonymous =
        intruder::Intruder::start(&other_user(), &exe, TEST, &intruder::Orders { cert: None, ..orders.clone() });
    let plain = intruder::Intruder::start(
        &other_user(),
        &exe,
        TEST,
        &intruder::Orders { endpoint: tcp, ca: None, cert: None, ..orders },
    );
    let agents = intruder::start_agents(&key, &tls, &security, (&run[..], &dir), 4);
    let v = intruder::finish(world.take(), agents);
    for (who, r) in [
        ("another authority's robot 0", impostor.stop()),
        ("no certificate", anonymous.stop()),
        ("plain TCP", plain.stop()),
    ] {
        assert!(r.reached, "{who}: the world's port never answered: {r:?}");
        assert_eq!((r.opened, r.read, r.received), (false, 0, 0), "{who} got in: {r:?}");
    }
    assert_eq!(
        v["transport"]["security"],
        serde_json::json!({"mode": "mutual-tls", "authenticated": true, "encrypted": true})
    );
    intruder::same_as_simulate(&out, &run);
}

#[test]
fn with_insecure_another_user_reads_the_whole_run() {
    const TEST: &str = "with_insecure_another_user_reads_the_whole_run";
    if let Ok(spec) = std::env::var(intruder::SPEC) {
        return intruder::act(&spec);
    }
    if !can_switch_user(TEST) {
        return;
    }
    let _s = serial();
    let dir = scratch("zenoh-insecure");
    let exe = runnable_by_other(&[std::env::current_exe().unwrap()], &dir)[0].clone();
    let endpoint = format!("tcp/127.0.0.1:{}", intruder::free_port());
    let key = format!("plain{}", std::process::id());
    let security = ["--insecure".to_string()];
    let run = ["--scenario", "paper", "--seed", "3", "--robots", "4"];
    let out = dir.join("run");
    let mut world = Reaped(Some(intruder::start_world(&key, &endpoint, &security, &run, &out)));
    let orders = intruder::Orders { endpoint: endpoint.clone(), key: key.clone(), ..Default::default() };
    let listener = intruder::Intruder::start(&other_user(), &exe, TEST, &orders);
    let agents = intruder::start_agents(&key, &endpoint, &security, (&run[..], &dir), 4);
    let v = intruder::finish(world.take(), agents);
    let r = listener.stop();
    assert!(r.opened && r.received > 100, "plain TCP is open to anyone: {r:?}");
    for k in ["in/0", "out/3", "alive/1"] {
        assert!(r.keys.contains(&format!("gridswarm/{key}/{k}")), "{k} heard: {r:?}");
    }
    assert_eq!(
        v["transport"]["security"],
        serde_json::json!({"mode": "none", "authenticated": false, "encrypted": false})
    );
}

/// Every file of the run with this prefix, its root folder included,
/// removed when dropped, also when the test fails.
struct RunGone(String);

impl Drop for RunGone {
    fn drop(&mut self) {
        let root = gridswarm::ipc::run_root(&self.0);
        let _ = gridswarm::ipc::cleanup_run(&self.0);
        let _ = fs::remove_dir_all(&root);
    }
}

/// A prefix whose owner is surely dead: no pid reaches this (`pid_max` is
/// at most 2^22), so the sweep of dead runs looks at everything under it.
fn dead_prefix(nonce: u32) -> String {
    format!("gs{}x{nonce:x}_", u32::MAX - 9)
}

/// `sh -c SCRIPT` as the other user; it must succeed.
fn as_other_sh(script: &str) {
    let out = as_other_user(Path::new("/bin/sh")).args(["-c", script]).output().expect("setpriv runs");
    assert!(out.status.success(), "`{script}` as uid {OTHER_UID} failed: {}", text(&out.stderr));
}

/// Entries the test put in `/dev/shm`, removed when dropped (as root),
/// also when the test fails.
struct Litter(Vec<PathBuf>);

impl Drop for Litter {
    fn drop(&mut self) {
        for p in &self.0 {
            let _ = fs::remove_file(p).or_else(|_| fs::remove_dir_all(p));
        }
    }
}

/// How many entries `dir` holds.
fn count(dir: &Path) -> usize {
    fs::read_dir(dir).map(|d| d.count()).unwrap_or(0)
}

/// Issue 23: the other user names a symlink after a dead run's root folder,
/// pointing at a folder only root may enter, and puts a folder of their own
/// under a dead run's name. Root's next run removes nothing of either: the
/// clean-up never follows a symlink and removes only its own uid's files.
#[test]
fn the_clean_up_of_dead_runs_never_follows_a_symlink_or_removes_anothers_files() {
    if !can_switch_user("the_clean_up_of_dead_runs_never_follows_a_symlink_or_removes_anothers_files") {
        return;
    }
    let _s = serial();
    let dir = scratch("symlink");
    let (linked, owned) = (dead_prefix(1), dead_prefix(2));
    let secret = dir.join("root-only");
    fs::create_dir_all(secret.join("deep")).unwrap();
    fs::set_permissions(&secret, fs::Permissions::from_mode(0o700)).unwrap();
    let precious = [secret.join(format!("{linked}precious")), secret.join("deep").join(format!("{linked}deeper"))];
    for p in &precious {
        fs::write(p, b"keep").unwrap();
    }
    let link = gridswarm::ipc::run_root(&linked);
    let file_link = PathBuf::from(format!("/dev/shm/{linked}data"));
    let theirs = gridswarm::ipc::run_root(&owned);
    let _litter = Litter(vec![link.clone(), file_link.clone(), theirs.clone()]);
    as_other_sh(&format!(
        "ln -s {s} {link} && ln -s {p} {file_link} && mkdir {theirs} && touch {theirs}/{owned}x.service /dev/shm/{owned}y.data",
        s = secret.display(),
        p = precious[0].display(),
        link = link.display(),
        file_link = file_link.display(),
        theirs = theirs.display(),
    ));
    // A dead run of root's own, which the clean-up does remove.
    let own = dead_prefix(3);
    let own_files = [PathBuf::from(format!("/dev/shm/{own}z.data")), gridswarm::ipc::run_root(&own)];
    let _litter2 = Litter([&own_files[..], &[PathBuf::from(format!("/dev/shm/{owned}y.data"))]].concat());
    fs::create_dir_all(own_files[1].join("nodes")).unwrap();
    fs::write(own_files[1].join("nodes").join(format!("{own}n.details")), b"x").unwrap();
    fs::write(&own_files[0], b"x").unwrap();
    let v = run_json(&["--robots", "2", "--seed", "1"]);
    assert_eq!(v["complete"], true);
    assert_eq!(gridswarm::ipc::run_files(&own), Vec::<PathBuf>::new(), "the dead run of root's own was not removed");
    for p in &precious {
        assert_eq!(fs::read(p).ok().as_deref(), Some(&b"keep"[..]), "{} was removed through a symlink", p.display());
    }
    for l in [&link, &file_link] {
        assert!(fs::symlink_metadata(l).is_ok(), "the other user's symlink {} was removed", l.display());
    }
    assert!(theirs.join(format!("{owned}x.service")).exists(), "a file in the other user's folder was removed");
    assert!(Path::new(&format!("/dev/shm/{owned}y.data")).exists(), "the other user's file was removed");
}

/// Issue 23: the other user fills `/dev/shm` with 2,000 files named like
/// 2,000 dead runs' and a folder of 20,000 more; the next run started
/// after 40 s when the clean-up walked every folder once per dead run. It
/// now lists `/dev/shm` once, never enters another user's folder and
/// removes none of their files; the start takes well under 20 s (about a
/// second without the files).
#[test]
fn files_another_user_puts_in_dev_shm_neither_stall_a_run_nor_are_removed() {
    if !can_switch_user("files_another_user_puts_in_dev_shm_neither_stall_a_run_nor_are_removed") {
        return;
    }
    let _s = serial();
    let head = format!("gs{}x", u32::MAX - 9);
    let flood = PathBuf::from(format!("/dev/shm/gridswarm-e2e-{}-flood", std::process::id()));
    let mut litter = Litter(vec![flood.clone()]);
    litter.0.extend((1..=2000).map(|k| PathBuf::from(format!("/dev/shm/{head}{k:x}_z"))));
    as_other_sh(&format!(
        "cd /dev/shm && seq 1 2000 | while read k; do printf '{head}%x_z\\n' $k; done | xargs touch \
         && mkdir {f} && cd {f} && seq -f '{head}1_%g' 1 20000 | xargs touch",
        f = flood.display()
    ));
    let started = Instant::now();
    let v = run_json(&["--robots", "2", "--seed", "1"]);
    let took = started.elapsed();
    assert_eq!(v["complete"], true);
    assert_eq!(count(&flood), 20_000, "files in the other user's folder were removed");
    let top = litter.0[1..].iter().filter(|p| p.exists()).count();
    assert_eq!(top, 2000, "the other user's files in /dev/shm were removed");
    assert!(took < Duration::from_secs(20), "the run took {took:?} beside 22,000 files of another user");
}
