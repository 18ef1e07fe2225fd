//! `gridswarm simulate`: one in-process run, with the same failure and
//! radio flags as `run` ([`crate::faults`]), a short summary or one JSON
//! object on stdout, and optionally its files (summary, trajectories,
//! route map, replay).

use std::path::PathBuf;

use gridswarm::outcome::RunConfig;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use serde_json::json;

use crate::contract::{self, Runner};
use crate::error::{Error, Result};
use crate::faults::FaultPlan;
use crate::rundir::{self, RunRecord};
use crate::staging::Staging;
use crate::{check, output};

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
    pub max_rounds: u32,
    /// Faults and radio impairments (grid policies only).
    pub faults: FaultPlan,
}

/// Runs once; returns the text for stdout (warnings go to stderr directly)
/// and whether the search completed.
pub fn simulate(opts: &SimulateOptions) -> Result<(String, bool)> {
    let mut scenario = contract::load_scenario(&opts.scenario)?;
    if let Some(s) = opts.situation {
        scenario.situation = s;
    }
    let robots = opts.robots.unwrap_or(scenario.robots);
    if robots == 0 {
        return Err(Error::Input("at least 1 robot is needed".into()));
    }
    if opts.algorithm.on_grid() {
        // A name only an --agent-bin program can run.
        gridswarm::choice::registry::runnable(opts.algorithm).map_err(Error::Usage)?;
    }
    let mut cfg = RunConfig::new(opts.algorithm, opts.seed, scenario.situation);
    // Usage errors before anything is created.
    opts.faults.configure(&mut cfg, robots)?;
    opts.faults.apply_params(&mut scenario.params);
    // Before the run, so a bad directory fails at once.
    let stage = opts.out.as_deref().map(Staging::begin).transpose()?;
    let world = scenario.world();
    let starts = contract::start_vertices(&scenario, &world, robots)?;
    for w in check::warnings(&contract::check_assumptions(&scenario, &world, &starts)) {
        eprintln!("{w}");
    }
    let lfp = contract::lfp_params(&scenario);
    cfg.max_rounds = opts.max_rounds;
    cfg.record_trajectories = opts.out.is_some();
    cfg.measure_coverage = true;
    let result = Runner::new(&world, lfp).run(&starts, &cfg);
    let extra = json!({
        "engine": "in-process",
        "max_rounds": opts.max_rounds,
        "radio": cfg.radio,
        "retries": world.params.retries,
        "faults": gridswarm::sim::schedule::to_args(&cfg.faults),
    });
    let record = RunRecord { scenario: &scenario, world: &world, starts: &starts, lfp: &lfp, result: &result, extra };
    let summary = record.summary();
    let written = match stage {
        Some(stage) => rundir::write_staged(stage, &record)?,
        None => Vec::new(),
    };

    if opts.json {
        return Ok((format!("{}\n", serde_json::to_string(&summary).expect("a JSON value serialises")), result.complete));
    }
    let mut text = output::headline(&scenario, &result, "", "");
    for p in written {
        text += &format!("wrote {}\n", p.display());
    }
    Ok((text, result.complete))
}
