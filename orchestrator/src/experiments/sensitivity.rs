//! How much a sweep's result depends on the readings of the paper that the
//! project had to choose (docs/paper.md, "Readings the project takes"): for
//! each baseline in the sweep whose reading is switchable, the first runs of
//! every robot count again under the other reading, paired with the same
//! runs under the scenario's own. Shown in report.html next to the results.
//! It changes one reading at a time on a few runs and judges no claim:
//! `experiment readings` ([`crate::readings`]) re-evaluates the claims over
//! a grid of readings at full size.

use gridswarm::lfp::{RepelRange, Turn};
use gridswarm::outcome::RunConfig;
use gridswarm::params::{RuCollisions, Situation};
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;
use gridswarm::world::World;
use rayon::prelude::*;
use serde::Serialize;

use crate::contract::Runner;
use crate::layouts::Layouts;
use crate::seeds::run_seed;

/// Runs per robot count and alternative reading: enough to see a factor,
/// cheap next to the sweep (its first runs, on its seeds and starts).
pub const RUNS: usize = 20;

/// One alternative reading at one robot count.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub algorithm: Policy,
    /// The alternative, as the scenario would set it (`ru_collisions = "back-off"`).
    pub reading: &'static str,
    pub robots: usize,
    pub runs: usize,
    /// Mean search time over the completed runs under the scenario's reading.
    pub scenario_s: Option<f64>,
    /// The same runs under the alternative.
    pub alternative_s: Option<f64>,
}

/// A reading to compare against the scenario's own, as a change to a copy
/// of the scenario.
struct Alternative {
    algorithm: Policy,
    reading: &'static str,
    apply: fn(&mut Scenario),
}

const ALTERNATIVES: [Alternative; 6] = [
    Alternative {
        algorithm: Policy::Ru,
        reading: "ru_collisions = \"per-event\"",
        apply: |s| s.params.ru_collisions = RuCollisions::PerEvent,
    },
    Alternative {
        algorithm: Policy::Ru,
        reading: "ru_collisions = \"back-off\"",
        apply: |s| s.params.ru_collisions = RuCollisions::BackOff,
    },
    Alternative {
        algorithm: Policy::Ru,
        reading: "ru_collisions = \"per-pair\"",
        apply: |s| s.params.ru_collisions = RuCollisions::PerPair,
    },
    Alternative { algorithm: Policy::Lfp, reading: "turn = \"uniform\"", apply: |s| s.lfp.turn = Turn::Uniform },
    Alternative { algorithm: Policy::Lfp, reading: "turn = 0.5", apply: |s| s.lfp.turn = Turn::Sigma(0.5) },
    Alternative {
        algorithm: Policy::Lfp,
        reading: "repel_range = \"radio\"",
        apply: |s| s.lfp.repel_range = RepelRange::Radio,
    },
];

/// The sweep whose readings are varied: its first map's scenario and
/// world, starts (map 0's of [`Layouts`]), seed and round limits (one per
/// robot count, as the sweep's runs on map 0 have them).
pub struct Sweep<'a> {
    pub scenario: &'a Scenario,
    pub world: &'a World,
    pub robots: &'a [usize],
    pub starts: &'a Layouts,
    pub seed: u64,
    pub max_rounds: &'a [u32],
}

/// Every alternative reading of an algorithm the sweep ran, at every robot
/// count, on the sweep's first `runs` runs (at most [`RUNS`]).
/// `scenario_mean(algorithm, r)` is the mean of those same runs under the
/// scenario's own reading, which the sweep already ran: they are not run
/// again. An alternative the scenario already uses is skipped.
pub fn run(
    sweep: &Sweep,
    algorithms: &[Policy],
    runs: usize,
    scenario_mean: impl Fn(Policy, usize) -> Option<f64>,
) -> Vec<Row> {
    let scenario = sweep.scenario;
    let mut rows = Vec::new();
    for alt in ALTERNATIVES.iter().filter(|a| algorithms.contains(&a.algorithm)) {
        let mut other = scenario.clone();
        (alt.apply)(&mut other);
        if other.params == scenario.params && other.lfp == scenario.lfp {
            continue;
        }
        // Only a change of `[params]` changes the world.
        let own_world = (other.params != scenario.params).then(|| other.world());
        let changed = Runner::new(own_world.as_ref().unwrap_or(sweep.world), other.lfp);
        for (r, &n) in sweep.robots.iter().enumerate() {
            // Counted in the progress lines, drawn as no bar of its own.
            let bar = crate::progress::phase(runs as u64, false);
            let times: Vec<f64> = (0..runs)
                .into_par_iter()
                .filter_map(|k| {
                    let seed = run_seed(sweep.seed, n, k as u64);
                    let cfg = config(alt.algorithm, seed, scenario.situation, sweep.max_rounds[r]);
                    let res = changed.run(sweep.starts.of(0, r, k), &cfg);
                    bar.inc(1);
                    res.complete.then_some(res.search_time_s)
                })
                .collect();
            rows.push(Row {
                algorithm: alt.algorithm,
                reading: alt.reading,
                robots: n,
                runs,
                scenario_s: scenario_mean(alt.algorithm, r),
                alternative_s: (!times.is_empty()).then(|| times.iter().sum::<f64>() / times.len() as f64),
            });
        }
    }
    rows
}

fn config(policy: Policy, seed: u64, situation: Situation, max_rounds: u32) -> RunConfig {
    let mut cfg = RunConfig::new(policy, seed, situation);
    cfg.max_rounds = max_rounds;
    cfg.record_trajectories = false;
    cfg.measure_coverage = false;
    cfg
}
