//! `gridswarm experiment readings`: the Fig. 7 sweep over a grid of the
//! readings the paper leaves open (docs/paper.md "Readings the project
//! takes"), with the three claims evaluated under every combination and
//! over several base seeds. It answers "does the paper reproduce, and under
//! which readings?" with the region of readings where all three claims
//! hold, drawn as a heat map.
//!
//! Each curve is run once per reading that changes it and the combinations
//! reuse them: the turning law changes only LFP's runs, the grid policies
//! never collide so neither reading changes them, and RU's collision
//! charge changes RU's runs and LFP's (the world charges LFP's collisions,
//! two or three a run at 13 robots, by the same rule). So 2 RU readings
//! and 6 turning laws cost 12 + 2 + 2 curves, not 12 sweeps of 4. Every
//! run's seed is the Fig. 7 sweep's ([`run_seed`]), so a combination's
//! claims are exactly those `gridswarm experiment` finds on a scenario
//! with those readings.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use gridswarm::lfp::Turn;
use gridswarm::params::{RuCollisions, Situation};
use gridswarm::policy::Policy;
use gridswarm::scenario::{Scenario, StartRule};
use gridswarm::world::World;
use plotters::style::RGBColor;
use rayon::prelude::*;
use serde_json::json;

use crate::budget::Budgets;
use crate::claims::{self, ClaimResult, Verdict};
use crate::contract::{self, Runner};
use crate::error::{Error, Result};
use crate::experiment::{place, record, Times};
use crate::heatmap::{self, Cell, Heat};
use crate::layouts::Layouts;
use crate::output;
use crate::progress::phase as progress_bar;
use crate::provenance;
use crate::report::{self, Block, Claim, Report, Section, Table};
use crate::seeds::run_seed;
use crate::staging::Staging;
use crate::stats::{CellStats, RunRecord};

pub const DEFAULT_OUT: &str = "readings-out";
/// RU's readings of "an additional move time ... for each collision".
pub const DEFAULT_RU: &str = "per-event,per-pair,back-off";
/// LFP's turning laws: the normal law's sigma over a range, and uniform.
pub const DEFAULT_TURNS: &str = "0.5,1,1.5,2,2.5,uniform";

#[derive(Clone, Debug)]
pub struct ReadingsOptions {
    pub scenario: String,
    pub robots: Vec<usize>,
    pub runs: u32,
    /// Base seeds; the whole grid is evaluated under each.
    pub seeds: Vec<u64>,
    pub ru: Vec<RuCollisions>,
    pub turns: Vec<Turn>,
    pub situation: Option<Situation>,
    /// Every run's round limit; `None`: the round budget of its robot count ([`Budgets`]).
    pub max_rounds: Option<u32>,
    pub out: PathBuf,
    pub progress: bool,
    /// Where the robots start: the scenario's layout, or drawn per run.
    pub starts: StartRule,
}

/// A turning law as the grid and `[lfp] turn` name it.
pub fn turn_name(t: Turn) -> String {
    match t {
        Turn::Uniform => "uniform".into(),
        Turn::Sigma(s) => format!("{s}"),
    }
}

/// `0.5`, `uniform`: one law of `--turns`.
pub fn parse_turn(s: &str) -> std::result::Result<Turn, String> {
    match s.trim() {
        "uniform" => Ok(Turn::Uniform),
        t => match t.parse::<f64>() {
            Ok(x) if x.is_finite() && x >= 0.0 => Ok(Turn::Sigma(x)),
            _ => Err(format!("`{t}` is neither `uniform` nor a turn sigma in radians (a number >= 0)")),
        },
    }
}

/// `per-event`, `per-pair`, `back-off`: one reading of `--ru`.
pub fn parse_ru(s: &str) -> std::result::Result<RuCollisions, String> {
    RuCollisions::from_name(s.trim())
        .ok_or_else(|| format!("`{}` is not an RU reading: one of {}", s.trim(), RuCollisions::NAMES.join(", ")))
}

/// One curve of the grid: an algorithm under the reading of its own that
/// the grid varies (none for the grid policies).
#[derive(Clone, Copy, Debug)]
struct Curve {
    policy: Policy,
    ru: Option<RuCollisions>,
    turn: Option<Turn>,
}

impl Curve {
    fn reading(&self) -> String {
        match (self.ru, self.turn) {
            (Some(r), Some(t)) => format!("ru_collisions={} turn={}", r.name(), turn_name(t)),
            (Some(r), None) => format!("ru_collisions={}", r.name()),
            _ => "-".into(),
        }
    }
}

/// Every claim's verdict under one combination and seed, and the claims.
struct Outcome {
    seed: u64,
    ru: usize,
    turn: usize,
    claims: Vec<ClaimResult>,
}

impl Outcome {
    /// (a), (b), (c), and all three together.
    fn verdicts(&self) -> [Verdict; 4] {
        let v: Vec<Verdict> = self.claims.iter().map(|c| c.verdict).collect();
        let all = if v.contains(&Verdict::NotEvaluated) { Verdict::NotEvaluated } else { Verdict::all(v.clone()) };
        [v[0], v[1], v[2], all]
    }
}

/// What the grid found.
pub struct Readings {
    /// `[seed][combination]`, combinations RU-major.
    pub verdicts: Vec<Vec<[Verdict; 4]>>,
    /// The combinations `(ru, turn)` where all three claims held at every seed.
    pub region: Vec<(RuCollisions, Turn)>,
    pub wall_time_s: f64,
}

const CLAIM_NAMES: [&str; 4] = ["(a)", "(b)", "(c)", "all three"];

pub fn run(opts: &ReadingsOptions) -> Result<(Readings, String)> {
    // The command's clock, for the wall time it prints.
    let started = Instant::now();
    check(opts)?;
    let mut scenario = contract::load_scenario(&opts.scenario)?;
    if let Some(s) = opts.situation {
        scenario.situation = s;
    }
    contract::needs_targets(&scenario, &opts.scenario)?;
    let stage = Staging::begin(&opts.out)?;
    let curves = curves(opts);
    let worlds: Vec<World> = opts.ru.iter().map(|&r| with_ru(&scenario, r).world()).collect();
    let base_world = scenario.world();
    let fixed = place(&scenario, &base_world, &opts.robots)?;
    let budgets = Budgets::new(opts.max_rounds, std::slice::from_ref(&base_world), std::slice::from_ref(&fixed));
    // One set of layouts per base seed; the RU readings' worlds differ from
    // the base world in a parameter only, so its vertices are theirs too.
    let starts = (opts.seeds.iter())
        .map(|&s| {
            Layouts::new(
                opts.starts,
                &[(&scenario, &base_world)],
                &opts.robots,
                vec![fixed.clone()],
                (s, opts.runs as usize),
            )
        })
        .collect::<Result<Vec<_>>>()?;
    let runners: Vec<Runner> = curves
        .iter()
        .map(|c| {
            let world = c.ru.map_or(&base_world, |r| &worlds[opts.ru.iter().position(|&x| x == r).unwrap_or(0)]);
            let mut lfp = contract::lfp_params(&scenario);
            if let Some(t) = c.turn {
                lfp.turn = t;
            }
            Runner::new(world, lfp)
        })
        .collect();
    let runs_started = Instant::now();
    let records = execute(opts, &curves, &runners, &starts, (scenario.situation, &budgets));
    let wall_time_s = runs_started.elapsed().as_secs_f64();
    let grid = Grid { opts, curves: &curves, records: &records, budgets: &budgets };
    let outcomes = grid.outcomes();
    let found = grid.summarise(&outcomes, wall_time_s);
    let text = grid.text(&scenario, &found);
    let out = stage.path().to_path_buf();
    let write = || -> Result<()> {
        output::write_text(&out.join("readings.csv"), &grid.verdicts_csv(&outcomes))?;
        output::write_text(&out.join("cells.csv"), &grid.cells_csv())?;
        output::write_text(&out.join("claims.txt"), &grid.claims_text(&outcomes))?;
        let path = out.join("readings.svg");
        let svg = heatmap::svg(&grid.heat(&found)).map_err(|message| Error::Plot { path, message })?;
        output::write_text(&out.join("readings.svg"), &svg)?;
        let mut summary = grid.summary(&scenario, &outcomes, &found);
        summary[provenance::KEY] = provenance::Record {
            scenario_arg: Some(&opts.scenario),
            parameters: json!({
                "robots": opts.robots,
                "runs": opts.runs,
                "ru": opts.ru,
                "turns": opts.turns,
                "situation": scenario.situation.number(),
                "max_rounds": budgets.max(),
                "params": scenario.params,
                "lfp": scenario.lfp,
            }),
            seeds: json!({ "bases": opts.seeds }),
            starts: json!({ "rule": opts.starts, "derivation": crate::experiment::START_NOTE }),
        }
        .value()?;
        output::write_json(&out.join("summary.json"), &summary)?;
        let mut page = grid.report(&summary, &outcomes, &found, svg);
        page.sections.push(provenance::section(&summary[provenance::KEY]));
        output::write_text(&out.join("report.html"), &report::render(&page))
    };
    write().and_then(|()| stage.commit()).inspect_err(|_| print!("{text}"))?;
    let times = Times { command_s: started.elapsed().as_secs_f64(), runs_s: found.wall_time_s };
    let text = format!(
        "{text}{} runs; {times} on {} threads; wrote readings.csv, cells.csv, claims.txt, readings.svg, \
         summary.json, report.html in {}\n",
        grid.records.len(),
        rayon::current_num_threads(),
        opts.out.display()
    );
    Ok((found, text))
}

fn check(opts: &ReadingsOptions) -> Result<()> {
    if opts.runs < 2 {
        return Err(Error::Input("--runs must be at least 2 (the claims need intervals)".into()));
    }
    let empty = [("--robots", opts.robots.is_empty()), ("--seeds", opts.seeds.is_empty())]
        .into_iter()
        .chain([("--ru", opts.ru.is_empty()), ("--turns", opts.turns.is_empty())]);
    for (flag, is_empty) in empty {
        if is_empty {
            return Err(Error::Usage(format!("{flag} needs at least one value")));
        }
    }
    let dup = |n: usize, names: Vec<String>| {
        let mut sorted = names.clone();
        sorted.sort();
        sorted.dedup();
        sorted.len() != n
    };
    if dup(opts.ru.len(), opts.ru.iter().map(|r| r.name().into()).collect())
        || dup(opts.turns.len(), opts.turns.iter().map(|&t| turn_name(t)).collect())
        || dup(opts.seeds.len(), opts.seeds.iter().map(u64::to_string).collect())
    {
        return Err(Error::Usage("--ru, --turns and --seeds take each value once".into()));
    }
    Ok(())
}

/// The scenario with RU's reading set.
fn with_ru(s: &Scenario, r: RuCollisions) -> Scenario {
    let mut s = s.clone();
    s.params.ru_collisions = r;
    s
}

/// LFP under each law and collision charge, RU under each charge, then the
/// grid policies: in Fig. 7's legend order.
fn curves(opts: &ReadingsOptions) -> Vec<Curve> {
    let lfp = opts
        .ru
        .iter()
        .flat_map(|&r| opts.turns.iter().map(move |&t| Curve { policy: Policy::Lfp, ru: Some(r), turn: Some(t) }));
    let ru = opts.ru.iter().map(|&r| Curve { policy: Policy::Ru, ru: Some(r), turn: None });
    let grid = [Policy::Sequential, Policy::Repulsive].map(|p| Curve { policy: p, ru: None, turn: None });
    lfp.chain(ru).chain(grid).collect()
}

/// Every run on all cores, in the order seed, curve, robot count, run.
fn execute(
    opts: &ReadingsOptions,
    curves: &[Curve],
    runners: &[Runner],
    starts: &[Layouts],
    (situation, budgets): (Situation, &Budgets),
) -> Vec<RunRecord> {
    let (nc, nr, runs) = (curves.len(), opts.robots.len(), opts.runs as usize);
    let jobs: Vec<(usize, usize, usize, usize)> = (0..opts.seeds.len())
        .flat_map(|s| (0..nc).flat_map(move |c| (0..nr).flat_map(move |r| (0..runs).map(move |k| (s, c, r, k)))))
        .collect();
    let bar = progress_bar(jobs.len() as u64, opts.progress);
    let records = jobs
        .par_iter()
        .map(|&(s, c, r, k)| {
            let seed = run_seed(opts.seeds[s], opts.robots[r], k as u64);
            let rec =
                record(&runners[c], starts[s].of(0, r, k), curves[c].policy, seed, situation, budgets.of(0, r), false);
            bar.inc(1);
            rec
        })
        .collect();
    bar.finish_and_clear();
    records
}

/// The grid's runs and the views of them.
struct Grid<'a> {
    opts: &'a ReadingsOptions,
    curves: &'a [Curve],
    records: &'a [RunRecord],
    budgets: &'a Budgets,
}

impl Grid<'_> {
    /// The runs of curve `c` at robot-count index `r` under seed index `s`.
    fn runs(&self, s: usize, c: usize, r: usize) -> &[RunRecord] {
        let (nc, nr, runs) = (self.curves.len(), self.opts.robots.len(), self.opts.runs as usize);
        &self.records[((s * nc + c) * nr + r) * runs..][..runs]
    }

    fn cell(&self, s: usize, c: usize, r: usize) -> CellStats {
        CellStats::of(self.curves[c].policy, self.opts.robots[r], self.runs(s, c, r))
    }

    /// The curve of `policy` in combination (`ru`, `turn`).
    fn curve_of(&self, policy: Policy, ru: usize, turn: usize) -> usize {
        let want = |c: &Curve| match policy {
            Policy::Lfp => c.turn == Some(self.opts.turns[turn]) && c.ru == Some(self.opts.ru[ru]),
            Policy::Ru => c.ru == Some(self.opts.ru[ru]),
            _ => true,
        };
        self.curves.iter().position(|c| c.policy == policy && want(c)).expect("every curve is run")
    }

    /// The claims of every combination under every seed.
    fn outcomes(&self) -> Vec<Outcome> {
        let mut out = Vec::new();
        for (s, &seed) in self.opts.seeds.iter().enumerate() {
            for ru in 0..self.opts.ru.len() {
                for turn in 0..self.opts.turns.len() {
                    out.push(Outcome { seed, ru, turn, claims: self.claims(s, ru, turn) });
                }
            }
        }
        out
    }

    fn claims(&self, s: usize, ru: usize, turn: usize) -> Vec<ClaimResult> {
        let order = [Policy::Lfp, Policy::Ru, Policy::Sequential, Policy::Repulsive];
        let mut cells = Vec::new();
        let mut runs = Vec::new();
        for p in order {
            let c = self.curve_of(p, ru, turn);
            for r in 0..self.opts.robots.len() {
                cells.push(self.cell(s, c, r));
                runs.push(self.runs(s, c, r));
            }
        }
        claims::evaluate(&cells, &runs)
    }

    fn summarise(&self, outcomes: &[Outcome], wall_time_s: f64) -> Readings {
        let per_seed = self.opts.ru.len() * self.opts.turns.len();
        let verdicts: Vec<Vec<[Verdict; 4]>> =
            outcomes.chunks(per_seed).map(|o| o.iter().map(Outcome::verdicts).collect()).collect();
        let region = (0..per_seed)
            .filter(|&i| verdicts.iter().all(|v| v[i][3] == Verdict::Holds))
            .map(|i| (self.opts.ru[i / self.opts.turns.len()], self.opts.turns[i % self.opts.turns.len()]))
            .collect();
        Readings { verdicts, region, wall_time_s }
    }

    /// A combination's verdicts of claim `k` over the seeds: one letter each.
    fn letters(&self, found: &Readings, i: usize, k: usize) -> String {
        found.verdicts.iter().map(|v| v[i][k].letter()).collect()
    }

    /// The verdict of claim `k` in combination `i` if every seed agrees.
    fn agreed(&self, found: &Readings, i: usize, k: usize) -> Option<Verdict> {
        let first = found.verdicts[0][i][k];
        found.verdicts.iter().all(|v| v[i][k] == first).then_some(first)
    }

    fn region_text(&self, found: &Readings) -> String {
        let seeds = if self.opts.seeds.len() > 1 { " at every seed" } else { "" };
        if found.region.is_empty() {
            return format!("No combination of the grid has all three claims holding{seeds}.\n");
        }
        let names: Vec<String> =
            found.region.iter().map(|(r, t)| format!("ru_collisions={} turn={}", r.name(), turn_name(*t))).collect();
        format!("All three claims hold{seeds} under: {}\n", names.join("; "))
    }

    fn text(&self, scenario: &Scenario, found: &Readings) -> String {
        let o = self.opts;
        let mut s = format!(
            "scenario {}, situation {}, robots {}, {} runs per cell, base seeds {}; {} curves, {} runs\n\
             verdicts: H holds, F does not hold, U not decidable at this sample size, - not evaluated{}\n\n",
            output::shown(&scenario.name),
            scenario.situation.number(),
            crate::robots::compress(&o.robots),
            o.runs,
            o.seeds.iter().map(u64::to_string).collect::<Vec<_>>().join(","),
            self.curves.len(),
            self.records.len(),
            if o.seeds.len() > 1 { " (one letter per seed)" } else { "" }
        );
        s += &report::text_table(&self.verdict_table(found));
        s += "\n";
        s += &self.region_text(found);
        s
    }

    /// One row per combination: its verdicts per claim (letters per seed),
    /// and whether the seeds agree.
    fn verdict_table(&self, found: &Readings) -> Table {
        let mut header: Vec<String> = ["RU reading", "LFP turn"].map(String::from).to_vec();
        header.extend(CLAIM_NAMES.map(String::from));
        let several = self.opts.seeds.len() > 1;
        if several {
            header.push("same at every seed".into());
        }
        let mut rows = Vec::new();
        for (i, (ru, turn)) in self.combinations().enumerate() {
            let mut row = vec![ru.name().to_string(), turn_name(turn)];
            row.extend((0..4).map(|k| self.letters(found, i, k)));
            if several {
                let same = (0..4).filter(|&k| self.agreed(found, i, k).is_some()).count();
                row.push(if same == 4 { "yes".into() } else { format!("{same} of 4") });
            }
            rows.push(row);
        }
        Table { header, rows }
    }

    fn combinations(&self) -> impl Iterator<Item = (RuCollisions, Turn)> + '_ {
        self.opts.ru.iter().flat_map(|&r| self.opts.turns.iter().map(move |&t| (r, t)))
    }

    fn verdicts_csv(&self, outcomes: &[Outcome]) -> String {
        let mut s = String::from("seed,ru_collisions,turn,claim,verdict\n");
        for o in outcomes {
            for (k, v) in o.verdicts().iter().enumerate() {
                let claim = ["a", "b", "c", "all"][k];
                let _ = writeln!(
                    s,
                    "{},{},{},{claim},{}",
                    o.seed,
                    self.opts.ru[o.ru].name(),
                    turn_name(self.opts.turns[o.turn]),
                    serde_json::to_value(v).ok().and_then(|x| x.as_str().map(String::from)).unwrap_or_default()
                );
            }
        }
        s
    }

    fn cells_csv(&self) -> String {
        let mut s = String::from(
            "seed,algorithm,reading,robots,runs,completed_runs,mean_search_time_s,std_search_time_s,ci95_s,\
             mean_rounds,mean_collisions,median_search_time_s\n",
        );
        let n = output::csv_num;
        for (si, seed) in self.opts.seeds.iter().enumerate() {
            for (c, curve) in self.curves.iter().enumerate() {
                for r in 0..self.opts.robots.len() {
                    let x = self.cell(si, c, r);
                    let _ = writeln!(
                        s,
                        "{seed},{},{},{},{},{},{},{},{},{},{},{}",
                        curve.policy.name(),
                        curve.reading(),
                        x.robots,
                        x.runs,
                        x.completed_runs,
                        n(x.mean_search_time_s),
                        n(x.std_search_time_s),
                        n(x.ci95_s),
                        n(x.mean_rounds),
                        n(x.mean_collisions),
                        n(x.median_search_time_s)
                    );
                }
            }
        }
        s
    }

    fn claims_text(&self, outcomes: &[Outcome]) -> String {
        let mut s = String::new();
        for o in outcomes {
            let _ = writeln!(
                s,
                "=== seed {}, ru_collisions = {}, turn = {}\n{}",
                o.seed,
                self.opts.ru[o.ru].name(),
                turn_name(self.opts.turns[o.turn]),
                claims::render(&o.claims)
            );
        }
        s
    }

    /// Claims (rows, per RU reading) against LFP's turning law (columns).
    fn heat(&self, found: &Readings) -> Heat {
        let nt = self.opts.turns.len();
        let mut cells = Vec::new();
        for ru in 0..self.opts.ru.len() {
            for k in 0..4 {
                cells.push(
                    (0..nt)
                        .map(|t| {
                            let i = ru * nt + t;
                            let text = if self.opts.seeds.len() == 1 {
                                word(found.verdicts[0][i][k]).to_string()
                            } else {
                                self.letters(found, i, k)
                            };
                            Cell { fill: colour(self.agreed(found, i, k)), text }
                        })
                        .collect(),
                );
            }
        }
        Heat {
            title: format!("Fig. 7's claims under the readings ({} runs a cell)", self.opts.runs),
            columns_desc: "LFP: turning law (sigma of the normal turn in rad, or uniform)".into(),
            columns: self.opts.turns.iter().map(|&t| turn_name(t)).collect(),
            rows: self.opts.ru.iter().flat_map(|r| CLAIM_NAMES.map(|c| format!("RU {}: {c}", r.name()))).collect(),
            cells,
            legend: legend(self.opts.seeds.len()),
        }
    }

    fn summary(&self, scenario: &Scenario, outcomes: &[Outcome], found: &Readings) -> serde_json::Value {
        let o = self.opts;
        json!({
            "scenario": scenario.name,
            "situation": scenario.situation.number(),
            "robots": o.robots,
            "runs": o.runs,
            "seeds": o.seeds,
            "seed_derivation": "run k with N robots under base seed S has seed derive(derive(S, N), k), the same for \
                every algorithm and reading (as gridswarm experiment)",
            "ru_readings": o.ru.iter().map(|r| r.name()).collect::<Vec<_>>(),
            "turns": o.turns.iter().map(|&t| turn_name(t)).collect::<Vec<_>>(),
            "max_rounds": self.budgets.max(),
            "round_budget": self.budgets.json(&o.robots),
            "starts": o.starts,
            "params": varied(json!(scenario.params), "ru_collisions", "varied: see ru_readings"),
            "lfp": varied(json!(scenario.lfp), "turn", "varied: see turns"),
            "region_all_three_hold": found.region.iter().map(|(r, t)| json!({"ru_collisions": r.name(), "turn": turn_name(*t)})).collect::<Vec<_>>(),
            "wall_time_s": found.wall_time_s,
            "outcomes": outcomes.iter().map(|x| json!({
                "seed": x.seed, "ru_collisions": o.ru[x.ru].name(), "turn": turn_name(o.turns[x.turn]),
                "verdicts": x.verdicts(), "claims": x.claims,
            })).collect::<Vec<_>>(),
        })
    }

    fn report(&self, summary: &serde_json::Value, outcomes: &[Outcome], found: &Readings, svg: String) -> Report {
        let mut setup: Vec<(String, String)> = [
            "scenario",
            "situation",
            "robots",
            "runs",
            "seeds",
            "seed_derivation",
            "ru_readings",
            "turns",
            "max_rounds",
        ]
        .iter()
        .map(|k| (k.to_string(), summary[*k].to_string()))
        .collect();
        setup.extend(report::params_of("params", &summary["params"]));
        setup.extend(report::params_of("lfp", &summary["lfp"]));
        let first = &outcomes[..self.opts.ru.len() * self.opts.turns.len()];
        let claims = first.iter().map(|o| {
            Section::new(
                format!(
                    "Seed {}: RU {}, LFP turn {}",
                    o.seed,
                    self.opts.ru[o.ru].name(),
                    turn_name(self.opts.turns[o.turn])
                ),
                vec![Block::Claims(o.claims.iter().map(Claim::from).collect())],
            )
        });
        let mut sections = vec![
            Section::new(
                "Where the claims hold",
                vec![
                    Block::Figure {
                        svg,
                        caption: "Each claim's verdict under every combination of RU's reading (rows) and LFP's \
                                  turning law (columns); with several seeds one letter per seed, and the colour only \
                                  where every seed agrees."
                            .into(),
                    },
                    Block::Text(self.region_text(found)),
                    Block::Table(self.verdict_table(found)),
                ],
            ),
            Section::new("Setup", vec![Block::Params(setup)]),
        ];
        sections.extend(claims);
        sections.push(Section::new(
            "Files",
            vec![Block::Files(
                [
                    ("readings.csv", "every verdict by seed, RU reading, turning law and claim"),
                    ("cells.csv", "every curve's cells: mean, interval, rounds, collisions"),
                    ("claims.txt", "every combination's claims with their evidence, for every seed"),
                    ("summary.json", "all of the above as data, with every parameter"),
                ]
                .map(|(a, b)| (a.to_string(), b.to_string()))
                .to_vec(),
            )],
        ));
        Report {
            title: "Fig. 7's claims under the paper's readings".into(),
            subtitle: format!("the {} runs took {:.1} s of wall time", self.records.len(), found.wall_time_s),
            sections,
        }
    }
}

/// `v` with `key` replaced by `note`: a parameter the grid sets per curve.
fn varied(mut v: serde_json::Value, key: &str, note: &str) -> serde_json::Value {
    v[key] = note.into();
    v
}

const HOLDS: RGBColor = RGBColor(0x2c, 0xa0, 0x2c);
const FAILS: RGBColor = RGBColor(0xd6, 0x27, 0x28);
const UNDECIDED: RGBColor = RGBColor(0xe6, 0xa1, 0x00);
const NOT_EVALUATED: RGBColor = RGBColor(0x99, 0x99, 0x99);
const VARIES: RGBColor = RGBColor(0x94, 0x67, 0xbd);

/// A verdict's colour; `None`: the seeds disagree.
fn colour(v: Option<Verdict>) -> RGBColor {
    match v {
        Some(Verdict::Holds) => HOLDS,
        Some(Verdict::Fails) => FAILS,
        Some(Verdict::Undecided) => UNDECIDED,
        Some(Verdict::NotEvaluated) => NOT_EVALUATED,
        None => VARIES,
    }
}

fn word(v: Verdict) -> &'static str {
    match v {
        Verdict::Holds => "holds",
        Verdict::Fails => "fails",
        Verdict::Undecided => "undecided",
        Verdict::NotEvaluated => "-",
    }
}

fn legend(seeds: usize) -> Vec<(RGBColor, String)> {
    let mut v = vec![
        (HOLDS, "holds beyond the 95% intervals".to_string()),
        (FAILS, "does not hold beyond them".to_string()),
        (UNDECIDED, "not decidable at this sample size".to_string()),
        (NOT_EVALUATED, "not evaluated (the sweep lacks what it needs)".to_string()),
    ];
    if seeds > 1 {
        v.push((VARIES, "the verdict changes with the seed (letters: H, F, U per seed)".to_string()));
    }
    v
}
