//! `gridswarm experiment scale`: distributed runs (one process per robot)
//! at growing robot counts: wall time per round, start-up, memory and
//! descriptors, next to the in-process engine timed on the same runs (same
//! scenario, robots, seed and algorithm, so the same search).
//!
//! Runs are sequential (each distributed run already uses every core). Run
//! `r` with `N` robots has seed `derive(derive(seed, N), r)`.

use crate::seeds::run_seed;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use gridswarm::outcome::RunConfig;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;
use gridswarm::world::World;
use serde_json::{json, Value};

use crate::contract::{self, Runner};
use crate::error::{Error, Result};
use crate::experiment::Times;
use crate::failures::text_table;
use crate::panels::{self, Panel, Series};
use crate::progress::phase as progress_bar;
use crate::report::{self, Block, Report, Section, Table};
use crate::run::{self, RunOptions};
use crate::staging::Staging;
use crate::stats::median;
use crate::{check, output};

pub const DEFAULT_ROBOTS: &str = "13,50,100,200";
pub const DEFAULT_RUNS: u32 = 1;
pub const DEFAULT_OUT: &str = "scale-out";
/// The scenario for counts above the paper's 13 robots, unless `--scenario` says otherwise.
pub const LARGE: &str = "large";
/// The in-process engine is timed over repeats of the run until this much wall time has passed.
const INPROC_MIN_WALL: Duration = Duration::from_millis(200);

#[derive(Clone, Debug)]
pub struct ScaleOptions {
    pub robots: Vec<usize>,
    pub runs: u32,
    pub seed: u64,
    /// `paper` up to 13 robots and `large` above when `None`.
    pub scenario: Option<String>,
    pub algorithm: Policy,
    pub situation: Option<Situation>,
    /// `--max-rounds`; else each count's round budget ([`crate::budget`]).
    pub max_rounds: Option<u32>,
    pub out: PathBuf,
    pub progress: bool,
    /// What carries the runs' messages (the bench compares both).
    pub transport: gridswarm::transport::Transport,
}

/// The scenario of a robot count.
pub fn scenario_for(opts: &ScaleOptions, robots: usize) -> String {
    match &opts.scenario {
        Some(s) => s.clone(),
        None if robots <= 13 => "paper".into(),
        None => LARGE.into(),
    }
}

/// One distributed run and the in-process engine on the same run.
#[derive(Clone, Debug, PartialEq)]
pub struct ScaleRun {
    pub robots: usize,
    pub scenario: String,
    pub run: u32,
    pub seed: u64,
    pub complete: bool,
    pub rounds: u64,
    pub round_wall_p50_ms: Option<f64>,
    pub round_wall_p99_ms: Option<f64>,
    /// From the orchestrator's start until the world-server is ready.
    pub world_ready_ms: Option<f64>,
    /// From the orchestrator's start until every agent is spawned.
    pub agents_spawned_ms: Option<f64>,
    /// Until every agent said hello, on the world-server's clock (from its start).
    pub hello_ms: Option<f64>,
    pub run_wall_ms: Option<f64>,
    pub agent_rss_max_kib: Option<f64>,
    pub agent_rss_p50_kib: Option<f64>,
    pub world_rss_kib: Option<f64>,
    pub world_fds: Option<f64>,
    /// Frames handed to the radio, and wake-ups, per robot per round.
    pub messages_per_robot_round: Option<f64>,
    pub wakeups_per_robot_round: Option<f64>,
    pub inproc_rounds: u64,
    pub inproc_ms_per_round: f64,
}

impl ScaleRun {
    pub fn ratio(&self) -> Option<f64> {
        self.round_wall_p50_ms.filter(|_| self.inproc_ms_per_round > 0.0).map(|d| d / self.inproc_ms_per_round)
    }
}

/// Means over the runs of one robot count.
#[derive(Clone, Debug, PartialEq)]
pub struct ScaleRow {
    pub robots: usize,
    pub scenario: String,
    pub runs: usize,
    pub completed_runs: usize,
    pub rounds: Option<f64>,
    pub round_wall_p50_ms: Option<f64>,
    pub round_wall_p99_ms: Option<f64>,
    pub inproc_ms_per_round: Option<f64>,
    pub ratio: Option<f64>,
    pub world_ready_ms: Option<f64>,
    pub agents_spawned_ms: Option<f64>,
    pub hello_ms: Option<f64>,
    pub agent_rss_max_kib: Option<f64>,
    pub agent_rss_p50_kib: Option<f64>,
    pub world_rss_kib: Option<f64>,
    pub world_fds: Option<f64>,
    pub messages_per_robot_round: Option<f64>,
    pub wakeups_per_robot_round: Option<f64>,
    /// Whether the in-process engine took the same number of rounds in every run.
    pub same_rounds: bool,
}

impl ScaleRow {
    pub fn of(robots: usize, scenario: &str, runs: &[ScaleRun]) -> Self {
        // Medians: one slow run on a shared machine should not move the row.
        let m = |f: &dyn Fn(&ScaleRun) -> Option<f64>| median(&runs.iter().filter_map(f).collect::<Vec<_>>());
        let p50 = m(&|r| r.round_wall_p50_ms);
        let inproc = m(&|r| Some(r.inproc_ms_per_round));
        ScaleRow {
            robots,
            scenario: scenario.to_string(),
            runs: runs.len(),
            completed_runs: runs.iter().filter(|r| r.complete).count(),
            rounds: m(&|r| Some(r.rounds as f64)),
            round_wall_p50_ms: p50,
            round_wall_p99_ms: m(&|r| r.round_wall_p99_ms),
            inproc_ms_per_round: inproc,
            ratio: p50.zip(inproc).filter(|&(_, i)| i > 0.0).map(|(d, i)| d / i),
            world_ready_ms: m(&|r| r.world_ready_ms),
            agents_spawned_ms: m(&|r| r.agents_spawned_ms),
            hello_ms: m(&|r| r.hello_ms),
            agent_rss_max_kib: m(&|r| r.agent_rss_max_kib),
            agent_rss_p50_kib: m(&|r| r.agent_rss_p50_kib),
            world_rss_kib: m(&|r| r.world_rss_kib),
            world_fds: m(&|r| r.world_fds),
            messages_per_robot_round: m(&|r| r.messages_per_robot_round),
            wakeups_per_robot_round: m(&|r| r.wakeups_per_robot_round),
            same_rounds: runs.iter().all(|r| r.rounds == r.inproc_rounds),
        }
    }
}

pub const CSV_HEADER: &str = "robots,scenario,runs,completed_runs,median_rounds,round_wall_p50_ms,round_wall_p99_ms,\
                              inproc_ms_per_round,ratio_p50_to_inproc,world_ready_ms,agents_spawned_ms,hello_ms,\
                              agent_peak_rss_max_kib,agent_peak_rss_p50_kib,world_peak_rss_kib,world_fds,\
                              messages_per_robot_round,wakeups_per_robot_round,inproc_same_rounds";

pub fn csv(rows: &[ScaleRow]) -> String {
    let n = output::csv_num;
    let mut s = format!("{CSV_HEADER}\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.robots,
            r.scenario,
            r.runs,
            r.completed_runs,
            n(r.rounds),
            n(r.round_wall_p50_ms),
            n(r.round_wall_p99_ms),
            n(r.inproc_ms_per_round),
            n(r.ratio),
            n(r.world_ready_ms),
            n(r.agents_spawned_ms),
            n(r.hello_ms),
            n(r.agent_rss_max_kib),
            n(r.agent_rss_p50_kib),
            n(r.world_rss_kib),
            n(r.world_fds),
            n(r.messages_per_robot_round),
            n(r.wakeups_per_robot_round),
            r.same_rounds
        );
    }
    s
}

pub const RUNS_CSV_HEADER: &str = "robots,scenario,run,seed,complete,rounds,round_wall_p50_ms,round_wall_p99_ms,\
                                   inproc_rounds,inproc_ms_per_round,agents_spawned_ms,hello_ms,run_wall_ms,\
                                   agent_peak_rss_max_kib,agent_peak_rss_p50_kib,world_peak_rss_kib,world_fds,\
                                   messages_per_robot_round,wakeups_per_robot_round";

fn runs_csv(runs: &[ScaleRun]) -> String {
    let n = output::csv_num;
    let mut s = format!("{RUNS_CSV_HEADER}\n");
    for r in runs {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{:.6},{},{},{},{},{},{},{},{},{}",
            r.robots,
            r.scenario,
            r.run,
            r.seed,
            r.complete,
            r.rounds,
            n(r.round_wall_p50_ms),
            n(r.round_wall_p99_ms),
            r.inproc_rounds,
            r.inproc_ms_per_round,
            n(r.agents_spawned_ms),
            n(r.hello_ms),
            n(r.run_wall_ms),
            n(r.agent_rss_max_kib),
            n(r.agent_rss_p50_kib),
            n(r.world_rss_kib),
            n(r.world_fds),
            n(r.messages_per_robot_round),
            n(r.wakeups_per_robot_round)
        );
    }
    s
}

fn table(rows: &[ScaleRow]) -> Table {
    let f = |x: Option<f64>, d: usize| x.map(|v| format!("{v:.d$}")).unwrap_or_else(|| "-".into());
    let mib = |x: Option<f64>| f(x.map(|k| k / 1024.0), 1);
    Table {
        header: [
            "robots",
            "scenario",
            "runs",
            "rounds",
            "round p50 (ms)",
            "round p99 (ms)",
            "in-process (ms/round)",
            "p50 / in-process",
            "agents spawned (ms)",
            "all hello (ms)",
            "agent RSS max (MiB)",
            "agent RSS p50 (MiB)",
            "world RSS (MiB)",
            "world fds",
            "messages/robot/round",
            "wake-ups/robot/round",
        ]
        .map(String::from)
        .to_vec(),
        rows: rows
            .iter()
            .map(|r| {
                vec![
                    r.robots.to_string(),
                    r.scenario.clone(),
                    format!("{}/{}", r.completed_runs, r.runs),
                    f(r.rounds, 0),
                    f(r.round_wall_p50_ms, 3),
                    f(r.round_wall_p99_ms, 3),
                    f(r.inproc_ms_per_round, 4),
                    f(r.ratio, 0),
                    f(r.agents_spawned_ms, 0),
                    f(r.hello_ms, 0),
                    mib(r.agent_rss_max_kib),
                    mib(r.agent_rss_p50_kib),
                    mib(r.world_rss_kib),
                    f(r.world_fds, 0),
                    f(r.messages_per_robot_round, 2),
                    f(r.wakeups_per_robot_round, 2),
                ]
            })
            .collect(),
    }
}

fn figure(rows: &[ScaleRow], title: &str) -> std::result::Result<String, String> {
    let xs: Vec<f64> = rows.iter().map(|r| r.robots as f64).collect();
    let x = |r: &ScaleRow| r.robots as f64;
    let robots = x_desc(rows);
    let mut wall = Panel::new(
        "Wall time per round (log scale)",
        &robots,
        "ms per round",
        vec![
            Series::new("distributed p50", rows.iter().map(|r| (x(r), r.round_wall_p50_ms))),
            Series::new("distributed p99", rows.iter().map(|r| (x(r), r.round_wall_p99_ms))),
            Series::new("in-process (median)", rows.iter().map(|r| (x(r), r.inproc_ms_per_round))),
        ],
    );
    wall.log_y = true;
    let mib = |v: Option<f64>| v.map(|k| k / 1024.0);
    let mem = Panel::new(
        "Peak memory (RSS)",
        &robots,
        "MiB",
        vec![
            Series::new("agent max", rows.iter().map(|r| (x(r), mib(r.agent_rss_max_kib)))),
            Series::new("agent p50", rows.iter().map(|r| (x(r), mib(r.agent_rss_p50_kib)))),
            Series::new("world-server", rows.iter().map(|r| (x(r), mib(r.world_rss_kib)))),
        ],
    );
    let startup = Panel::new(
        "Start-up",
        &robots,
        "ms after start",
        vec![
            Series::new("world-server ready", rows.iter().map(|r| (x(r), r.world_ready_ms))),
            Series::new("every agent spawned", rows.iter().map(|r| (x(r), r.agents_spawned_ms))),
            Series::new("every hello (world-server's clock)", rows.iter().map(|r| (x(r), r.hello_ms))),
        ],
    );
    panels::panels_svg(title, &[wall, mem, startup], &xs)
}

/// "robots", and on which map each count ran when the map changes along
/// the axis (N = 13 on `paper`, larger counts on `large`).
fn x_desc(rows: &[ScaleRow]) -> String {
    let mut runs: Vec<(String, Vec<usize>)> = Vec::new();
    for r in rows {
        match runs.last_mut() {
            Some((name, ns)) if *name == r.scenario => ns.push(r.robots),
            _ => runs.push((r.scenario.clone(), vec![r.robots])),
        }
    }
    if runs.len() <= 1 {
        return "robots".into();
    }
    let parts: Vec<String> = runs.iter().map(|(name, ns)| format!("{name}: {}", crate::robots::compress(ns))).collect();
    format!("robots (map changes: {})", parts.join("; "))
}

/// The in-process engine on the same run, timed: (rounds, ms per round).
/// Short runs are repeated until [`INPROC_MIN_WALL`] has passed.
fn time_in_process(
    world: &World,
    scenario: &Scenario,
    starts: &[gridswarm::grid::VertexId],
    cfg: &RunConfig,
) -> (u64, f64) {
    let runner = Runner::new(world, contract::lfp_params(scenario));
    let t = Instant::now();
    let mut repeats = 0u32;
    let mut rounds = 0;
    while repeats == 0 || t.elapsed() < INPROC_MIN_WALL {
        rounds = u64::from(runner.run(starts, cfg).rounds);
        repeats += 1;
    }
    let ms = t.elapsed().as_secs_f64() * 1e3 / f64::from(repeats);
    (rounds, ms / rounds.max(1) as f64)
}

/// Each count's round budget and its rule (`null` under `--max-rounds`).
fn budget_json(opts: &ScaleOptions, budgets: &[(usize, u32)]) -> Value {
    if opts.max_rounds.is_some() {
        return Value::Null;
    }
    let per_count: Vec<Value> =
        opts.robots.iter().zip(budgets).map(|(n, (va, b))| json!({ "robots": n, "va": va, "rounds": b })).collect();
    json!({ "rule": crate::budget::rule(), "per_count": per_count })
}

/// Runs the experiment; returns the rows and the text for stdout.
pub fn run(opts: &ScaleOptions) -> Result<(Vec<ScaleRow>, String)> {
    // The command's clock, for the wall time it prints.
    let command = Instant::now();
    if opts.runs == 0 {
        return Err(Error::Usage("--runs must be at least 1".into()));
    }
    if opts.robots.is_empty() {
        return Err(Error::Usage("--robots needs at least one count".into()));
    }
    if !opts.algorithm.on_grid() {
        return Err(Error::Usage(format!(
            "`experiment scale` runs one process per robot on the grid; `{}` moves off the grid",
            opts.algorithm
        )));
    }
    if let Some(&n) = opts.robots.iter().find(|&&n| n == 0 || n > gridswarm::ipc::MAX_ROBOTS) {
        return Err(Error::Usage(format!("--robots must be 1 to {}, got {n}", gridswarm::ipc::MAX_ROBOTS)));
    }
    crate::run::admit(opts.robots.iter().copied().max().unwrap_or(1))?;
    // Every scenario loaded and every count placed before the first run.
    let mut worlds: BTreeMap<String, (Scenario, World)> = BTreeMap::new();
    let mut starts = Vec::with_capacity(opts.robots.len());
    for &n in &opts.robots {
        let name = scenario_for(opts, n);
        if !worlds.contains_key(&name) {
            let mut s = contract::load_scenario(&name)?;
            if let Some(sit) = opts.situation {
                s.situation = sit;
            }
            contract::needs_targets(&s, &name)?;
            let w = s.world();
            worlds.insert(name.clone(), (s, w));
        }
        let (s, w) = &worlds[&name];
        let st = contract::start_vertices(s, w, n)?;
        for warning in check::warnings(&contract::check_assumptions(s, w, &st)) {
            eprintln!("{warning} ({name}, {n} robots)");
        }
        starts.push(st);
    }
    // Each count's round budget, blind to the algorithm (crate::budget).
    let budgets: Vec<(usize, u32)> = (opts.robots.iter().zip(&starts))
        .map(|(&n, st)| crate::budget::rounds(&worlds[&scenario_for(opts, n)].1, st))
        .collect();
    let limits: Vec<u32> = budgets.iter().map(|b| opts.max_rounds.unwrap_or(b.1)).collect();
    // Before any run: an unwritable --out fails now, not after the runs.
    let stage = Staging::begin(&opts.out)?;

    let total = opts.robots.len() * opts.runs as usize;
    let bar = progress_bar(total as u64, opts.progress);
    let started = Instant::now();
    let mut runs: Vec<ScaleRun> = Vec::with_capacity(total);
    let mut warnings = Vec::new();
    for (i, &n) in opts.robots.iter().enumerate() {
        let name = scenario_for(opts, n);
        let (scenario, world) = &worlds[&name];
        for r in 0..opts.runs {
            let seed = run_seed(opts.seed, n, u64::from(r));
            let mut ro =
                RunOptions::for_experiment(name.clone(), opts.algorithm, n, seed, scenario.situation, 0, limits[i]);
            ro.net.transport = opts.transport;
            let what = format!("run {r} with {n} robots, seed {seed}");
            let v = run::execute_as(&ro, &what, &mut warnings).inspect_err(|_| bar.finish_and_clear())?;
            let mut cfg = RunConfig::new(opts.algorithm, seed, scenario.situation);
            cfg.max_rounds = limits[i];
            cfg.record_trajectories = false;
            cfg.measure_coverage = false;
            let (inproc_rounds, inproc_ms_per_round) = time_in_process(world, scenario, &starts[i], &cfg);
            let g = |p: &str| v.pointer(p).and_then(Value::as_f64);
            runs.push(ScaleRun {
                robots: n,
                scenario: name.clone(),
                run: r,
                seed,
                complete: v["complete"].as_bool().unwrap_or(false),
                rounds: v["rounds"].as_u64().unwrap_or(0),
                round_wall_p50_ms: g("/round_wall_ms/p50"),
                round_wall_p99_ms: g("/round_wall_ms/p99"),
                world_ready_ms: g("/startup_ms/world_ready"),
                agents_spawned_ms: g("/startup_ms/agents_spawned"),
                hello_ms: g("/startup_ms/all_hello"),
                run_wall_ms: g("/run_wall_ms"),
                agent_rss_max_kib: g("/agent_peak_rss_kib/max"),
                agent_rss_p50_kib: g("/agent_peak_rss_kib/p50"),
                world_rss_kib: g("/world_peak_rss_kib"),
                world_fds: g("/world_fds"),
                messages_per_robot_round: g("/messages_per_robot_round"),
                wakeups_per_robot_round: g("/wakeups_per_robot_round"),
                inproc_rounds,
                inproc_ms_per_round,
            });
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    let wall_time_s = started.elapsed().as_secs_f64();
    for w in &warnings {
        eprintln!("{w}");
    }

    let rows: Vec<ScaleRow> = opts
        .robots
        .iter()
        .map(|&n| {
            let of_n: Vec<ScaleRun> = runs.iter().filter(|r| r.robots == n).cloned().collect();
            ScaleRow::of(n, &scenario_for(opts, n), &of_n)
        })
        .collect();
    let out = &stage.path().to_path_buf();
    output::write_text(&out.join("scale.csv"), &csv(&rows))?;
    output::write_text(&out.join("scale-runs.csv"), &runs_csv(&runs))?;
    let scen_names: Vec<&str> = worlds.keys().map(String::as_str).collect();
    let title = format!(
        "Scaling: {} ({}), {} run(s) per count, one process per robot vs in-process",
        opts.algorithm,
        scen_names.join(", "),
        opts.runs
    );
    let svg_path = out.join("scale.svg");
    let svg = figure(&rows, &title).map_err(|message| Error::Plot { path: svg_path.clone(), message })?;
    output::write_text(&svg_path, &svg)?;

    let threads = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1);
    let params = json!({
        "robots": opts.robots,
        "scenarios": opts.robots.iter().map(|&n| format!("{n}: {}", scenario_for(opts, n))).collect::<Vec<_>>(),
        "algorithm": opts.algorithm.name(),
        "runs": opts.runs,
        "seed": opts.seed,
        "seed_derivation": "run r with N robots has seed derive(derive(seed, N), r) with gridswarm::rng::derive",
        "situation": opts.situation.map(|s| s.number().to_string()).unwrap_or_else(|| "the scenario's".into()),
        "max_rounds": limits.iter().max(),
        "round_budget": budget_json(opts, &budgets),
        "cores": threads,
        "transport": super::sweep::Engine::Distributed.transport(),
        "distributed": "one world-server and one robot-agent process per robot over iceoryx2; round wall time \
            p50/p99 over the rounds of a run, as the world-server measures it; peak RSS from /proc",
        "in_process": format!(
            "gridswarm::engine on the same scenario, robots, seed and algorithm in this process, one thread, \
             no trajectories or coverage recorded; repeated until {} ms passed; wall time / rounds",
            INPROC_MIN_WALL.as_millis()
        ),
        "statistics": "medians over the runs of each count",
    });
    let tab = table(&rows);
    let mut notes = Vec::new();
    if rows.iter().any(|r| !r.same_rounds) {
        notes.push(Block::Text(
            "note: for some counts the in-process engine took a different number of rounds than the distributed \
             run; the two should agree without failures, so compare those rows with care."
                .into(),
        ));
    }
    let mut page = Report {
        title: "Scaling: one process per robot".into(),
        subtitle: format!(
            "robots {}, {} run(s) each, base seed {}, {} cores; the {} distributed runs took {:.1} s of wall time",
            opts.robots.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(", "),
            opts.runs,
            opts.seed,
            threads,
            runs.len(),
            wall_time_s
        ),
        sections: vec![
            Section::new(
                "Plots",
                vec![Block::Figure {
                    svg: svg.clone(),
                    caption: "Against the number of robots: wall time per round of the distributed engine \
                              (median and 99th percentile over a run's rounds) and of the in-process engine on the \
                              same run; peak resident memory of the agents and the world-server; start-up (on the orchestrator's clock from \
                              the run's start, except the hellos, timed by the world-server from its own start)."
                        .into(),
                }],
            ),
            Section::new("Results", notes.into_iter().chain([Block::Table(tab.clone())]).collect()),
            Section::new("Parameters", vec![Block::Params(report::params_of("", &params))]),
            Section::new(
                "Files",
                vec![Block::Files(
                    [("scale.csv", "the results table"), ("scale-runs.csv", "every run"), ("scale.svg", "the figure")]
                        .map(|(a, b)| (a.to_string(), b.to_string()))
                        .to_vec(),
                )],
            ),
        ],
    };
    let record = crate::provenance::Record {
        scenario_arg: opts.scenario.as_deref(),
        parameters: params.clone(),
        seeds: json!({ "base": opts.seed }),
        starts: json!({ "rule": "fixed" }),
    };
    crate::provenance::stamp(out, &mut page, &record)?;
    output::write_text(&out.join("report.html"), &report::render(&page))?;
    stage.commit()?;
    let text = format!(
        "scale: algorithm {}, robots {}, {} run(s) each, base seed {}\n{}\n\
         {} runs; {}; wrote scale.csv, scale-runs.csv, scale.svg, report.html, provenance.json in {}\n",
        opts.algorithm,
        opts.robots.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(","),
        opts.runs,
        opts.seed,
        text_table(&tab),
        runs.len(),
        Times { command_s: command.elapsed().as_secs_f64(), runs_s: wall_time_s },
        opts.out.display()
    );
    Ok((rows, text))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run_of(n: usize, p50: f64, inproc: f64) -> ScaleRun {
        ScaleRun {
            robots: n,
            scenario: "paper".into(),
            run: 0,
            seed: 1,
            complete: true,
            rounds: 10,
            round_wall_p50_ms: Some(p50),
            round_wall_p99_ms: Some(p50 * 2.0),
            world_ready_ms: Some(80.0),
            agents_spawned_ms: Some(100.0),
            hello_ms: Some(50.0),
            run_wall_ms: Some(400.0),
            agent_rss_max_kib: Some(5000.0),
            agent_rss_p50_kib: Some(4000.0),
            world_rss_kib: Some(6000.0),
            world_fds: Some(90.0),
            messages_per_robot_round: Some(4.0),
            wakeups_per_robot_round: Some(3.0),
            inproc_rounds: 10,
            inproc_ms_per_round: inproc,
        }
    }

    #[test]
    fn rows_and_csv() {
        let row = ScaleRow::of(5, "paper", &[run_of(5, 1.0, 0.01), run_of(5, 3.0, 0.03)]);
        assert_eq!(row.round_wall_p50_ms, Some(2.0));
        assert!((row.ratio.unwrap() - 100.0).abs() < 1e-9);
        assert!(row.same_rounds);
        let text = csv(&[row]);
        assert_eq!(text.lines().next().unwrap(), CSV_HEADER);
        assert_eq!(text.lines().nth(1).unwrap().split(',').count(), CSV_HEADER.split(',').count());
    }

    #[test]
    fn scenario_by_count() {
        let mut o = ScaleOptions {
            robots: vec![13, 14],
            runs: 1,
            seed: 1,
            scenario: None,
            algorithm: Policy::Repulsive,
            situation: None,
            max_rounds: Some(10),
            out: PathBuf::from("x"),
            progress: false,
            transport: Default::default(),
        };
        assert_eq!(scenario_for(&o, 13), "paper");
        assert_eq!(scenario_for(&o, 14), "large");
        o.scenario = Some("open".into());
        assert_eq!(scenario_for(&o, 200), "open");
    }
}
