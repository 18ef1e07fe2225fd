//! `frontier`: decentralized nearest-frontier exploration in the manner of
//! Yamauchi (1998). Each robot heads along a shortest path on its own map to
//! the nearest known unvisited vertex (the frontier) it can start towards
//! this round; ties between frontiers and between shortest paths' first
//! steps are broken at random. There is no repulsion: only the choice rule
//! differs from the paper's robots, which share the grid, sensing, radio
//! and the collision-avoidance order.

use super::paths::Paths;
use super::{uniform, ChoiceRule, RuleRng, View};
use crate::grid::VertexId;

#[derive(Clone, Debug, Default)]
pub struct Frontier {
    paths: Paths,
    nearest: Vec<VertexId>,
    /// Blocked vertices plus the adjacent ones the core does not allow this
    /// round, so the search only finds frontiers the robot can start towards.
    closed: Vec<VertexId>,
}

impl ChoiceRule for Frontier {
    fn choose(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        let step = self.pick(view, rng);
        self.release();
        step
    }
}

impl Frontier {
    fn pick(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        let (unvisited, visited) = view.split();
        if !unvisited.is_empty() {
            return uniform(rng, &unvisited);
        }
        if let Some(s) = self.towards_reachable(view, rng) {
            return Some(s);
        }
        // Every frontier is out of reach this round (robots in the way, or
        // none is left that this robot can reach): a random step keeps two
        // robots from facing each other in a corridor for ever.
        uniform(rng, &visited)
    }

    /// Gives the search's space back: nothing of it is read next round.
    pub fn release(&mut self) {
        self.paths.release();
    }

    /// The first step of a shortest path to a nearest unvisited vertex
    /// among those the robot can start towards this round (its first step
    /// a candidate); `None` when there is none.
    pub fn towards_reachable(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        super::close(view, &mut self.closed);
        self.paths.nearest_unvisited(view.grid, view.map, view.position, &self.closed, &mut self.nearest)?;
        let t = uniform(rng, &self.nearest)?;
        let steps = self.paths.first_steps(view, t, &self.closed);
        uniform(rng, &steps)
    }
}
