//! `gridswarm experiment`: the Monte Carlo sweep of Fig. 7. Every run of
//! every (algorithm, robot count) goes through one rayon pool; each run's
//! seed depends only on the base seed and its cell and index ([`seeds`]),
//! and results are collected in run order, so every file the sweep writes
//! is the same whatever the thread count. With `--maps K` the sweep runs on
//! K random maps ([`maps`]) and pools their runs; every file says which map
//! a number comes from.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::time::Instant;

use gridswarm::grid::VertexId;
use gridswarm::outcome::RunConfig;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::scenario::{Scenario, StartRule};
use gridswarm::world::World;
use rayon::prelude::*;
use serde_json::json;

use crate::budget::Budgets;
use crate::claims::{self, ClaimResult};
use crate::contract::{self, Runner};
use crate::curves::{self, Curve};
use crate::error::{Error, Result};
use crate::layouts::Layouts;
use crate::maps;
use crate::progress::phase as progress_bar;
use crate::robots::compress;
use crate::seeds::run_seed;
use crate::sensitivity;
use crate::staging::Staging;
use crate::stats::{CellMetrics, CellStats, Estimate, Measured, RunRecord};
use crate::{check, metrics, output, plot, provenance, report};

/// The algorithms of Fig. 7, in its legend's order.
pub const DEFAULT_ALGORITHMS: &str = "lfp,ru,sequential,repulsive";
pub const DEFAULT_ROBOTS: &str = "1-13";
pub const DEFAULT_RUNS: u32 = 500;
pub const DEFAULT_OUT: &str = "experiment-out";

#[derive(Clone, Debug)]
pub struct ExperimentOptions {
    pub scenario: String,
    pub algorithms: Vec<Policy>,
    pub robots: Vec<usize>,
    pub runs: u32,
    pub seed: u64,
    pub situation: Option<Situation>,
    pub out: PathBuf,
    /// Every run's round limit; `None`: each cell's round budget ([`budget`]).
    pub max_rounds: Option<u32>,
    /// Show a progress bar (only sensible when stderr is a terminal).
    pub progress: bool,
    /// Average over this many random maps (`scenario` must be `random:...`).
    pub maps: Option<u32>,
    /// Print every claim's evidence, not only its verdict (claims.txt has it always).
    pub verbose: bool,
    /// Where the robots start: the scenario's layout, or drawn per run.
    pub starts: StartRule,
    /// `--set`: scenario keys to sweep over, every combination of their values.
    pub set: Vec<crate::settings::Setting>,
}

impl ExperimentOptions {
    /// The paper's Fig. 7: its four algorithms, 1 to 13 robots on `paper`,
    /// `runs` runs a cell (500 in the paper), quiet; files go to `out`.
    pub fn fig7(runs: u32, out: PathBuf) -> Self {
        ExperimentOptions {
            scenario: "paper".into(),
            algorithms: DEFAULT_ALGORITHMS.split(',').map(|a| a.parse().expect("known algorithm")).collect(),
            robots: (1..=13).collect(),
            runs,
            seed: 1,
            situation: None,
            out,
            max_rounds: None,
            progress: false,
            maps: None,
            verbose: false,
            starts: StartRule::Fixed,
            set: Vec::new(),
        }
    }
}

/// Everything a sweep produced.
pub struct Sweep {
    pub cells: Vec<CellStats>,
    pub claims: Vec<ClaimResult>,
    pub wall_time_s: f64,
    /// Rounds times robots, summed over every run: the engine's unit of work.
    pub robot_rounds: u64,
}

/// Whether to draw a progress bar: only for a person watching a terminal.
pub fn stderr_is_terminal() -> bool {
    std::io::stderr().is_terminal()
}

pub fn run(opts: &ExperimentOptions) -> Result<(Sweep, String)> {
    // The command's clock: the printed wall time covers the maps, the
    // references, the readings and the files, not only the runs.
    let started = Instant::now();
    if opts.runs == 0 {
        return Err(Error::Input("--runs must be at least 1".into()));
    }
    let mut algorithms: Vec<Policy> = Vec::new();
    for &p in &opts.algorithms {
        if !algorithms.contains(&p) {
            algorithms.push(p);
        }
    }
    if algorithms.is_empty() || opts.robots.is_empty() {
        return Err(Error::Input("the sweep needs at least one algorithm and one robot count".into()));
    }
    let mut maps = maps::resolve(&opts.scenario, opts.maps)?;
    for m in &mut maps {
        if let Some(s) = opts.situation {
            m.scenario.situation = s;
        }
        contract::needs_targets(&m.scenario, &opts.scenario)?;
    }
    if !opts.set.is_empty() {
        return crate::set_sweep::run(opts, &algorithms, &maps, started);
    }
    // Before any run, so a bad directory fails at once.
    let stage = Staging::begin(&opts.out)?;
    let part = Part::compute(opts, &algorithms, &maps)?;
    let Part { scenario, cells, claims, refs, wall_time_s, robot_rounds, .. } = &part;
    let several = opts.maps.is_some();
    let spreads = maps::spreads(&part.per_map);
    let maps_line = if several { maps::summary_line(&maps) } else { String::new() };
    let spread_note = if several { format!("{}\n", crate::spread::one_line(&spreads)) } else { String::new() };
    let setup = part.setup(opts, &maps);
    let text = format!(
        "{}{}{}{spread_note}\n{}{}\n",
        if opts.verbose { setup.clone() } else { short_setup(scenario, opts, maps.len()) + &maps_line },
        table(cells, refs),
        refs.note(),
        part.incomplete_note(),
        part.shown_claims(opts),
    );
    // Every file goes into a staging folder renamed into place at the end;
    // if a write fails the table is still shown, then the error.
    let out = &stage.path().to_path_buf();
    let write = || -> Result<()> {
        let map_cells: &[Vec<CellStats>] = if several { &part.per_map } else { &[] };
        output::write_text(&out.join("results.csv"), &results_csv(cells, map_cells, refs))?;
        output::write_file(&out.join("runs.csv"), |w| part.plan().write_runs_csv(w, &part.records))?;
        output::write_text(&out.join("coverage.csv"), &curves::csv(&part.curves))?;
        let map_rows = maps::rows(&maps);
        if several {
            output::write_text(&out.join("maps.csv"), &maps::csv(&map_rows))?;
        }
        let svg = part.svg(out, &fig_title(scenario, opts, maps.len()))?;
        output::write_text(&out.join("fig7.svg"), &svg)?;
        output::write_text(&out.join("claims.txt"), &format!("{setup}\n{}", part.claims_text(opts)))?;
        let mut summary = part.summary(opts);
        summary[provenance::KEY] = provenance_of(opts, &summary)?;
        if several {
            summary["maps"] = json!(map_rows);
            summary["map_derivation"] = json!(
                "map k is the scenario named with seed SEED + k; run k of a cell on map m \
            has the seed of run m * runs + k"
            );
            summary["per_map_spread"] = json!(spreads);
        }
        output::write_json(&out.join("summary.json"), &summary)?;
        let page = report::fig7(&report::Fig7Inputs {
            summary: &summary,
            cells,
            claims,
            fig7_svg: &svg,
            incomplete_note: &part.incomplete_note(),
            wall_time_s: *wall_time_s,
            threads: rayon::current_num_threads(),
            runs_total: part.records.len(),
            refs,
            extra: [Some(part.metrics_section(out)?), report::sensitivity_section(&part.readings)]
                .into_iter()
                .flatten()
                .chain(if several { crate::spread::sections(&maps, &map_rows, &spreads) } else { Vec::new() })
                .chain([provenance::section(&summary[provenance::KEY])])
                .collect(),
        });
        output::write_text(&out.join("report.html"), &report::render(&page))
    };
    write().and_then(|()| stage.commit()).inspect_err(|_| print!("{text}"))?;
    let times = Times { command_s: started.elapsed().as_secs_f64(), runs_s: *wall_time_s };
    let text = text + &ran_line(part.records.len(), times, several, &opts.out);
    let sweep =
        Sweep { cells: cells.clone(), claims: claims.clone(), wall_time_s: *wall_time_s, robot_rounds: *robot_rounds };
    Ok((sweep, text))
}

/// A sweep's wall times: the whole command's, and the part of it its runs took.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Times {
    pub command_s: f64,
    pub runs_s: f64,
}

impl std::fmt::Display for Times {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:.2} s wall time ({:.2} s of it running the sweep's runs)", self.command_s, self.runs_s)
    }
}

/// The last line of the printed text: what ran, how long the command took,
/// and what was written.
pub(crate) fn ran_line(runs: usize, times: Times, several: bool, out: &std::path::Path) -> String {
    format!(
        "{runs} runs; {times} on {} threads; \
         wrote results.csv, runs.csv, coverage.csv, {}fig7.svg, claims.txt, summary.json, report.html in {}\n",
        rayon::current_num_threads(),
        if several { "maps.csv, " } else { "" },
        out.display()
    )
}

/// The figure's title.
pub(crate) fn fig_title(scenario: &Scenario, opts: &ExperimentOptions, maps: usize) -> String {
    if opts.maps.is_some() {
        format!(
            "{} random maps from {}: mean search time of {} runs",
            maps,
            output::shown(&scenario.name),
            opts.runs * maps as u32
        )
    } else {
        format!("{}: mean search time of {} runs", output::shown(&scenario.name), opts.runs)
    }
}

/// One sweep's numbers (every algorithm and robot count, on every map of
/// one scenario setting), before any file is written.
pub(crate) struct Part {
    /// The first map's scenario.
    pub scenario: Scenario,
    pub algorithms: Vec<Policy>,
    pub robots: Vec<usize>,
    pub starts: Layouts,
    pub maps: usize,
    pub runs: usize,
    /// Every run, in the plan's order.
    pub records: Vec<RunRecord>,
    pub per_map: Vec<Vec<CellStats>>,
    pub cells: Vec<CellStats>,
    /// Each cell's coverage against time, over every map.
    pub curves: Vec<Curve>,
    pub claims: Vec<ClaimResult>,
    /// The same claims judged on each run's last find instead of its end
    /// (situation 1 only; empty otherwise).
    pub claims_at_last_find: Vec<ClaimResult>,
    /// The oracle's means and the lower bounds.
    pub refs: crate::refs::Refs,
    pub readings: Vec<sensitivity::Row>,
    /// Every run's round limit.
    pub budgets: Budgets,
    pub wall_time_s: f64,
    pub robot_rounds: u64,
}

impl Part {
    /// Runs the sweep on `maps` (their scenarios as given, already set).
    pub fn compute(opts: &ExperimentOptions, algorithms: &[Policy], maps: &[maps::Map]) -> Result<Part> {
        let scenario = maps[0].scenario.clone();
        let worlds: Vec<World> = maps.iter().map(|m| m.scenario.world()).collect();
        let fixed =
            maps.iter().zip(&worlds).map(|(m, w)| place(&m.scenario, w, &opts.robots)).collect::<Result<Vec<_>>>()?;
        let budgets = Budgets::new(opts.max_rounds, &worlds, &fixed);
        let pairs: Vec<(&Scenario, &World)> = maps.iter().map(|m| &m.scenario).zip(&worlds).collect();
        let starts = Layouts::new(opts.starts, &pairs, &opts.robots, fixed, (opts.seed, opts.runs as usize))?;

        let started = Instant::now();
        let plan =
            Plan { algorithms, robots: &opts.robots, starts: &starts, maps: maps.len(), runs: opts.runs as usize };
        let runners: Vec<Runner> =
            maps.iter().zip(&worlds).map(|(m, w)| Runner::new(w, contract::lfp_params(&m.scenario))).collect();
        let records = plan.execute(&runners, scenario.situation, opts, &budgets);
        let wall_time_s = started.elapsed().as_secs_f64();

        let per_map: Vec<Vec<CellStats>> = records
            .chunks(plan.per_map())
            .map(|m| plan.cells().zip(m.chunks(plan.runs)).map(|((p, r), c)| CellStats::of(p, r, c)).collect())
            .collect();
        let pooled = plan.pooled_runs(&records);
        let per_cell: Vec<&[RunRecord]> = pooled.iter().map(|c| &c[..]).collect();
        let cells: Vec<CellStats> =
            plan.cells().zip(&per_cell).map(|((p, r), runs)| CellStats::of(p, r, runs)).collect();
        let curves = curves::curves(&plan.cells().collect::<Vec<_>>(), &per_cell);
        let robot_rounds =
            plan.jobs().iter().zip(&records).map(|(j, x)| x.rounds as u64 * opts.robots[j.2] as u64).sum();
        // Paired run by run: run k of every algorithm shares its seed and map.
        let claims = claims::evaluate(&cells, &per_cell);
        let claims_at_last_find = if scenario.situation == Situation::One {
            claims_at_last_find(plan.cells(), &per_cell)
        } else {
            Vec::new()
        };
        let (oracle, oracle_runs) = oracle_reference(&plan, &runners, &cells, scenario.situation, (opts, &budgets));
        let bound = crate::refs::bounds(&worlds, &starts, &opts.robots, plan.runs, algorithms, scenario.situation);
        let refs = crate::refs::Refs { oracle, oracle_runs, cell_runs: plan.runs * maps.len(), bound };
        // On the first map, the sweep's first runs under the other readings.
        let first_limits = budgets.first_map();
        let sweep = sensitivity::Sweep {
            scenario: &maps[0].scenario,
            world: &worlds[0],
            robots: &opts.robots,
            starts: &starts,
            seed: opts.seed,
            max_rounds: &first_limits,
        };
        let first = plan.runs.min(sensitivity::RUNS);
        let readings = sensitivity::run(&sweep, algorithms, first, |p, r| {
            let a = algorithms.iter().position(|&q| q == p)?;
            // Map 0's runs of the cell come first in the sweep's records.
            let cell = &records[(a * opts.robots.len() + r) * plan.runs..][..first];
            let done: Vec<f64> = cell.iter().filter(|x| x.complete).map(|x| x.search_time_s).collect();
            (!done.is_empty()).then(|| done.iter().sum::<f64>() / done.len() as f64)
        });
        Ok(Part {
            scenario,
            algorithms: algorithms.to_vec(),
            robots: opts.robots.clone(),
            starts,
            maps: maps.len(),
            runs: opts.runs as usize,
            records,
            per_map,
            cells,
            curves,
            claims,
            claims_at_last_find,
            refs,
            readings,
            budgets,
            wall_time_s,
            robot_rounds,
        })
    }

    fn plan(&self) -> Plan<'_> {
        Plan {
            algorithms: &self.algorithms,
            robots: &self.robots,
            starts: &self.starts,
            maps: self.maps,
            runs: self.runs,
        }
    }

    /// runs.csv's text.
    pub fn runs_csv(&self) -> String {
        let mut w = Vec::new();
        self.plan().write_runs_csv(&mut w, &self.records).expect("writing to memory");
        String::from_utf8(w).expect("runs.csv is text")
    }

    /// Every parameter of the setting, for claims.txt and `--verbose`.
    pub fn setup(&self, opts: &ExperimentOptions, maps: &[maps::Map]) -> String {
        let scenario = &self.scenario;
        let several = opts.maps.is_some();
        let maps_line = if several { maps::summary_line(maps) } else { String::new() };
        format!(
            "scenario {} ({} grid), situation {}, {} runs per cell{}, base seed {}, max {}, {} starts\n\
             {maps_line}params: {}\nlfp: {}\n",
            output::shown(&scenario.name),
            scenario.grid.name(),
            scenario.situation.number(),
            opts.runs,
            if several {
                format!(" and map ({} runs per cell in all)", opts.runs as usize * maps.len())
            } else {
                String::new()
            },
            opts.seed,
            self.budgets.text(),
            opts.starts,
            serde_json::to_string(&scenario.params).expect("params serialise"),
            serde_json::to_string(&contract::lfp_params(scenario)).expect("lfp params serialise"),
        )
    }

    /// The claims as claims.txt has them, with the incomplete note: at
    /// the search's end, then at the last find.
    pub fn claims_text(&self, _opts: &ExperimentOptions) -> String {
        let mut text = self.incomplete_note() + &claims::render(&self.claims);
        if !self.claims_at_last_find.is_empty() {
            text += &format!("\n{LAST_FIND_HEADING}\n{}", claims::render(&self.claims_at_last_find));
        }
        text
    }

    /// Which cells had runs that hit their round limit.
    pub fn incomplete_note(&self) -> String {
        incomplete_note(&self.cells, &self.budgets.text())
    }

    /// The claims as the terminal shows them; at the last find, one line.
    pub fn shown_claims(&self, opts: &ExperimentOptions) -> String {
        let mut text = if opts.verbose { claims::render(&self.claims) } else { claims::render_short(&self.claims) };
        if !self.claims_at_last_find.is_empty() {
            let verdicts: Vec<String> =
                self.claims_at_last_find.iter().map(|c| format!("({}) {}", c.id, c.verdict.word())).collect();
            text += &format!("Measured at the last find instead: {}\n", verdicts.join(", "));
        }
        text
    }

    /// Draws fig7.svg (not written).
    pub fn svg(&self, out: &std::path::Path, title: &str) -> Result<String> {
        plot::fig7_svg(&self.cells, &self.algorithms, title)
            .map_err(|message| Error::Plot { path: out.join("fig7.svg"), message })
    }

    /// The report's section of the runs' metrics: coverage against time,
    /// the times to the targets, and what each robot spent.
    pub fn metrics_section(&self, out: &std::path::Path) -> Result<report::Section> {
        let plot = |svg: std::result::Result<String, String>, name: &str| {
            svg.map_err(|message| Error::Plot { path: out.join(name), message })
        };
        let name = output::shown(&self.scenario.name);
        let cov = plot(
            metrics::coverage_svg(
                &self.curves,
                &self.algorithms,
                &self.robots,
                &format!("{name}: coverage against time"),
            ),
            "report.html (coverage)",
        )?;
        let targets = plot(
            metrics::targets_svg(&self.cells, &self.algorithms, &format!("{name}: time to the k-th target")),
            "report.html (targets)",
        )?;
        let effort = plot(
            metrics::effort_svg(&self.cells, &self.algorithms, &format!("{name}: what the robots spent")),
            "report.html (effort)",
        )?;
        use report::Block::Figure;
        Ok(report::Section::new(
            "Metrics of the runs",
            vec![
                Figure {
                    svg: cov,
                    caption: "Mean detected fraction of Ad of the completed runs against simulated time, with its \
                              95% interval as a band; a run counts its final fraction after its end (coverage.csv)."
                        .into(),
                },
                Figure {
                    svg: targets,
                    caption: "Mean time at which the k-th target was first found, with 95% intervals (completed runs \
                              that found k targets)."
                        .into(),
                },
                Figure {
                    svg: effort,
                    caption: "Per robot: metres driven (a back-off's return included), turns to a new direction, \
                              frames handed to the radio and their bytes as encoded (grid policies: LFP has no \
                              radio); per run: collisions; and the time the detected fraction first reached one \
                              half. Means of the completed runs with 95% intervals (results.csv)."
                        .into(),
                },
            ],
        ))
    }

    /// summary.json without its provenance.
    pub fn summary(&self, opts: &ExperimentOptions) -> serde_json::Value {
        let scenario = &self.scenario;
        json!({
            "scenario": scenario.name,
            "grid": scenario.grid.name(),
            "situation": scenario.situation.number(),
            "algorithms": self.algorithms.iter().map(|p| p.name()).collect::<Vec<_>>(),
            "robots": opts.robots,
            "runs": opts.runs,
            "seed": opts.seed,
            "seed_derivation": "run k with N robots has seed derive(derive(seed, N), k) with gridswarm::rng::derive, \
                the same for every algorithm (common random numbers: claims compare runs pairwise)",
            "max_rounds": self.budgets.max(),
            "round_budget": self.budgets.json(&self.robots),
            "starts": opts.starts,
            "start_derivation": START_NOTE,
            "transport": super::sweep::Engine::InProcess.transport(),
            "params": scenario.params,
            "lfp": contract::lfp_params(scenario),
            "statistics": "mean, std (n-1), ci95 = 1.96 std / sqrt(n), median, rounds and collisions over completed \
                runs; mean_targets_found over all runs",
            "cells": self.cells,
            "oracle_reference_s": self.refs.oracle,
            "oracle_reference": ORACLE_NOTE,
            "references": self.refs.json(),
            "sensitivity": self.readings,
            "claims": self.claims,
            "claims_at_last_find": self.claims_at_last_find,
            "claims_measures": CLAIMS_MEASURES,
        })
    }
}
/// The sweep's provenance, its parameters as `summary` has them.
pub(crate) fn provenance_of(opts: &ExperimentOptions, summary: &serde_json::Value) -> Result<serde_json::Value> {
    let mut parameters = json!({ "maps": opts.maps });
    for k in ["algorithms", "robots", "runs", "situation", "max_rounds", "params", "lfp"] {
        parameters[k] = summary[k].clone();
    }
    // A `--set` grid: its keys and values (each combination's own
    // parameters are in summary.json's `combinations`).
    if let Some(set) = summary.get("set") {
        parameters["set"] = set.clone();
    }
    provenance::Record {
        scenario_arg: Some(&opts.scenario),
        parameters,
        seeds: json!({ "base": opts.seed, "derivation": summary["seed_derivation"] }),
        starts: json!({ "rule": opts.starts, "derivation": START_NOTE }),
    }
    .value()
}

/// How `--starts` places the robots, for summary.json.
pub const START_NOTE: &str = "fixed: the scenario's [starts] for every run; random: run k draws distinct vertices \
    from its own seed (on the border when the scenario starts there, else anywhere the fixed layout reaches), \
    the same layout for every algorithm";

/// How the oracle's reference times are made, for summary.json and reports.
pub const ORACLE_NOTE: &str = "the oracle (a centralized planner that knows the map, not the targets) at each \
    robot count: its cell when the sweep runs it, else the first 10 runs per map on the same seeds and starts, \
    an estimate when the cells have more runs (references.oracle_estimate)";

/// Runs of the oracle per map made only for the reference (it takes about
/// 10 ms a run, the robots a fraction of that).
const ORACLE_REFERENCE_RUNS: usize = 10;

/// The oracle's mean search time at each robot count, and the runs per
/// robot count it rests on: from the sweep when it ran the oracle, else
/// from a few runs of its own.
fn oracle_reference(
    plan: &Plan,
    runners: &[Runner],
    cells: &[CellStats],
    situation: Situation,
    (opts, budgets): (&ExperimentOptions, &Budgets),
) -> (BTreeMap<usize, f64>, usize) {
    if plan.algorithms.contains(&Policy::Oracle) {
        let means = cells
            .iter()
            .filter(|c| c.algorithm == Policy::Oracle)
            .filter_map(|c| Some((c.robots, c.mean_search_time_s?)))
            .collect();
        return (means, plan.runs * runners.len());
    }
    let runs = plan.runs.min(ORACLE_REFERENCE_RUNS);
    let jobs: Vec<(usize, usize, usize)> = (0..runners.len())
        .flat_map(|m| (0..plan.robots.len()).flat_map(move |r| (0..runs).map(move |k| (m, r, k))))
        .collect();
    // Counted in the progress lines, drawn as no bar of its own.
    let bar = progress_bar(jobs.len() as u64, false);
    let times: Vec<(usize, Option<f64>)> = jobs
        .par_iter()
        .map(|&(m, r, k)| {
            let seed = run_seed(opts.seed, plan.robots[r], (m * plan.runs + k) as u64);
            let mut cfg = RunConfig::new(Policy::Oracle, seed, situation);
            cfg.max_rounds = budgets.of(m, r);
            cfg.record_trajectories = false;
            cfg.measure_coverage = false;
            let res = runners[m].run(plan.starts.of(m, r, k), &cfg);
            bar.inc(1);
            (r, res.complete.then_some(res.search_time_s))
        })
        .collect();
    bar.finish_and_clear();
    let mut out = BTreeMap::new();
    for (r, &n) in plan.robots.iter().enumerate() {
        let done: Vec<f64> = times.iter().filter(|t| t.0 == r).filter_map(|t| t.1).collect();
        if !done.is_empty() {
            out.insert(n, done.iter().sum::<f64>() / done.len() as f64);
        }
    }
    (out, runs * runners.len())
}

/// The sweep's setting in one line, for the terminal (claims.txt and
/// summary.json have every parameter).
fn short_setup(scenario: &Scenario, opts: &ExperimentOptions, maps: usize) -> String {
    format!(
        "scenario {} ({} grid), situation {}, {} runs per cell{}, base seed {} (parameters in summary.json)\n",
        output::shown(&scenario.name),
        scenario.grid.name(),
        scenario.situation.number(),
        opts.runs,
        if maps > 1 { format!(" and map, {maps} maps") } else { String::new() },
        opts.seed
    )
}

/// Start vertices for every robot count, placed before any run: a count the
/// map cannot hold is an input error, better found before hours of runs than
/// after. Failing assumptions are warned about once each, with the counts.
pub fn place(scenario: &Scenario, world: &World, robots: &[usize]) -> Result<Vec<Vec<VertexId>>> {
    let mut starts = Vec::with_capacity(robots.len());
    let mut failing: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for &r in robots {
        let s = contract::start_vertices(scenario, world, r)?;
        for w in check::warnings(&contract::check_assumptions(scenario, world, &s)) {
            failing.entry(w).or_default().push(r);
        }
        starts.push(s);
    }
    for (w, counts) in &failing {
        eprintln!("{w} (robots {})", compress(counts));
    }
    Ok(starts)
}

/// One run of a sweep, kept as numbers only (no poses), with its coverage
/// measured as it goes when `coverage` (its other metrics always).
pub fn record(
    runner: &Runner,
    starts: &[VertexId],
    policy: Policy,
    seed: u64,
    situation: Situation,
    max_rounds: u32,
    coverage: bool,
) -> RunRecord {
    let mut cfg = RunConfig::new(policy, seed, situation);
    cfg.max_rounds = max_rounds;
    cfg.record_trajectories = false;
    cfg.measure_coverage = coverage;
    let res = runner.run(starts, &cfg);
    let all_found = res.targets_total > 0 && res.targets_found == res.targets_total;
    RunRecord {
        seed,
        search_time_s: res.search_time_s,
        rounds: res.rounds,
        collisions: res.collisions,
        targets_found: res.targets_found,
        complete: res.complete,
        last_target_s: all_found.then(|| res.metrics.targets_s.last().copied()).flatten(),
        measured: Measured::of(res),
    }
}

/// What `claims` and `claims_at_last_find` measure (summary.json).
const CLAIMS_MEASURES: &str = "claims: each run's search time, when a robot's stop ended the search \
    (search_time_s); claims_at_last_find: when its last target was found (last_target_s), complete runs \
    that found every target; docs/paper.md, \"Comparing algorithms fairly\"";

/// claims.txt's heading of the claims judged at the last find.
const LAST_FIND_HEADING: &str = "Measured at the last find (last_target_s) instead of the search's end:";

/// The claims judged on every run's last find ([`RunRecord::at_last_find`]).
fn claims_at_last_find(cells: impl Iterator<Item = (Policy, usize)>, per_cell: &[&[RunRecord]]) -> Vec<ClaimResult> {
    let runs: Vec<Vec<RunRecord>> =
        per_cell.iter().map(|rs| rs.iter().map(RunRecord::at_last_find).collect()).collect();
    let stats: Vec<CellStats> = cells.zip(&runs).map(|((p, r), rs)| CellStats::of(p, r, rs)).collect();
    let by_cell: Vec<&[RunRecord]> = runs.iter().map(|r| &r[..]).collect();
    claims::evaluate(&stats, &by_cell)
}

/// The sweep's runs in their fixed order: map, then algorithm, then robot
/// count, then run index. Every output is laid out in this order.
struct Plan<'a> {
    algorithms: &'a [Policy],
    robots: &'a [usize],
    starts: &'a Layouts,
    maps: usize,
    runs: usize,
}

impl Plan<'_> {
    /// (algorithm, robots) of each cell, in order.
    fn cells(&self) -> impl Iterator<Item = (Policy, usize)> + '_ {
        self.algorithms.iter().flat_map(|&p| self.robots.iter().map(move |&r| (p, r)))
    }

    /// Runs on one map.
    fn per_map(&self) -> usize {
        self.algorithms.len() * self.robots.len() * self.runs
    }

    /// (map, algorithm index, robot-count index, run index) of each run, in order.
    fn jobs(&self) -> Vec<(usize, usize, usize, usize)> {
        let (na, nr, runs) = (self.algorithms.len(), self.robots.len(), self.runs);
        (0..self.maps)
            .flat_map(|m| (0..na).flat_map(move |a| (0..nr).flat_map(move |r| (0..runs).map(move |k| (m, a, r, k)))))
            .collect()
    }

    /// Each cell's runs over every map, in map order, then run order (so
    /// run `i` of every cell has the same map and seed): on one map, the
    /// records themselves (each run's coverage curve is not copied).
    fn pooled_runs<'r>(&self, records: &'r [RunRecord]) -> Vec<Cow<'r, [RunRecord]>> {
        let cell_len = self.runs;
        self.cells()
            .enumerate()
            .map(|(c, _)| {
                if self.maps == 1 {
                    return Cow::Borrowed(&records[c * cell_len..(c + 1) * cell_len]);
                }
                records
                    .chunks(self.per_map())
                    .flat_map(|m| m[c * cell_len..(c + 1) * cell_len].iter().cloned())
                    .collect()
            })
            .collect()
    }

    /// Runs everything on all cores. `collect` keeps the job order whatever
    /// thread ran a job, and the statistics are summed in that order, so the
    /// output does not depend on scheduling.
    fn execute(
        &self,
        runners: &[Runner],
        situation: Situation,
        opts: &ExperimentOptions,
        budgets: &Budgets,
    ) -> Vec<RunRecord> {
        let jobs = self.jobs();
        let bar = progress_bar(jobs.len() as u64, opts.progress);
        let records = jobs
            .par_iter()
            .map(|&(m, a, r, k)| {
                // Map 0 keeps the seeds of a one-map sweep; each later map
                // continues the run index, so no two runs share a seed.
                let seed = run_seed(opts.seed, self.robots[r], (m * self.runs + k) as u64);
                let starts = self.starts.of(m, r, k);
                let rec = record(&runners[m], starts, self.algorithms[a], seed, situation, budgets.of(m, r), true);
                bar.inc(1);
                rec
            })
            .collect();
        bar.finish_and_clear();
        records
    }

    /// `runs.csv`: every run, for analyses the summary does not foresee.
    fn write_runs_csv(&self, w: &mut impl Write, records: &[RunRecord]) -> std::io::Result<()> {
        writeln!(
            w,
            "algorithm,robots,run,seed,search_time_s,rounds,collisions,targets_found,complete,map,{RUN_METRICS},\
             last_target_s"
        )?;
        for ((m, a, r, k), rec) in self.jobs().into_iter().zip(records) {
            writeln!(
                w,
                "{},{},{k},{},{:.6},{},{},{},{},{m},{},{}",
                self.algorithms[a].name(),
                self.robots[r],
                rec.seed,
                rec.search_time_s,
                rec.rounds,
                rec.collisions,
                rec.targets_found,
                rec.complete,
                run_metrics(&rec.measured),
                rec.last_target_s.map(|t| format!("{t:.6}")).unwrap_or_default()
            )?;
        }
        Ok(())
    }
}

/// Incomplete runs hit the round limit (`limit`, in words) and are left out
/// of the means, which biases them down; say where that happened.
pub fn incomplete_note(cells: &[CellStats], limit: &str) -> String {
    let short: Vec<String> = cells
        .iter()
        .filter(|c| c.completed_runs < c.runs)
        .map(|c| format!("{} with {} robots {}/{}", c.algorithm.name(), c.robots, c.completed_runs, c.runs))
        .collect();
    if short.is_empty() {
        return String::new();
    }
    format!(
        "note: cells with runs that did not finish within {limit}; they are incomplete runs, left out of the \
         means: {}\n",
        short.join("; ")
    )
}

pub const RESULTS_HEADER: &str = "algorithm,robots,runs,completed_runs,mean_search_time_s,std_search_time_s,ci95_s,\
                                  mean_rounds,mean_collisions,label,median_search_time_s,mean_targets_found,map,\
                                  oracle_reference_s,oracle_runs,lower_bound_s,\
                                  ci95_collisions,mean_coverage,ci95_coverage,mean_half_coverage_s,ci95_half_coverage_s,\
                                  mean_distance_m,ci95_distance_m,mean_rotations,ci95_rotations,mean_frames,ci95_frames,\
                                  mean_bytes,ci95_bytes,mean_target_times_s,ci95_target_times_s,\
                                  mean_last_target_s,ci95_last_target_s";

/// runs.csv's columns of a run's metrics, after its others: per robot,
/// means over the team; the targets' times as one field, `;` between them.
pub const RUN_METRICS: &str = "coverage,half_coverage_s,distance_m,rotations,frames,bytes,target_times_s";

/// A run's metrics as runs.csv's cells, in [`RUN_METRICS`]' order.
fn run_metrics(m: &Measured) -> String {
    let n = output::csv_num;
    format!(
        "{},{},{:.6},{:.6},{},{},{}",
        n(m.coverage),
        n(m.half_coverage_s()),
        m.distance_m,
        m.rotations,
        n(m.frames),
        n(m.bytes),
        m.targets_s.iter().map(|t| format!("{t:.6}")).collect::<Vec<_>>().join(";")
    )
}

/// A cell's metrics as results.csv's cells after the references: each
/// mean and its interval; the k-th targets' as `;`-separated lists.
fn cell_metrics(c: &CellMetrics) -> String {
    let n = output::csv_num;
    let mut s = n(c.collisions.ci95);
    for e in [c.coverage, c.half_coverage_s, c.distance_m, c.rotations, c.frames, c.bytes] {
        let _ = write!(s, ",{},{}", n(e.mean), n(e.ci95));
    }
    let list = |f: &dyn Fn(&Estimate) -> Option<f64>| c.targets_s.iter().map(|e| n(f(e))).collect::<Vec<_>>().join(";");
    let _ = write!(s, ",{},{}", list(&|e| e.mean), list(&|e| e.ci95));
    let _ = write!(s, ",{},{}", n(c.last_target_s.mean), n(c.last_target_s.ci95));
    s
}

/// `results.csv`: one row per cell over every map (`map` = `all`), then,
/// with several maps, one per cell and map (`map` = its index, as in
/// maps.csv); empty fields where there were too few completed runs for the
/// statistic. The references (the oracle's mean, the runs it rests on, the
/// mean lower bound) are the pooled cells' only.
pub fn results_csv(cells: &[CellStats], per_map: &[Vec<CellStats>], refs: &crate::refs::Refs) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{RESULTS_HEADER}");
    let tagged = cells
        .iter()
        .map(|c| (c, "all".to_string()))
        .chain(per_map.iter().enumerate().flat_map(|(m, cs)| cs.iter().map(move |c| (c, m.to_string()))));
    for (c, map) in tagged {
        let pooled = map == "all";
        let oracle = refs.oracle.get(&c.robots).copied().filter(|_| pooled);
        let oracle_runs = if pooled && oracle.is_some() { refs.oracle_runs.to_string() } else { String::new() };
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},\"{}\",{},{:.6},{map},{},{oracle_runs},{},{}",
            c.algorithm.name(),
            c.robots,
            c.runs,
            c.completed_runs,
            output::csv_num(c.mean_search_time_s),
            output::csv_num(c.std_search_time_s),
            output::csv_num(c.ci95_s),
            output::csv_num(c.mean_rounds),
            output::csv_num(c.mean_collisions),
            c.algorithm.paper_label(),
            output::csv_num(c.median_search_time_s),
            c.mean_targets_found,
            output::csv_num(oracle),
            output::csv_num(refs.bound(c).filter(|_| pooled)),
            cell_metrics(&c.metrics)
        );
    }
    s
}

/// The terminal's results table; `x_oracle` is the mean over the oracle's
/// mean at the same robot count, `x_bound` over the cell's mean lower bound.
pub fn table(cells: &[CellStats], refs: &crate::refs::Refs) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<14} {:<14} {:>6} {:>7} {:>9} {:>8} {:>8} {:>10} {:>9} {:>8} {:>7}",
        "algorithm",
        "label",
        "robots",
        "done",
        "mean_s",
        "ci95_s",
        "rounds",
        "collisions",
        refs.x_oracle_name(),
        "bound_s",
        "x_bound"
    );
    let f = |x: Option<f64>, d: usize| x.map(|v| format!("{v:.d$}")).unwrap_or_else(|| "-".into());
    for c in cells {
        let _ = writeln!(
            s,
            "{:<14} {:<14} {:>6} {:>7} {:>9} {:>8} {:>8} {:>10} {:>9} {:>8} {:>7}",
            c.algorithm.name(),
            c.algorithm.paper_label(),
            c.robots,
            format!("{}/{}", c.completed_runs, c.runs),
            f(c.mean_search_time_s, 1),
            f(c.ci95_s, 1),
            f(c.mean_rounds, 1),
            f(c.mean_collisions, 2),
            f(refs.x_oracle(c), 2),
            f(refs.bound(c), 1),
            f(refs.x_bound(c), 2)
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_header_and_empty_fields() {
        let recs = [RunRecord {
            seed: 1,
            search_time_s: 10.0,
            rounds: 2,
            collisions: 0,
            targets_found: 3,
            complete: false,
            ..Default::default()
        }];
        let cells = vec![CellStats::of(Policy::Sequential, 4, &recs)];
        let refs = crate::refs::Refs::default();
        let csv = results_csv(&cells, std::slice::from_ref(&cells), &refs);
        let mut lines = csv.lines();
        assert!(lines.next().unwrap().starts_with(
            "algorithm,robots,runs,completed_runs,mean_search_time_s,std_search_time_s,ci95_s,mean_rounds,mean_collisions"
        ));
        // No completed run: every statistic, the references' and metrics' too, left empty.
        let empty = ",".repeat(RESULTS_HEADER.split(',').count() - 13);
        assert_eq!(lines.next().unwrap(), format!("sequential,4,1,0,,,,,,\"(1)&(3)\",,3.000000,all{empty}"));
        assert_eq!(lines.next().unwrap(), format!("sequential,4,1,0,,,,,,\"(1)&(3)\",,3.000000,0{empty}"));
    }
}
