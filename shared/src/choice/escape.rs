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
//! target or then any other nearest one, before rules (1)/(2) take over.

use super::paths::Paths;
use super::repulsive::repel;
use super::{uniform, ChoiceRule, RuleRng, View};
use crate::grid::VertexId;

/// Nearest targets tried when the chosen one's shortest paths are all
/// blocked: each costs a search of the map.
const MAX_TRIES: usize = 4;

#[derive(Clone, Debug, Default)]
pub struct Escape {
    paths: Paths,
    nearest: Vec<VertexId>,
    target: Option<VertexId>,
}

impl ChoiceRule for Escape {
    fn choose(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        let (unvisited, visited) = view.split();
        if !unvisited.is_empty() {
            self.target = None;
            return repel(view, &unvisited, rng);
        }
        if let Some(step) = self.towards_unvisited(view, rng) {
            return Some(step);
        }
        repel(view, &visited, rng)
    }
}

impl Escape {
    fn towards_unvisited(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        if let Some(t) = self.target.filter(|&t| !view.visited(t)) {
            let steps = self.paths.first_steps(view, t, view.blocked);
            if !steps.is_empty() {
                return uniform(rng, &steps);
            }
        }
        self.target = None;
        self.paths.nearest_unvisited(view.grid, view.map, view.position, view.blocked, &mut self.nearest)?;
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
}

use rand::Rng;
