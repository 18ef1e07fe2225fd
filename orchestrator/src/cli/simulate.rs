//! `gridswarm simulate`: one in-process run, with the same failure and
//! radio flags as `run` ([`crate::faults`]), a short summary or one JSON
//! object on stdout, and optionally its files (summary, trajectories,
//! route map, replay).

use std::path::PathBuf;

use gridswarm::agreement::{Agreement, ScenarioId};
use gridswarm::outcome::RunConfig;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::scenario::limits;
use gridswarm::world::World;
use serde_json::json;

use crate::cli::view::ViewFlags;
use crate::contract::{self, Runner};
use crate::error::{Error, Result};
use crate::faults::FaultPlan;
use crate::rundir::{self, RunRecord};
use crate::staging::Staging;
use crate::{check, output, provenance};

#[derive(Clone, Debug)]
pub struct SimulateOptions {
    pub scenario: String,
    pub algorithm: Policy,
    /// Robot count; the scenario's own when `None`.
    pub robots: Option<usize>,
    pub seed: u64,
    /// The scenario's own when `None`.
    pub situation: Option<Situation>,
    pub out: Option<PathBuf>,
    pub json: bool,
    /// The round limit; `None` derives it from the work budget
    /// ([`round_limit`]).
    pub max_rounds: Option<u32>,
    /// Faults and radio impairments (grid policies only).
    pub faults: FaultPlan,
    /// `--mcap`, `--live`.
    pub view: ViewFlags,
}

/// Runs once; returns the text for stdout (warnings go to stderr directly)
/// and the exit status ([`crate::error::search_status`]).
pub fn simulate(opts: &SimulateOptions) -> Result<(String, u8)> {
    let mut scenario = contract::load_scenario(&opts.scenario)?;
    let scenario_id = ScenarioId::of(&scenario);
    if let Some(s) = opts.situation {
        scenario.situation = s;
    }
    contract::needs_targets(&scenario, &opts.scenario)?;
    let robots = opts.robots.unwrap_or(scenario.robots);
    if robots == 0 {
        return Err(Error::Input("at least 1 robot is needed".into()));
    }
    if opts.algorithm.on_grid() {
        // A name only an --agent-bin program can run.
        gridswarm::choice::registry::runnable(opts.algorithm).map_err(Error::Usage)?;
    }
    opts.view.check(opts.algorithm)?;
    let mut cfg = RunConfig::new(opts.algorithm, opts.seed, scenario.situation);
    // Usage errors before anything is created.
    opts.faults.configure(&mut cfg, robots)?;
    opts.faults.apply_params(&mut scenario.params);
    // Before the run, so a bad directory fails at once.
    let stage = opts.out.as_deref().map(Staging::begin).transpose()?;
    let world = scenario.world();
    // Before the assumption checks, which are dear on a big map.
    let frames = limits::frame_factor(cfg.radio.is_perfect(), cfg.radio.dup);
    let (max_rounds, budget) =
        round_limit(opts.max_rounds, &world, robots, opts.algorithm, frames).map_err(Error::Input)?;
    let starts = contract::starts(&scenario, &world, robots, opts.faults.starts, opts.seed)?;
    let report = contract::check_assumptions(&scenario, &world, &starts);
    check::refuse(&report, opts.algorithm)?;
    for w in check::warnings(&report) {
        eprintln!("{w}");
    }
    let lfp = contract::lfp_params(&scenario);
    cfg.max_rounds = max_rounds;
    cfg.record_trajectories = opts.out.is_some();
    cfg.measure_coverage = true;
    let (result, viewed) = match opts.view.any() {
        true => opts.view.run(&world, &starts, &cfg)?,
        false => (Runner::new(&world, lfp).run(&starts, &cfg), Vec::new()),
    };
    // What a distributed run's processes would have agreed on; no key.
    let mut agreement = json!(Agreement::of("", scenario_id, &cfg.robot_setup(&world, 0, robots)));
    agreement["key"] = serde_json::Value::Null;
    let extra = json!({
        "engine": "in-process",
        "transport": {
            "name": "in-process",
            "endpoints": [],
            "remote_agents": false,
            "security": crate::run::security(None),
        },
        "agreement": agreement,
        "max_rounds": max_rounds,
        "radio": cfg.radio,
        "retries": world.params.retries,
        "faults": gridswarm::sim::schedule::to_args(&cfg.faults),
        "start_rule": opts.faults.starts,
        "provenance": provenance::of_run(&opts.scenario, &world, &starts, opts.faults.starts, opts.seed, json!({
            "algorithm": opts.algorithm,
            "robots": robots,
            "situation": scenario.situation.number(),
            "max_rounds": max_rounds,
            "params": world.params,
            "lfp": lfp,
            "radio": cfg.radio,
            "faults": gridswarm::sim::schedule::to_args(&cfg.faults),
        }))?,
    });
    let record = RunRecord { scenario: &scenario, world: &world, starts: &starts, lfp: &lfp, result: &result, extra };
    let summary = record.summary();
    let mut written = match stage {
        Some(stage) => rundir::write_staged(stage, &record)?,
        None => Vec::new(),
    };
    written.extend(viewed);

    // Said even with --json (on stderr there), so a cut run is never a
    // silent mystery.
    let note = budget.filter(|_| result.protocol.ended_by == "max_rounds").map(|b| b.note(max_rounds));
    if opts.json {
        if let Some(n) = &note {
            eprint!("{n}");
        }
        return Ok((
            format!("{}\n", serde_json::to_string(&summary).expect("a JSON value serialises")),
            crate::error::search_status(&result),
        ));
    }
    let mut text = output::headline(&scenario, &result, "", "");
    text += note.as_deref().unwrap_or("");
    for p in written {
        text += &format!("wrote {}\n", p.display());
    }
    Ok((text, crate::error::search_status(&result)))
}

/// A round limit the work budget lowered: what it was lowered from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budgeted {
    /// One round's work, in [`limits::MAX_SEARCH_WORK`]'s units.
    pub round_work: f64,
}

impl Budgeted {
    /// The line that says why the run stopped where it did and how to go on.
    pub fn note(&self, max_rounds: u32) -> String {
        format!(
            "note: stopped at the round limit {max_rounds} set by the work budget MAX_SEARCH_WORK = {:e} \
             ({:.3e} a round, as docs/scenario-format.md counts it); \
             ask for more with --max-rounds N (default {})\n",
            limits::MAX_SEARCH_WORK,
            self.round_work,
            limits::DEFAULT_MAX_ROUNDS
        )
    }
}

/// The run's round limit: the command line's, else the default lowered to
/// fit the work budget, with what lowered it (`None` when nothing did); an
/// error when not one round fits.
pub fn round_limit(
    given: Option<u32>,
    world: &World,
    robots: usize,
    algorithm: Policy,
    frames: f64,
) -> std::result::Result<(u32, Option<Budgeted>), String> {
    if let Some(n) = given {
        return Ok((n, None));
    }
    let p = &world.params;
    let round_work = if algorithm == Policy::Lfp {
        limits::lfp_round_work(robots)
    } else {
        let heard = limits::hearable(robots, p.r_c, p.a, world.grid.lattice.kind);
        limits::round_work(robots, world.grid.len() as f64, heard, frames)
    };
    let n = limits::round_limit(round_work)?;
    Ok((n, (n < limits::DEFAULT_MAX_ROUNDS).then_some(Budgeted { round_work })))
}
