//! A run is one agreement (issue 23, point 1): every robot-agent presents
//! the run key, its robot number, its scenario's hash, seed, algorithm,
//! situation, parameters and protocol version in its hello, and the world
//! refuses one that differs, one whose number is outside the team, or a
//! second claim to a number taken, naming what is wrong on both sides.
//! The refused agent exits 2 with the world's words, and `gridswarm run`
//! ends the run with them, exit status 2 (README's table), writing
//! nothing; a claim once the run is under way is refused, and the run
//! stays `simulate`'s. The reproducers, with agents started by
//! hand over zenoh (`--remote-agents`, as README's "Running on several
//! machines"), and one over iceoryx2 through `--agent-bin`.

use std::fs;
use std::os::unix::fs::PermissionsExt;
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::Duration;

use gridswarm_e2e::*;

/// A refused agent or run ends in seconds; past this it hangs (the bug).
const GUARD: Duration = Duration::from_secs(60);

/// `gridswarm run` with agents started by hand, killed if the test fails.
struct World {
    child: Option<Child>,
    endpoint: String,
    key: String,
    /// The agents' setup files (`gridswarm setup`).
    setups: Scratch,
}

impl World {
    /// `gridswarm run --transport zenoh --listen tcp/127.0.0.1:<free>
    /// --insecure --remote-agents KEY ARGS`: plain TCP on loopback, so
    /// that an agent can claim a robot number no certificate names (the
    /// agreement is checked whatever secures the link).
    fn start(key: &str, args: &[&str]) -> Self {
        let port = std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
        let endpoint = format!("tcp/127.0.0.1:{port}");
        let child = gridswarm()
            .args(["run", "--transport", "zenoh", "--listen", &endpoint, "--insecure", "--remote-agents", key])
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        World { child: Some(child), endpoint, key: key.into(), setups: scratch(&format!("setups-{key}")) }
    }

    /// Robot `robot`'s agent as README says to start one by hand: `gridswarm
    /// setup --key KEY RUN --robot K --out FILE`, then `robot-agent
    /// --transport zenoh --prefix KEY --connect ENDPOINT --insecure --setup
    /// FILE`, started.
    fn agent(&self, run: &[&str], robot: usize) -> Child {
        self.agent_with(run, robot, &[])
    }

    /// [`World::agent`] with more variables in its environment.
    fn agent_with(&self, run: &[&str], robot: usize, env: &[(&str, &str)]) -> Child {
        self.agent_of(&setup_file(&self.setups, &self.key, run, robot), env)
    }

    /// An agent started by hand with the setup file `setup`.
    fn agent_of(&self, setup: &Path, env: &[(&str, &str)]) -> Child {
        Command::new(bin_dir().join("robot-agent"))
            .args(["--transport", "zenoh", "--prefix", &self.key, "--connect", &self.endpoint, "--insecure"])
            .arg("--setup")
            .arg(setup)
            .envs(env.iter().copied())
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    }

    /// The command's end, within [`GUARD`].
    fn end(mut self) -> Output {
        ended(self.child.take().unwrap(), "gridswarm run")
    }
}

impl Drop for World {
    fn drop(&mut self) {
        if let Some(c) = &mut self.child {
            // SIGTERM: it ends its world-server and removes the run's files.
            // SAFETY: kill(2) on our own child.
            unsafe { libc::kill(c.id() as i32, libc::SIGTERM) };
            let _ = c.wait();
        }
    }
}

/// `child`'s output once it exits, failing the test if it is still
/// running after [`GUARD`] (it is killed then).
fn ended(mut child: Child, what: &str) -> Output {
    let exited = wait_until(GUARD, || child.try_wait().ok().flatten().is_some());
    if !exited {
        let _ = child.kill();
    }
    let out = child.wait_with_output().unwrap();
    assert!(exited, "{what} still running after {GUARD:?}: {}", text(&out.stderr));
    out
}

/// An agent's end: exit status 2, one line naming the refusal and holding `words`.
fn refused(agent: Child, words: &[&str]) -> String {
    let out = ended(agent, "robot-agent");
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.contains(": error: refused by the world: "), "{err}");
    for w in words {
        assert!(err.contains(w), "{w:?} in {err}");
    }
    err
}

/// The run's end: exit status 2, its last line an error holding `words`,
/// no panic, and no output folder.
fn run_refused(world: World, out_dir: &Path, words: &[&str]) -> String {
    let out = world.end();
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    let last = err.lines().last().unwrap_or_default();
    assert!(last.starts_with("error: the world-server refused the run: "), "{err}");
    for w in words {
        assert!(last.contains(w), "{w:?} in {last}");
    }
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out_dir.exists(), "nothing is recorded: {}", out_dir.display());
    err
}

/// README's exit table says a refused run is a usage error.
fn readme_says_refusals_exit_2() {
    let readme = fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md")).unwrap();
    let row = readme.lines().find(|l| l.starts_with("| 2 | ")).unwrap();
    assert!(row.contains("a robot-agent the world refuses"), "{row}");
}

#[test]
fn agents_with_another_seed_are_refused_and_nothing_is_recorded() {
    let _s = serial();
    readme_says_refusals_exit_2();
    let dir = scratch("agreement-seed");
    let out_dir = dir.join("result");
    let world = World::start(
        "seed78",
        &["--scenario", "small", "--robots", "2", "--seed", "7", "--out", out_dir.to_str().unwrap()],
    );
    let agents: Vec<Child> =
        (0..2).map(|k| world.agent(&["--scenario", "small", "--seed", "8", "--robots", "2"], k)).collect();
    for a in agents {
        // The first heard is refused for its seed, the other told the run is off, why included.
        refused(a, &["seed: world 7, agent 8"]);
    }
    run_refused(world, &out_dir, &["does not agree with the world: seed: world 7, agent 8"]);
}

/// Issue 36's reproducer: a setup file edited by hand in each of seed,
/// algorithm, t_wait, team and r_c. The agent presents what its setup
/// runs, not a declared copy beside it, so the world refuses it naming the
/// edit, and nothing is recorded as a run of the world's settings.
#[test]
fn an_edited_setup_is_refused_for_what_it_would_run() {
    let _s = serial();
    let dir = scratch("agreement-edited");
    let edits = [
        ("seed", "/setup/seed", serde_json::json!(8), "seed: world 7, agent 8"),
        ("algorithm", "/setup/policy", serde_json::json!("sequential"), "algorithm: world repulsive, agent sequential"),
        ("t_wait", "/setup/params/t_wait", serde_json::json!(9.5), "params.t_wait: world "),
        ("team", "/setup/team", serde_json::json!(3), "team: world 2, agent 3"),
        ("r_c", "/setup/params/r_c", serde_json::json!(30.0), "params.r_c: world "),
    ];
    let run = ["--scenario", "small", "--seed", "7", "--robots", "2"];
    for (what, field, value, words) in edits {
        let out_dir = dir.join(what);
        let key = format!("edit-{}", what.replace('_', ""));
        let world = World::start(&key, &[&run[..], &["--out", out_dir.to_str().unwrap()]].concat());
        let file = setup_file(&world.setups, &key, &run, 0);
        let mut v: serde_json::Value = serde_json::from_slice(&fs::read(&file).unwrap()).unwrap();
        let old = v.pointer(field).unwrap_or_else(|| panic!("{field} in {v}")).clone();
        assert_ne!(old, value, "{what}: an edit");
        *v.pointer_mut(field).unwrap() = value;
        fs::write(&file, v.to_string()).unwrap();
        refused(world.agent_of(&file, &[]), &[words]);
        run_refused(world, &out_dir, &[words]);
    }
}

#[test]
fn agents_of_another_scenario_are_refused_at_their_hello_not_100_rounds_in() {
    let _s = serial();
    let dir = scratch("agreement-scenario");
    let out_dir = dir.join("result");
    let world = World::start("paperopen", &["--robots", "2", "--seed", "7", "--out", out_dir.to_str().unwrap()]);
    let agents: Vec<Child> =
        (0..2).map(|k| world.agent(&["--scenario", "open", "--seed", "7", "--robots", "2"], k)).collect();
    for a in agents {
        refused(a, &["scenario: world `paper` (sha3 ", "agent `open` (sha3 "]);
    }
    run_refused(world, &out_dir, &["scenario: world `paper`"]);
}

#[test]
fn a_robot_number_outside_the_team_is_refused_in_words_a_bash_user_reads() {
    let _s = serial();
    let dir = scratch("agreement-outside");
    let out_dir = dir.join("result");
    let world = World::start("thirteen", &["--robots", "13", "--seed", "7", "--out", out_dir.to_str().unwrap()]);
    let agent = world.agent(&["--scenario", "paper", "--seed", "7", "--robots", "13"], 13);
    refused(agent, &["claims robot 13, which is not in this run: its 13 robot(s) are numbered 0 to 12"]);
    let err = run_refused(world, &out_dir, &["numbered 0 to 12"]);
    // The hint to start the agents says the range in words too.
    assert!(err.contains("for each robot number K (0 to 12)"), "{err}");
    assert!(!err.contains("0..13"), "{err}");
}

#[test]
fn a_second_claim_to_a_robot_number_is_refused() {
    let _s = serial();
    let dir = scratch("agreement-twice");
    // The case: an impostor with another seed, started before the real robot 1.
    let out_dir = dir.join("other-seed");
    let world = World::start(
        "twice1",
        &["--scenario", "small", "--robots", "2", "--seed", "7", "--out", out_dir.to_str().unwrap()],
    );
    let impostor = world.agent(&["--scenario", "small", "--seed", "9", "--robots", "2"], 1);
    refused(impostor, &["robot-agent 1 (pid ", "seed: world 7, agent 9"]);
    run_refused(world, &out_dir, &["seed: world 7, agent 9"]);

    // An impostor that agrees in everything: whichever of the two claims
    // is heard first holds the number (the impostor's, started first, as
    // a rule), the other is refused as a second claim, and the first told
    // the run is off.
    let out_dir = dir.join("same-seed");
    let world = World::start(
        "twice2",
        &["--scenario", "small", "--robots", "2", "--seed", "7", "--out", out_dir.to_str().unwrap()],
    );
    let args = ["--scenario", "small", "--seed", "7", "--robots", "2"];
    let impostor = world.agent(&args, 1);
    std::thread::sleep(Duration::from_millis(500));
    let real = world.agent(&args, 1);
    let (ids, agents) = ([impostor.id(), real.id()], [impostor, real]);
    let said: Vec<String> =
        agents.into_iter().map(|a| refused(a, &["claims robot 1, which is already taken by pid "])).collect();
    let second = said.iter().position(|e| !e.contains("the run is off")).expect("one refused as the second claim");
    let taken = format!("claims robot 1, which is already taken by pid {} on ", ids[1 - second]);
    assert!(said[second].contains(&format!("robot-agent 1 (pid {} on ", ids[second])), "{}", said[second]);
    assert!(said[second].contains(&taken), "{}", said[second]);
    assert!(said[1 - second].contains(&format!("the run is off: robot-agent 1 (pid {} on ", ids[second])));
    run_refused(world, &out_dir, &[&taken]);
}

#[test]
fn an_agent_that_differs_is_refused_over_iceoryx2_as_over_zenoh() {
    let _s = serial();
    // An agent program that ignores the setup file it is given and takes
    // one `gridswarm setup` writes for seed 8, as a hand-started agent might.
    let dir = scratch("agreement-iceoryx2");
    let agent = dir.join("agent");
    let real = bin_dir().join("robot-agent");
    let (real, gs) = (real.to_str().unwrap(), bin_dir().join("gridswarm"));
    let (gs, setups) = (gs.to_str().unwrap(), dir.to_str().unwrap());
    fs::write(
        &agent,
        format!(
            "#!/bin/sh\nif [ \"$1\" = --list-rules ]; then exec {real} --list-rules; fi\n\
             k=$(basename \"$4\" .json); k=${{k#robot-}}\n\
             {gs} setup --key \"$2\" --scenario small --seed 8 --robot \"$k\" --out {setups}/seed8-$k.json >/dev/null || exit 1\n\
             exec {real} --prefix \"$2\" --world-pid \"$6\" --setup {setups}/seed8-$k.json\n"
        ),
    )
    .unwrap();
    fs::set_permissions(&agent, fs::Permissions::from_mode(0o755)).unwrap();
    let out_dir = dir.join("result");
    let child = gridswarm()
        .args(["run", "--scenario", "small", "--robots", "3", "--seed", "3", "--out", out_dir.to_str().unwrap()])
        .arg("--agent-bin")
        .arg(&agent)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let prefixes = format!("gs{}x", child.id());
    let out = ended(child, "gridswarm run");
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("error: ") && err.contains("seed: world 3, agent 8"), "{err}");
    assert!(!out_dir.exists());
    assert_no_leftovers(&prefixes);
}

#[test]
fn a_claim_once_the_run_is_under_way_is_refused_and_changes_nothing() {
    let _s = serial();
    let dir = scratch("agreement-late");
    let (out_dir, sim) = (dir.join("run"), dir.join("sim"));
    let run = ["--scenario", "small", "--seed", "7"];
    let world = World::start("late1", &[&run[..], &["--robots", "2", "--out", out_dir.to_str().unwrap()]].concat());
    // Robot 0 stops itself on the readings of slot 2: the world waits on it.
    let team = [&run[..], &["--robots", "2"]].concat();
    let hung = world.agent_with(&team, 0, &[("GRIDSWARM_AGENT_HANG", "0@2")]);
    let real = world.agent(&team, 1);
    assert!(wait_until(GUARD, || stopped(hung.id())), "robot 0 stops in slot 2");
    let impostor = world.agent(&team, 1);
    refused(impostor, &[&format!("already taken by pid {} on ", real.id()), "and the run is under way"]);
    // SAFETY: kill(2) on our own child.
    unsafe { libc::kill(hung.id() as i32, libc::SIGCONT) };
    let out = world.end();
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    for a in [hung, real] {
        assert_eq!(ended(a, "robot-agent").status.code(), Some(0));
    }
    search(&[&["simulate", "--robots", "2", "--out", sim.to_str().unwrap()][..], &run[..]].concat());
    let (a, b) =
        (fs::read(out_dir.join("trajectories.jsonl")).unwrap(), fs::read(sim.join("trajectories.jsonl")).unwrap());
    assert!(!a.is_empty() && a == b, "the run is simulate's, the late claim aside");
}
