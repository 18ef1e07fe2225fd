//! A run across real network stacks (issue 10, item 3): network namespaces
//! joined by veth pairs stand in for hosts, one for the world and three
//! for the agents, started by hand as README's "Running on several
//! machines" says: `gridswarm credentials`, then `gridswarm run
//! --transport zenoh --listen tls/... --credentials DIR --remote-agents
//! KEY` in the world's namespace, `gridswarm setup --key KEY --scenario ...
//! --seed ... --robot K --out FILE` for each agent, and `robot-agent
//! --transport zenoh --connect tls/... --credentials DIR --setup FILE` in
//! the agents' namespaces. It checks that a run
//! without faults is `simulate`'s byte for byte while a host without the
//! run's credentials tries to join, read and disturb it (issue 23, item
//! 2), and that a host lost mid-run (its link cut, its processes killed,
//! its namespace deleted) is declared by the robots while the search
//! completes without a collision.
//!
//! Namespaces and addresses are this test's own: named after its pid
//! (`gsnt<pid>...`), 10.x addresses inside them only, nothing in the
//! namespace the test runs in. Everything is removed afterwards, on
//! failure too ([`Hosts`]'s drop), and a start sweeps what a killed run of
//! this test left. Making namespaces takes root, as in CI; without it the
//! tests say so and check nothing (as `other_users.rs` does).

use std::fs;
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::Duration;

use gridswarm_e2e::*;
use serde_json::Value;

mod intruder;

const HEAD: &str = "gsnt";
const AGENT_HOSTS: usize = 3;
const PORT: u16 = 7447;

fn can_make_hosts(test: &str) -> bool {
    as_root(test, "no network namespaces")
}

fn ip(args: &[&str]) -> Output {
    let out = Command::new("ip").args(args).output().expect("iproute2's ip runs");
    assert!(out.status.success(), "ip {args:?}: {}", text(&out.stderr));
    out
}

/// Deletes the namespaces of runs of this test whose process is gone.
fn sweep_leftovers() {
    let list = text(&ip(&["netns", "list"]).stdout);
    for name in list.lines().filter_map(|l| l.split_whitespace().next()) {
        let Some(rest) = name.strip_prefix(HEAD) else { continue };
        let pid: String = rest.chars().take_while(char::is_ascii_digit).collect();
        if pid.parse::<u32>().is_ok_and(|p| p != std::process::id() && !alive(p)) {
            let _ = Command::new("ip").args(["netns", "del", name]).status();
        }
    }
}

/// One world host and three agent hosts, star-wired; `case` keeps the
/// tests of one process apart. Dropping it kills every process it started
/// and deletes every namespace.
struct Hosts {
    world: String,
    agents: Vec<String>,
    /// `10.<net>.<case*10+k>.1` is the world's side of agent host k's link.
    net: u32,
    case: u32,
    procs: Vec<Child>,
}

impl Hosts {
    fn new(case: u32) -> Self {
        sweep_leftovers();
        let pid = std::process::id();
        let h = Hosts {
            world: format!("{HEAD}{pid}c{case}w"),
            agents: (1..=AGENT_HOSTS).map(|k| format!("{HEAD}{pid}c{case}a{k}")).collect(),
            net: pid % 250 + 1,
            case,
            procs: Vec::new(),
        };
        for ns in std::iter::once(&h.world).chain(&h.agents).cloned().collect::<Vec<_>>() {
            ip(&["netns", "add", &ns]);
            ip(&["-n", &ns, "link", "set", "lo", "up"]);
        }
        for k in 1..=AGENT_HOSTS {
            let (w, a) = (format!("w{k}"), format!("a{k}"));
            let ans = h.agents[k - 1].clone();
            ip(&["-n", &h.world, "link", "add", &w, "type", "veth", "peer", "name", &a, "netns", &ans]);
            ip(&["-n", &h.world, "addr", "add", &format!("{}/24", h.world_addr(k)), "dev", &w]);
            ip(&["-n", &ans, "addr", "add", &format!("{}/24", h.agent_addr(k)), "dev", &a]);
            ip(&["-n", &h.world, "link", "set", &w, "up"]);
            ip(&["-n", &ans, "link", "set", &a, "up"]);
        }
        h
    }

    fn world_addr(&self, k: usize) -> String {
        format!("10.{}.{}.1", self.net, self.case * 10 + k as u32)
    }

    fn agent_addr(&self, k: usize) -> String {
        format!("10.{}.{}.2", self.net, self.case * 10 + k as u32)
    }

    /// `program args` inside namespace `ns` (`ip netns exec` execs it, so
    /// the child is the program); its stderr is the test's.
    fn spawn(&mut self, ns: &str, program: &Path, args: &[String], env: &[(&str, String)], stdout: Stdio) -> usize {
        let child = Command::new("ip")
            .args(["netns", "exec", ns])
            .arg(program)
            .args(args)
            .envs(env.iter().map(|(k, v)| (*k, v.as_str())))
            .stdin(Stdio::null())
            .stdout(stdout)
            .spawn()
            .expect("ip netns exec runs");
        self.procs.push(child);
        self.procs.len() - 1
    }

    /// Robot `r` lives on agent host `r % 3` (1-based: `r % 3 + 1`).
    fn host_of(r: usize) -> usize {
        r % AGENT_HOSTS + 1
    }

    /// The run's credentials in `dir`, the world's certificate naming its
    /// address on every link (`gridswarm credentials ... --host ADDR`).
    fn credentials(&self, dir: &Path, robots: usize) -> std::path::PathBuf {
        let keys = dir.join("keys");
        let addrs: Vec<String> = (1..=AGENT_HOSTS).map(|k| self.world_addr(k)).collect();
        intruder::credentials(&keys, robots, &addrs.iter().map(String::as_str).collect::<Vec<_>>());
        keys
    }

    /// Starts robot-agents 0..robots, each on its host with its setup file
    /// (`gridswarm setup`, written beside `keys`), connecting to the
    /// world's side of its host's link with the credentials in `keys`;
    /// returns their indices in `procs`.
    fn start_agents(
        &mut self,
        key: &str,
        keys: &Path,
        run: &[&str],
        robots: usize,
        env: &[(&str, String)],
    ) -> Vec<usize> {
        let bin = bin_dir().join("robot-agent");
        // The team's size is part of the agreement: every setup names it.
        let n = robots.to_string();
        let run = [run, &["--robots", &n]].concat();
        (0..robots)
            .map(|r| {
                let k = Self::host_of(r);
                let mut args: Vec<String> =
                    ["--transport", "zenoh", "--prefix", key, "--connect"].iter().map(|s| s.to_string()).collect();
                args.push(format!("tls/{}:{PORT}", self.world_addr(k)));
                args.extend(["--credentials".to_string(), keys.display().to_string()]);
                let setup = setup_file(keys.parent().unwrap(), key, &run, r);
                args.extend(["--setup".to_string(), setup.display().to_string()]);
                let ns = self.agents[k - 1].clone();
                self.spawn(&ns, &bin, &args, env, Stdio::null())
            })
            .collect()
    }

    /// Starts the orchestrator in the world's namespace, following a
    /// world that listens on every address and waits for agents by hand.
    fn start_world(&mut self, key: &str, keys: &Path, run: &[&str], out: &Path) -> usize {
        let mut args: Vec<String> = ["run", "--json", "--transport", "zenoh", "--remote-agents", key, "--listen"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        args.push(format!("tls/0.0.0.0:{PORT}"));
        args.extend(["--credentials".to_string(), keys.display().to_string()]);
        args.extend(["--out".to_string(), out.to_str().unwrap().to_string()]);
        args.extend(run.iter().map(|s| s.to_string()));
        let world = self.world.clone();
        self.spawn(&world, &bin_dir().join("gridswarm"), &args, &[], Stdio::piped())
    }

    /// Waits for the orchestrator (index `k`) and returns its summary.
    fn finish(&mut self, k: usize) -> Value {
        let mut stdout = self.procs[k].stdout.take().expect("the orchestrator's stdout");
        let mut json = Vec::new();
        std::io::Read::read_to_end(&mut stdout, &mut json).unwrap();
        let status = self.procs[k].wait().unwrap();
        finished(&Output { status, stdout: json, stderr: Vec::new() }, &["run across namespaces"])
    }

    /// A host lost: its link cut first (nothing it says gets out any
    /// more, not even its sockets closing), then its processes killed and
    /// its namespace deleted.
    fn lose(&mut self, k: usize, procs: &[usize]) {
        ip(&["-n", &self.world, "link", "del", &format!("w{k}")]);
        for &p in procs {
            let _ = self.procs[p].kill();
            let _ = self.procs[p].wait();
        }
        ip(&["netns", "del", &self.agents[k - 1]]);
    }
}

impl Drop for Hosts {
    fn drop(&mut self) {
        for c in &mut self.procs {
            let _ = c.kill();
            let _ = c.wait();
        }
        for ns in std::iter::once(&self.world).chain(&self.agents) {
            let _ = Command::new("ip").args(["netns", "del", ns]).stderr(Stdio::null()).status();
        }
    }
}

/// The namespaces of this process still there.
fn own_namespaces() -> Vec<String> {
    let mine = format!("{HEAD}{}c", std::process::id());
    text(&ip(&["netns", "list"]).stdout).lines().filter(|l| l.starts_with(&mine)).map(str::to_string).collect()
}

#[test]
fn a_run_across_namespaces_is_the_in_process_run() {
    const TEST: &str = "a_run_across_namespaces_is_the_in_process_run";
    if let Ok(spec) = std::env::var(intruder::SPEC) {
        return intruder::act(&spec);
    }
    if !can_make_hosts(TEST) {
        return;
    }
    let _s = serial();
    let dir = scratch("netns-equivalence");
    let run = ["--scenario", "paper", "--seed", "7"];
    let (out, sim) = (dir.join("run"), dir.join("sim"));
    let key = format!("netns{}", std::process::id());
    {
        let mut hosts = Hosts::new(1);
        let keys = hosts.credentials(&dir, 13);
        let world = hosts.start_world(&key, &keys, &[&run[..], &["--robots", "13"]].concat(), &out);
        // A host of the network without the run's credentials: it has the
        // authority's certificate (no secret) and its own authority's
        // certificate for `robot-0`, and tries TLS with and without it,
        // and plain TCP; each subscribes to everything and speaks as robot 0.
        let own = dir.join("own");
        intruder::credentials(&own, 1, &[]);
        let tls = format!("tls/{}:{PORT}", hosts.world_addr(1));
        let orders = intruder::Orders {
            endpoint: tls.clone(),
            key: key.clone(),
            ca: Some(keys.join("ca.pem")),
            cert: Some((own.join("robot-0.pem"), own.join("robot-0.key"))),
            read: Vec::new(),
            disturb: true,
        };
        let launcher = ["ip", "netns", "exec", hosts.agents[0].as_str()].map(String::from);
        let exe = std::env::current_exe().unwrap();
        let intruders = [
            orders.clone(),
            intruder::Orders { cert: None, ..orders.clone() },
            intruder::Orders { endpoint: tls.replace("tls/", "tcp/"), ca: None, cert: None, ..orders },
        ]
        .map(|o| intruder::Intruder::start(&launcher, &exe, TEST, &o));
        hosts.start_agents(&key, &keys, &run, 13, &[]);
        let v = hosts.finish(world);
        for r in intruders.map(intruder::Intruder::stop) {
            assert!(r.reached, "the world's port never answered the intruder: {r:?}");
            assert_eq!((r.opened, r.received), (false, 0), "a host without credentials got in: {r:?}");
        }
        assert_eq!(v["complete"], true, "{v}");
        assert_eq!(v["robots"], 13);
        assert_eq!(v["collisions"], 0);
        assert_eq!(v["died"], serde_json::json!([]));
        // Agents on other hosts are not measured: unknown, not 0.
        assert!(v["agent_cpu_ms_total"].is_null(), "{v}");
        let listen = format!("tls/0.0.0.0:{PORT}");
        let security = serde_json::json!({"mode": "mutual-tls", "authenticated": true, "encrypted": true});
        let transport =
            serde_json::json!({"name": "zenoh", "endpoints": [listen], "remote_agents": true, "security": security});
        assert_eq!(v["transport"], transport);
        assert_eq!((&v["agreement"]["key"], &v["agreement"]["seed"]), (&serde_json::json!(key), &serde_json::json!(7)));
    }
    assert!(own_namespaces().iter().all(|n| !n.contains("c1")), "namespaces left: {:?}", own_namespaces());
    search(&[&["simulate", "--robots", "13", "--out", sim.to_str().unwrap()][..], &run[..]].concat());
    for file in ["trajectories.jsonl", "rounds.csv"] {
        let (a, b) = (fs::read(out.join(file)).unwrap(), fs::read(sim.join(file)).unwrap());
        assert!(!a.is_empty() && a == b, "{file} differs between the run across namespaces and simulate");
    }
}

#[test]
fn a_host_lost_mid_run_is_declared_and_the_search_completes() {
    if !can_make_hosts("a_host_lost_mid_run_is_declared_and_the_search_completes") {
        return;
    }
    let _s = serial();
    let dir = scratch("netns-lost");
    let run = ["--scenario", "paper", "--seed", "5"];
    let key = format!("netnslost{}", std::process::id());
    let mut hosts = Hosts::new(2);
    let keys = hosts.credentials(&dir, 13);
    let world = hosts.start_world(&key, &keys, &[&run[..], &["--robots", "13"]].concat(), &dir.join("run"));
    // Robot 2 (host 3) stops itself on slot 4's readings: the world then
    // waits on it, so the host is lost at a known point mid-run.
    let hang = [("GRIDSWARM_AGENT_HANG", "2@4".to_string())];
    let agents = hosts.start_agents(&key, &keys, &run, 13, &hang);
    let lost_host = Hosts::host_of(2);
    let on_lost: Vec<usize> = (0..13).filter(|&r| Hosts::host_of(r) == lost_host).collect();
    let hung = hosts.procs[agents[2]].id();
    assert!(wait_until(Duration::from_secs(60), || stopped(hung)), "robot 2 never reached slot 4");
    let procs: Vec<usize> = on_lost.iter().map(|&r| agents[r]).collect();
    hosts.lose(lost_host, &procs);
    let v = hosts.finish(world);
    assert_eq!(v["complete"], true, "{v}");
    assert_eq!(v["collisions"], 0, "{v}");
    let died: Vec<u64> = v["died"].as_array().unwrap().iter().map(|x| x.as_u64().unwrap()).collect();
    assert!(died.contains(&2), "the world found the lost host's robot it waited on dead: {v}");
    let declared: Vec<u64> =
        v["failures_detected"].as_array().unwrap().iter().filter_map(|d| d["robot"].as_u64()).collect();
    assert!(
        on_lost.iter().any(|r| declared.contains(&(*r as u64))),
        "the robots declare the lost host's robots ({on_lost:?}): {v}"
    );
    drop(hosts);
    assert!(own_namespaces().iter().all(|n| !n.contains("c2")), "namespaces left: {:?}", own_namespaces());
}
