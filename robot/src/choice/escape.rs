//! `escape`: the paper's (1),(2)&(3), except that a robot with no
//! unvisited candidate heads along a shortest path on its own map to a
//! nearest unvisited vertex, instead of random-walking over visited ones
//! (rule (2) there only spreads robots over explored ground).
//!
//! Ties among nearest unvisited vertices are broken at random (the first
//! found in slot order biased robots towards +x); the robot keeps its target
//! across rounds while it stays unvisited and reachable by a shortest-path
//! step the core allows, so equal targets never make it dither; a blocked
//! step is replaced by another shortest path's first step, towards the same
//! target or then any other nearest one, then by the first step towards
//! the nearest unvisited vertex the robot can start towards this round
//! (a detour), before rules (1)/(2) take over. A fresh target is one no
//! searching neighbour is nearer to, when there is one, so neighbours
//! share the unvisited vertices out instead of racing for the same one;
//! among equally near ones, those farthest from the neighbours' centre
//! (rule (2)'s spreading); and a kept target is given up once a neighbour
//! is more than one step nearer to it.

use super::frontier::Frontier;
use super::paths::Paths;
use super::repulsive::{centre, repel, TIE};
use super::{uniform, ChoiceRule, RuleRng, View};
use crate::grid::VertexId;
use rand::Rng;

/// Nearest targets tried when the chosen one's shortest paths are all
/// blocked: each costs a search of the map.
const MAX_TRIES: usize = 4;

#[derive(Clone, Debug, Default)]
pub struct Escape {
    paths: Paths,
    nearest: Vec<VertexId>,
    target: Option<VertexId>,
    /// Distances from the searching neighbours, for sharing out targets.
    others: Paths,
    sources: Vec<VertexId>,
    detour: Frontier,
}

impl ChoiceRule for Escape {
    fn choose(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        let step = self.pick(view, rng);
        // Searches' space back to the pool: only the target is kept.
        self.paths.release();
        self.others.release();
        self.detour.release();
        step
    }
}

impl Escape {
    fn pick(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        let (unvisited, visited) = view.split();
        if !unvisited.is_empty() {
            self.target = None;
            return repel(view, &unvisited, rng);
        }
        if let Some(step) = self.towards_unvisited(view, rng) {
            return Some(step);
        }
        // Every shortest path is blocked this round: a longer way round
        // still beats a step over visited ground.
        if let Some(step) = self.detour.towards_reachable(view, rng) {
            return Some(step);
        }
        repel(view, &visited, rng)
    }

    fn towards_unvisited(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        if let Some(t) = self.target.filter(|&t| !view.visited(t) && !self.taken(view, t)) {
            let steps = self.paths.first_steps(view, t, view.blocked);
            if !steps.is_empty() {
                return uniform(rng, &steps);
            }
        }
        self.target = None;
        self.nearest_mine(view)?;
        self.keep_farthest(view);
        for _ in 0..MAX_TRIES.min(self.nearest.len()) {
            let k = if self.nearest.len() == 1 { 0 } else { rng.random_range(0..self.nearest.len()) };
            let t = self.nearest.swap_remove(k);
            let steps = self.paths.first_steps(view, t, view.blocked);
            if !steps.is_empty() {
                self.target = Some(t);
                return uniform(rng, &steps);
            }
        }
        None
    }

    /// Among the nearest targets, only those farthest from the searching
    /// neighbours' centre: rule (2)'s spreading, applied to targets.
    fn keep_farthest(&mut self, view: &View<'_>) {
        let Some(c) = centre(view) else {
            return;
        };
        let d = |v: VertexId| (view.grid.position(v) - c).norm();
        let best = self.nearest.iter().map(|&v| d(v)).fold(f64::NEG_INFINITY, f64::max);
        self.nearest.retain(|&v| d(v) >= best - TIE);
    }

    /// Whether a searching neighbour is now more than one step nearer to
    /// `t` than this robot: it is theirs, and this robot picks again.
    fn taken(&mut self, view: &View<'_>, t: VertexId) -> bool {
        self.collect_sources(view);
        if self.sources.is_empty() {
            return false;
        }
        // Only sources nearer to `t` than this robot matter: all have their distance.
        self.others.distances_to(view.grid, view.map, t, view.position, view.blocked);
        let Some(mine) = self.others.dist(view.position) else {
            return false;
        };
        self.sources.iter().any(|&s| self.others.dist(s).is_some_and(|o| o + 1 < mine))
    }

    fn collect_sources(&mut self, view: &View<'_>) {
        self.sources.clear();
        self.sources.extend(view.neighbours.iter().filter(|n| n.searching).map(|n| n.choice.unwrap_or(n.at)));
    }

    /// The nearest unvisited vertices no searching neighbour is nearer to
    /// (on this robot's map, from where it will be), so that neighbours
    /// head for different places; all the nearest when every one is
    /// nearer to someone else.
    fn nearest_mine(&mut self, view: &View<'_>) -> Option<u32> {
        self.collect_sources(view);
        if !self.sources.is_empty() {
            self.others.distances_from(view.grid, view.map, &self.sources, view.blocked);
            let others = &self.others;
            let d = self.paths.nearest_where(
                view.grid,
                view.map,
                view.position,
                view.blocked,
                &mut self.nearest,
                |v, d| others.dist(v).is_none_or(|o| d <= o),
            );
            if d.is_some() {
                return d;
            }
        }
        self.paths.nearest_unvisited(view.grid, view.map, view.position, view.blocked, &mut self.nearest)
    }
}
