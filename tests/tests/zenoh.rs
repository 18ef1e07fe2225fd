//! `gridswarm run --transport zenoh` on one machine: the world-server
//! listens on 127.0.0.1 (a free port, no scouting) and every robot-agent
//! connects to it over TCP. The run must be the in-process run byte for
//! byte, as over iceoryx2, also when a robot's process is killed (the
//! world learns it from the robot's liveliness token), and leave nothing
//! behind. A robot silent past its lease is dead for good, also when its
//! process comes back. The links are mutual TLS with credentials the run
//! makes for itself, and one robot's credentials speak and hear for that
//! robot only (issue 23, item 2).

mod intruder;

use std::fs;
use std::path::Path;
use std::time::Duration;

use gridswarm_e2e::*;
use serde_json::Value;

/// `gridswarm run --json --transport zenoh --out DIR ARGS`; checks nothing is left.
fn zenoh_run(dir: &Path, args: &[&str]) -> Value {
    let all = [&["run", "--json", "--transport", "zenoh", "--out", dir.to_str().unwrap()][..], args].concat();
    let v = finished(&gridswarm().args(&all).output().unwrap(), &all);
    assert_no_leftovers(v["ipc_prefix"].as_str().unwrap());
    v
}

fn same_files(tag: &str, run: &Path, sim: &Path) {
    for file in ["trajectories.jsonl", "rounds.csv"] {
        let (a, b) = (fs::read(run.join(file)).unwrap(), fs::read(sim.join(file)).unwrap());
        assert!(!a.is_empty(), "{tag}: {file} is empty");
        assert!(a == b, "{tag}: {file} differs between run over zenoh and simulate");
    }
}

#[test]
fn a_zenoh_run_on_paper_is_the_in_process_run() {
    let _s = serial();
    let dir = scratch("zenoh-equivalence");
    let args = ["--scenario", "paper", "--robots", "13", "--seed", "7"];
    let (run, sim) = (dir.join("run"), dir.join("sim"));
    let v = zenoh_run(&run, &args);
    search(&[&["simulate", "--out", sim.to_str().unwrap()][..], &args[..]].concat());
    same_files("paper-13-7", &run, &sim);
    let endpoints = v["transport"]["endpoints"].as_array().unwrap();
    assert_eq!((&v["transport"]["name"], endpoints.len()), (&serde_json::json!("zenoh"), 1), "{v}");
    assert!(endpoints[0].as_str().unwrap().starts_with("tls/127.0.0.1:"), "{v}");
    assert_eq!(v["transport"]["security"]["mode"], "mutual-tls", "{v}");
    assert_eq!(v["agreement"]["key"], v["ipc_prefix"], "the run key of a run on one machine is its prefix");
    assert_eq!(v["agreement"]["seed"], 7);
    assert_eq!(v["complete"], true);
    assert_eq!(v["collisions"], 0);
    assert_eq!(v["dropped_messages"]["total"], 0);
    assert_eq!(v["died"], serde_json::json!([]));
    assert_eq!(v["agents_killed_at_end"], 0, "every agent ends by itself on End");
    assert!(v["agent_peak_rss_kib"]["max"].as_f64().unwrap() > 0.0, "agents on this host are measured");
}

#[test]
fn a_robot_killed_over_zenoh_is_dead_to_the_world_as_in_process() {
    let _s = serial();
    let dir = scratch("zenoh-kill");
    let args = ["--scenario", "paper", "--robots", "13", "--seed", "3", "--kill", "4@3+0.2"];
    let (run, sim) = (dir.join("run"), dir.join("sim"));
    let v = zenoh_run(&run, &args);
    search(&[&["simulate", "--out", sim.to_str().unwrap()][..], &args[..]].concat());
    same_files("kill", &run, &sim);
    assert_eq!(v["collisions"], 0);
    let declared = v["failures_detected"].as_array().unwrap();
    assert!(!declared.is_empty(), "the robots declare the dead one: {v}");
}

#[test]
fn a_robot_silent_past_its_lease_stays_dead_when_it_comes_back() {
    let _s = serial();
    let dir = scratch("zenoh-lease");
    // Robot 2 stops itself in slot 2: the world waits for its answer until
    // its lease (2 s) runs out and its token vanishes. Robot 5 stops in
    // slot 9, so the world waits again; meanwhile robot 2's process goes on,
    // and its session comes back to a world that buried it.
    let args =
        ["run", "--json", "--transport", "zenoh", "--robots", "13", "--seed", "7", "--out", dir.to_str().unwrap()];
    let child = spawn_hanging(&args, "2@2,5@9");
    let pid = child.id();
    let two = stopped_agent(pid, 2);
    stopped_agent(pid, 5);
    signal(two, libc::SIGCONT);
    assert!(wait_until(Duration::from_secs(5), || !stopped(two)), "robot 2's process did not go on");
    let out = child.wait_with_output().unwrap();
    let v = finished(&out, &["run --transport zenoh, robots 2 and 5 hung"]);
    assert_no_leftovers(v["ipc_prefix"].as_str().unwrap());
    assert_eq!(v["died"], serde_json::json!([2, 5]), "{v}");
    assert_eq!(v["complete"], true, "{v}");
    assert_eq!(v["collisions"], 0, "{v}");
    // Dead for physics from slot 2 on: its body never moves again.
    let traj = fs::read_to_string(dir.join("trajectories.jsonl")).unwrap();
    let at: Vec<Value> = traj
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).unwrap())
        .filter(|p| p["robot"] == 2 && p["round"].as_u64().unwrap() >= 2)
        .map(|p| p["vertex"].clone())
        .collect();
    assert!(at.len() > 7, "robot 2 is in every later round: {}", at.len());
    assert!(at.iter().all(|v| *v == at[0]), "robot 2 moved after it was found dead: {at:?}");
}

#[test]
fn zenoh_only_flags_are_refused_on_iceoryx2_and_keys_are_checked() {
    let _s = serial();
    let out = gridswarm().args(["run", "--listen", "tcp/127.0.0.1:7447"]).output().unwrap();
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("need --transport zenoh"), "{}", text(&out.stderr));
    let out = gridswarm().args(["run", "--transport", "zenoh", "--remote-agents", "a/*"]).output().unwrap();
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("not a run key"), "{}", text(&out.stderr));
    let out =
        gridswarm().args(["run", "--transport", "zenoh", "--remote-agents", "k", "--kill", "1@2"]).output().unwrap();
    assert!(text(&out.stderr).contains("--remote-agents the orchestrator has none"), "{}", text(&out.stderr));
    let out = gridswarm().args(["run", "--transport", "carrier-pigeon"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_robot_s_credentials_speak_and_hear_for_that_robot_only() {
    const TEST: &str = "a_robot_s_credentials_speak_and_hear_for_that_robot_only";
    if let Ok(spec) = std::env::var(intruder::SPEC) {
        return intruder::act(&spec);
    }
    let _s = serial();
    let dir = scratch("zenoh-robot-acl");
    let keys = dir.join("keys");
    intruder::credentials(&keys, 4, &[]);
    let endpoint = format!("tls/127.0.0.1:{}", intruder::free_port());
    let key = format!("acl{}", std::process::id());
    let security = ["--credentials".to_string(), keys.display().to_string()];
    let run = ["--scenario", "paper", "--seed", "5", "--robots", "4"];
    let out = dir.join("run");
    let world = intruder::start_world(&key, &endpoint, &security, &run, &out);
    // Robot 1's own certificate, in the hands of someone who subscribes to
    // everything and speaks as robot 0 (its answers, its inbox, its token).
    let orders = intruder::Orders {
        endpoint: endpoint.clone(),
        key: key.clone(),
        ca: Some(keys.join("ca.pem")),
        cert: Some((keys.join("robot-1.pem"), keys.join("robot-1.key"))),
        disturb: true,
        ..Default::default()
    };
    let robot1 = intruder::Intruder::start(&[], &std::env::current_exe().unwrap(), TEST, &orders);
    let agents = intruder::start_agents(&key, &endpoint, &security, (&run[..], &dir), 4);
    let v = intruder::finish(world, agents);
    let r = robot1.stop();
    assert!(r.opened && r.received > 0, "robot 1's credentials join and hear robot 1's inbox: {r:?}");
    let own = format!("gridswarm/{key}/in/1");
    assert_eq!(r.keys.iter().collect::<Vec<_>>(), [&own], "nothing but robot 1's inbox is heard: {r:?}");
    assert_eq!(v["complete"], true, "{v}");
    intruder::same_as_simulate(&out, &run);
}

#[test]
fn a_robot_refuses_a_world_whose_certificate_does_not_name_the_host() {
    let _s = serial();
    let dir = scratch("zenoh-names");
    // The world's certificate names localhost, 127.0.0.1 and ::1 only.
    let keys = dir.join("keys");
    intruder::credentials(&keys, 2, &[]);
    let port = intruder::free_port();
    let (named, unnamed) = (format!("tls/127.0.0.1:{port}"), format!("tls/127.0.0.2:{port}"));
    let key = format!("names{}", std::process::id());
    let security = ["--credentials".to_string(), keys.display().to_string()];
    let run = ["--scenario", "small", "--seed", "2", "--robots", "2"];
    let listen_both = [&security[..], &["--listen".to_string(), unnamed.clone()]].concat();
    let world = intruder::start_world(&key, &named, &listen_both, &run, &dir.join("run"));
    let wrong = [&security[..], &["--connect-timeout-ms".to_string(), "3000".into()]].concat();
    let mut refused = intruder::start_agents(&key, &unnamed, &wrong, (&run[..], &dir), 1);
    let out = refused.pop().unwrap().wait_with_output().unwrap();
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("must name the host in --connect"), "{err}");
    // The same credentials through a name the certificate holds: the run goes on.
    let v = intruder::finish(world, intruder::start_agents(&key, &named, &security, (&run[..], &dir), 2));
    assert_eq!(v["complete"], true, "{v}");
}
