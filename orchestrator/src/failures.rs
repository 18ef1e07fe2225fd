//! `gridswarm experiment failures`: distributed runs (`gridswarm run`, one
//! process per robot) with 0, 1, 2, ... robots SIGKILLed at random rounds,
//! and what the killing costs: search time, completion, collisions, refused
//! moves, and how long the survivors take to notice.
//!
//! Runs are sequential (each already uses every core). Run `r` with `k`
//! killed has seed `derive(derive(seed, k), r)`; its victims and their rounds
//! are drawn from that seed by [`crate::run::schedule`], so the same seed
//! gives the same runs.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::str::FromStr;
use std::time::Instant;

use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::rng::derive;
use serde_json::{json, Value};

use crate::claims::Verdict;
use crate::error::{Error, Result};
use crate::experiment::progress_bar;
use crate::panels::{self, Panel, Series};
use crate::report::{self, Block, Claim, Report, Section, Table};
use crate::run::{self, RunOptions};
use crate::stats::{mean, sample_std};
use crate::{check, contract, output};

pub const DEFAULT_ROBOTS: u32 = 13;
pub const DEFAULT_KILLED: &str = "0-3";
pub const DEFAULT_RUNS: u32 = 10;
pub const DEFAULT_OUT: &str = "failures-out";

/// Numbers of robots to kill: `0-3`, `2` or `0,2,4`; sorted, distinct.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Killed(pub Vec<usize>);

impl FromStr for Killed {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let num = |t: &str| -> std::result::Result<usize, String> {
            t.trim().parse().map_err(|_| format!("bad --killed `{s}`: `{}` is not a whole number", t.trim()))
        };
        let mut out = Vec::new();
        for part in s.split(',') {
            if part.trim().is_empty() {
                return Err(format!("bad --killed `{s}`: empty item"));
            }
            let (lo, hi) = match part.split_once('-') {
                Some((a, b)) => (num(a)?, num(b)?),
                None => (num(part)?, num(part)?),
            };
            if lo > hi {
                return Err(format!("bad --killed range `{}`: {lo} is greater than {hi}", part.trim()));
            }
            if hi > gridswarm::ipc::MAX_ROBOTS {
                return Err(format!("bad --killed `{s}`: at most {} robots", gridswarm::ipc::MAX_ROBOTS));
            }
            out.extend(lo..=hi);
        }
        out.sort_unstable();
        out.dedup();
        Ok(Killed(out))
    }
}

#[derive(Clone, Debug)]
pub struct FailuresOptions {
    pub scenario: String,
    pub algorithm: Policy,
    /// The scenario's own count when `None`.
    pub robots: Option<usize>,
    pub killed: Vec<usize>,
    pub runs: u32,
    pub seed: u64,
    pub situation: Option<Situation>,
    pub max_rounds: u32,
    pub out: PathBuf,
    pub progress: bool,
}

/// The seed of run `run` with `killed` robots killed.
pub fn run_seed(base: u64, killed: usize, run: u32) -> u64 {
    derive(derive(base, killed as u64), u64::from(run))
}

/// What the experiment keeps of one distributed run.
#[derive(Clone, Debug, PartialEq)]
pub struct FailureRun {
    pub killed: usize,
    pub run: u32,
    pub seed: u64,
    pub complete: bool,
    pub search_time_s: f64,
    pub rounds: u64,
    pub collisions: u64,
    pub refused_moves: u64,
    /// Kills actually applied (a search may end before a kill's round).
    pub injected: usize,
    /// Applied kills the survivors declared.
    pub detected: usize,
    pub delay_rounds: Vec<f64>,
    pub delay_ms: Vec<f64>,
    pub round_wall_p50_ms: Option<f64>,
    pub run_wall_ms: Option<f64>,
}

impl FailureRun {
    /// Reads a run's summary (the object `run --json` prints).
    pub fn from_summary(killed: usize, run: u32, seed: u64, v: &Value) -> Self {
        let u = |x: &Value| x.as_u64().unwrap_or(0);
        let detected: Vec<&Value> = v["failures_detected"]
            .as_array()
            .map(|a| a.iter().filter(|d| !d["injected_round"].is_null()).collect())
            .unwrap_or_default();
        FailureRun {
            killed,
            run,
            seed,
            complete: v["complete"].as_bool().unwrap_or(false),
            search_time_s: v["search_time_s"].as_f64().unwrap_or(f64::NAN),
            rounds: u(&v["rounds"]),
            collisions: u(&v["collisions"]),
            refused_moves: u(&v["refused_moves"]),
            injected: v["failures_injected"]
                .as_array()
                .map(|a| a.iter().filter(|i| i["applied"].as_bool() == Some(true)).count())
                .unwrap_or(0),
            detected: detected.len(),
            delay_rounds: detected.iter().filter_map(|d| d["delay_rounds"].as_f64()).collect(),
            delay_ms: detected.iter().filter_map(|d| d["delay_ms"].as_f64()).collect(),
            round_wall_p50_ms: v["round_wall_ms"]["p50"].as_f64(),
            run_wall_ms: v["run_wall_ms"].as_f64(),
        }
    }
}

/// One row of `failures.csv`: the runs with `killed` robots killed.
#[derive(Clone, Debug, PartialEq)]
pub struct FailureRow {
    pub killed: usize,
    pub runs: usize,
    pub completed_runs: usize,
    pub completion_rate: f64,
    /// Over completed runs.
    pub mean_search_time_s: Option<f64>,
    pub std_search_time_s: Option<f64>,
    pub mean_rounds: Option<f64>,
    /// Over all runs.
    pub mean_collisions: f64,
    pub mean_refused_moves: f64,
    pub injected: usize,
    pub detected: usize,
    /// Over every detected kill of every run.
    pub mean_delay_rounds: Option<f64>,
    pub mean_delay_ms: Option<f64>,
    pub mean_round_wall_p50_ms: Option<f64>,
}

impl FailureRow {
    pub fn of(killed: usize, runs: &[FailureRun]) -> Self {
        let done: Vec<&FailureRun> = runs.iter().filter(|r| r.complete).collect();
        let times: Vec<f64> = done.iter().map(|r| r.search_time_s).collect();
        let all = |f: &dyn Fn(&FailureRun) -> f64| mean(&runs.iter().map(f).collect::<Vec<_>>()).unwrap_or(0.0);
        FailureRow {
            killed,
            runs: runs.len(),
            completed_runs: done.len(),
            completion_rate: if runs.is_empty() { 0.0 } else { done.len() as f64 / runs.len() as f64 },
            mean_search_time_s: mean(&times),
            std_search_time_s: sample_std(&times),
            mean_rounds: mean(&done.iter().map(|r| r.rounds as f64).collect::<Vec<_>>()),
            mean_collisions: all(&|r| r.collisions as f64),
            mean_refused_moves: all(&|r| r.refused_moves as f64),
            injected: runs.iter().map(|r| r.injected).sum(),
            detected: runs.iter().map(|r| r.detected).sum(),
            mean_delay_rounds: mean(&runs.iter().flat_map(|r| r.delay_rounds.iter().copied()).collect::<Vec<_>>()),
            mean_delay_ms: mean(&runs.iter().flat_map(|r| r.delay_ms.iter().copied()).collect::<Vec<_>>()),
            mean_round_wall_p50_ms: mean(&runs.iter().filter_map(|r| r.round_wall_p50_ms).collect::<Vec<_>>()),
        }
    }
}

pub const CSV_HEADER: &str = "killed,runs,completed_runs,completion_rate,mean_search_time_s,std_search_time_s,\
                              mean_rounds,mean_collisions,mean_refused_moves,failures_injected,failures_detected,\
                              mean_detection_delay_rounds,mean_detection_delay_ms,mean_round_wall_p50_ms";

pub fn csv(rows: &[FailureRow]) -> String {
    let n = output::csv_num;
    let mut s = format!("{CSV_HEADER}\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{:.6},{},{},{},{:.6},{:.6},{},{},{},{},{}",
            r.killed,
            r.runs,
            r.completed_runs,
            r.completion_rate,
            n(r.mean_search_time_s),
            n(r.std_search_time_s),
            n(r.mean_rounds),
            r.mean_collisions,
            r.mean_refused_moves,
            r.injected,
            r.detected,
            n(r.mean_delay_rounds),
            n(r.mean_delay_ms),
            n(r.mean_round_wall_p50_ms)
        );
    }
    s
}

pub const RUNS_CSV_HEADER: &str = "killed,run,seed,complete,search_time_s,rounds,collisions,refused_moves,\
                                   failures_injected,failures_detected,mean_detection_delay_rounds,\
                                   mean_detection_delay_ms,round_wall_p50_ms,run_wall_ms";

fn runs_csv(runs: &[FailureRun]) -> String {
    let n = output::csv_num;
    let mut s = format!("{RUNS_CSV_HEADER}\n");
    for r in runs {
        let _ = writeln!(
            s,
            "{},{},{},{},{:.6},{},{},{},{},{},{},{},{},{}",
            r.killed,
            r.run,
            r.seed,
            r.complete,
            r.search_time_s,
            r.rounds,
            r.collisions,
            r.refused_moves,
            r.injected,
            r.detected,
            n(mean(&r.delay_rounds)),
            n(mean(&r.delay_ms)),
            n(r.round_wall_p50_ms),
            n(r.run_wall_ms)
        );
    }
    s
}

fn fmt(x: Option<f64>, d: usize) -> String {
    x.map(|v| format!("{v:.d$}")).unwrap_or_else(|| "-".into())
}

fn table(rows: &[FailureRow]) -> Table {
    Table {
        header: [
            "killed",
            "runs",
            "completed",
            "mean time (s)",
            "std (s)",
            "mean rounds",
            "mean collisions",
            "mean refused moves",
            "detected/injected",
            "delay (rounds)",
            "delay (ms)",
            "round wall p50 (ms)",
        ]
        .map(String::from)
        .to_vec(),
        rows: rows
            .iter()
            .map(|r| {
                vec![
                    r.killed.to_string(),
                    r.runs.to_string(),
                    format!("{}/{}", r.completed_runs, r.runs),
                    fmt(r.mean_search_time_s, 1),
                    fmt(r.std_search_time_s, 1),
                    fmt(r.mean_rounds, 1),
                    format!("{:.2}", r.mean_collisions),
                    format!("{:.2}", r.mean_refused_moves),
                    format!("{}/{}", r.detected, r.injected),
                    fmt(r.mean_delay_rounds, 2),
                    fmt(r.mean_delay_ms, 1),
                    fmt(r.mean_round_wall_p50_ms, 3),
                ]
            })
            .collect(),
    }
}

/// The table as aligned text for the terminal.
pub fn text_table(t: &Table) -> String {
    let cols = t.header.len();
    let width: Vec<usize> =
        (0..cols).map(|c| t.rows.iter().map(|r| r[c].len()).chain([t.header[c].len()]).max().unwrap_or(0)).collect();
    let mut s = String::new();
    for row in std::iter::once(&t.header).chain(&t.rows) {
        let cells: Vec<String> = row
            .iter()
            .enumerate()
            .map(|(c, x)| if c == 0 { format!("{x:<w$}", w = width[c]) } else { format!("{x:>w$}", w = width[c]) })
            .collect();
        let _ = writeln!(s, "{}", cells.join("  "));
    }
    s
}

fn figure(rows: &[FailureRow], title: &str) -> std::result::Result<String, String> {
    let xs: Vec<f64> = rows.iter().map(|r| r.killed as f64).collect();
    let x = |r: &FailureRow| r.killed as f64;
    let time = Panel::new(
        "Search time (completed runs)",
        "robots killed",
        "mean search time (s), ± std",
        vec![Series::with_err(
            "mean search time",
            rows.iter().map(|r| (x(r), r.mean_search_time_s, r.std_search_time_s)),
        )],
    );
    let mut done = Panel::new(
        "Completion and safety",
        "robots killed",
        "per run",
        vec![
            Series::new("completion rate", rows.iter().map(|r| (x(r), Some(r.completion_rate)))),
            Series::new("mean collisions", rows.iter().map(|r| (x(r), Some(r.mean_collisions)))),
        ],
    );
    let top = rows.iter().map(|r| r.mean_collisions.max(r.completion_rate)).fold(1.0, f64::max);
    done.y_range = Some((0.0, top * 1.35)); // room for the legend above the rate of 1
    let delay = Panel::new(
        "Detection delay",
        "robots killed",
        "mean delay after the kill",
        vec![
            Series::new("ms", rows.iter().map(|r| (x(r), r.mean_delay_ms))),
            Series::new("rounds", rows.iter().map(|r| (x(r), r.mean_delay_rounds))),
        ],
    );
    panels::panels_svg(title, &[time, done, delay], &xs)
}

/// Runs the experiment; returns the rows and the text for stdout.
pub fn run(opts: &FailuresOptions) -> Result<(Vec<FailureRow>, String)> {
    if opts.runs == 0 {
        return Err(Error::Input("--runs must be at least 1".into()));
    }
    if opts.killed.is_empty() {
        return Err(Error::Input("--killed needs at least one count".into()));
    }
    if !opts.algorithm.on_grid() {
        return Err(Error::Input(format!(
            "`experiment failures` runs one process per robot on the grid; `{}` moves off the grid",
            opts.algorithm
        )));
    }
    let mut scenario = contract::load_scenario(&opts.scenario)?;
    if let Some(s) = opts.situation {
        scenario.situation = s;
    }
    let robots = opts.robots.unwrap_or(scenario.robots);
    if robots == 0 || robots > gridswarm::ipc::MAX_ROBOTS {
        return Err(Error::Input(format!("robots must be in 1..={}, got {robots}", gridswarm::ipc::MAX_ROBOTS)));
    }
    if let Some(&k) = opts.killed.iter().find(|&&k| k >= robots) {
        return Err(Error::Input(format!(
            "--killed {k}: the run has {robots} robots, and at least one must survive to search"
        )));
    }
    output::create_dir(&opts.out)?;
    let world = scenario.world();
    let starts = contract::start_vertices(&scenario, &world, robots)?;
    for w in check::warnings(&contract::check_assumptions(&scenario, &world, &starts)) {
        eprintln!("{w}");
    }

    let total = opts.killed.len() * opts.runs as usize;
    let bar = progress_bar(total as u64, opts.progress);
    let started = Instant::now();
    let mut runs: Vec<FailureRun> = Vec::with_capacity(total);
    let mut warnings: Vec<String> = Vec::new();
    for &k in &opts.killed {
        for r in 0..opts.runs {
            let seed = run_seed(opts.seed, k, r);
            let ro = RunOptions::for_experiment(
                opts.scenario.clone(),
                opts.algorithm,
                robots,
                seed,
                scenario.situation,
                k,
                opts.max_rounds,
            );
            let what = format!("run {r} with {k} killed, seed {seed}");
            let v = run::execute_as(&ro, &what, &mut warnings).inspect_err(|_| bar.finish_and_clear())?;
            runs.push(FailureRun::from_summary(k, r, seed, &v));
            bar.inc(1);
        }
    }
    bar.finish_and_clear();
    let wall_time_s = started.elapsed().as_secs_f64();
    for w in &warnings {
        eprintln!("{w}");
    }

    let rows: Vec<FailureRow> = opts
        .killed
        .iter()
        .map(|&k| FailureRow::of(k, &runs.iter().filter(|r| r.killed == k).cloned().collect::<Vec<_>>()))
        .collect();
    let out = &opts.out;
    output::write_text(&out.join("failures.csv"), &csv(&rows))?;
    output::write_text(&out.join("failures-runs.csv"), &runs_csv(&runs))?;
    let title = format!(
        "{}: {} robots, {}, {} runs per point, robots killed at random rounds",
        scenario.name, robots, opts.algorithm, opts.runs
    );
    let svg_path = out.join("failures.svg");
    let svg = figure(&rows, &title).map_err(|message| Error::Plot { path: svg_path.clone(), message })?;
    output::write_text(&svg_path, &svg)?;

    let params = json!({
        "scenario": scenario.name,
        "grid": scenario.grid.name(),
        "situation": scenario.situation.number(),
        "algorithm": opts.algorithm.name(),
        "robots": robots,
        "killed": opts.killed,
        "runs": opts.runs,
        "seed": opts.seed,
        "seed_derivation": "run r with k killed has seed derive(derive(seed, k), r) with gridswarm::rng::derive; \
            its victims and kill rounds (1..=20) are drawn from that seed as by `run --kill-random k`",
        "max_rounds": opts.max_rounds,
        "engine": "distributed: one world-server and one robot-agent process per robot over iceoryx2",
        "statistics": "search time, rounds over completed runs (std n-1); collisions, refused moves, round wall \
            p50 over all runs; detection delay over every detected kill (rounds and ms after the kill's round began)",
        "params": scenario.params,
    });
    let tab = table(&rows);
    let page = Report {
        title: format!("Failures: {} scenario, {} robots", scenario.name, robots),
        subtitle: format!(
            "{} killed, {} runs each, base seed {}; {} distributed runs in {:.1} s wall time",
            crate::robots::compress(&opts.killed).replace('-', "–"),
            opts.runs,
            opts.seed,
            runs.len(),
            wall_time_s
        ),
        sections: vec![
            Section::new(
                "Plots",
                vec![Block::Figure {
                    svg: svg.clone(),
                    caption: "Against the number of robots SIGKILLed at random rounds: mean search time of the \
                              completed runs (bars: one std), completion rate and collisions per run, and how long \
                              after a kill the survivors declared the robot failed."
                        .into(),
                }],
            ),
            Section::new("Checks", vec![Block::Claims(checks(&rows))]),
            Section::new("Results", vec![Block::Table(tab.clone())]),
            Section::new("Runs", vec![Block::Table(runs_table(&runs))]),
            Section::new("Parameters", vec![Block::Params(report::params_of("", &params))]),
            Section::new(
                "Files",
                vec![Block::Files(
                    [
                        ("failures.csv", "the results table"),
                        ("failures-runs.csv", "every run"),
                        ("failures.svg", "the figure"),
                    ]
                    .map(|(a, b)| (a.to_string(), b.to_string()))
                    .to_vec(),
                )],
            ),
        ],
    };
    output::write_text(&out.join("report.html"), &report::render(&page))?;
    let text = format!(
        "failures: scenario {}, {} robots, algorithm {}, {} runs per count, base seed {}\n{}\n\
         {} runs in {wall_time_s:.1} s; wrote failures.csv, failures-runs.csv, failures.svg, report.html in {}\n",
        scenario.name,
        robots,
        opts.algorithm,
        opts.runs,
        opts.seed,
        text_table(&tab),
        runs.len(),
        out.display()
    );
    Ok((rows, text))
}

fn runs_table(runs: &[FailureRun]) -> Table {
    Table {
        header: ["killed", "run", "seed", "complete", "time (s)", "rounds", "collisions", "refused", "detected"]
            .map(String::from)
            .to_vec(),
        rows: runs
            .iter()
            .map(|r| {
                vec![
                    r.killed.to_string(),
                    r.run.to_string(),
                    r.seed.to_string(),
                    r.complete.to_string(),
                    format!("{:.1}", r.search_time_s),
                    r.rounds.to_string(),
                    r.collisions.to_string(),
                    r.refused_moves.to_string(),
                    format!("{}/{}", r.detected, r.injected),
                ]
            })
            .collect(),
    }
}

/// What the distributed protocol promises under failures, checked on the runs.
fn checks(rows: &[FailureRow]) -> Vec<Claim> {
    let verdict = |ok: bool| if ok { Verdict::Holds } else { Verdict::Fails };
    let runs: usize = rows.iter().map(|r| r.runs).sum();
    let collisions: f64 = rows.iter().map(|r| r.mean_collisions * r.runs as f64).sum();
    let (inj, det): (usize, usize) = rows.iter().fold((0, 0), |a, r| (a.0 + r.injected, a.1 + r.detected));
    let done: usize = rows.iter().map(|r| r.completed_runs).sum();
    vec![
        Claim {
            id: "1".into(),
            statement: "No collisions, whatever the number killed.".into(),
            criterion: "zero collisions in every run".into(),
            verdict: verdict(collisions == 0.0),
            evidence: rows
                .iter()
                .map(|r| format!("{} killed: {:.2} collisions per run", r.killed, r.mean_collisions))
                .collect(),
        },
        Claim {
            id: "2".into(),
            statement: "Every killed robot is detected by the survivors.".into(),
            criterion: "detected kills = applied kills".into(),
            verdict: if inj == 0 { Verdict::NotEvaluated } else { verdict(det == inj) },
            evidence: vec![format!("{det} of {inj} applied kills detected")],
        },
        Claim {
            id: "3".into(),
            statement: "The survivors complete the search.".into(),
            criterion: "every run finds every target within the round limit".into(),
            verdict: verdict(done == runs),
            evidence: rows
                .iter()
                .map(|r| format!("{} killed: {}/{} complete", r.killed, r.completed_runs, r.runs))
                .collect(),
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn killed_counts_parse() {
        assert_eq!("0-3".parse::<Killed>().unwrap().0, vec![0, 1, 2, 3]);
        assert_eq!("2,0,2".parse::<Killed>().unwrap().0, vec![0, 2]);
        assert!("3-1".parse::<Killed>().is_err());
        assert!("a".parse::<Killed>().is_err());
        assert!("1,".parse::<Killed>().is_err());
    }

    #[test]
    fn rows_from_summaries() {
        let v = json!({
            "complete": true, "search_time_s": 100.0, "rounds": 10, "collisions": 0, "refused_moves": 2,
            "failures_injected": [{"applied": true}, {"applied": false}],
            "failures_detected": [{"injected_round": 3, "delay_rounds": 1, "delay_ms": 20.0}],
            "round_wall_ms": {"p50": 0.5}, "run_wall_ms": 300.0,
        });
        let a = FailureRun::from_summary(2, 0, 9, &v);
        assert_eq!((a.injected, a.detected, a.refused_moves), (1, 1, 2));
        let mut b = a.clone();
        b.complete = false;
        b.delay_ms = vec![40.0];
        let row = FailureRow::of(2, &[a, b]);
        assert_eq!(row.completion_rate, 0.5);
        assert_eq!(row.mean_search_time_s, Some(100.0));
        assert_eq!(row.mean_delay_ms, Some(30.0));
        let text = csv(&[row]);
        assert_eq!(text.lines().next().unwrap(), CSV_HEADER);
        assert_eq!(text.lines().nth(1).unwrap().split(',').count(), CSV_HEADER.split(',').count());
        assert_ne!(run_seed(1, 0, 0), run_seed(1, 1, 0));
        assert_ne!(run_seed(1, 0, 0), run_seed(1, 0, 1));
    }
}
