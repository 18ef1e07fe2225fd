//! `frontier-coord`: coordinated frontier exploration in the manner of
//! Burgard et al. (2005, "Coordinated multi-robot exploration"). As in
//! `frontier`, a frontier is a known unvisited vertex and the robot heads
//! along a shortest path on its own map; but instead of the nearest one it
//! takes the frontier of least cost, its distance plus a discount of its
//! utility near the other robots: `max(0, RANGE - o)` moves, `o` the
//! distance from the nearest vertex a searching neighbour announced (its
//! choice, or where it stands while it has not chosen). A frontier right
//! on another robot's next vertex costs `RANGE` moves more than one no
//! robot heads for, so neighbours spread out instead of crowding the same
//! frontier. Only what the robot heard this round counts: neighbours out
//! of radio range, or their targets beyond their next vertex, are unknown
//! to it (Burgard's robots share their assigned targets; these share only
//! their next vertex). Ties are broken at random, as are shortest paths'
//! first steps.

use super::frontier::Frontier;
use super::paths::Paths;
use super::{uniform, ChoiceRule, RuleRng, View};
use crate::grid::VertexId;

/// Moves over which another robot's announced vertex discounts a frontier:
/// about two sensing radii (`2 r_st` is 2.6 a with the defaults).
pub(super) const RANGE: u32 = 3;

#[derive(Clone, Debug, Default)]
pub struct FrontierCoord {
    paths: Paths,
    /// Distances from the searching neighbours' announced vertices.
    others: Paths,
    /// Frontiers within reach of the least cost, with their distances.
    found: Vec<(VertexId, u32)>,
    best: Vec<VertexId>,
    sources: Vec<VertexId>,
    closed: Vec<VertexId>,
    /// What to do when no way to the chosen frontier is found.
    fallback: Frontier,
}

/// A fresh rule, for the registry.
pub fn new() -> Box<dyn ChoiceRule> {
    Box::<FrontierCoord>::default()
}

impl ChoiceRule for FrontierCoord {
    fn choose(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        let step = self.pick(view, rng);
        self.paths.release();
        self.others.release();
        step
    }
}

impl FrontierCoord {
    fn pick(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        super::close(view, &mut self.closed);
        let near =
            self.paths.unvisited_within(view.grid, view.map, view.position, &self.closed, RANGE, &mut self.found);
        if near.is_some() {
            discount(view, &mut self.others, &mut self.sources, &self.found, &mut self.best);
            let t = uniform(rng, &self.best)?;
            let steps = self.paths.first_steps(view, t, &self.closed);
            if !steps.is_empty() {
                return uniform(rng, &steps);
            }
            // No first step towards the frontier was found (the search
            // from it may close edges the search to it passed: on the
            // honeycomb a misread edge once did so for good): staying, or
            // stepping at random, could repeat for ever; `frontier` takes
            // the unvisited vertex next to it first.
            return self.fallback.choose(view, rng);
        }
        // No frontier the robot can start towards this round: a random
        // step, as `frontier` takes, keeps corridors from jamming.
        let (_, visited) = view.split();
        uniform(rng, &visited)
    }
}

/// Keeps in `best` those of `found` (frontiers with their distances) of
/// least cost: distance plus the discount near the searching neighbours'
/// announced vertices (`sources` and `others` are scratch space).
pub(super) fn discount(
    view: &View<'_>,
    others: &mut Paths,
    sources: &mut Vec<VertexId>,
    found: &[(VertexId, u32)],
    best: &mut Vec<VertexId>,
) {
    sources.clear();
    sources.extend(view.neighbours.iter().filter(|n| n.searching).map(|n| n.choice.unwrap_or(n.at)));
    let heard = !sources.is_empty();
    if heard {
        others.distances_from(view.grid, view.map, sources, view.blocked);
    }
    let cost = |&(v, d): &(VertexId, u32)| {
        let o = if heard { others.dist(v).unwrap_or(RANGE) } else { RANGE };
        d + RANGE.saturating_sub(o)
    };
    let least = found.iter().map(cost).min().unwrap_or(0);
    best.clear();
    best.extend(found.iter().filter(|f| cost(f) == least).map(|f| f.0));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::choice::NeighbourView;
    use crate::geometry::Point;
    use crate::grid::Grid;
    use crate::lattice::{Coord, Lattice, LatticeKind};
    use crate::map::Map;
    use rand::SeedableRng;

    /// Everything known and open, everything visited but `left` and `right`,
    /// three moves either side of the robot at the origin along a row; a
    /// neighbour, when there is one, announced the vertex next to `left`.
    fn steps(neighbour: bool) -> Vec<f64> {
        let g = &Grid::new(Lattice::new(LatticeKind::Triangular, 1.0), Point::new(-6.0, -6.0), Point::new(6.0, 6.0));
        let at = |i, j| g.id_of(Coord::new(i, j)).unwrap();
        let mut map = Map::new(g.len());
        for v in 0..g.len() as VertexId {
            map.set_known(v, true);
            map.set_visited(v, true);
            map.or_open(v, 0xff);
        }
        let (left, right, me) = (at(-3, 0), at(3, 0), at(0, 0));
        map.set_visited(left, false);
        map.set_visited(right, false);
        let candidates: Vec<VertexId> = g.neighbors(me)[..g.degree()].to_vec();
        let others = [NeighbourView { id: 1, at: at(-2, 1), choice: Some(at(-2, 0)), searching: true }];
        let view = View::of(g, &map, me, &candidates, if neighbour { &others } else { &[] });
        (0..20)
            .map(|seed| {
                let mut rng = RuleRng::seed_from_u64(seed);
                let step = FrontierCoord::default().choose(&view, &mut rng).unwrap();
                g.position(step).x - g.position(me).x
            })
            .collect()
    }

    #[test]
    fn a_frontier_near_another_robots_next_vertex_is_left_to_it() {
        // Alone, both frontiers are as good: seeds pick either side.
        let alone = steps(false);
        assert!(alone.iter().any(|&dx| dx < 0.0) && alone.iter().any(|&dx| dx > 0.0), "{alone:?}");
        // The neighbour heads for the left one: this robot goes right.
        let heard = steps(true);
        assert!(heard.iter().all(|&dx| dx > 0.0), "{heard:?}");
    }
}
