//! `gridswarm experiment failures`: runs with 0, 1, 2, ... robots crashed
//! at random times inside rounds (`--kill-random`), and what the crashes
//! cost: completion, search time, how long the survivors take to notice,
//! false suspicions, rejoins, radio traffic, collisions, unsure stays.
//! Every run is made twice, with the same crashes: under the paper's rules
//! as written, and with the survivor step (`[params] survivor_step`,
//! docs/paper.md "Survivors"), which replaces the paper's walk over
//! visited vertices once a failure is known; the two are shown side by side.
//!
//! In-process by default (every core, thousands of runs in seconds); with
//! `--engine distributed`, one `gridswarm run` after another. Run `r` with
//! `k` killed has seed `derive(derive(seed, k), r)`; its victims and their
//! times are drawn from that seed by [`gridswarm::sim::schedule::kill_random`],
//! so both engines run the same schedule.

use std::fmt::Write as _;
use std::str::FromStr;

use gridswarm::sim::schedule;
use serde_json::json;

use crate::claims::Verdict;
use crate::error::{Error, Result};
use crate::experiment::Times;
use crate::faults::FaultPlan;
use crate::panels::{self, Panel, Series};
use crate::report::{self, Block, Claim, Report, Section, Table};
use crate::seeds::run_seed;
use crate::staging::Staging;
use crate::sweep::{self, Job, ProtocolOptions};
use crate::tally::{self, ProtoRun, ProtoStats};
use crate::{check, contract, output};

pub use crate::report::text_table;

pub const DEFAULT_ROBOTS: u32 = 13;
pub const DEFAULT_KILLED: &str = "0-3";
/// Runs per number killed, in-process.
pub const DEFAULT_RUNS: u32 = 500;
/// Runs per number killed with `--engine distributed` (each takes seconds).
pub const DEFAULT_RUNS_DISTRIBUTED: u32 = 10;
pub const DEFAULT_OUT: &str = "failures-out";

/// Numbers of robots to kill: `0-3`, `2` or `0,2,4`; sorted, distinct.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Killed(pub Vec<usize>);

impl FromStr for Killed {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let out = crate::robots::counts(s, "--killed", 0)?;
        Ok(Killed(out))
    }
}

#[derive(Clone, Debug)]
pub struct FailuresOptions {
    pub protocol: ProtocolOptions,
    /// The scenario's own count when `None`.
    pub robots: Option<usize>,
    pub killed: Vec<usize>,
}

/// The rules the survivors follow: the paper's as written, or with the
/// survivor step. Both are run on the same seeds, so on the same crashes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Rules {
    /// `survivor_step = false`: the paper's algorithm under failure.
    Paper,
    /// `survivor_step = true`: once a failure or a body is known, a robot
    /// with every candidate visited steps towards the nearest unvisited vertex.
    Step,
}

impl Rules {
    pub const BOTH: [Rules; 2] = [Rules::Paper, Rules::Step];

    /// The value of `params.survivor_step` under these rules.
    pub fn survivor_step(self) -> bool {
        self == Rules::Step
    }

    /// The `survivor_step` column's value.
    pub fn cell(self) -> &'static str {
        if self.survivor_step() {
            "on"
        } else {
            "off"
        }
    }

    /// How tables and legends name the rules.
    pub fn label(self) -> &'static str {
        match self {
            Rules::Paper => "paper's rules",
            Rules::Step => "with survivor step",
        }
    }
}

/// One row of `failures.csv`: the runs with `killed` robots killed under `rules`.
#[derive(Clone, Debug, PartialEq)]
pub struct FailureRow {
    pub rules: Rules,
    pub killed: usize,
    pub stats: ProtoStats,
}

/// A point of the experiment: the rules and the number killed.
type Point = (Rules, usize);

pub fn csv_header() -> String {
    format!("survivor_step,killed,{}", tally::CSV_COLUMNS)
}

pub fn csv(rows: &[FailureRow]) -> String {
    let mut s = csv_header() + "\n";
    for r in rows {
        let _ = writeln!(s, "{},{},{}", r.rules.cell(), r.killed, tally::csv_cells(&r.stats));
    }
    s
}

fn runs_csv(runs: &[(Point, u32, ProtoRun)]) -> String {
    let mut s = format!("survivor_step,killed,run,{}\n", tally::RUN_CSV_COLUMNS);
    for ((rules, k), r, run) in runs {
        let _ = writeln!(s, "{},{k},{r},{}", rules.cell(), tally::run_csv_cells(run));
    }
    s
}

fn fmt(x: Option<f64>, d: usize) -> String {
    x.map(|v| format!("{v:.d$}")).unwrap_or_else(|| "-".into())
}

fn table(rows: &[FailureRow]) -> Table {
    let header = [
        "rules",
        "killed",
        "completed",
        "time (s) ± CI95",
        "detected",
        "delay (rounds)",
        "delay (s)",
        "false susp./run",
        "rejoins/run",
        "retrans./run",
        "coll./10^6 moves",
        "unsure/run",
        "ended by",
    ];
    Table {
        header: header.map(String::from).to_vec(),
        rows: rows
            .iter()
            .map(|r| {
                let s = &r.stats;
                vec![
                    r.rules.label().to_string(),
                    r.killed.to_string(),
                    format!("{}/{}", s.completed_runs, s.runs),
                    s.time_text(),
                    format!("{}/{}", s.detected, s.injected),
                    fmt(s.mean_delay_rounds, 2),
                    fmt(s.mean_delay_s, 2),
                    format!("{:.3}", s.mean_false_suspicions),
                    format!("{:.3}", s.mean_rejoins),
                    format!("{:.1}", s.mean_retransmissions),
                    format!("{:.1}", s.collisions_per_million_moves),
                    format!("{:.2}", s.mean_unsure),
                    s.endings(),
                ]
            })
            .collect(),
    }
}

/// One series per rules of `quantity` against the number killed: the
/// paper's rules solid, with the survivor step dashed; in `colour`, or
/// one colour per rules when `None`.
fn per_rules(
    rows: &[FailureRow],
    name: &str,
    colour: Option<usize>,
    quantity: impl Fn(&ProtoStats) -> (Option<f64>, Option<f64>),
) -> Vec<Series> {
    Rules::BOTH
        .iter()
        .enumerate()
        .map(|(dash, &rules)| {
            let points = rows.iter().filter(|r| r.rules == rules).map(|r| {
                let (y, err) = quantity(&r.stats);
                (r.killed as f64, y, err)
            });
            let label = if name.is_empty() { rules.label().to_string() } else { format!("{name}, {}", rules.label()) };
            Series::with_err(label, points).styled(colour.unwrap_or(dash), dash)
        })
        .collect()
}

fn figure(rows: &[FailureRow], title: &str) -> std::result::Result<String, String> {
    let mut xs: Vec<f64> = rows.iter().map(|r| r.killed as f64).collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup();
    let time = Panel::new(
        "Search time (completed runs)",
        "robots killed",
        "mean search time (s), ± 95% CI",
        per_rules(rows, "", None, |s| (s.mean_search_time_s, s.ci95_search_time_s)),
    );
    let mut done = Panel::new(
        "Completion",
        "robots killed",
        "fraction of runs",
        per_rules(rows, "", None, |s| (Some(s.completion_rate), None)),
    );
    done.y_range = Some((0.0, 1.05));
    // One quantity per axis: rounds and seconds, counts per run and a
    // rate per 10^6 moves, each on a panel of its own.
    let delay_rounds = Panel::new(
        "Detection delay in rounds",
        "robots killed",
        "mean rounds after the crash",
        per_rules(rows, "", None, |s| (s.mean_delay_rounds, None)),
    );
    let delay_s = Panel::new(
        "Detection delay in simulated time",
        "robots killed",
        "mean simulated s after the crash",
        per_rules(rows, "", None, |s| (s.mean_delay_s, None)),
    );
    let mut events = per_rules(rows, "false suspicions", Some(0), |s| (Some(s.mean_false_suspicions), None));
    events.extend(per_rules(rows, "rejoins", Some(1), |s| (Some(s.mean_rejoins), None)));
    events.extend(per_rules(rows, "unsure stays", Some(2), |s| (Some(s.mean_unsure), None)));
    let protocol = Panel::new("Protocol events per run", "robots killed", "mean per run", events);
    let collisions = Panel::new(
        "Collisions",
        "robots killed",
        "collisions per 10^6 moves",
        per_rules(rows, "", None, |s| (Some(s.collisions_per_million_moves), None)),
    );
    panels::panels_svg(title, &[time, done, delay_rounds, delay_s, protocol, collisions], &xs)
}

/// The options checked, the scenario loaded; the robot count.
fn prepare(opts: &FailuresOptions) -> Result<(gridswarm::scenario::Scenario, usize)> {
    if opts.killed.is_empty() {
        return Err(Error::Input("--killed needs at least one count".into()));
    }
    let scenario = opts.protocol.load("failures")?;
    let robots = opts.robots.unwrap_or(scenario.robots);
    if robots == 0 {
        return Err(Error::Input("at least 1 robot is needed".into()));
    }
    if let Some(&k) = opts.killed.iter().find(|&&k| k >= robots) {
        return Err(Error::Usage(format!(
            "--killed {k}: the run has {robots} robots, and at least one must survive to search"
        )));
    }
    Ok((scenario, robots))
}

fn jobs(opts: &FailuresOptions, rules: Rules, robots: usize, runs: u32) -> Vec<(Point, u32, Job)> {
    let mut out = Vec::new();
    for &k in &opts.killed {
        for r in 0..runs {
            // The same seed under both rules: the same victims at the same times.
            let seed = run_seed(opts.protocol.seed, k, u64::from(r));
            let plan = FaultPlan { kill_random: k, ..FaultPlan::default() };
            let what = format!("run {r} with {k} killed under the {}, seed {seed}", rules.label());
            out.push(((rules, k), r, Job { robots, seed, plan, what }));
        }
    }
    out
}

/// The scenario under `rules`, and how a run names it: the scenario as
/// given when it already has that `survivor_step`, or else a copy written
/// into `dir` as `file` (distributed runs load it; reproducers name it).
struct Variant {
    rules: Rules,
    scenario: gridswarm::scenario::Scenario,
    file: Option<String>,
}

fn variants(scenario: &gridswarm::scenario::Scenario, dir: &std::path::Path) -> Result<Vec<Variant>> {
    let mut out = Vec::new();
    for rules in Rules::BOTH {
        let mut s = scenario.clone();
        s.params.survivor_step = rules.survivor_step();
        let file = if s.params == scenario.params {
            None
        } else {
            let name = format!("scenario-survivor-step-{}.toml", rules.cell());
            let header = format!(
                "`{}` with survivor_step = {}, written by `experiment failures`",
                s.name,
                rules.survivor_step()
            );
            output::write_text(&dir.join(&name), &s.to_toml(&header))?;
            Some(name)
        };
        out.push(Variant { rules, scenario: s, file });
    }
    Ok(out)
}

/// Runs the experiment; returns the rows and the text for stdout.
pub fn run(opts: &FailuresOptions) -> Result<(Vec<FailureRow>, String)> {
    // The command's clock, for the wall time it prints.
    let started = std::time::Instant::now();
    let (scenario, robots) = prepare(opts)?;
    let opts = &FailuresOptions { protocol: opts.protocol.with_round_limit(&scenario, &[robots])?, ..opts.clone() };
    let runs_per = opts.protocol.runs_per(DEFAULT_RUNS, DEFAULT_RUNS_DISTRIBUTED);
    // Before any run: an unwritable --out fails now, not after the runs.
    let stage = Staging::begin(&opts.protocol.out)?;
    let world = scenario.world();
    let starts = contract::start_vertices(&scenario, &world, robots)?;
    for w in check::warnings(&contract::check_assumptions(&scenario, &world, &starts)) {
        eprintln!("{w}");
    }
    let dir = stage.path().to_path_buf();
    let variants = variants(&scenario, &dir)?;
    let (mut runs, mut wall_time_s) = (Vec::new(), 0.0);
    for v in &variants {
        let mut protocol = opts.protocol.clone();
        if let Some(f) = &v.file {
            protocol.scenario = dir.join(f).to_string_lossy().into_owned();
        }
        let (r, t) = protocol.execute(&v.scenario, &jobs(opts, v.rules, robots, runs_per))?;
        runs.extend(r);
        wall_time_s += t;
    }
    let rows: Vec<FailureRow> = Rules::BOTH
        .iter()
        .flat_map(|&rules| opts.killed.iter().map(move |&k| (rules, k)))
        .map(|(rules, k)| FailureRow { rules, killed: k, stats: sweep::stats_at(&runs, &(rules, k)) })
        .collect();
    let page = Page {
        dir: &dir,
        opts,
        scenario: &scenario,
        variants: &variants,
        robots,
        runs_per,
        wall_time_s,
        started,
        runs: &runs,
        rows: &rows,
    };
    // The files go in whole or not at all; if they cannot, the table is
    // still shown before the error.
    page.write().and_then(|()| stage.commit()).inspect_err(|_| print!("{}", page.text()))?;
    Ok((rows.clone(), page.text()))
}

/// Which curve and row is which, for the page and the terminal.
const RULES_NOTE: &str = "Rules: \"paper's rules\" (solid lines) is the paper's algorithm under failure, \
    survivor_step = false: a robot whose neighbours are all visited walks over visited vertices as the \
    paper's rules say, failures or not. \"with survivor step\" (dashed) is survivor_step = true: once a robot \
    knows of a failure or a body, such a robot steps towards the nearest unvisited vertex instead (escape's \
    rule). Both run on the same seeds and crashes; with nobody killed they are the same runs.";

/// What the experiment writes, and its terminal text.
struct Page<'a> {
    /// The staging folder the files are written to.
    dir: &'a std::path::Path,
    opts: &'a FailuresOptions,
    scenario: &'a gridswarm::scenario::Scenario,
    variants: &'a [Variant],
    robots: usize,
    runs_per: u32,
    /// The runs' wall time; `started` the command's start.
    wall_time_s: f64,
    started: std::time::Instant,
    runs: &'a [(Point, u32, ProtoRun)],
    rows: &'a [FailureRow],
}

impl Page<'_> {
    fn title(&self) -> String {
        format!(
            "{}: {} robots, {}, {} runs per point, robots crashed at random times inside rounds",
            self.scenario.name, self.robots, self.opts.protocol.algorithm, self.runs_per
        )
    }

    /// The `simulate` command of any run under `v`'s rules.
    fn reproduce(&self, v: &Variant) -> String {
        let o = self.opts;
        let scenario = match &v.file {
            Some(f) => o.protocol.out.join(f).display().to_string(),
            None => o.protocol.scenario.clone(),
        };
        format!(
            "gridswarm simulate --scenario {scenario} --situation {} --algorithm {} --robots {} --seed SEED \
             --kill-random K --max-rounds {} (SEED and K from the rows of failures-runs.csv with survivor_step {})",
            self.scenario.situation.number(),
            o.protocol.algorithm,
            self.robots,
            o.protocol.rounds(),
            v.rules.cell()
        )
    }

    fn params(&self) -> serde_json::Value {
        let o = self.opts;
        json!({
            "scenario": self.scenario.name,
            "grid": self.scenario.grid.name(),
            "situation": self.scenario.situation.number(),
            "algorithm": o.protocol.algorithm.name(),
            "robots": self.robots,
            "killed": o.killed,
            "runs": self.runs_per,
            "seed": o.protocol.seed,
            "seed_derivation": "run r with k killed has seed derive(derive(seed, k), r) with gridswarm::rng::derive; \
                its victims and crash times are drawn from that seed as by `--kill-random k`; the same seed under \
                both rules",
            "rules": "every run twice: survivor_step off (the paper's rules as written, failures or not) and on \
                (once a failure or a body is known, a robot with every candidate visited steps towards the nearest \
                unvisited vertex); `params` below is the scenario as loaded, with survivor_step set per rules",
            "reproduce": self.variants.iter().map(|v| (v.rules.cell().to_string(), json!(self.reproduce(v)))).collect::<serde_json::Map<_, _>>(),
            "crash_times": format!("rounds 1 to {}, at an offset below {} s into the round", schedule::RANDOM_ROUNDS, schedule::RANDOM_OFFSET_S),
            "max_rounds": o.protocol.rounds(),
            "engine": o.protocol.engine.describe(),
            "transport": o.protocol.engine.transport(),
            "statistics": "search time (mean ± 1.96 std/sqrt(n)) and rounds over completed runs; counts are means per \
                run over all runs; collisions per 10^6 moves pool every run; detection delay over every detected \
                crash (rounds, and simulated s after the crash)",
            "params": self.scenario.params,
        })
    }

    fn write(&self) -> Result<()> {
        let out = self.dir;
        output::write_text(&out.join("failures.csv"), &csv(self.rows))?;
        output::write_text(&out.join("failures-runs.csv"), &runs_csv(self.runs))?;
        let svg_path = out.join("failures.svg");
        let svg =
            figure(self.rows, &self.title()).map_err(|message| Error::Plot { path: svg_path.clone(), message })?;
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
        let mut files: Vec<(String, String)> =
            [("failures.csv", "the results table"), ("failures-runs.csv", "every run"), ("failures.svg", "the figure")]
                .map(|(a, b)| (a.to_string(), b.to_string()))
                .to_vec();
        for v in self.variants {
            if let Some(f) = &v.file {
                files.push((f.clone(), format!("the scenario as run under the {}", v.rules.label())));
            }
        }
        Report {
            title: format!("Failures: {} scenario, {} robots", crate::output::shown(&self.scenario.name), self.robots),
            subtitle: format!(
                "{} killed, {} runs each, base seed {}; the {} runs took {:.1} s of wall time ({})",
                crate::robots::compress(&self.opts.killed).replace('-', "–"),
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
                        caption: format!(
                            "Against the number of robots crashed at random times inside rounds: mean search \
                             time of the completed runs (bars: 95% CI), completion rate, how long after a crash \
                             a survivor first declared it (in rounds, and in simulated seconds), the protocol's \
                             false suspicions, rejoins and unsure stays per run, and collisions per 10^6 moves. {}",
                            RULES_NOTE
                        ),
                    }],
                ),
                Section::new("Checks", vec![Block::Claims(checks(self.rows))]),
                Section::new("Results", vec![Block::Table(table(self.rows))]),
                Section::new("Parameters", vec![Block::Params(report::params_of("", &self.params()))]),
                Section::new("Files", vec![Block::Files(files)]),
            ],
        }
    }

    fn text(&self) -> String {
        format!(
            "failures: scenario {}, {} robots, algorithm {}, {} runs per count and rules, base seed {}, engine {}\n{}\n{}\n\
             {} runs; {}; wrote failures.csv, failures-runs.csv, failures.svg, report.html, provenance.json{} in {}\n",
            crate::output::shown(&self.scenario.name),
            self.robots,
            self.opts.protocol.algorithm,
            self.runs_per,
            self.opts.protocol.seed,
            self.opts.protocol.engine.name(),
            text_table(&table(self.rows)),
            RULES_NOTE,
            self.runs.len(),
            Times { command_s: self.started.elapsed().as_secs_f64(), runs_s: self.wall_time_s },
            // The other rules' scenario, written beside the results for its runs.
            self.variants.iter().filter_map(|v| v.file.as_deref()).map(|f| format!(", {f}")).collect::<String>(),
            self.opts.protocol.out.display()
        )
    }
}

/// What the protocol promises under crashes, checked on the runs.
fn checks(rows: &[FailureRow]) -> Vec<Claim> {
    let verdict = |ok: bool| if ok { Verdict::Holds } else { Verdict::Fails };
    let collisions: u64 = rows.iter().map(|r| r.stats.collisions).sum();
    let (inj, det): (usize, usize) = rows.iter().fold((0, 0), |a, r| (a.0 + r.stats.injected, a.1 + r.stats.detected));
    let unaware: usize = rows.iter().map(|r| r.stats.unaware).sum();
    let false_susp: f64 = rows.iter().map(|r| r.stats.mean_false_suspicions * r.stats.runs as f64).sum();
    let mut claims = vec![
        Claim {
            id: "1".into(),
            statement: "No collisions, whatever the number killed.".into(),
            criterion: "zero collisions in every run".into(),
            verdict: verdict(collisions == 0),
            evidence: rows
                .iter()
                .map(|r| {
                    format!(
                        "{}, {} killed: {} collisions in {} moves",
                        r.rules.label(),
                        r.killed,
                        r.stats.collisions,
                        r.stats.moves
                    )
                })
                .collect(),
        },
        Claim {
            id: "2".into(),
            statement: "A crashed robot that a survivor waits on is declared by it.".into(),
            criterion: "no survivor waited on a crashed robot, kept searching suspect_rounds + 1 more rounds, and \
                        never declared it (a crash far from every survivor blocks nobody and may go undeclared)"
                .into(),
            verdict: if inj == 0 { Verdict::NotEvaluated } else { verdict(unaware == 0) },
            evidence: vec![format!("{det} of {inj} crashes declared; {unaware} unaware waiters")],
        },
        Claim {
            id: "3".into(),
            statement: "No running robot is declared failed on a perfect radio.".into(),
            criterion: "zero false suspicions".into(),
            verdict: verdict(false_susp == 0.0),
            evidence: vec![format!("{false_susp:.0} false suspicions in all")],
        },
    ];
    claims.extend(Rules::BOTH.map(|rules| completes(rows, rules)));
    claims
}

/// Claim 4 under `rules`: every run complete.
fn completes(rows: &[FailureRow], rules: Rules) -> Claim {
    let mine: Vec<&FailureRow> = rows.iter().filter(|r| r.rules == rules).collect();
    let ok = mine.iter().all(|r| r.stats.completed_runs == r.stats.runs);
    Claim {
        id: format!("4 ({})", rules.label()),
        statement: format!("The survivors complete the search under the {}.", rules.label()),
        criterion: "every run complete within the round limit".into(),
        verdict: if ok { Verdict::Holds } else { Verdict::Fails },
        evidence: mine
            .iter()
            .map(|r| {
                let s = &r.stats;
                format!("{} killed: {}/{} complete ({})", r.killed, s.completed_runs, s.runs, s.endings())
            })
            .collect(),
    }
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
    fn seeds_and_csv_shape() {
        assert_ne!(run_seed(1, 0, 0), run_seed(1, 1, 0));
        assert_ne!(run_seed(1, 0, 0), run_seed(1, 0, 1));
        let row = FailureRow { rules: Rules::Paper, killed: 2, stats: ProtoStats::of(&[ProtoRun::default()]) };
        let text = csv(&[row]);
        assert_eq!(text.lines().next().unwrap(), csv_header());
        assert_eq!(text.lines().nth(1).unwrap().split(',').count(), csv_header().split(',').count());
        assert!(text.lines().nth(1).unwrap().starts_with("off,2,"), "{text}");
    }
}
