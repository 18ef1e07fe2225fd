//! The round budget of a sweep's runs: how many rounds a run may take
//! before it ends incomplete, when `--max-rounds` does not say. A search
//! that cannot end (LFP's robots trapped in a strip of a small map, rule
//! (2) shuttling between two vertices) then costs a bounded number of
//! rounds instead of hanging the sweep, and is counted as an incomplete run
//! of its cell, left out of the means like any other.
//!
//! The rule looks at the map and the team, never at an algorithm or a
//! claim: a lone robot that visits every vertex of `Va` in turn, one vertex
//! a round, needs `|Va|` rounds (at most `2 |Va|` along a spanning tree's
//! walk); the budget is [`ROUNDS_PER_VERTEX`] times `|Va|`, `Va` being the
//! vertices the team's starts (the scenario's layout for that robot count)
//! reach, and never more than the old fixed limit
//! [`limits::DEFAULT_MAX_ROUNDS`]. The same budget holds for every
//! algorithm of a cell, LFP's sub-steps included (one a round).

use gridswarm::grid::VertexId;
use gridswarm::scenario::limits;
use gridswarm::world::World;
use serde_json::{json, Value};

/// Rounds a run gets per vertex of `Va`: fifty tours of a lone robot along
/// a spanning tree. A round number far above what any run of the default
/// Fig. 7 sweep takes (docs/paper.md, "Comparing algorithms fairly").
pub const ROUNDS_PER_VERTEX: u32 = 100;

/// The budget of a team starting at `starts`: [`ROUNDS_PER_VERTEX`] x
/// `|Va|`, at most [`limits::DEFAULT_MAX_ROUNDS`], at least one round.
pub fn rounds(world: &World, starts: &[VertexId]) -> (usize, u32) {
    let va = world.reachable_from(starts).iter().filter(|&&b| b).count();
    let budget = (va as u64 * ROUNDS_PER_VERTEX as u64).clamp(1, limits::DEFAULT_MAX_ROUNDS as u64);
    (va, budget as u32)
}

/// The budget's rule in words, as summaries record it.
pub fn rule() -> String {
    format!(
        "{ROUNDS_PER_VERTEX} rounds per vertex of Va (the vertices the scenario's layout for the team \
         reaches), at most {}, for every algorithm; --max-rounds overrides it",
        limits::DEFAULT_MAX_ROUNDS
    )
}

/// Every run's round limit in one sweep: `--max-rounds` when given, else
/// each (map, robot count)'s budget.
#[derive(Clone, Debug)]
pub struct Budgets {
    given: Option<u32>,
    /// `cells[map][count]`: `|Va|` and the budget of that team on that map.
    cells: Vec<Vec<(usize, u32)>>,
}

impl Budgets {
    /// The limits of teams starting at `fixed[map][count]` on `worlds[map]`.
    pub fn new(given: Option<u32>, worlds: &[World], fixed: &[Vec<Vec<VertexId>>]) -> Self {
        let cells = worlds.iter().zip(fixed).map(|(w, f)| f.iter().map(|s| rounds(w, s)).collect()).collect();
        Budgets { given, cells }
    }

    /// The round limit of a run on map `m` with the `r`-th robot count.
    pub fn of(&self, m: usize, r: usize) -> u32 {
        self.given.unwrap_or(self.cells[m][r].1)
    }

    /// The limits of the runs on map 0, one per robot count.
    pub fn first_map(&self) -> Vec<u32> {
        (0..self.cells.first().map_or(0, Vec::len)).map(|r| self.of(0, r)).collect()
    }

    /// The largest limit of any run.
    pub fn max(&self) -> u32 {
        self.given.unwrap_or_else(|| self.cells.iter().flatten().map(|c| c.1).max().unwrap_or(1))
    }

    /// The limit in words: `100000 rounds` when given, else the budget's
    /// rounds (or their range) and its rule.
    pub fn text(&self) -> String {
        if let Some(n) = self.given {
            return format!("{n} rounds");
        }
        let all = self.cells.iter().flatten();
        let (lo, hi) = (all.clone().map(|c| c.1).min().unwrap_or(1), self.max());
        let range = if lo == hi { lo.to_string() } else { format!("{lo}-{hi}") };
        format!(
            "{range} rounds (the round budget: {ROUNDS_PER_VERTEX} rounds a vertex of Va, at most {})",
            limits::DEFAULT_MAX_ROUNDS
        )
    }

    /// For summary.json: `null` when `--max-rounds` was given, else the
    /// rule and each robot count's `|Va|` and budget per map.
    pub fn json(&self, robots: &[usize]) -> Value {
        if self.given.is_some() {
            return Value::Null;
        }
        let per_map: Vec<Value> = self
            .cells
            .iter()
            .map(|m| robots.iter().zip(m).map(|(n, (va, b))| json!({ "robots": n, "va": va, "rounds": b })).collect())
            .collect();
        json!({
            "rule": rule(),
            "rounds_per_vertex": ROUNDS_PER_VERTEX,
            "per_map": per_map,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridswarm::scenario::Scenario;

    #[test]
    fn the_budget_is_a_multiple_of_va_and_the_flag_overrides_it() {
        let sc = Scenario::builtin("paper").unwrap();
        let w = sc.world();
        let starts = sc.start_vertices(&w, 3).unwrap();
        let va = w.reachable_from(&starts).iter().filter(|&&b| b).count();
        assert!(va > 100, "{va}");
        assert_eq!(rounds(&w, &starts), (va, va as u32 * ROUNDS_PER_VERTEX));
        let fixed = vec![vec![starts.clone()]];
        let b = Budgets::new(None, std::slice::from_ref(&w), &fixed);
        assert_eq!(b.of(0, 0), va as u32 * ROUNDS_PER_VERTEX);
        assert!(b.text().contains("round budget"), "{}", b.text());
        assert_eq!(b.json(&[3])["per_map"][0][0]["va"], va);
        let given = Budgets::new(Some(7), std::slice::from_ref(&w), &fixed);
        assert_eq!((given.of(0, 0), given.max(), given.text()), (7, 7, "7 rounds".to_string()));
        assert!(given.json(&[3]).is_null());
    }

    #[test]
    fn a_big_map_keeps_the_old_fixed_limit() {
        // `large` has thousands of vertices: 100 a vertex is past the cap.
        let sc = Scenario::builtin("large").unwrap();
        let w = sc.world();
        let starts = sc.start_vertices(&w, 2).unwrap();
        let (va, budget) = rounds(&w, &starts);
        assert!(va as u64 * ROUNDS_PER_VERTEX as u64 > limits::DEFAULT_MAX_ROUNDS as u64, "{va}");
        assert_eq!(budget, limits::DEFAULT_MAX_ROUNDS);
    }
}
