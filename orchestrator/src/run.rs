//! `gridswarm run`: one search with one OS process per robot (issue "One
//! process per robot over iceoryx2"): a `world-server` and N `robot-agent`s
//! talking over iceoryx2, with failure injection. Same files as `simulate`
//! (through [`crate::rundir::write_run_dir`]), plus the failures injected and
//! detected, refused moves, dropped messages and wall time per round.
//!
//! Sequence: sweep the files of dead runs; pick a fresh iceoryx2 prefix;
//! spawn the world-server, wait for its `ready` (every service exists); spawn
//! the agents (after the world, so no child inherits an iceoryx2 descriptor);
//! then follow the world's stdout. At each `round K` it pauses for, apply the
//! failures scheduled for round K (SIGKILL, SIGSTOP, SIGCONT) and answer
//! `go`. On `done`, read the world's report, reap the agents, remove every
//! file of the run, write the outputs. If the world-server dies, or SIGINT /
//! SIGTERM arrives, every child is killed and reaped and the run's files
//! removed before the one-line error.

use std::collections::BTreeSet;
use std::fs;
use std::io::Write;
use std::path::PathBuf;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use gridswarm::ipc::{self, RunReport};
use gridswarm::lattice::Coord;
use gridswarm::outcome::Pose;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::sim::{self, Fault, FaultKind};
use serde_json::{json, Value};

use crate::check;
use crate::contract;
use crate::error::{Error, Result};
use crate::launch::{self, Event};
use crate::rundir::{self, RunRecord};

/// How long agents get to exit by themselves after the end.
const AGENT_GRACE: Duration = Duration::from_secs(5);

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// SIGKILL: the robot's process dies.
    Kill,
    /// SIGSTOP, and SIGCONT at `wake` if given.
    Freeze,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Kill => "kill",
            Kind::Freeze => "freeze",
        }
    }
}

/// One failure to inject at the start of `round`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Injection {
    pub robot: usize,
    pub round: u32,
    pub kind: Kind,
    pub wake: Option<u32>,
}

/// A robot silent this long (while nothing it waits for is missing) is
/// declared failed by this build's world-server, which predates the
/// simulated world's protocol timing.
const SUSPECT_MS: u64 = 2000;

#[derive(Clone, Debug)]
pub struct RunOptions {
    pub scenario: String,
    pub algorithm: Policy,
    pub robots: Option<usize>,
    pub seed: u64,
    pub situation: Option<Situation>,
    pub max_rounds: u32,
    pub radio: sim::Radio,
    /// Overrides the scenario's `params.retries`.
    pub retries: Option<u32>,
    /// Faults given explicitly.
    pub faults: Vec<Fault>,
    /// Crash this many more robots at times drawn from the seed.
    pub kill_random: usize,
    pub out: Option<PathBuf>,
    pub json: bool,
}

impl RunOptions {
    /// A run for an experiment: no files, nothing printed, a perfect radio,
    /// and no faults but `kill_random` robots crashed at random times.
    pub fn for_experiment(
        scenario: String,
        algorithm: Policy,
        robots: usize,
        seed: u64,
        situation: Situation,
        kill_random: usize,
        max_rounds: u32,
    ) -> Self {
        RunOptions {
            scenario,
            algorithm,
            robots: Some(robots),
            seed,
            situation: Some(situation),
            max_rounds,
            radio: sim::Radio::default(),
            retries: None,
            faults: Vec::new(),
            kill_random,
            out: None,
            json: true,
        }
    }
}

/// Robots that react late, and by how many milliseconds (`--slow`).
fn slow(opts: &RunOptions) -> Vec<(usize, u32)> {
    opts.faults
        .iter()
        .filter_map(|f| match f.kind {
            FaultKind::Slow(t) => Some((f.robot, (t / 1000) as u32)),
            _ => None,
        })
        .collect()
}

/// The injection schedule: the given crashes and freezes, and
/// `kill_random` more crashes drawn from the seed. This build's world-server
/// injects at the start of a round only, and has no simulated radio.
pub fn schedule(opts: &RunOptions, robots: usize) -> Result<Vec<Injection>> {
    if !opts.radio.is_perfect() || opts.retries.is_some() {
        return Err(Error::Input(
            "this build's world-server has no simulated radio: --loss, --delay, --dup and --retries need the new distributed engine".into(),
        ));
    }
    sim::schedule::check(&opts.faults, robots).map_err(Error::Input)?;
    let taken: Vec<usize> = opts.faults.iter().map(|f| f.robot).collect();
    let mut faults = opts.faults.clone();
    faults.extend(sim::schedule::kill_random(opts.seed, robots, opts.kill_random, &taken).map_err(Error::Input)?);
    let mut out: Vec<Injection> = Vec::new();
    for f in &faults {
        let wake = || faults.iter().find(|g| g.robot == f.robot && g.kind == FaultKind::Thaw).map(|g| g.round);
        match f.kind {
            FaultKind::Crash => out.push(Injection { robot: f.robot, round: f.round, kind: Kind::Kill, wake: None }),
            FaultKind::Freeze => out.push(Injection { robot: f.robot, round: f.round, kind: Kind::Freeze, wake: wake() }),
            FaultKind::Thaw | FaultKind::Slow(_) => {}
        }
    }
    out.sort_by_key(|i| (i.round, i.robot));
    Ok(out)
}

fn run_err(s: impl Into<String>) -> Error {
    Error::Run(s.into())
}

/// Nearest-rank percentile of unsorted samples.
fn percentile(samples: &[f64], p: f64) -> Option<f64> {
    if samples.is_empty() {
        return None;
    }
    let mut v = samples.to_vec();
    v.sort_by(f64::total_cmp);
    let rank = ((p / 100.0) * v.len() as f64).ceil().max(1.0) as usize;
    Some(v[rank.min(v.len()) - 1])
}

/// Everything the run started, so every exit path can end it.
struct Processes {
    world: Option<Child>,
    agents: Vec<Child>,
    prefix: String,
    root: PathBuf,
    report: PathBuf,
    agent_log: PathBuf,
}

impl Processes {
    /// Kills and reaps every child, removes the run's files.
    fn abort(&mut self) {
        if let Some(w) = self.world.as_mut() {
            let _ = w.kill();
            let _ = w.wait();
        }
        launch::kill_and_reap(&mut self.agents);
        self.cleanup();
    }

    fn cleanup(&mut self) {
        let _ = ipc::cleanup_run(&self.prefix, &self.root);
        let _ = fs::remove_file(&self.report);
    }
}

impl Drop for Processes {
    fn drop(&mut self) {
        // Whatever path left `run` (an error, a panic), nothing outlives it.
        self.abort();
        let _ = fs::remove_file(&self.agent_log);
    }
}

fn say(stdin: &mut ChildStdin, line: &str) -> std::io::Result<()> {
    writeln!(stdin, "{line}")?;
    stdin.flush()
}

/// The orchestrator's own temporary files of a run (`gridswarm-<prefix>...`).
pub fn temp_files(prefix: &str) -> Vec<PathBuf> {
    let head = format!("gridswarm-{prefix}");
    fs::read_dir(std::env::temp_dir())
        .map(|d| {
            d.flatten()
                .filter(|e| e.file_name().to_string_lossy().starts_with(&head))
                .map(|e| e.path())
                .collect()
        })
        .unwrap_or_default()
}

/// Removes the temporary files (report, agents' log) of runs whose
/// orchestrator is gone.
fn sweep_stale_temp() {
    let Ok(dir) = fs::read_dir(std::env::temp_dir()) else {
        return;
    };
    for e in dir.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name.strip_prefix("gridswarm-") else {
            continue;
        };
        let Some(end) = rest.find('_') else { continue };
        let prefix = &rest[..=end];
        if let Some(owner) = ipc::prefix_owner(prefix) {
            if owner != std::process::id() && !ipc::pid_alive(owner) {
                let _ = fs::remove_file(e.path());
            }
        }
    }
}

/// Runs once; returns the text for stdout.
pub fn run(opts: &RunOptions) -> Result<String> {
    let done = perform(opts, false)?;
    if opts.json {
        return Ok(format!(
            "{}\n",
            serde_json::to_string(&done.summary).expect("a JSON value serialises")
        ));
    }
    Ok(text_summary(
        &done.scenario,
        &done.result,
        &done.report,
        &done.injections,
        &done.applied,
        &done.summary,
        &done.written,
    ))
}

/// Runs once as a library call and prints nothing: returns the summary
/// object `run --json` prints (and `--out` writes, if set). Warnings that
/// `run` prints to stderr are in the summary's `warnings` array instead.
/// `opts.json` is ignored.
pub fn execute(opts: &RunOptions) -> Result<Value> {
    let done = perform(opts, true)?;
    let mut summary = done.summary;
    summary["warnings"] = json!(done.warnings);
    Ok(summary)
}

/// One run of an experiment, as [`execute`]. `what` names the run (e.g.
/// `run 3 with 2 killed, seed 9`): an error says which run failed, and the
/// run's warnings are added to `warnings` tagged with it.
pub fn execute_as(opts: &RunOptions, what: &str, warnings: &mut Vec<String>) -> Result<Value> {
    let v = execute(opts).map_err(|e| Error::Run(format!("{what}: {e}")))?;
    for w in v["warnings"].as_array().into_iter().flatten().filter_map(Value::as_str) {
        warnings.push(format!("{w} ({what})"));
    }
    Ok(v)
}

/// What one run produced, for [`run`]'s text and [`execute`]'s summary.
struct Done {
    scenario: gridswarm::scenario::Scenario,
    result: gridswarm::outcome::RunResult,
    report: RunReport,
    injections: Vec<Injection>,
    applied: Vec<bool>,
    summary: Value,
    written: Vec<PathBuf>,
    /// Warnings not printed (`quiet`), in order.
    warnings: Vec<String>,
}

/// One run. `quiet`: collect the warnings instead of printing them.
fn perform(opts: &RunOptions, quiet: bool) -> Result<Done> {
    let mut warnings: Vec<String> = Vec::new();
    let mut warn = |w: String| {
        if quiet {
            warnings.push(w);
        } else {
            eprintln!("{w}");
        }
    };
    if !opts.algorithm.on_grid() {
        return Err(Error::Input(format!(
            "`run` drives one process per robot on the grid; `{}` moves off the grid (use `simulate --algorithm {}`)",
            opts.algorithm, opts.algorithm
        )));
    }
    let mut scenario = contract::load_scenario(&opts.scenario)?;
    if let Some(s) = opts.situation {
        scenario.situation = s;
    }
    let robots = opts.robots.unwrap_or(scenario.robots);
    if robots == 0 || robots > ipc::MAX_ROBOTS {
        return Err(Error::Input(format!(
            "robots must be in 1..={}, got {robots}",
            ipc::MAX_ROBOTS
        )));
    }
    let injections = schedule(opts, robots)?;
    if let Some(dir) = &opts.out {
        crate::output::create_dir(dir)?;
    }
    let world = scenario.world();
    let starts = contract::start_vertices(&scenario, &world, robots)?;
    for w in check::warnings(&contract::check_assumptions(&scenario, &world, &starts)) {
        warn(w);
    }
    let world_bin = launch::binary("world-server").map_err(run_err)?;
    let agent_bin = launch::binary("robot-agent").map_err(run_err)?;

    let prefix = ipc::new_prefix();
    let config = ipc::config(&prefix).map_err(run_err)?;
    let root = ipc::root_dir(&config);
    // What SIGKILLed orchestrators left behind.
    ipc::sweep_stale(&root);
    sweep_stale_temp();

    let (tx, rx) = mpsc::channel();
    launch::forward_signals(tx.clone()).map_err(run_err)?;
    let tmp = std::env::temp_dir();
    let mut procs = Processes {
        world: None,
        agents: Vec::with_capacity(robots),
        report: tmp.join(format!("gridswarm-{prefix}report.json")),
        agent_log: tmp.join(format!("gridswarm-{prefix}agents.log")),
        prefix: prefix.clone(),
        root,
    };
    let mut pauses: BTreeSet<u32> = injections.iter().map(|i| i.round).collect();
    pauses.extend(injections.iter().filter_map(|i| i.wake));
    let pause_list: Vec<String> = pauses.iter().map(|r| r.to_string()).collect();
    let situation = scenario.situation.number().to_string();
    let common = [
        "--scenario".to_string(),
        opts.scenario.clone(),
        "--algorithm".into(),
        opts.algorithm.name().into(),
        "--robots".into(),
        robots.to_string(),
        "--seed".into(),
        opts.seed.to_string(),
        "--situation".into(),
        situation,
    ];

    let started = Instant::now();
    let mut cmd = Command::new(&world_bin);
    cmd.arg("--prefix")
        .arg(&prefix)
        .args(&common)
        .arg("--max-rounds")
        .arg(opts.max_rounds.to_string())
        .arg("--suspect-ms")
        .arg(SUSPECT_MS.to_string())
        .arg("--report")
        .arg(&procs.report)
        .arg("--progress")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit());
    if !pause_list.is_empty() {
        cmd.arg("--pause-at").arg(pause_list.join(","));
    }
    launch::guard(&mut cmd);
    let mut child = cmd
        .spawn()
        .map_err(|e| run_err(format!("cannot start {}: {e}", world_bin.display())))?;
    let world_pid = child.id();
    let mut world_in = child.stdin.take().expect("piped");
    launch::read_lines(child.stdout.take().expect("piped"), tx);
    procs.world = Some(child);

    // The world's verdict on its own end, once its stdout closes.
    let world_died = |procs: &mut Processes, round: Option<u32>| -> Error {
        let status = procs.world.as_mut().and_then(|w| w.wait().ok());
        let how = status
            .map(launch::describe)
            .unwrap_or_else(|| "unknown status".into());
        let when = match round {
            Some(k) => format!("in round {k}"),
            None => "before it was ready".into(),
        };
        procs.abort();
        let verb = if how.starts_with("signal") {
            "died"
        } else {
            "failed"
        };
        run_err(format!("world-server {verb} ({how}) {when}"))
    };
    let interrupted = |procs: &mut Processes, sig: i32| -> Error {
        procs.abort();
        let name = if sig == libc::SIGINT {
            "SIGINT"
        } else {
            "SIGTERM"
        };
        run_err(format!("interrupted by {name}: stopped the world-server and every robot-agent, removed the run's files"))
    };

    // Until `ready`, the world is building the world and the services.
    loop {
        match rx.recv() {
            Ok(Event::Line(l)) if l == "ready" => break,
            Ok(Event::Line(_)) => {}
            Ok(Event::WorldClosed) | Err(_) => return Err(world_died(&mut procs, None)),
            Ok(Event::Signal(s)) => return Err(interrupted(&mut procs, s)),
        }
    }
    let ready_ms = started.elapsed().as_secs_f64() * 1e3;
    let log = fs::File::create(&procs.agent_log).map_err(Error::write(&procs.agent_log))?;
    for i in 0..robots {
        let mut cmd = Command::new(&agent_bin);
        cmd.arg("--prefix")
            .arg(&prefix)
            .arg("--robot")
            .arg(i.to_string())
            .args(&common)
            .arg("--world-pid")
            .arg(world_pid.to_string())
            .args(
                slow(opts)
                    .iter()
                    .filter(|s| s.0 == i)
                    .flat_map(|s| ["--slow-ms".to_string(), s.1.to_string()]),
            )
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(log.try_clone().map_err(Error::write(&procs.agent_log))?);
        launch::guard(&mut cmd);
        match cmd.spawn() {
            Ok(c) => procs.agents.push(c),
            Err(e) => {
                procs.abort();
                return Err(run_err(format!("cannot start robot-agent {i}: {e}")));
            }
        }
    }
    let spawned_ms = started.elapsed().as_secs_f64() * 1e3;

    // Follow the rounds; inject at the pauses.
    let mut round: Option<u32> = None;
    let mut applied: Vec<bool> = vec![false; injections.len()];
    let mut inject_ms: Vec<f64> = vec![0.0; injections.len()];
    loop {
        match rx.recv() {
            Ok(Event::Line(l)) => {
                if l == "done" {
                    break;
                }
                if let Some(k) = l.strip_prefix("tick ").and_then(|k| k.parse().ok()) {
                    round = Some(k);
                } else if let Some(k) = l.strip_prefix("round ").and_then(|k| k.parse::<u32>().ok())
                {
                    round = Some(k);
                    for (n, inj) in injections.iter().enumerate() {
                        let pid = procs.agents[inj.robot].id();
                        if inj.round == k {
                            let sig = match inj.kind {
                                Kind::Kill => libc::SIGKILL,
                                Kind::Freeze => libc::SIGSTOP,
                            };
                            applied[n] = launch::signal(pid, sig);
                            inject_ms[n] = started.elapsed().as_secs_f64() * 1e3;
                        }
                        if inj.wake == Some(k) && applied[n] {
                            launch::signal(pid, libc::SIGCONT);
                        }
                    }
                    // The world must see a stopped robot as stopped before it
                    // goes on: SIGSTOP is delivered asynchronously.
                    for (n, inj) in injections.iter().enumerate() {
                        if inj.round == k && inj.kind == Kind::Freeze && applied[n] {
                            let pid = procs.agents[inj.robot].id();
                            let t = Instant::now();
                            while !ipc::pid_stopped(pid) && t.elapsed() < Duration::from_secs(1) {
                                std::thread::sleep(Duration::from_micros(200));
                            }
                        }
                    }
                    if say(&mut world_in, "go").is_err() {
                        return Err(world_died(&mut procs, round));
                    }
                }
            }
            Ok(Event::WorldClosed) | Err(_) => return Err(world_died(&mut procs, round)),
            Ok(Event::Signal(s)) => return Err(interrupted(&mut procs, s)),
        }
    }
    let run_ms = started.elapsed().as_secs_f64() * 1e3;
    let status = procs.world.as_mut().map(|w| w.wait());
    if let Some(Ok(st)) = status {
        if !st.success() {
            return Err(world_died(&mut procs, round));
        }
    }
    let text = fs::read_to_string(&procs.report)
        .map_err(|e| run_err(format!("cannot read the world's report: {e}")))?;
    let report: RunReport = serde_json::from_str(&text)
        .map_err(|e| run_err(format!("the world's report is malformed: {e}")))?;
    // A frozen robot that was never woken cannot read `End`.
    for (n, inj) in injections.iter().enumerate() {
        if applied[n] && inj.kind == Kind::Freeze {
            let _ = procs.agents[inj.robot].kill();
        }
    }
    let killed_at_end = launch::reap_within(&mut procs.agents, AGENT_GRACE);
    let agent_status: Vec<Option<i32>> = procs
        .agents
        .iter_mut()
        .map(|c| c.try_wait().ok().flatten().and_then(|s| s.code()))
        .collect();
    procs.cleanup();
    // A signal that came while the agents were ending.
    while let Ok(ev) = rx.try_recv() {
        if let Event::Signal(s) = ev {
            return Err(interrupted(&mut procs, s));
        }
    }
    launch::default_signals();
    let leftovers = ipc::run_files(&prefix, &procs.root);
    if !leftovers.is_empty() {
        warn(format!(
            "warning: {} file(s) of run {prefix} could not be removed",
            leftovers.len()
        ));
    }
    let injected_robot = |r: usize| {
        injections
            .iter()
            .zip(&applied)
            .any(|(i, &a)| a && i.robot == r)
    };
    let agent_errors: Vec<usize> = (0..robots)
        .filter(|&r| !injected_robot(r) && agent_status[r] != Some(0))
        .collect();
    if !agent_errors.is_empty() {
        let log = fs::read_to_string(&procs.agent_log).unwrap_or_default();
        warn(format!(
            "warning: robot-agent(s) {:?} did not end cleanly{}",
            agent_errors,
            log.lines()
                .next()
                .map(|l| format!(": {l}"))
                .unwrap_or_default()
        ));
    }

    // The result, in the in-process engine's shape.
    let mut result = report.result.clone();
    let grid = &world.grid;
    result.trajectories = report
        .vertices
        .iter()
        .map(|vs| {
            vs.iter()
                .map(|&v| {
                    let c: Coord = grid.coord(v);
                    Pose {
                        vertex: Some(c),
                        position: grid.position(v),
                    }
                })
                .collect()
        })
        .collect();
    result.round_end_times_s = report.round_end_times_s.clone();

    let go_ms = |k: u32| report.pauses.iter().find(|p| p.round == k).map(|p| p.go_ms);
    let injected: Vec<Value> = injections
        .iter()
        .enumerate()
        .map(|(n, i)| {
            json!({
                "robot": i.robot,
                "round": i.round,
                "kind": i.kind.name(),
                "wake_round": i.wake,
                "applied": applied[n],
            })
        })
        .collect();
    let detected: Vec<Value> = report
        .failures
        .iter()
        .map(|d| {
            let inj = injections
                .iter()
                .enumerate()
                .find(|(n, i)| i.robot == d.robot as usize && applied[*n]);
            let (round, delay_rounds, delay_ms) = match inj {
                Some((_, i)) => (
                    Some(i.round),
                    Some(d.round as i64 - i.round as i64),
                    go_ms(i.round).map(|g| ((d.at_ms - g) * 1e3).round() / 1e3),
                ),
                None => (None, None, None),
            };
            json!({
                "robot": d.robot,
                "round": d.round,
                "at": d.at,
                "cause": d.cause,
                "detected_by": d.detected_by,
                "at_ms": d.at_ms,
                "injected_round": round,
                "delay_rounds": delay_rounds,
                "delay_ms": delay_ms,
            })
        })
        .collect();
    let wall = &report.round_wall_ms;
    let rss: Vec<f64> = report
        .agent_peak_rss_kib
        .iter()
        .filter(|&&k| k > 0)
        .map(|&k| k as f64)
        .collect();
    let extra = json!({
        "engine": "distributed",
        "ipc_prefix": prefix,
        "max_rounds": opts.max_rounds,
        "suspect_ms": SUSPECT_MS,
        "failures_injected": injected,
        "failures_detected": detected,
        "refused_moves": report.refused_moves,
        "dropped_messages": {
            "stale": report.dropped.stale,
            "malformed": report.dropped.malformed,
            "spoofed": report.dropped.spoofed,
            "unexpected": report.dropped.unexpected,
            "total": report.dropped.total(),
        },
        "round_wall_ms": {
            "p50": percentile(wall, 50.0),
            "p99": percentile(wall, 99.0),
            "max": percentile(wall, 100.0),
        },
        "exchange_wall_ms_p50": percentile(&report.exchange_wall_ms, 50.0),
        "choice_wall_ms_p50": percentile(&report.choice_wall_ms, 50.0),
        "chain_p50": percentile(&report.chain.iter().map(|&c| c as f64).collect::<Vec<_>>(), 50.0),
        "startup_ms": {
            "world_ready": ready_ms,
            "agents_spawned": spawned_ms,
            "all_hello": report.startup_ms,
        },
        "run_wall_ms": run_ms,
        "world_fds": report.world_fds,
        "world_peak_rss_kib": report.world_peak_rss_kib,
        "agent_peak_rss_kib": {
            "p50": percentile(&rss, 50.0),
            "max": percentile(&rss, 100.0),
        },
        "agents_killed_at_end": killed_at_end,
        "world_cpu_ms_per_round": report.world_cpu_ms / f64::from(report.result.rounds.max(1)),
        "agent_cpu_ms_total": report.agent_cpu_ms.iter().sum::<f64>(),
        "ended_by": report.ended_by,
    });

    let record = RunRecord {
        scenario: &scenario,
        world: &world,
        starts: &starts,
        lfp: &contract::lfp_params(&scenario),
        result: &result,
        extra,
    };
    let summary = record.summary();
    let written = match &opts.out {
        Some(dir) => rundir::write_run_dir(dir, &record)?,
        None => Vec::new(),
    };
    Ok(Done {
        scenario,
        result,
        report,
        injections,
        applied,
        summary,
        written,
        warnings,
    })
}

fn text_summary(
    scenario: &gridswarm::scenario::Scenario,
    result: &gridswarm::outcome::RunResult,
    report: &RunReport,
    injections: &[Injection],
    applied: &[bool],
    summary: &Value,
    written: &[PathBuf],
) -> String {
    let mut text = crate::output::headline(
        scenario,
        result,
        ": one process per robot",
        &format!("refused moves {}; ", report.refused_moves),
    );
    let ms = |v: &Value| {
        v.as_f64()
            .map(|x| format!("{x:.3}"))
            .unwrap_or_else(|| "-".into())
    };
    text += &format!(
        "wall time per round: p50 {} ms, p99 {} ms; start-up {:.0} ms; dropped messages {}\n",
        ms(&summary["round_wall_ms"]["p50"]),
        ms(&summary["round_wall_ms"]["p99"]),
        summary["startup_ms"]["all_hello"].as_f64().unwrap_or(0.0),
        report.dropped.total()
    );
    for (n, i) in injections.iter().enumerate() {
        let wake = i
            .wake
            .map(|w| format!(", woken in round {w}"))
            .unwrap_or_default();
        let done = if applied[n] {
            ""
        } else {
            " (not applied: the search ended first)"
        };
        text += &format!(
            "injected: {} robot {} in round {}{wake}{done}\n",
            i.kind.name(),
            i.robot,
            i.round
        );
    }
    for d in &report.failures {
        text += &format!(
            "detected: robot {} failed in round {} ({}), at [{}, {}], told {:?}\n",
            d.robot, d.round, d.cause, d.at[0], d.at[1], d.detected_by
        );
    }
    for p in written {
        text += &format!("wrote {}\n", p.display());
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts() -> RunOptions {
        RunOptions::for_experiment("paper".into(), Policy::Repulsive, 13, 7, Situation::One, 0, 100)
    }

    #[test]
    fn random_kills_are_reproducible_distinct_and_in_range() {
        let mut o = opts();
        o.kill_random = 5;
        o.faults = vec![sim::schedule::parse_kill("0@3").unwrap()];
        let a = schedule(&o, 13).unwrap();
        assert_eq!(a, schedule(&o, 13).unwrap());
        assert_eq!(a.len(), 6);
        let robots: BTreeSet<usize> = a.iter().map(|i| i.robot).collect();
        assert_eq!(robots.len(), 6);
        o.seed = 8;
        assert_ne!(a, schedule(&o, 13).unwrap());
        o.kill_random = 13;
        assert!(schedule(&o, 13).is_err(), "only 12 left");
        let mut o = opts();
        o.radio.loss = 0.1;
        assert!(schedule(&o, 13).is_err(), "no radio in this build");
    }

    #[test]
    fn percentiles() {
        assert_eq!(percentile(&[], 50.0), None);
        assert_eq!(percentile(&[3.0, 1.0, 2.0], 50.0), Some(2.0));
        assert_eq!(percentile(&[3.0, 1.0, 2.0], 99.0), Some(3.0));
        assert_eq!(percentile(&[5.0], 99.0), Some(5.0));
    }
}
