//! The build the README asks for first (`cargo build --release`) and its
//! test command (`cargo test --release --workspace`) must build every crate
//! with the same features: a crate whose features differ is compiled again,
//! and with it every crate above it (iceoryx2, zenoh, gridswarm, the
//! programs: most of the build). The tests' dev-dependencies add features to
//! crates the programs share; tests/Cargo.toml names them as dependencies of
//! its own. This compares cargo's two resolutions, with and without the
//! dev-dependencies, crate by crate: every way the build compiles a crate
//! must be one the tests compile it (they may add others of their own, for
//! a crate only they use on the target side).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::Command;

/// Every crate of the workspace's resolution (`name vVERSION`) with the sets
/// of features it is built with (one per way it is built: for the target,
/// for build scripts and macros), as `cargo tree` reports them.
fn resolution(with_dev: bool) -> BTreeMap<String, BTreeSet<String>> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let mut cmd = Command::new(cargo);
    cmd.current_dir(root).args(["tree", "--workspace", "--offline", "--locked", "--prefix", "none"]);
    cmd.args(["--format", "{p}|{f}"]);
    if !with_dev {
        cmd.args(["--edges", "no-dev"]);
    }
    let out = cmd.output().expect("cargo runs");
    assert!(out.status.success(), "cargo tree failed: {}", String::from_utf8_lossy(&out.stderr));
    let mut crates: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for line in String::from_utf8(out.stdout).unwrap().lines() {
        let (name, features) = line.split_once('|').unwrap_or((line, ""));
        let features = features.trim_end_matches(" (*)").to_string();
        crates.entry(name.trim().to_string()).or_default().insert(features);
    }
    crates
}

#[test]
fn the_tests_build_every_crate_of_the_programs_with_the_build_features() {
    let build = resolution(false);
    let test = resolution(true);
    assert!(build.keys().any(|k| k.starts_with("iceoryx2 ")), "the resolution lists the crates: {build:?}");
    let differ: Vec<String> = build
        .iter()
        .filter(|(name, features)| !test.get(*name).is_some_and(|t| t.is_superset(features)))
        .map(|(name, features)| format!("{name}: build {features:?}, test {:?}", test[name]))
        .collect();
    assert!(
        differ.is_empty(),
        "the tests would compile these crates (and every crate above them) again; name the \
         test's features in tests/Cargo.toml:\n{}",
        differ.join("\n")
    );
}
