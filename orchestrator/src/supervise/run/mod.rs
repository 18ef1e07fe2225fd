//! `gridswarm run`: one search with one OS process per robot: a
//! `world-server` (the simulated world: the same kernel as `simulate`) and
//! N `robot-agent`s over iceoryx2. With the same settings it gives the
//! same trajectories, rounds and numbers as the in-process engine, faults
//! and radio loss included; the world pauses at every fault while the
//! process is signalled ([`inject`]).
//!
//! Sequence: sweep the files of dead runs; pick a fresh iceoryx2 prefix;
//! write the run file and every robot's setup ([`files`]); spawn the
//! world-server, wait for its `ready`; spawn the agents ([`spawn`]); follow
//! the world's stdout (`tick K`, `fault K` → signal → `go`, `done`); read
//! its report; reap the agents; remove every file of the run; write the
//! outputs ([`summary`]). If the world-server dies or says nothing for
//! [`WORLD_SILENCE`], an agent exits with an error (or at all before the
//! first slot: its own line is shown at once, not after the world's
//! hello time-out), or SIGINT, SIGTERM, SIGHUP or SIGQUIT arrives, every
//! child is killed and reaped and the run's files removed before the
//! one-line error. A run the open-file limit cannot hold is refused before
//! anything starts ([`admit`]).

pub mod credentials;
mod files;
mod inject;
mod net;
mod spawn;
mod summary;

use std::path::PathBuf;
use std::sync::mpsc::{self, Receiver};
use std::time::{Duration, Instant};

use gridswarm::agreement::{Agreement, ScenarioId};
use gridswarm::ipc::{self, RunFile, RunReport};
use gridswarm::nofile;
use gridswarm::outcome::{RunConfig, RunResult};
use gridswarm::params::Situation;
use gridswarm::params::{Order, SlotRule};
use gridswarm::policy::Policy;
use gridswarm::scenario::{Scenario, StartRule};
use gridswarm::sim::{self, schedule, Fault};
use gridswarm::world::World;
use serde_json::{json, Value};

use crate::check;
use crate::cli::view::ViewFlags;
use crate::contract;
use crate::error::{Error, Result};
use crate::launch::{self, Event};
use crate::rundir::{self, RunRecord};
use crate::staging::Staging;

pub use files::temp_files;
use files::RunFiles;
pub use net::NetOptions;
use spawn::Processes;
pub use summary::security;

/// How long agents get to exit by themselves after the end.
const AGENT_GRACE: Duration = Duration::from_secs(5);
/// How often the orchestrator looks for agents that exited with an error.
const AGENT_POLL: Duration = Duration::from_millis(100);
/// A world that says nothing this long ends the run: it prints `tick K`
/// every slot and `alive` every second while it waits for robots, so its
/// silence means it is stopped (SIGSTOP) or stuck. Before `ready` (no
/// heartbeat yet) only a world stopped this long does.
pub const WORLD_SILENCE: Duration = Duration::from_secs(10);

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
    /// Overrides the scenario's `params.slot`.
    pub slot: Option<SlotRule>,
    /// Overrides the scenario's `params.order`.
    pub order: Option<Order>,
    /// Faults given explicitly (checked with [`schedule::check`]).
    pub faults: Vec<Fault>,
    /// Crash this many more robots at times drawn from the seed.
    pub kill_random: usize,
    pub out: Option<PathBuf>,
    pub json: bool,
    /// iceoryx2 or zenoh, and where zenoh's processes meet.
    pub net: NetOptions,
    /// Where the robots start (the world-server places them by the same rule).
    pub starts: StartRule,
    /// `--mcap`, `--live`: followed from the world-server's tape.
    pub view: ViewFlags,
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
            slot: None,
            order: None,
            faults: Vec::new(),
            kill_random,
            out: None,
            json: true,
            net: NetOptions::default(),
            starts: StartRule::Fixed,
            view: ViewFlags::default(),
        }
    }
}

/// Runs once; returns the text for stdout and the exit status
/// ([`crate::error::search_status`]).
pub fn run(opts: &RunOptions) -> Result<(String, u8)> {
    let done = perform(opts, false)?;
    let complete = crate::error::search_status(&done.result);
    if opts.json {
        return Ok((format!("{}\n", serde_json::to_string(&done.summary).expect("a JSON value serialises")), complete));
    }
    Ok((summary::text(&done.plan.scenario, &done.result, &done.report, &done.summary, &done.written), complete))
}

/// Refuses a run of `robots` robots whose descriptors the open-file limit
/// cannot hold, raising the soft limit to the hard one first if that is
/// enough (the children inherit it). Experiments call it with their
/// largest count before their first run.
pub fn admit(robots: usize) -> Result<()> {
    let what = format!("a distributed run of {robots} robots");
    nofile::ensure(nofile::needed(robots), &what).map(|_| ()).map_err(Error::Run)
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

/// What a run is, before any process starts.
pub struct Plan {
    pub scenario: Scenario,
    /// The scenario's id, taken before the run's overrides, as the world
    /// and a hand-started agent take it.
    pub scenario_id: ScenarioId,
    pub world: World,
    pub starts: Vec<u32>,
    pub robots: usize,
    /// The settings both engines run with.
    pub cfg: RunConfig,
}

/// Checks the options and builds the run: world, starts, faults.
pub fn plan(opts: &RunOptions) -> Result<Plan> {
    if !opts.algorithm.on_grid() {
        return Err(Error::Usage(format!(
            "`run` drives one process per robot on the grid; `{}` is not a robot program (use `simulate --algorithm {}`)",
            opts.algorithm, opts.algorithm
        )));
    }
    let overrides = Overrides { situation: opts.situation, retries: opts.retries, slot: opts.slot, order: opts.order };
    let (scenario, scenario_id) = overrides.load(&opts.scenario)?;
    let robots = opts.robots.unwrap_or(scenario.robots);
    if robots == 0 || robots > ipc::MAX_ROBOTS {
        let msg = format!("robots must be 1 to {}, got {robots}", ipc::MAX_ROBOTS);
        // Out of range on the command line is a usage error; in a scenario file, the file's.
        return Err(if opts.robots.is_some() { Error::Usage(msg) } else { Error::Scenario(msg) });
    }
    schedule::check(&opts.faults, robots).map_err(Error::Usage)?;
    if opts.net.remote_agents.is_some() && (!opts.faults.is_empty() || opts.kill_random > 0) {
        return Err(Error::Usage(
            "faults are applied by signalling the agents' processes; with --remote-agents the orchestrator has none"
                .into(),
        ));
    }
    opts.net.check()?;
    for (name, p) in [("--loss", opts.radio.loss), ("--dup", opts.radio.dup)] {
        if !(0.0..=1.0).contains(&p) {
            return Err(Error::Usage(format!("{name} {p}: a probability is between 0 and 1")));
        }
    }
    let taken: Vec<usize> = opts.faults.iter().map(|f| f.robot).collect();
    let mut faults = opts.faults.clone();
    faults.extend(schedule::kill_random(opts.seed, robots, opts.kill_random, &taken).map_err(Error::Usage)?);
    let world = scenario.world();
    let starts = contract::starts(&scenario, &world, robots, opts.starts, opts.seed)?;
    let mut cfg = RunConfig::new(opts.algorithm, opts.seed, scenario.situation);
    cfg.max_rounds = opts.max_rounds;
    cfg.radio = opts.radio;
    cfg.faults = faults;
    Ok(Plan { scenario, scenario_id, world, starts, robots, cfg })
}

impl Plan {
    /// The agreement of this run under `key`, as its world holds it.
    pub fn agreement(&self, key: &str) -> Agreement {
        agreement(key, &self.scenario_id, &self.cfg, &self.world, self.robots)
    }
}

/// What a run changes of its scenario's settings (`--situation`,
/// `--retries`, `--slot`, `--order`), the same for the world and for
/// every robot's setup.
#[derive(Clone, Copy, Debug, Default)]
pub struct Overrides {
    pub situation: Option<Situation>,
    pub retries: Option<u32>,
    pub slot: Option<SlotRule>,
    pub order: Option<Order>,
}

impl Overrides {
    /// The scenario `name`, with its id taken before the overrides (as
    /// the world takes it: a file names its own parameters), overridden.
    pub fn load(&self, name: &str) -> Result<(Scenario, ScenarioId)> {
        let mut scenario = contract::load_scenario(name)?;
        let id = ScenarioId::of(&scenario);
        if let Some(s) = self.situation {
            scenario.situation = s;
        }
        contract::needs_targets(&scenario, name)?;
        if let Some(r) = self.retries {
            scenario.params.retries = r;
        }
        if let Some(s) = self.slot {
            scenario.params.slot = s;
        }
        if let Some(o) = self.order {
            scenario.params.order = o;
        }
        Ok((scenario, id))
    }
}

/// The agreement of run `key` of `world` (its scenario `id`) under `cfg`
/// with `team` robots: what the world holds and every robot's setup file
/// presents, derived from a robot's setup as the agent derives it.
pub fn agreement(key: &str, id: &ScenarioId, cfg: &RunConfig, world: &World, team: usize) -> Agreement {
    Agreement::of(key, id.clone(), &cfg.robot_setup(world, 0, team))
}

/// What one run produced, for [`run`]'s text and [`execute`]'s summary.
struct Done {
    plan: Plan,
    result: RunResult,
    report: RunReport,
    summary: Value,
    written: Vec<PathBuf>,
    /// Warnings not printed (`quiet`), in order.
    warnings: Vec<String>,
}

/// What happened while the world ran.
pub struct Followed {
    /// Whether each fault of the schedule was applied to its process.
    pub applied: Vec<bool>,
    pub ready_ms: f64,
    pub spawned_ms: f64,
    pub run_ms: f64,
}

/// One run. `quiet`: collect the warnings instead of printing them.
fn perform(opts: &RunOptions, quiet: bool) -> Result<Done> {
    let mut warnings: Vec<String> = Vec::new();
    let mut warn = |w: String| if quiet { warnings.push(w) } else { eprintln!("{w}") };
    let plan = plan(opts)?;
    admit(plan.robots)?;
    let stage = opts.out.as_deref().map(Staging::begin).transpose()?;
    let report = contract::check_assumptions(&plan.scenario, &plan.world, &plan.starts);
    check::refuse(&report, plan.cfg.policy)?;
    for w in check::warnings(&report) {
        warn(w);
    }
    let world_bin = launch::binary("world-server").map_err(Error::Run)?;
    let agent_bin = match crate::cli::agents::agent_bin() {
        Some(bin) => bin,
        None => launch::binary("robot-agent").map_err(Error::Run)?,
    };

    let prefix = ipc::new_prefix();
    // What SIGKILLed orchestrators left behind.
    ipc::sweep_stale();
    files::sweep_stale();
    let files = RunFiles::create(&prefix)?;
    let run_file = RunFile {
        scenario: opts.scenario.clone(),
        robots: plan.robots,
        retries: opts.retries,
        slot: opts.slot,
        order: opts.order,
        starts: opts.starts,
        config: plan.cfg.clone(),
    };
    files.write(&run_file, &plan.world, &plan.cfg, (&prefix, &plan.scenario_id))?;

    let (tx, rx) = mpsc::channel();
    launch::forward_signals(tx.clone()).map_err(Error::Run)?;
    let mut procs = Processes::new(&prefix);
    let mut launch = opts.net.args(&prefix, &files.dir)?;
    let tape = files.dir.join("world.tape");
    if opts.view.any() {
        launch.world.extend(["--watch".to_string(), tape.display().to_string()]);
    }
    if let Some(hosts) = &launch.own_credentials {
        // Valid for the day: the folder goes with the run.
        credentials::write(&files.dir, &credentials::Order { robots: plan.robots, hosts, days: 1 })?;
    }
    if let Some(key) = &opts.net.remote_agents {
        eprintln!("{}", net::hand_hint(key, opts, &plan));
    }
    let bins = (world_bin.as_path(), agent_bin.as_path());
    let (followed, viewed) = match opts.view.any() {
        true => opts
            .view
            .watching(&plan.world, &plan.starts, &tape, || follow(&mut procs, &files, &plan, bins, &launch, tx, &rx))?,
        false => (follow(&mut procs, &files, &plan, bins, &launch, tx, &rx)?, Vec::new()),
    };
    let report = read_report(&files)?;
    // A robot still frozen cannot read `End`.
    for r in inject::still_frozen(&plan.cfg.faults, &followed.applied) {
        let _ = procs.agents[r].kill();
    }
    let killed_at_end = launch::reap_within(&mut procs.agents, AGENT_GRACE);
    let statuses: Vec<Option<i32>> =
        procs.agents.iter_mut().map(|c| c.try_wait().ok().flatten().and_then(|s| s.code())).collect();
    procs.cleanup();
    // From here a signal ends the command itself (the unfinished folders
    // removed); one that came while the agents were ending is in `rx`.
    launch::default_signals();
    while let Ok(ev) = rx.try_recv() {
        if let Event::Signal(s) = ev {
            return Err(interrupted(&mut procs, s));
        }
    }
    let leftovers = ipc::run_files(&prefix);
    if !leftovers.is_empty() {
        warn(format!("warning: {} file(s) of run {prefix} could not be removed", leftovers.len()));
    }
    for line in procs.world_said() {
        warn(format!("world-server: {line}"));
    }
    if let Some(w) = summary::agent_warning(&plan.cfg, &followed.applied, &statuses, &files.agent_log()) {
        warn(w);
    }
    drop(files);

    let result = summary::result_of(&plan.world, &report);
    let mut extra = summary::extra(&prefix, opts, (&plan, &launch), &report, &followed, killed_at_end);
    extra["provenance"] = crate::provenance::of_run(
        &opts.scenario,
        &plan.world,
        &plan.starts,
        opts.starts,
        opts.seed,
        json!({
            "algorithm": opts.algorithm,
            "robots": plan.robots,
            "situation": plan.scenario.situation.number(),
            "max_rounds": opts.max_rounds,
            "params": plan.world.params,
            "lfp": plan.scenario.lfp,
            "radio": plan.cfg.radio,
            "faults": schedule::to_args(&plan.cfg.faults),
            "transport": extra["transport"],
        }),
    )?;
    let record = RunRecord {
        scenario: &plan.scenario,
        world: &plan.world,
        starts: &plan.starts,
        lfp: &contract::lfp_params(&plan.scenario),
        result: &result,
        extra,
    };
    let summary = record.summary();
    let mut written = match stage {
        Some(stage) => rundir::write_staged(stage, &record)?,
        None => Vec::new(),
    };
    written.extend(viewed);
    Ok(Done { plan, result, report, summary, written, warnings })
}

/// Starts the processes and follows the world until `done`.
fn follow(
    procs: &mut Processes,
    files: &RunFiles,
    plan: &Plan,
    (world_bin, agent_bin): (&std::path::Path, &std::path::Path),
    launch: &net::Launch,
    tx: mpsc::Sender<Event>,
    rx: &Receiver<Event>,
) -> Result<Followed> {
    let started = Instant::now();
    if let Err(e) = procs.start_world(world_bin, files, tx, &launch.world) {
        procs.abort();
        return Err(e);
    }
    // Until `ready`, the world is building the world and the services.
    wait_ready(procs, rx)?;
    let ready_ms = started.elapsed().as_secs_f64() * 1e3;
    // Agents started by hand elsewhere find the world by themselves.
    let here = if launch.agents_here { plan.robots } else { 0 };
    if let Err(e) = procs.start_agents(agent_bin, files, here, &launch.agents) {
        procs.abort();
        return Err(e);
    }
    let spawned_ms = started.elapsed().as_secs_f64() * 1e3;
    let faults = &plan.cfg.faults;
    let mut applied = vec![false; faults.len()];
    let mut watch = Watch { round: None, polled: Instant::now(), heard: Instant::now() };
    loop {
        match next_event(procs, rx, &mut watch)? {
            Ok(Event::Line(l)) if l == "done" => break,
            Ok(Event::Line(l)) => {
                if let Some(k) = l.strip_prefix("tick ").and_then(|k| k.parse().ok()) {
                    watch.round = Some(k);
                } else if let Some(k) = l.strip_prefix("fault ").and_then(|k| k.parse::<usize>().ok()) {
                    if let Some(f) = faults.get(k) {
                        applied[k] = inject::apply(f.kind, &mut procs.agents[f.robot]);
                    }
                    if !procs.go() {
                        return Err(world_died(procs, true, watch.round));
                    }
                    // The world waited for us meanwhile.
                    watch.heard = Instant::now();
                }
            }
            Ok(Event::WorldClosed) | Err(_) => return Err(world_died(procs, true, watch.round)),
            Ok(Event::Signal(s)) => return Err(interrupted(procs, s)),
        }
    }
    let round = watch.round;
    let run_ms = started.elapsed().as_secs_f64() * 1e3;
    if let Some(Ok(st)) = procs.world.as_mut().map(|w| w.wait()) {
        if !st.success() {
            return Err(world_died(procs, true, round));
        }
    }
    Ok(Followed { applied, ready_ms, spawned_ms, run_ms })
}

/// What the orchestrator follows of a live run.
struct Watch {
    /// The world's last `tick`; `None` before the first slot.
    round: Option<u32>,
    /// When the agents were last looked at.
    polled: Instant,
    /// When the world last printed a line.
    heard: Instant,
}

/// The next event; an agent that exited with an error, or exited at all
/// before the first slot, ends the run first, in its own words, and so
/// does a world silent for [`WORLD_SILENCE`].
fn next_event(
    procs: &mut Processes,
    rx: &Receiver<Event>,
    watch: &mut Watch,
) -> Result<std::result::Result<Event, mpsc::RecvError>> {
    loop {
        let ev = match rx.recv_timeout(AGENT_POLL.saturating_sub(watch.polled.elapsed())) {
            Ok(ev) => Some(Ok(ev)),
            Err(mpsc::RecvTimeoutError::Timeout) => None,
            Err(mpsc::RecvTimeoutError::Disconnected) => Some(Err(mpsc::RecvError)),
        };
        if let Some(Ok(Event::Line(_))) = ev {
            watch.heard = Instant::now();
        }
        if watch.polled.elapsed() >= AGENT_POLL {
            watch.polled = Instant::now();
            // Before the first `tick`, the agents have not all said hello.
            if let Some((k, status)) = procs.failed_agent(watch.round.is_none()) {
                // An agent that found its world gone: the world's end is the news.
                if status.code() == Some(ipc::EXIT_WORLD_GONE) && procs.world_exited() {
                    return Err(world_died(procs, true, watch.round));
                }
                return Err(agent_failed(procs, k, status, watch.round));
            }
            if watch.heard.elapsed() >= WORLD_SILENCE {
                return Err(world_silent(procs, watch.round));
            }
        }
        if let Some(ev) = ev {
            return Ok(ev);
        }
    }
}

/// Ends the run on agent `k`'s error exit, with the line it printed.
fn agent_failed(procs: &mut Processes, k: usize, status: std::process::ExitStatus, round: Option<u32>) -> Error {
    let when = match round {
        Some(r) => format!("in round {r}"),
        None => "at start".into(),
    };
    let own = format!("robot-agent {k}: ");
    let said = procs.agent_said(k).map(|l| {
        let l = l.strip_prefix(&own).unwrap_or(&l);
        format!(": {}", l.strip_prefix("error: ").unwrap_or(l))
    });
    let shm = files::shm_note(std::os::unix::process::ExitStatusExt::signal(&status) == Some(libc::SIGBUS));
    procs.abort();
    launch::default_signals();
    let how = launch::describe(status);
    let msg = format!("robot-agent {k} failed {when} ({how}){}{shm}", said.unwrap_or_default());
    // Refused by the world (or its arguments refused): the run's settings
    // do not fit together.
    if status.code() == Some(2) {
        Error::Usage(msg)
    } else {
        Error::Run(msg)
    }
}

/// Waits for the world's `ready`. Building the services of thousands of
/// robots takes a while and prints nothing, so only a world stopped for
/// [`WORLD_SILENCE`] ends the run here.
fn wait_ready(procs: &mut Processes, rx: &Receiver<Event>) -> Result<()> {
    let mut running = Instant::now();
    loop {
        match rx.recv_timeout(AGENT_POLL) {
            Ok(Event::Line(l)) if l == "ready" => return Ok(()),
            Ok(Event::Line(_)) | Err(mpsc::RecvTimeoutError::Timeout) => {}
            Ok(Event::WorldClosed) | Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(world_died(procs, false, None))
            }
            Ok(Event::Signal(s)) => return Err(interrupted(procs, s)),
        }
        if !ipc::pid_stopped(procs.world_pid()) {
            running = Instant::now();
        } else if running.elapsed() >= WORLD_SILENCE {
            return Err(world_silent(procs, None));
        }
    }
}

fn read_report(files: &RunFiles) -> Result<RunReport> {
    let text = std::fs::read_to_string(files.report())
        .map_err(|e| Error::Run(format!("cannot read the world's report: {e}")))?;
    serde_json::from_str(&text).map_err(|e| Error::Run(format!("the world's report is malformed: {e}")))
}

/// The world's verdict on its own end, once its stdout closed (`ready`:
/// after it said `ready`; `round`: its last `tick`).
fn world_died(procs: &mut Processes, ready: bool, round: Option<u32>) -> Error {
    let status = procs.world.as_mut().and_then(|w| w.wait().ok());
    let how = status.map(launch::describe).unwrap_or_else(|| "unknown status".into());
    let when = match round {
        Some(k) => format!("in round {k}"),
        None if ready => "at start".into(),
        None => "before it was ready".into(),
    };
    // Before the run's files go and free the space they held.
    let sigbus = status.is_some_and(|s| std::os::unix::process::ExitStatusExt::signal(&s) == Some(libc::SIGBUS));
    let shm = files::shm_note(sigbus);
    procs.abort();
    launch::default_signals();
    let verb = if how.starts_with("signal") { "died" } else { "failed" };
    // Its own one-line reason, when it gave one.
    let said = procs.world_said();
    let why = said.iter().rev().find_map(|l| l.strip_prefix("error: ")).map(|r| format!(": {r}")).unwrap_or_default();
    // Status 2: it refused an agent that does not agree with its run.
    if status.and_then(|s| s.code()) == Some(2) {
        return Error::Usage(format!("the world-server refused the run{why}"));
    }
    Error::Run(format!("world-server {verb} ({how}) {when}{why}{shm}"))
}

/// Ends the run whose world said nothing for [`WORLD_SILENCE`].
fn world_silent(procs: &mut Processes, round: Option<u32>) -> Error {
    let pid = procs.world_pid();
    let how = if ipc::pid_stopped(pid) { "is stopped (SIGSTOP?) and " } else { "" };
    let when = match round {
        Some(k) => format!("in round {k}"),
        None => "at start".into(),
    };
    procs.abort();
    launch::default_signals();
    Error::Run(format!(
        "world-server (pid {pid}) {how}has said nothing for {} s {when}: stopped it and every robot-agent, \
         removed the run's shared-memory files",
        WORLD_SILENCE.as_secs()
    ))
}

fn interrupted(procs: &mut Processes, sig: i32) -> Error {
    procs.abort();
    launch::default_signals();
    let name = launch::signal_name(sig);
    Error::Run(format!("interrupted by {name}: stopped the world-server and every robot-agent, removed the run's shared-memory files (results written so far are kept)"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridswarm::sim::FaultKind;

    fn opts() -> RunOptions {
        let mut o = RunOptions::for_experiment("paper".into(), Policy::Repulsive, 13, 7, Situation::Two, 0, 100);
        o.json = false;
        o
    }

    #[test]
    fn faults_are_checked_and_random_kills_added() {
        let mut o = opts();
        o.faults = vec![schedule::parse_kill("0@3").unwrap()];
        o.kill_random = 5;
        let p = plan(&o).unwrap();
        assert_eq!(p.cfg.faults.len(), 6);
        assert_eq!(p.cfg.faults, plan(&o).unwrap().cfg.faults, "reproducible");
        assert!(p.cfg.faults[1..].iter().all(|f| f.robot != 0 && f.kind == FaultKind::Crash));
        o.kill_random = 13;
        assert!(plan(&o).is_err(), "only 12 left");
        let mut o = opts();
        o.faults = vec![schedule::parse_kill("13@1").unwrap()];
        assert!(plan(&o).is_err());
        o.algorithm = Policy::Lfp;
        assert!(plan(&o).is_err());
        o.algorithm = Policy::Oracle;
        assert!(plan(&o).is_err_and(|e| e.to_string().contains("`oracle` is not a robot program")));
        let mut o = opts();
        o.retries = Some(2);
        assert_eq!(plan(&o).unwrap().world.params.retries, 2);
    }
}
