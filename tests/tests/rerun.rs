//! A results folder is data (issue 36, point 9): `gridswarm rerun DIR` of
//! a folder whose provenance was edited to name an agent program, an MCAP
//! file outside it, a live server on 0.0.0.0 and a zenoh world listening
//! on the network executes nothing the folder names, writes nothing
//! outside its output folder and listens on no socket; the agent program
//! runs only when rerun's own command line names the same path.

use std::fs;
use std::net::{Ipv4Addr, SocketAddr, TcpListener, TcpStream};
use std::os::unix::fs::PermissionsExt;
use std::path::Path;
use std::process::Stdio;
use std::time::Duration;

use gridswarm_e2e::*;
use serde_json::Value;

/// A rerun ends in seconds; past this it waits for a viewer (the bug).
const GUARD: Duration = Duration::from_secs(120);

/// A port nothing listens on now.
fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

/// Whether something accepts connections on `port` of this host.
fn listening(port: u16) -> bool {
    let addr = SocketAddr::from((Ipv4Addr::LOCALHOST, port));
    TcpStream::connect_timeout(&addr, Duration::from_millis(50)).is_ok()
}

/// `gridswarm rerun ARGS`, watching `ports` while it runs: its output,
/// and whether any of them accepted a connection meanwhile.
fn rerun_watching(args: &[&str], ports: &[u16]) -> (std::process::Output, bool) {
    let mut child = gridswarm().arg("rerun").args(args).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let mut heard = false;
    let ended = wait_until(GUARD, || {
        heard |= ports.iter().any(|&p| listening(p));
        child.try_wait().ok().flatten().is_some()
    });
    if !ended {
        let _ = child.kill();
    }
    let out = child.wait_with_output().unwrap();
    assert!(ended, "rerun still running after {GUARD:?}: {}", text(&out.stderr));
    (out, heard)
}

/// `dir`'s summary.json with `extra` appended to its recorded command.
fn edit_command(dir: &Path, extra: &[String]) {
    let path = dir.join("summary.json");
    let mut v: Value = serde_json::from_slice(&fs::read(&path).unwrap()).unwrap();
    let cmd = v["provenance"]["command"].as_array_mut().unwrap();
    cmd.extend(extra.iter().map(|a| Value::from(a.as_str())));
    fs::write(&path, v.to_string()).unwrap();
}

#[test]
fn a_hostile_folder_executes_nothing_writes_nothing_outside_and_serves_nothing() {
    let _s = serial();
    let dir = scratch("rerun-hostile");
    let made = dir.join("made");
    ok(&["run", "--scenario", "small", "--robots", "2", "--seed", "3", "--out", made.to_str().unwrap()]);

    // The program the edited folder names: it would leave a marker, then be the agent.
    let (marker, evil) = (dir.join("executed"), dir.join("evil-agent"));
    let real = bin_dir().join("robot-agent");
    let script = format!("#!/bin/sh\ntouch '{}'\nexec '{}' \"$@\"\n", marker.display(), real.display());
    fs::write(&evil, script).unwrap();
    fs::set_permissions(&evil, fs::Permissions::from_mode(0o755)).unwrap();
    let (mcap, live, zenoh) = (dir.join("outside.mcap"), free_port(), free_port());
    let hostile = [
        "--agent-bin".to_string(),
        evil.display().to_string(),
        "--mcap".into(),
        mcap.display().to_string(),
        "--live".into(),
        format!("0.0.0.0:{live}"),
        "--transport".into(),
        "zenoh".into(),
        "--listen".into(),
        format!("tcp/0.0.0.0:{zenoh}"),
        "--insecure".into(),
        "--insecure-network".into(),
    ];
    edit_command(&made, &hostile);
    let made_s = made.to_str().unwrap();

    // Not asked on rerun's own command line: refused, naming the option; nothing runs.
    let (out, heard) = rerun_watching(&[made_s], &[live, zenoh]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.starts_with("error: ") && err.contains(&format!("--agent-bin {}", evil.display())), "{err}");
    assert!(!marker.exists(), "the folder's agent program was executed");
    assert!(!made.join("rerun").exists() && !mcap.exists() && !heard);

    // Another program on rerun's command line is not the folder's either.
    let (out, _) = rerun_watching(&[made_s, "--agent-bin", real.to_str().unwrap()], &[]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out.stderr));
    assert!(!marker.exists());

    // The same path given to rerun: it runs, as the recorded run did; the
    // MCAP file, the live server and zenoh's listener are still dropped.
    let (out, heard) = rerun_watching(&[made_s, "--agent-bin", evil.to_str().unwrap()], &[live, zenoh]);
    let said = text(&out.stdout);
    assert!(out.status.success(), "{said}{}", text(&out.stderr));
    assert!(marker.exists(), "the agent program named on rerun's command line ran");
    assert!(!mcap.exists(), "written outside the output folder");
    assert!(!heard, "a socket was listening on the folder's --live or --listen port");
    for note in ["--mcap", "is not served", "over iceoryx2"] {
        assert!(said.contains(note), "{note} in {said}");
    }
    assert!(said.contains("same     trajectories.jsonl\n"), "{said}");
}

#[test]
fn a_folder_naming_another_command_is_not_run() {
    let dir = scratch("rerun-other-command");
    let target = dir.join("written-by-the-folder.toml");
    let cmd = ["gridswarm", "export-map", "paper", "--format", "toml", "--out", target.to_str().unwrap()];
    fs::write(dir.join("provenance.json"), serde_json::json!({ "command": cmd }).to_string()).unwrap();
    let out = gridswarm().arg("rerun").arg(&*dir).output().unwrap();
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("is not one whose outputs a rerun repeats"), "{err}");
    assert!(!target.exists() && !dir.join("rerun").exists());
}
