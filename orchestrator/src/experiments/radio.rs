//! `gridswarm experiment radio`: the protocol on a lossy radio. Loss
//! probabilities × robot counts × retransmission counts, each run many
//! times: collisions per 10^6 moves, completion, search time,
//! retransmissions, time-outs and unsure stays, false suspicions.
//!
//! In-process by default, `--engine distributed` optional ([`crate::sweep`]).
//! Run `r` with `N` robots has seed `derive(derive(seed, N), r)` whatever
//! the loss and the retries, so each loss and retries value is compared on
//! the same starts and the same draws of the decision core (paired runs);
//! the radio's own draws depend on the seed and the transmission only.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::str::FromStr;

use gridswarm::sim::Radio;
use serde_json::json;

use crate::error::{Error, Result};
use crate::experiment::Times;
use crate::faults::{self, FaultPlan};
use crate::panels::{self, Panel, Series};
use crate::report::{self, keyed_text_table, Block, Report, Section, Table};
// The seed of a run is the sweep's, the same for every loss and retries.
use crate::seeds::run_seed;
use crate::staging::Staging;
use crate::sweep::{self, Job, ProtocolOptions};
use crate::tally::{self, ProtoRun, ProtoStats};
use crate::{check, contract, output};

pub const DEFAULT_LOSS: &str = "0,0.05,0.1,0.2,0.3";
pub const DEFAULT_ROBOTS: &str = "4,8,13";
pub const DEFAULT_RETRIES: &str = "0,1,2";
/// Runs per (loss, robots, retries), in-process.
pub const DEFAULT_RUNS: u32 = 100;
/// Runs per point with `--engine distributed`.
pub const DEFAULT_RUNS_DISTRIBUTED: u32 = 3;
pub const DEFAULT_OUT: &str = "radio-out";

/// Loss probabilities: `0,0.05,0.1`; sorted, distinct, each in `[0, 1]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Losses(pub Vec<f64>);

impl FromStr for Losses {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let mut out = Vec::new();
        for part in s.split(',') {
            out.push(faults::parse_probability(part.trim()).map_err(|e| format!("bad --loss `{s}`: {e}"))?);
        }
        out.sort_by(f64::total_cmp);
        out.dedup();
        Ok(Losses(out))
    }
}

/// Retransmission counts: `0,1,2`; sorted, distinct.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RetryCounts(pub Vec<u32>);

impl FromStr for RetryCounts {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let mut out = Vec::new();
        for part in s.split(',') {
            let r: u32 = part
                .trim()
                .parse()
                .map_err(|_| format!("bad --retries `{s}`: `{}` is not a whole number", part.trim()))?;
            if r > 254 {
                return Err(format!("bad --retries `{s}`: at most 254"));
            }
            out.push(r);
        }
        out.sort_unstable();
        out.dedup();
        Ok(RetryCounts(out))
    }
}

#[derive(Clone, Debug)]
pub struct RadioOptions {
    pub protocol: ProtocolOptions,
    pub loss: Vec<f64>,
    pub robots: Vec<usize>,
    pub retries: Vec<u32>,
}

/// One point of the experiment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    pub loss: f64,
    pub robots: usize,
    pub retries: u32,
}

/// One row of `radio.csv`.
#[derive(Clone, Debug, PartialEq)]
pub struct RadioRow {
    pub point: Point,
    pub stats: ProtoStats,
}

pub fn csv_header() -> String {
    format!("loss,robots,retries,{}", tally::CSV_COLUMNS)
}

pub fn csv(rows: &[RadioRow]) -> String {
    let mut s = csv_header() + "\n";
    for r in rows {
        let p = r.point;
        let _ = writeln!(s, "{},{},{},{}", p.loss, p.robots, p.retries, tally::csv_cells(&r.stats));
    }
    s
}

fn runs_csv(runs: &[(Point, u32, ProtoRun)]) -> String {
    let mut s = format!("loss,robots,retries,run,{}\n", tally::RUN_CSV_COLUMNS);
    for (p, r, run) in runs {
        let _ = writeln!(s, "{},{},{},{r},{}", p.loss, p.robots, p.retries, tally::run_csv_cells(run));
    }
    s
}

fn table(rows: &[RadioRow]) -> Table {
    let header = [
        "loss",
        "robots",
        "retries",
        "completed",
        "time (s) ± CI95",
        "coll./10^6 moves",
        "collisions",
        "retrans./run",
        "lost/run",
        "time-outs/run",
        "unsure/run",
        "false susp./run",
        "ended by",
    ];
    Table {
        header: header.map(String::from).to_vec(),
        rows: rows
            .iter()
            .map(|r| {
                let (p, s) = (r.point, &r.stats);
                vec![
                    format!("{}", p.loss),
                    p.robots.to_string(),
                    p.retries.to_string(),
                    format!("{}/{}", s.completed_runs, s.runs),
                    s.time_text(),
                    format!("{:.1}", s.collisions_per_million_moves),
                    s.collisions.to_string(),
                    format!("{:.1}", s.mean_retransmissions),
                    format!("{:.1}", s.mean_lost),
                    format!("{:.2}", s.mean_timeouts),
                    format!("{:.2}", s.mean_unsure),
                    format!("{:.3}", s.mean_false_suspicions),
                    s.endings(),
                ]
            })
            .collect(),
    }
}

/// One series per (robots, retries), against the loss: coloured by the
/// robot count and dashed by the retries, so that a line's look says both.
fn series(rows: &[RadioRow], y: impl Fn(&ProtoStats) -> (Option<f64>, Option<f64>)) -> Vec<Series> {
    let mut keys: Vec<(usize, u32)> = Vec::new();
    for r in rows {
        if !keys.contains(&(r.point.robots, r.point.retries)) {
            keys.push((r.point.robots, r.point.retries));
        }
    }
    let robots: BTreeSet<usize> = keys.iter().map(|k| k.0).collect();
    let retries: BTreeSet<u32> = keys.iter().map(|k| k.1).collect();
    keys.iter()
        .map(|&(n, k)| {
            let pts = rows.iter().filter(|r| (r.point.robots, r.point.retries) == (n, k)).map(|r| {
                let (v, e) = y(&r.stats);
                (r.point.loss, v, e)
            });
            let colour = robots.iter().position(|&m| m == n).unwrap_or(0);
            let dash = retries.iter().position(|&m| m == k).unwrap_or(0);
            Series::with_err(format!("N={n}, R={k}"), pts).styled(colour, dash)
        })
        .collect()
}

fn figure(rows: &[RadioRow], losses: &[f64], title: &str) -> std::result::Result<String, String> {
    // Log scale: the rate spans decades; a point without collisions has no
    // logarithm and is left out (the table has it).
    let mut collisions = Panel::new(
        "Collisions per 10^6 moves (log; 0 not drawn)",
        "loss probability P",
        "collisions per 10^6 moves",
        series(rows, |s| ((s.collisions_per_million_moves > 0.0).then_some(s.collisions_per_million_moves), None)),
    );
    collisions.log_y = true;
    let mut done = Panel::new(
        "Completion",
        "loss probability P",
        "fraction of runs",
        series(rows, |s| (Some(s.completion_rate), None)),
    );
    done.y_range = Some((0.0, 1.05));
    let time = Panel::new(
        "Search time (completed runs)",
        "loss probability P",
        "mean search time (s), ± 95% CI",
        series(rows, |s| (s.mean_search_time_s, s.ci95_search_time_s)),
    );
    let unsure =
        Panel::new("Unsure stays", "loss probability P", "per run", series(rows, |s| (Some(s.mean_unsure), None)));
    // Every panel has the same lines: one key, in the first.
    let mut panels = [collisions, done, time, unsure];
    panels.iter_mut().skip(1).for_each(|p| p.legend = false);
    panels::panels_svg(title, &panels, losses)
}

fn points(opts: &RadioOptions) -> Vec<Point> {
    let mut out = Vec::new();
    for &loss in &opts.loss {
        for &robots in &opts.robots {
            for &retries in &opts.retries {
                out.push(Point { loss, robots, retries });
            }
        }
    }
    out
}

fn jobs(opts: &RadioOptions, runs: u32) -> Vec<(Point, u32, Job)> {
    let mut out = Vec::new();
    for p in points(opts) {
        for r in 0..runs {
            let seed = run_seed(opts.protocol.seed, p.robots, u64::from(r));
            let plan = FaultPlan {
                radio: Radio { loss: p.loss, ..Radio::default() },
                retries: Some(p.retries),
                ..FaultPlan::default()
            };
            let what = format!("run {r}, loss {}, {} robots, {} retries, seed {seed}", p.loss, p.robots, p.retries);
            out.push((p, r, Job { robots: p.robots, seed, plan, what }));
        }
    }
    out
}

fn prepare(opts: &RadioOptions) -> Result<gridswarm::scenario::Scenario> {
    if opts.loss.is_empty() || opts.robots.is_empty() || opts.retries.is_empty() {
        return Err(Error::Input(
            "the experiment needs at least one loss, one robot count and one retries value".into(),
        ));
    }
    opts.protocol.load("radio")
}

/// Runs the experiment; returns the rows and the text for stdout.
pub fn run(opts: &RadioOptions) -> Result<(Vec<RadioRow>, String)> {
    // The command's clock, for the wall time it prints.
    let started = std::time::Instant::now();
    let scenario = prepare(opts)?;
    let opts = &RadioOptions { protocol: opts.protocol.with_round_limit(&scenario, &opts.robots)?, ..opts.clone() };
    let runs_per = opts.protocol.runs_per(DEFAULT_RUNS, DEFAULT_RUNS_DISTRIBUTED);
    // Before any run: an unwritable --out fails now, not after the runs.
    let stage = Staging::begin(&opts.protocol.out)?;
    let world = scenario.world();
    for &n in &opts.robots {
        let starts = contract::start_vertices(&scenario, &world, n)?;
        for w in check::warnings(&contract::check_assumptions(&scenario, &world, &starts)) {
            eprintln!("{w} (robots {n})");
        }
    }
    let (runs, wall_time_s) = opts.protocol.execute(&scenario, &jobs(opts, runs_per))?;
    let rows: Vec<RadioRow> =
        points(opts).into_iter().map(|p| RadioRow { point: p, stats: sweep::stats_at(&runs, &p) }).collect();
    let dir = stage.path().to_path_buf();
    let page = Page { dir: &dir, opts, scenario: &scenario, runs_per, wall_time_s, started, runs: &runs, rows: &rows };
    // The files go in whole or not at all; if they cannot, the table is
    // still shown before the error.
    page.write().and_then(|()| stage.commit()).inspect_err(|_| print!("{}", page.text()))?;
    Ok((rows.clone(), page.text()))
}

/// What the experiment writes, and its terminal text.
struct Page<'a> {
    /// The staging folder the files are written to.
    dir: &'a std::path::Path,
    opts: &'a RadioOptions,
    scenario: &'a gridswarm::scenario::Scenario,
    runs_per: u32,
    /// The runs' wall time; `started` the command's start.
    wall_time_s: f64,
    started: std::time::Instant,
    runs: &'a [(Point, u32, ProtoRun)],
    rows: &'a [RadioRow],
}

impl Page<'_> {
    fn params(&self) -> serde_json::Value {
        let o = self.opts;
        json!({
            "scenario": self.scenario.name,
            "grid": self.scenario.grid.name(),
            "situation": self.scenario.situation.number(),
            "algorithm": o.protocol.algorithm.name(),
            "loss": o.loss,
            "robots": o.robots,
            "retries": o.retries,
            "runs": self.runs_per,
            "seed": o.protocol.seed,
            "seed_derivation": "run r with N robots has seed derive(derive(seed, N), r) with gridswarm::rng::derive, \
                the same for every loss and retries value (paired runs)",
            "radio": "loss P per transmission per link; no extra delay, jitter or duplication",
            "reproduce": format!(
                "gridswarm simulate --scenario {} --situation {} --algorithm {} --robots N --seed SEED --loss P \
                 --retries R --max-rounds {} (from radio-runs.csv)",
                o.protocol.scenario,
                self.scenario.situation.number(),
                o.protocol.algorithm,
                o.protocol.rounds()
            ),
            "max_rounds": o.protocol.rounds(),
            "engine": o.protocol.engine.describe(),
            "transport": o.protocol.engine.transport(),
            "statistics": "search time (mean ± 1.96 std/sqrt(n)) over completed runs; counts are means per run over \
                all runs; collisions per 10^6 moves pool every run's collisions and moves",
            "params": self.scenario.params,
        })
    }

    fn write(&self) -> Result<()> {
        let out = self.dir;
        output::write_text(&out.join("radio.csv"), &csv(self.rows))?;
        output::write_text(&out.join("radio-runs.csv"), &runs_csv(self.runs))?;
        let svg_path = out.join("radio.svg");
        let title = format!(
            "{}: {}, {} runs per point, loss per transmission per link",
            self.scenario.name, self.opts.protocol.algorithm, self.runs_per
        );
        let svg = figure(self.rows, &self.opts.loss, &title)
            .map_err(|message| Error::Plot { path: svg_path.clone(), message })?;
        output::write_text(&svg_path, &svg)?;
        let mut page = self.report(svg);
        let params = self.params();
        let record = crate::provenance::Record {
            scenario_arg: Some(&self.opts.protocol.scenario),
            seeds: json!({ "base": params["seed"], "derivation": params["seed_derivation"] }),
            parameters: params,
            starts: json!({ "rule": "fixed" }),
        };
        crate::provenance::stamp(out, &mut page, &record)?;
        output::write_text(&out.join("report.html"), &report::render(&page))
    }

    fn report(&self, svg: String) -> Report {
        let files = [("radio.csv", "the results table"), ("radio-runs.csv", "every run"), ("radio.svg", "the figure")];
        Report {
            title: format!("Radio loss: {} scenario", crate::output::shown(&self.scenario.name)),
            subtitle: format!(
                "{} points, {} runs each, base seed {}; the {} runs took {:.1} s of wall time ({})",
                self.rows.len(),
                self.runs_per,
                self.opts.protocol.seed,
                self.runs.len(),
                self.wall_time_s,
                self.opts.protocol.engine.describe()
            ),
            sections: vec![
                Section::new(
                    "Plots",
                    vec![Block::Figure {
                        svg,
                        caption: "Against the probability P that one transmission is lost on one link, one line per \
                                  robot count N (its colour) and retransmission count R (its dash: solid for the \
                                  fewest), keyed in the first panel: collisions per 10^6 moves (all runs \
                                  pooled; log scale, points with no collision left out), completion rate, mean \
                                  search time of the completed runs (bars: 95% CI) and unsure stays per run. \
                                  Measurements only."
                            .into(),
                    }],
                ),
                Section::new("Results", vec![Block::Table(table(self.rows))]),
                Section::new("Parameters", vec![Block::Params(report::params_of("", &self.params()))]),
                Section::new("Files", vec![Block::Files(files.map(|(a, b)| (a.to_string(), b.to_string())).to_vec())]),
            ],
        }
    }

    fn text(&self) -> String {
        format!(
            "radio: scenario {}, algorithm {}, {} runs per point, base seed {}, engine {}\n{}\n\
             {} runs; {}; wrote radio.csv, radio-runs.csv, radio.svg, report.html, provenance.json in {}\n",
            crate::output::shown(&self.scenario.name),
            self.opts.protocol.algorithm,
            self.runs_per,
            self.opts.protocol.seed,
            self.opts.protocol.engine.name(),
            keyed_text_table(&table(self.rows), 3),
            self.runs.len(),
            Times { command_s: self.started.elapsed().as_secs_f64(), runs_s: self.wall_time_s },
            self.opts.protocol.out.display()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::Engine;
    use gridswarm::policy::Policy;
    use std::path::PathBuf;

    #[test]
    fn lists_parse() {
        assert_eq!("0.1,0,0.1".parse::<Losses>().unwrap().0, vec![0.0, 0.1]);
        assert!("0.1,1.5".parse::<Losses>().is_err() && "x".parse::<Losses>().is_err());
        assert_eq!("2,0,1".parse::<RetryCounts>().unwrap().0, vec![0, 1, 2]);
        assert!("-1".parse::<RetryCounts>().is_err() && "255".parse::<RetryCounts>().is_err());
    }

    #[test]
    fn seeds_pair_runs_across_loss_and_retries() {
        let protocol = ProtocolOptions {
            scenario: "paper".into(),
            algorithm: Policy::Repulsive,
            runs: Some(2),
            seed: 5,
            situation: None,
            max_rounds: Some(10),
            engine: Engine::InProcess,
            out: PathBuf::new(),
            progress: false,
        };
        let opts = RadioOptions { protocol, loss: vec![0.0, 0.2], robots: vec![3], retries: vec![0, 1] };
        let j = jobs(&opts, 2);
        assert_eq!(j.len(), 8);
        assert!(j.iter().all(|(_, r, job)| job.seed == run_seed(5, 3, u64::from(*r))));
        assert_eq!(j[7].2.plan.radio.loss, 0.2);
        assert_eq!(j[7].2.plan.retries, Some(1));
        let row = RadioRow { point: j[0].0, stats: ProtoStats::of(&[ProtoRun::default()]) };
        let text = csv(&[row]);
        assert_eq!(text.lines().nth(1).unwrap().split(',').count(), csv_header().split(',').count());
    }
}
