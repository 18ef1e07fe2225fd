//! Placing robots on start vertices (Assumption 2.2: "allocated at different
//! vertices along the border of the area"): the scenario's own layout
//! ([`StartRule::Fixed`], Fig. 5), or one drawn from the run's seed
//! ([`StartRule::Random`]), so that a Monte Carlo result is not conditional
//! on one layout.

use std::collections::VecDeque;

use rand::seq::index;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use super::ScenarioError;
use crate::geometry::Point;
use crate::grid::{VertexId, NONE};
use crate::world::World;

/// How a run places its robots (`--starts`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StartRule {
    /// The scenario's `[starts]`: the same vertices in every run (Fig. 5).
    #[default]
    Fixed,
    /// Distinct vertices drawn from the run's seed alone: on the scenario's
    /// start region (the border, for a `border` rule) when it holds the
    /// robots, else anywhere accessible, always in the part of the map the
    /// fixed layout reaches. Runs sharing a seed share their starts, so a
    /// sweep's algorithms meet the same layouts (common random numbers).
    Random,
}

impl StartRule {
    pub const NAMES: [&'static str; 2] = ["fixed", "random"];

    pub fn name(self) -> &'static str {
        match self {
            StartRule::Fixed => "fixed",
            StartRule::Random => "random",
        }
    }
}

impl std::fmt::Display for StartRule {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A command-line value (`--starts`), one parser for every program.
impl std::str::FromStr for StartRule {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "fixed" => Ok(StartRule::Fixed),
            "random" => Ok(StartRule::Random),
            _ => Err(format!("`{s}`: one of {}", StartRule::NAMES.join(", "))),
        }
    }
}

/// The label that separates the starts' stream from every other stream
/// drawn from a run's seed (the robots' own use `rng::robot_rng`).
const STARTS_LABEL: u64 = 0x5354_4152_5453; // "STARTS"

/// `robots` distinct vertices drawn from `seed` among the vertices `fixed`
/// reaches: on the border when `border_only` and the border holds them,
/// else anywhere. Robot `k` gets the `k`-th draw. The same seed, world and
/// count give the same vertices on every machine (ChaCha8, vertex ids).
pub(crate) fn random(w: &World, fixed: &[VertexId], robots: usize, border_only: bool, seed: u64) -> Vec<VertexId> {
    let reach = w.reachable_from(fixed);
    let all: Vec<VertexId> = (0..w.grid.len() as VertexId).filter(|&v| reach[v as usize]).collect();
    let edge: Vec<VertexId> = all.iter().copied().filter(|&v| on_border(w, v)).collect();
    // `fixed` already proved `all` holds the robots.
    let pool = if border_only && edge.len() >= robots { edge } else { all };
    let mut rng = ChaCha8Rng::seed_from_u64(crate::rng::derive(seed, STARTS_LABEL));
    index::sample(&mut rng, pool.len(), robots).into_iter().map(|i| pool[i]).collect()
}

/// Whether `v` is on the border: accessible, missing a usable neighbour in
/// some slot, and near the area's own boundary. The distance test keeps the
/// ring around an obstacle out, so robots start along the edge of the area
/// as the paper's Fig. 5 shows, not around an obstacle in the middle.
fn on_border(w: &World, v: VertexId) -> bool {
    if !w.is_accessible(v) {
        return false;
    }
    let g = &w.grid;
    let blocked = g.neighbors(v)[..g.degree()].iter().any(|&n| n == NONE || !w.is_accessible(n));
    blocked && w.area.boundary_distance(g.position(v)) <= w.params.a + w.params.r_safe + 1e-9
}

/// `robots` distinct vertices that form a chain along the border, beginning
/// at the border vertex nearest to `from`: breadth-first over traversable
/// edges between border vertices, so every vertex taken is adjacent to one
/// taken before it. If the border is too short the search goes on over all of
/// `Va`. Ties go to the lower vertex id and neighbours are visited in slot
/// order, so the result depends on nothing but the world.
pub(crate) fn border(w: &World, from: Point, robots: usize, file: &str) -> Result<Vec<VertexId>, ScenarioError> {
    let g = &w.grid;
    let err = |msg: String| ScenarioError::new(file, None, "starts.border", msg);
    let border: Vec<bool> = (0..g.len() as VertexId).map(|v| on_border(w, v)).collect();
    let first = (0..g.len() as VertexId)
        .filter(|&v| border[v as usize])
        .min_by(|&u, &v| (g.position(u) - from).norm().total_cmp(&(g.position(v) - from).norm()))
        .ok_or_else(|| err("the area has no accessible vertex along its border".into()))?;
    let va = w.reachable_from(&[first]);
    let va_len = va.iter().filter(|&&b| b).count();
    if va_len < robots {
        let p = g.position(first);
        return Err(err(format!(
            "robots = {robots} but only {va_len} vertices are reachable from the border vertex ({:.2}, {:.2}) nearest to ({}, {})",
            p.x, p.y, from.x, from.y
        )));
    }

    let mut taken = Vec::with_capacity(robots);
    let mut seen = vec![false; g.len()];
    let bfs = |queue: &mut VecDeque<VertexId>, seen: &mut Vec<bool>, taken: &mut Vec<VertexId>, only_border: bool| {
        while let Some(v) = queue.pop_front() {
            if taken.len() == robots {
                return;
            }
            taken.push(v);
            for (d, &n) in g.neighbors(v)[..g.degree()].iter().enumerate() {
                if w.open_mask(v) >> d & 1 == 1 && !seen[n as usize] && (!only_border || border[n as usize]) {
                    seen[n as usize] = true;
                    queue.push_back(n);
                }
            }
        }
    };
    seen[first as usize] = true;
    bfs(&mut VecDeque::from([first]), &mut seen, &mut taken, true);
    if taken.len() < robots {
        // The border chain ran out: grow from every vertex taken so far, in
        // the order taken, over all of Va. Vertices queued but not taken in
        // the first pass cannot exist (it ended with an empty queue).
        let mut queue = VecDeque::new();
        let already = taken.clone();
        taken.clear();
        seen.iter_mut().for_each(|s| *s = false);
        for &v in &already {
            seen[v as usize] = true;
            queue.push_back(v);
        }
        bfs(&mut queue, &mut seen, &mut taken, false);
    }
    debug_assert_eq!(taken.len(), robots);
    Ok(taken)
}

/// The first `robots` given points, each snapped to its nearest vertex.
pub(crate) fn points(w: &World, pts: &[Point], robots: usize, file: &str) -> Result<Vec<VertexId>, ScenarioError> {
    if pts.len() < robots {
        return Err(ScenarioError::new(
            file,
            None,
            "starts.points",
            format!("{} start points for {robots} robots: give at least one point per robot", pts.len()),
        ));
    }
    let mut out: Vec<VertexId> = Vec::with_capacity(robots);
    for (k, &p) in pts[..robots].iter().enumerate() {
        let field = format!("starts.points[{k}]");
        let v = w.grid.nearest(p).filter(|&v| w.is_accessible(v)).ok_or_else(|| {
            ScenarioError::new(
                file,
                None,
                field.clone(),
                format!("the vertex nearest to ({}, {}) is not accessible", p.x, p.y),
            )
        })?;
        if let Some(j) = out.iter().position(|&u| u == v) {
            return Err(ScenarioError::new(file, None, field, format!("is on the same vertex as starts.points[{j}]")));
        }
        out.push(v);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::Scenario;

    fn distinct(v: &[VertexId]) -> bool {
        let mut s = v.to_vec();
        s.sort_unstable();
        s.dedup();
        s.len() == v.len()
    }

    #[test]
    fn random_starts_are_distinct_accessible_border_vertices_drawn_from_the_seed() {
        let sc = Scenario::builtin("paper").unwrap();
        let w = sc.world();
        let fixed = sc.starts_by(&w, 13, StartRule::Fixed, 7).unwrap();
        assert_eq!(fixed, sc.start_vertices(&w, 13).unwrap(), "fixed is the scenario's layout, whatever the seed");
        let mut layouts = Vec::new();
        for seed in 0..20 {
            let s = sc.starts_by(&w, 13, StartRule::Random, seed).unwrap();
            assert_eq!(s.len(), 13);
            assert!(distinct(&s), "seed {seed}: two robots on one vertex: {s:?}");
            assert!(s.iter().all(|&v| w.is_accessible(v) && on_border(&w, v)), "seed {seed}: {s:?}");
            assert_eq!(s, sc.starts_by(&w, 13, StartRule::Random, seed).unwrap(), "seed {seed} repeats");
            layouts.push(s);
        }
        layouts.sort();
        layouts.dedup();
        assert_eq!(layouts.len(), 20, "every seed its own layout");
    }

    #[test]
    fn random_starts_leave_the_border_only_when_it_cannot_hold_the_robots() {
        let sc = Scenario::builtin("paper").unwrap();
        let w = sc.world();
        let reach = w.reachable_from(&sc.start_vertices(&w, 1).unwrap());
        let edge = (0..w.grid.len() as VertexId).filter(|&v| reach[v as usize] && on_border(&w, v)).count();
        let s = sc.starts_by(&w, edge + 5, StartRule::Random, 3).unwrap();
        assert!(distinct(&s));
        assert!(s.iter().any(|&v| !on_border(&w, v)), "more robots than border vertices");
        assert!(s.iter().all(|&v| reach[v as usize]), "only where the fixed layout reaches");
        let all = reach.iter().filter(|&&b| b).count();
        assert!(sc.starts_by(&w, all + 1, StartRule::Random, 3).is_err(), "a count the map cannot hold");
    }

    #[test]
    fn given_points_make_anywhere_accessible_the_region() {
        let mut sc = Scenario::builtin("paper").unwrap();
        sc.starts = crate::scenario::Starts::Points(vec![Point::new(1.0, 1.0), Point::new(2.0, 1.0)]);
        let w = sc.world();
        let inner = (0..40).flat_map(|seed| sc.starts_by(&w, 2, StartRule::Random, seed).unwrap());
        assert!(inner.into_iter().any(|v| !on_border(&w, v)), "points: no border region");
    }

    #[test]
    fn the_rule_reads_its_names() {
        for n in StartRule::NAMES {
            assert_eq!(n.parse::<StartRule>().unwrap().name(), n);
        }
        assert_eq!("border".parse::<StartRule>().unwrap_err(), "`border`: one of fixed, random");
    }
}
