//! `scripts/install.sh DIR` puts the three programs in one folder, where
//! `gridswarm run` finds `world-server` and `robot-agent` next to itself,
//! whichever folder it is started from.

use std::fs;
use std::os::unix::fs::PermissionsExt;
use std::path::Path;
use std::process::Command;

use gridswarm_e2e::*;

#[test]
fn installed_programs_run_together_from_their_folder() {
    let _s = serial();
    let dir = scratch("install");
    let (stub, to) = (dir.join("stub"), dir.join("bin"));
    fs::create_dir_all(&stub).unwrap();
    // The build is cargo's, done already for these tests: a stub `cargo` records how it is asked.
    let calls = dir.join("cargo-calls");
    fs::write(stub.join("cargo"), format!("#!/bin/sh\necho \"$@\" >>{}\n", calls.display())).unwrap();
    fs::set_permissions(stub.join("cargo"), fs::Permissions::from_mode(0o755)).unwrap();
    let built = bin_dir();
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let out = Command::new(repo.join("scripts/install.sh"))
        .arg(&to)
        .env("PATH", format!("{}:{}", stub.display(), std::env::var("PATH").unwrap_or_default()))
        .env("CARGO_TARGET_DIR", built.parent().unwrap())
        .output()
        .unwrap();
    assert!(out.status.success(), "install.sh failed: {}", text(&out.stderr));
    assert_eq!(fs::read_to_string(&calls).unwrap(), "build --release --locked\n");
    for b in ["gridswarm", "world-server", "robot-agent"] {
        let meta = fs::metadata(to.join(b)).unwrap_or_else(|e| panic!("{b} not installed: {e}"));
        assert_eq!(meta.permissions().mode() & 0o777, 0o755, "{b}");
        assert_eq!(meta.len(), fs::metadata(built.join(b)).unwrap().len(), "{b} is the built one");
    }
    assert!(text(&out.stdout).contains(&to.display().to_string()), "it says where: {}", text(&out.stdout));

    // Started by its path from another folder, without GRIDSWARM_BIN_DIR.
    let args = ["run", "--json", "--robots", "3", "--seed", "5", "--max-rounds", "5"];
    let run = |dir: &Path| {
        Command::new(to.join("gridswarm")).args(args).current_dir(dir).env_remove("GRIDSWARM_BIN_DIR").output().unwrap()
    };
    let v = finished(&run(&dir), &args);
    assert_no_leftovers(v["ipc_prefix"].as_str().unwrap());
    assert_eq!(v["robots"], 3, "{v}");

    // It looked in its own folder: without the agent there, it says so.
    fs::remove_file(to.join("robot-agent")).unwrap();
    let out = run(&dir);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stderr));
    let looked = format!("looked for {}", to.join("robot-agent").display());
    assert!(text(&out.stderr).contains(&looked), "{}", text(&out.stderr));
}
