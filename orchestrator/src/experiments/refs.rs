//! What a sweep's cells are measured against: the oracle's mean search
//! time (a centralized plan, no lower bound) and the lower bound no run can
//! beat (`gridswarm::bound`), each cell's own, over its runs' starts. The
//! oracle's mean is an estimate when it rests on fewer runs than the cell;
//! every output says so.

use std::collections::BTreeMap;

use gridswarm::bound::lower_bound;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::world::World;
use serde::Serialize;

use crate::layouts::Layouts;
use crate::stats::CellStats;

/// The oracle's mean and the lower bounds of one sweep.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Refs {
    /// The oracle's mean search time by robot count.
    pub oracle: BTreeMap<usize, f64>,
    /// The oracle's runs behind each mean (over every map).
    pub oracle_runs: usize,
    /// Each cell's runs (over every map).
    pub cell_runs: usize,
    /// The mean lower bound over a cell's runs, by (LFP or grid, robots).
    #[serde(skip)]
    pub bound: BTreeMap<(bool, usize), f64>,
}

impl Refs {
    /// Whether `x_oracle` compares means of different runs.
    pub fn estimate(&self) -> bool {
        self.oracle_runs < self.cell_runs
    }

    /// The cell's mean search time over the oracle's at its robot count.
    pub fn x_oracle(&self, c: &CellStats) -> Option<f64> {
        Some(c.mean_search_time_s? / self.oracle.get(&c.robots).filter(|&&o| o > 0.0)?)
    }

    /// The mean lower bound over the cell's runs.
    pub fn bound(&self, c: &CellStats) -> Option<f64> {
        self.bound.get(&(c.algorithm == Policy::Lfp, c.robots)).copied()
    }

    /// The cell's mean search time over its mean bound.
    pub fn x_bound(&self, c: &CellStats) -> Option<f64> {
        Some(c.mean_search_time_s? / self.bound(c).filter(|&b| b > 0.0)?)
    }

    /// The name of the `x_oracle` column: marked `~` when an estimate.
    pub fn x_oracle_name(&self) -> &'static str {
        if self.estimate() {
            "x_oracle~"
        } else {
            "x_oracle"
        }
    }

    /// What the reference columns mean, one paragraph.
    pub fn note(&self) -> String {
        let oracle = if self.estimate() {
            format!(
                "x_oracle~ is an estimate: the oracle's mean rests on {} runs at each robot count (the first of \
                 each map), a cell's on {} (add oracle to --algorithms for the same runs)",
                self.oracle_runs, self.cell_runs
            )
        } else {
            format!("x_oracle: over the oracle's mean on the same {} runs", self.cell_runs)
        };
        format!(
            "{oracle}; bound_s: a lower bound no run can beat, mean over the cell's runs (the farthest target, \
             or in situation 2 vertex, from the nearest start at full speed: docs/paper.md, \"A lower bound\"); \
             x_bound = mean_s / bound_s\n"
        )
    }

    /// summary.json's `references`: the notes and numbers.
    pub fn json(&self) -> serde_json::Value {
        let bound = |lfp: bool| -> BTreeMap<usize, f64> {
            self.bound.iter().filter(|((l, _), _)| *l == lfp).map(|((_, n), b)| (*n, *b)).collect()
        };
        let (grid, lfp) = (bound(false), bound(true));
        serde_json::json!({
            "oracle_runs": self.oracle_runs,
            "cell_runs": self.cell_runs,
            "oracle_estimate": self.estimate(),
            "lower_bound_s": { "grid": grid, "lfp": lfp },
            "lower_bound": gridswarm::bound::NOTE,
        })
    }
}

/// The mean lower bound of each (LFP or grid, robot count) the sweep
/// runs, over every map and run index (one per map and count with fixed
/// starts: the layout is the same); missing where some run cannot finish.
pub fn bounds(
    worlds: &[World],
    starts: &Layouts,
    robots: &[usize],
    runs: usize,
    algorithms: &[Policy],
    situation: Situation,
) -> BTreeMap<(bool, usize), f64> {
    let kinds: Vec<bool> =
        [false, true].into_iter().filter(|&lfp| algorithms.iter().any(|&p| (p == Policy::Lfp) == lfp)).collect();
    let per_layout = if starts.fixed() { 1 } else { runs };
    let mut out = BTreeMap::new();
    for &lfp in &kinds {
        let policy = if lfp { Policy::Lfp } else { Policy::Repulsive };
        for (r, &n) in robots.iter().enumerate() {
            let each: Option<Vec<f64>> = (0..worlds.len())
                .flat_map(|m| (0..per_layout).map(move |k| (m, k)))
                .map(|(m, k)| lower_bound(&worlds[m], starts.of(m, r, k), situation, policy))
                .collect();
            if let Some(b) = each.as_deref().and_then(crate::stats::mean) {
                out.insert((lfp, n), b);
            }
        }
    }
    out
}
