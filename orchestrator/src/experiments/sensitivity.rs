//! How much a sweep's result depends on the readings of the paper that the
//! project had to choose (docs/paper.md, "Readings the project takes"): for
//! each baseline in the sweep whose reading is switchable, the first runs of
//! every robot count again under the other reading, paired with the same
//! runs under the scenario's own. Shown in report.html next to the results.

use gridswarm::grid::VertexId;
use gridswarm::lfp::{RepelRange, Turn};
use gridswarm::outcome::RunConfig;
use gridswarm::params::{RuCollisions, Situation};
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;
use rayon::prelude::*;
use serde::Serialize;

use crate::contract::Runner;
use crate::seeds::run_seed;

/// Runs per robot count and reading: enough to see a factor, cheap next to
/// the sweep (its first runs, on its seeds and starts).
pub const RUNS: usize = 20;

/// One alternative reading at one robot count.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub algorithm: Policy,
    /// The alternative, as the scenario would set it (`ru_collisions = "per-pair"`).
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

const ALTERNATIVES: [Alternative; 3] = [
    Alternative {
        algorithm: Policy::Ru,
        reading: "ru_collisions = \"per-pair\"",
        apply: |s| s.params.ru_collisions = RuCollisions::PerPair,
    },
    Alternative { algorithm: Policy::Lfp, reading: "turn = 0.5", apply: |s| s.lfp.turn = Turn::Sigma(0.5) },
    Alternative { algorithm: Policy::Lfp, reading: "repel_range = \"radio\"", apply: |s| s.lfp.repel_range = RepelRange::Radio },
];

/// Every alternative reading of an algorithm in `algorithms`, at every
/// robot count (`starts[r]` for `robots[r]`), on `scenario`. An alternative
/// the scenario already uses is skipped.
pub fn run(
    scenario: &Scenario,
    algorithms: &[Policy],
    robots: &[usize],
    starts: &[Vec<VertexId>],
    seed: u64,
    max_rounds: u32,
) -> Vec<Row> {
    let runs = RUNS;
    let mut rows = Vec::new();
    for alt in ALTERNATIVES.iter().filter(|a| algorithms.contains(&a.algorithm)) {
        let mut other = scenario.clone();
        (alt.apply)(&mut other);
        if other.params == scenario.params && other.lfp == scenario.lfp {
            continue;
        }
        let (w0, w1) = (scenario.world(), other.world());
        let (base, changed) = (Runner::new(&w0, scenario.lfp), Runner::new(&w1, other.lfp));
        for (r, &n) in robots.iter().enumerate() {
            let mean = |runner: &Runner| -> Option<f64> {
                let times: Vec<f64> = (0..runs)
                    .into_par_iter()
                    .filter_map(|k| {
                        let cfg = config(alt.algorithm, run_seed(seed, n, k as u64), scenario.situation, max_rounds);
                        let res = runner.run(&starts[r], &cfg);
                        res.complete.then_some(res.search_time_s)
                    })
                    .collect();
                (!times.is_empty()).then(|| times.iter().sum::<f64>() / times.len() as f64)
            };
            rows.push(Row {
                algorithm: alt.algorithm,
                reading: alt.reading,
                robots: n,
                runs,
                scenario_s: mean(&base),
                alternative_s: mean(&changed),
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
