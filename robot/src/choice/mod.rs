//! Choice rules: the one decision of step 5 that differs between grid
//! policies, behind a trait the decision core ([`crate::robot`]) calls.
//!
//! The core does everything the policies share: sensing, maps, neighbours,
//! the priority order, the collision-free candidate set (or, for RU, every
//! open adjacent vertex) and the stop rules. A [`ChoiceRule`] only picks
//! one candidate, or none to stay. It sees a read-only [`View`] of what the
//! robot knows and draws randomness only from the robot's own generator,
//! so a rule is deterministic per seed and the same in both engines.
//!
//! Built-in rules live one per file ([`repulsive`], [`sequential`],
//! [`ru`], [`escape`], [`frontier`], and, registered by name in
//! [`EXTRA`], [`coord`] as `frontier-coord` and [`sensed`] as
//! `frontier-sensed` and `frontier-sensed-coord`); [`paths`] holds the breadth-first
//! search several of them share. A researcher's rule is one file too,
//! implementing [`ChoiceRule`], made known by name in one of two ways:
//!
//! - in this repository: put the file here and a line in [`EXTRA`]; every
//!   program (`gridswarm simulate`, `gridswarm run`'s robot-agents) then
//!   accepts `--algorithm NAME`;
//! - in a program of one's own: [`register`] it before parsing arguments,
//!   and for `gridswarm run` make that program the agent
//!   (`robot_agent::main_with`, then `--agent-bin PATH`); see
//!   `robot-agent/examples/my_rule.rs`, which does both.

pub mod coord;
pub mod escape;
pub mod frontier;
pub mod paths;
pub mod registry;
pub mod repulsive;
pub mod ru;
pub mod sensed;
pub mod sequential;

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::grid::{Grid, VertexId, NONE};
use crate::lattice::MAX_DEGREE;
use crate::map::{Map, RobotId};
use crate::params::VisitedChoice;

pub use registry::{register, rule_for, Factory, RuleName};

/// Rules compiled into every program of the workspace, by name: one line
/// per rule added in this folder.
pub const EXTRA: &[(&str, Factory)] =
    &[("frontier-coord", coord::new), ("frontier-sensed", sensed::new), ("frontier-sensed-coord", sensed::new_coord)];

/// The generator a rule draws from: the robot's own, seeded from the run.
pub type RuleRng = ChaCha8Rng;

/// A communication neighbour of this round, as a rule may see it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NeighbourView {
    pub id: RobotId,
    /// Where it stands (as last heard this round).
    pub at: VertexId,
    /// Its announced next vertex, when this robot must avoid it (a
    /// higher-priority neighbour that chose); `None` otherwise.
    pub choice: Option<VertexId>,
    /// Whether it still searches: its map arrived this round, it is not
    /// suspected and has not stopped. Only these repel.
    pub searching: bool,
}

/// What a rule may read when it chooses: never the world, only the robot.
#[derive(Clone, Copy, Debug)]
pub struct View<'a> {
    pub grid: &'a Grid,
    /// The robot's own map, merged with every map heard this round.
    pub map: &'a Map,
    pub position: VertexId,
    pub round: u32,
    /// The adjacent vertices the core allows this round, in adjacency-slot
    /// order: open, and (for collision-free policies) clear of every known
    /// robot, choice and blocked vertex. A rule must return one of these
    /// or `None` (stay); anything else is treated as staying.
    pub candidates: &'a [VertexId],
    /// This round's neighbours, sorted by id.
    pub neighbours: &'a [NeighbourView],
    /// Vertices blocked for good as far as the robot knows (failed robots,
    /// silent bodies): paths must not cross them.
    pub blocked: &'a [VertexId],
    /// The scenario's reading of rule (2) over visited candidates.
    pub visited_choice: VisitedChoice,
}

/// For the rules' tests: a view at round 0 with nothing blocked for good
/// and the paper's reading of rule (2), the rest as given.
#[cfg(test)]
impl<'a> View<'a> {
    pub(crate) fn of(
        grid: &'a Grid,
        map: &'a Map,
        position: VertexId,
        candidates: &'a [VertexId],
        neighbours: &'a [NeighbourView],
    ) -> Self {
        View {
            grid,
            map,
            position,
            round: 0,
            candidates,
            neighbours,
            blocked: &[],
            visited_choice: VisitedChoice::default(),
        }
    }
}

impl View<'_> {
    pub fn visited(&self, v: VertexId) -> bool {
        self.map.visited(v)
    }

    /// The candidates split into (unvisited, visited), each in slot order.
    pub fn split(&self) -> (Slots, Slots) {
        let (mut u, mut v) = (Slots::default(), Slots::default());
        for &c in self.candidates {
            if self.visited(c) {
                v.push(c)
            } else {
                u.push(c)
            }
        }
        (u, v)
    }

    /// Rule (1)'s set: the unvisited candidates, or the visited ones when
    /// there are none.
    pub fn unvisited_first(&self) -> Slots {
        let (u, v) = self.split();
        if u.is_empty() {
            v
        } else {
            u
        }
    }
}

/// The decision of step 5 for one grid policy. One value per robot, kept
/// for the whole run, so a rule may remember things between rounds.
pub trait ChoiceRule: Send {
    /// The next vertex, one of `view.candidates`, or `None` to stay.
    fn choose(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId>;

    /// Whether the rule may pass unvisited vertices on purpose and heads
    /// for the ones it wants by itself. Once failures are known the core
    /// steps a robot with every candidate visited towards its nearest
    /// unvisited vertex ([`crate::robot::Robot`]'s survivor step); a rule
    /// that walks past unvisited vertices it counts as sensed would be
    /// pulled back one round and go on the next, for ever. Such a rule
    /// says so here, and the core leaves the choice to it.
    fn passes_unvisited(&self) -> bool {
        false
    }
}

/// Into `closed`, what a path this round may not pass: the blocked
/// vertices, and the adjacent ones the core does not allow this round (so
/// paths start with a candidate).
pub(crate) fn close(view: &View<'_>, closed: &mut Vec<VertexId>) {
    closed.clear();
    closed.extend_from_slice(view.blocked);
    let g = view.grid;
    for &n in &g.neighbors(view.position)[..g.degree()] {
        if n != crate::grid::NONE && !view.candidates.contains(&n) {
            closed.push(n);
        }
    }
}

/// Up to one vertex per adjacency slot, without allocating.
#[derive(Clone, Copy, Debug)]
pub struct Slots {
    v: [VertexId; MAX_DEGREE],
    n: usize,
}

impl Default for Slots {
    fn default() -> Self {
        Slots { v: [NONE; MAX_DEGREE], n: 0 }
    }
}

impl Slots {
    pub fn push(&mut self, v: VertexId) {
        if self.n < MAX_DEGREE {
            self.v[self.n] = v;
            self.n += 1;
        }
    }
    pub fn clear(&mut self) {
        self.n = 0;
    }
}

impl std::ops::Deref for Slots {
    type Target = [VertexId];
    fn deref(&self) -> &[VertexId] {
        &self.v[..self.n]
    }
}

/// One of `set` uniformly; a single element draws nothing, so a forced
/// choice leaves the generator untouched (the paper's runs depend on it).
pub fn uniform(rng: &mut RuleRng, set: &[VertexId]) -> Option<VertexId> {
    match set.len() {
        0 => None,
        1 => Some(set[0]),
        n => Some(set[rng.random_range(0..n)]),
    }
}
