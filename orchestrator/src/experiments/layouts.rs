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

    /// Whether every run of a map and robot count starts alike.
    pub fn fixed(&self) -> bool {
        self.drawn.is_empty()
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_layouts_are_each_runs_own_draw_and_fixed_ones_the_scenarios() {
        let sc = Scenario::builtin("paper").unwrap();
        let w = sc.world();
        let robots = [3, 5];
        let fixed: Vec<Vec<VertexId>> = robots.iter().map(|&n| sc.start_vertices(&w, n).unwrap()).collect();
        let maps = [(&sc, &w), (&sc, &w)];
        let random = Layouts::new(StartRule::Random, &maps, &robots, vec![fixed.clone(); 2], (7, 4)).unwrap();
        let same = Layouts::new(StartRule::Fixed, &maps, &robots, vec![fixed.clone(); 2], (7, 4)).unwrap();
        for (m, r, k) in [(0, 0, 0), (0, 1, 3), (1, 0, 2), (1, 1, 1)] {
            let seed = run_seed(7, robots[r], (m * 4 + k) as u64);
            assert_eq!(random.of(m, r, k), sc.starts_by(&w, robots[r], StartRule::Random, seed).unwrap());
            assert_eq!(same.of(m, r, k), fixed[r]);
        }
        assert_ne!(random.of(0, 1, 0), random.of(0, 1, 1), "each run index its own layout");
        assert_ne!(random.of(0, 1, 0), random.of(1, 1, 0), "map 1 continues the run index");
    }
}
