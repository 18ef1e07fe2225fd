//! Where each run of a sweep starts (`--starts`): the scenario's fixed
//! layout per robot count, or, with random starts, one layout per map,
//! robot count and run index, drawn from that run's seed before any run.
//! The seed is the same for every algorithm ([`crate::seeds`]), so every
//! algorithm of a run index meets the same layout (common random numbers)
//! and the claims' paired comparisons stay paired.

use gridswarm::grid::VertexId;
use gridswarm::scenario::{Scenario, StartRule};
use gridswarm::world::World;

use crate::contract;
use crate::error::Result;
use crate::seeds::run_seed;

/// Every run's start vertices, built once.
pub struct Layouts {
    /// `fixed[map][count]`: the scenario's layout (placed first, so a count
    /// the map cannot hold fails before any run, whatever the rule).
    fixed: Vec<Vec<Vec<VertexId>>>,
    /// Random starts: element `(map * counts + count) * runs + k`.
    drawn: Vec<Vec<VertexId>>,
    counts: usize,
    runs: usize,
}

impl Layouts {
    /// The fixed layouts `fixed[map][count]`, and with `rule` random, run
    /// `k` of map `m` (seed index `m * runs + k`, as the sweep numbers its
    /// runs) drawn from its seed under `base`.
    pub fn new(
        rule: StartRule,
        maps: &[(&Scenario, &World)],
        robots: &[usize],
        fixed: Vec<Vec<Vec<VertexId>>>,
        (base, runs): (u64, usize),
    ) -> Result<Self> {
        let mut drawn = Vec::new();
        if rule == StartRule::Random {
            for (m, (scenario, world)) in maps.iter().enumerate() {
                for &n in robots {
                    for k in 0..runs {
                        let seed = run_seed(base, n, (m * runs + k) as u64);
                        drawn.push(contract::starts(scenario, world, n, rule, seed)?);
                    }
                }
            }
        }
        Ok(Layouts { fixed, drawn, counts: robots.len(), runs })
    }

    /// Run `k` on map `m` with the `r`-th robot count.
    pub fn of(&self, m: usize, r: usize, k: usize) -> &[VertexId] {
        if self.drawn.is_empty() {
            &self.fixed[m][r]
        } else {
            &self.drawn[(m * self.counts + r) * self.runs + k]
        }
    }
}
