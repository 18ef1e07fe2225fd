//! The crate boundaries the compiler keeps (ARCHITECTURE.md, "The robot is
//! a crate"; issue 21, point 9): the robot (`gridswarm-robot`) depends on
//! no crate of the workspace, so it cannot name the world; the transports
//! (`gridswarm-transport`) and the robot-agent never depend on the world's
//! crate (`gridswarm`), so an agent holds only what a robot holds. Checked
//! on cargo's resolution, every crate each one links, however far down:
//! normal and build dependencies, not dev-dependencies (the agent's
//! example runs its rule in-process through the orchestrator).

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

use serde_json::Value;

fn cargo(args: &[&str]) -> Vec<u8> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let out = Command::new(cargo).current_dir(root).args(args).args(["--offline", "--locked"]).output().unwrap();
    assert!(out.status.success(), "cargo {args:?} failed: {}", String::from_utf8_lossy(&out.stderr));
    out.stdout
}

/// Every crate `package` links, however far down, by name: cargo's
/// resolution for this machine with every feature of `package` on,
/// without dev-dependencies.
fn below(package: &str) -> BTreeSet<String> {
    let edges = ["--all-features", "--edges", "normal,build", "--prefix", "none", "--format", "{p}"];
    let tree = cargo(&[&["tree", "-p", package][..], &edges].concat());
    let tree = String::from_utf8(tree).unwrap();
    let mut crates: BTreeSet<String> =
        tree.lines().filter_map(|l| l.split_whitespace().next()).map(String::from).collect();
    assert!(crates.remove(package), "cargo tree starts at {package}: {tree}");
    crates
}

/// The workspace's crates among `crates`.
fn ours(crates: &BTreeSet<String>) -> BTreeSet<String> {
    let meta: Value = serde_json::from_slice(&cargo(&["metadata", "--format-version", "1", "--no-deps"])).unwrap();
    let members: BTreeSet<&str> =
        meta["packages"].as_array().unwrap().iter().map(|p| p["name"].as_str().unwrap()).collect();
    assert!(members.contains("gridswarm") && members.contains("gridswarm-robot-agent"), "{members:?}");
    crates.iter().filter(|c| members.contains(c.as_str())).cloned().collect()
}

#[test]
fn the_robot_depends_on_no_crate_of_the_workspace() {
    let robot = below("gridswarm-robot");
    assert!(robot.contains("serde"), "the resolution lists what the robot links: {robot:?}");
    assert_eq!(ours(&robot), BTreeSet::new(), "gridswarm-robot must not link the workspace's crates");
}

#[test]
fn the_agent_and_the_transports_never_link_the_world() {
    let want = |names: &[&str]| names.iter().map(|n| n.to_string()).collect::<BTreeSet<_>>();
    let transport = below("gridswarm-transport");
    assert!(transport.contains("iceoryx2") && transport.contains("zenoh"), "{transport:?}");
    assert_eq!(ours(&transport), want(&["gridswarm-robot"]), "gridswarm-transport links the robot only");
    let agent = below("gridswarm-robot-agent");
    assert_eq!(
        ours(&agent),
        want(&["gridswarm-robot", "gridswarm-transport"]),
        "the robot-agent links the robot and a transport only, never `gridswarm` (the world's crate)"
    );
    // The world's crate does reach the transports (they are re-exported there).
    assert!(below("gridswarm").contains("gridswarm-transport"));
}
