//! An intruder against a zenoh run: a stock zenoh client (zenoh's own
//! crate, not gridswarm's transport) in a process of its own, started as
//! another user (`setpriv`), on another host (`ip netns exec`), or with
//! one robot's credentials. It reads what it is told to try to read (a
//! run's credentials), opens a session to the world's endpoint with what
//! it has, subscribes to everything, says `ready`, and then, until its
//! standard input closes, publishes random bytes as robot 0 (its inbox,
//! its answers, its token) if told to. Its last line says what worked:
//! `intruder reached=BOOL opened=BOOL read=N received=N keys=K1,K2`.
//!
//! The test that starts it re-runs its own binary with [`SPEC`] set; the
//! test function hands over to [`act`] when it finds the variable.

#![allow(dead_code)] // each test file uses part of it

use std::collections::BTreeSet;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use zenoh::Wait;

/// The environment variable holding an intruder's orders.
pub const SPEC: &str = "GRIDSWARM_TEST_INTRUDER";

/// What the intruder is told.
#[derive(Clone, Debug, Default)]
pub struct Orders {
    /// The world's endpoint (`tls/...` or `tcp/...`).
    pub endpoint: String,
    pub key: String,
    /// The authority it trusts, a certificate and key it presents.
    pub ca: Option<PathBuf>,
    pub cert: Option<(PathBuf, PathBuf)>,
    /// Files it tries to read first (the run's credentials).
    pub read: Vec<PathBuf>,
    /// Publish random bytes as robot 0 while it listens.
    pub disturb: bool,
}

impl Orders {
    fn encode(&self) -> String {
        let p = |p: &Option<PathBuf>| p.as_ref().map(|p| p.display().to_string()).unwrap_or_default();
        let (cert, key) = self.cert.clone().map_or((None, None), |(c, k)| (Some(c), Some(k)));
        let read: Vec<String> = self.read.iter().map(|f| f.display().to_string()).collect();
        [&self.endpoint, &self.key, &p(&self.ca), &p(&cert), &p(&key), &read.join(","), &self.disturb.to_string()]
            .map(|s| s.to_string())
            .join("|")
    }

    fn decode(s: &str) -> Self {
        let f: Vec<&str> = s.split('|').collect();
        let path = |s: &str| (!s.is_empty()).then(|| PathBuf::from(s));
        Orders {
            endpoint: f[0].into(),
            key: f[1].into(),
            ca: path(f[2]),
            cert: path(f[3]).zip(path(f[4])),
            read: f[5].split(',').filter(|s| !s.is_empty()).map(PathBuf::from).collect(),
            disturb: f[6] == "true",
        }
    }
}

/// What the intruder achieved.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct Report {
    /// Whether the world's port answered (so that the rest means something).
    pub reached: bool,
    pub opened: bool,
    /// Files it could read.
    pub read: usize,
    /// Samples it received, and the distinct key expressions they came on.
    pub received: usize,
    pub keys: BTreeSet<String>,
}

/// A running intruder.
pub struct Intruder(Option<Child>);

impl Intruder {
    /// Starts `launcher` (e.g. `setpriv ...`, `ip netns exec NS`, or
    /// nothing) with `exe --exact test` and `orders`, and waits until it
    /// is ready (it has tried everything but its puts).
    pub fn start(launcher: &[String], exe: &Path, test: &str, orders: &Orders) -> Self {
        let mut cmd = match launcher.split_first() {
            Some((first, rest)) => {
                let mut c = Command::new(first);
                c.args(rest).arg(exe);
                c
            }
            None => Command::new(exe),
        };
        let mut child = cmd
            .args(["--exact", test, "--nocapture", "--test-threads=1"])
            .env(SPEC, orders.encode())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the intruder starts");
        let mut out = BufReader::new(child.stdout.take().unwrap());
        let mut line = String::new();
        while !line.contains("intruder ready") {
            line.clear();
            if out.read_line(&mut line).unwrap_or(0) == 0 {
                let mut err = String::new();
                let _ = child.stderr.take().unwrap().read_to_string(&mut err);
                panic!("the intruder ended before it was ready: {err}");
            }
        }
        child.stdout = None;
        // The rest of its output, read at the end.
        let rest = std::thread::spawn(move || {
            let mut s = String::new();
            let _ = out.read_to_string(&mut s);
            s
        });
        RESTS.lock().unwrap().push((child.id(), rest));
        Intruder(Some(child))
    }

    /// Tells it to stop (closes its input) and reads its report.
    pub fn stop(mut self) -> Report {
        let mut child = self.0.take().unwrap();
        drop(child.stdin.take());
        let status = child.wait().unwrap();
        let mut rests = RESTS.lock().unwrap();
        let at = rests.iter().position(|(p, _)| *p == child.id()).unwrap();
        let out = rests.remove(at).1.join().unwrap();
        let mut err = String::new();
        let _ = child.stderr.take().unwrap().read_to_string(&mut err);
        let line = out.find("intruder reached=").map(|k| out[k..].lines().next().unwrap_or("")).unwrap_or_else(|| {
            panic!("the intruder did not report ({status}): {out}{err}");
        });
        parse(line)
    }
}

impl Drop for Intruder {
    fn drop(&mut self) {
        if let Some(mut c) = self.0.take() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

type Rest = (u32, std::thread::JoinHandle<String>);
static RESTS: Mutex<Vec<Rest>> = Mutex::new(Vec::new());

fn parse(line: &str) -> Report {
    let field = |name: &str| line.split_whitespace().find_map(|w| w.strip_prefix(name)).unwrap_or("").to_string();
    Report {
        reached: field("reached=") == "true",
        opened: field("opened=") == "true",
        read: field("read=").parse().unwrap(),
        received: field("received=").parse().unwrap(),
        keys: field("keys=").split(',').filter(|s| !s.is_empty()).map(String::from).collect(),
    }
}

/// The intruder's side: run by a test function when [`SPEC`] is set.
pub fn act(spec: &str) {
    let o = Orders::decode(spec);
    let read = o.read.iter().filter(|f| std::fs::read(f).is_ok()).count();
    let reached = reach(&o.endpoint);
    let seen = Arc::new(Mutex::new((0usize, BTreeSet::new())));
    // One session listens, another speaks: a session hears its own puts.
    let session = zenoh::open(config(&o)).wait().ok();
    let speaker = if o.disturb { zenoh::open(config(&o)).wait().ok() } else { None };
    let mut held = Vec::new();
    let root = format!("gridswarm/{}", o.key);
    if let Some(s) = &session {
        let mut keys = vec!["**".to_string(), format!("{root}/**")];
        for d in ["in", "out", "alive"] {
            keys.extend((0..16).map(|r| format!("{root}/{d}/{r}")));
        }
        for k in keys {
            let seen = seen.clone();
            let sub = s.declare_subscriber(k).callback(move |sample: zenoh::sample::Sample| {
                let mut g = seen.lock().unwrap();
                g.0 += 1;
                g.1.insert(sample.key_expr().as_str().to_string());
            });
            held.push(sub.wait().ok());
        }
        let seen2 = seen.clone();
        let tokens =
            s.liveliness().declare_subscriber(format!("{root}/**")).callback(move |sample: zenoh::sample::Sample| {
                let mut g = seen2.lock().unwrap();
                g.0 += 1;
                g.1.insert(sample.key_expr().as_str().to_string());
            });
        std::mem::forget(tokens.wait());
    }
    if let Some(s) = &speaker {
        std::mem::forget(s.liveliness().declare_token(format!("{root}/alive/0")).wait());
    }
    println!("intruder ready");
    let done = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let d2 = done.clone();
    std::thread::spawn(move || {
        let _ = std::io::stdin().read_to_end(&mut Vec::new());
        d2.store(true, std::sync::atomic::Ordering::SeqCst);
    });
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    while !done.load(std::sync::atomic::Ordering::SeqCst) {
        if let Some(s) = &speaker {
            for k in ["in/0", "out/0"] {
                let bytes: Vec<u8> = (0..64)
                    .map(|_| {
                        x ^= x << 13;
                        x ^= x >> 7;
                        x ^= x << 17;
                        x as u8
                    })
                    .collect();
                let _ = s.put(format!("gridswarm/{}/{k}", o.key), bytes).wait();
            }
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let g = seen.lock().unwrap();
    let keys: Vec<&str> = g.1.iter().map(String::as_str).collect();
    println!(
        "intruder reached={reached} opened={} read={read} received={} keys={}",
        session.is_some(),
        g.0,
        keys.join(",")
    );
}

/// Waits (up to 20 s) until the endpoint's port takes TCP connections.
fn reach(endpoint: &str) -> bool {
    let addr = endpoint.split_once('/').map_or(endpoint, |(_, a)| a).to_string();
    let deadline = std::time::Instant::now() + Duration::from_secs(20);
    while std::time::Instant::now() < deadline {
        if std::net::TcpStream::connect(&addr).is_ok() {
            return true;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    false
}

/// A client's configuration with what the intruder holds.
fn config(o: &Orders) -> zenoh::Config {
    let mut c = zenoh::Config::default();
    let mut set = |k: &str, v: String| c.insert_json5(k, &v).unwrap_or_else(|e| panic!("{k} = {v}: {e}"));
    set("mode", "\"client\"".into());
    set("connect/endpoints", format!("[\"{}\"]", o.endpoint));
    set("connect/timeout_ms", "3000".into());
    set("scouting/multicast/enabled", "false".into());
    let q = |p: &Path| format!("\"{}\"", p.display());
    if let Some(ca) = &o.ca {
        set("transport/link/tls/root_ca_certificate", q(ca));
    }
    if let Some((cert, key)) = &o.cert {
        set("transport/link/tls/connect_certificate", q(cert));
        set("transport/link/tls/connect_private_key", q(key));
        set("transport/link/tls/enable_mtls", "true".into());
    }
    c
}

/// A run with agents started by hand (README, "Running on several
/// machines"), on this machine: `gridswarm run --json --transport zenoh
/// --remote-agents KEY --listen ENDPOINT SECURITY RUN --out OUT`.
pub fn start_world(key: &str, endpoint: &str, security: &[String], run: &[&str], out: &Path) -> Child {
    gridswarm_e2e::gridswarm()
        .args(["run", "--json", "--transport", "zenoh", "--remote-agents", key, "--listen", endpoint])
        .args(security)
        .args(run)
        .arg("--out")
        .arg(out)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("gridswarm starts")
}

/// Its agents, 0 to `robots - 1`: `gridswarm setup --key KEY RUN --robot
/// K --out FILE` into `setups`, then `robot-agent --transport zenoh
/// --prefix KEY --connect ENDPOINT SECURITY --setup FILE`.
pub fn start_agents(
    key: &str,
    endpoint: &str,
    security: &[String],
    (run, setups): (&[&str], &Path),
    robots: usize,
) -> Vec<Child> {
    (0..robots)
        .map(|k| {
            let setup = gridswarm_e2e::setup_file(setups, key, run, k);
            Command::new(gridswarm_e2e::bin_dir().join("robot-agent"))
                .args(["--transport", "zenoh", "--prefix", key, "--connect", endpoint])
                .args(security)
                .arg("--setup")
                .arg(setup)
                .stdin(Stdio::null())
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .expect("robot-agent starts")
        })
        .collect()
}

/// A free TCP port of 127.0.0.1.
pub fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

/// `gridswarm credentials --out DIR --robots N --host HOST...`.
pub fn credentials(dir: &Path, robots: usize, hosts: &[&str]) {
    let mut args = vec!["credentials".to_string(), "--out".into(), dir.display().to_string()];
    args.extend(["--robots".to_string(), robots.to_string()]);
    for h in hosts {
        args.extend(["--host".to_string(), h.to_string()]);
    }
    let out = gridswarm_e2e::gridswarm().args(&args).output().unwrap();
    assert!(out.status.success(), "gridswarm {args:?}: {}", gridswarm_e2e::text(&out.stderr));
}

/// The run's summary once the world ends (within 2 minutes), its agents
/// reaped; the agents' errors are in the failure message.
pub fn finish(world: Child, agents: Vec<Child>) -> serde_json::Value {
    let mut world = world;
    let ended = gridswarm_e2e::wait_until(Duration::from_secs(120), || world.try_wait().ok().flatten().is_some());
    if !ended {
        let _ = world.kill();
    }
    let out = world.wait_with_output().unwrap();
    let mut errors = String::new();
    for mut a in agents {
        if !gridswarm_e2e::wait_until(Duration::from_secs(10), || a.try_wait().ok().flatten().is_some()) {
            let _ = a.kill();
        }
        let _ = a.wait();
        let _ = a.stderr.take().unwrap().read_to_string(&mut errors);
    }
    assert!(ended, "the run did not end: {}{errors}", gridswarm_e2e::text(&out.stderr));
    assert!(out.status.success(), "the run failed: {}{errors}", gridswarm_e2e::text(&out.stderr));
    gridswarm_e2e::finished(&out, &["run with agents started by hand"])
}

/// Whether `out`'s trajectories and rounds are `simulate RUN`'s, byte for byte.
pub fn same_as_simulate(out: &Path, run: &[&str]) {
    let sim = out.with_extension("sim");
    gridswarm_e2e::search(&[&["simulate", "--out", sim.to_str().unwrap()][..], run].concat());
    for file in ["trajectories.jsonl", "rounds.csv"] {
        let (a, b) = (std::fs::read(out.join(file)).unwrap(), std::fs::read(sim.join(file)).unwrap());
        assert!(!a.is_empty() && a == b, "{file} differs from simulate's");
    }
}
