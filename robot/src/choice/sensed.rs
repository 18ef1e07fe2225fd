//! `frontier-sensed` and `frontier-sensed-coord`: frontier exploration with
//! frontiers as the field defines them, borders of space nobody has sensed
//! (Yamauchi 1998), not merely known unvisited vertices as in `frontier`.
//!
//! A robot senses targets within `r_st = 1.3 a` of its vertex, so standing
//! on a vertex senses every lattice triangle that vertex is a corner of.
//! On the robot's own map (visited and known vertices only: what it sensed
//! or heard), a triangle at `v` (`v` and two consecutive adjacency slots,
//! [`triangles`]) is **covered** when one of its corners is visited. A
//! known unvisited vertex `v` is a **frontier** ([`is_frontier`]) when one
//! of its uncovered triangles
//!
//! - has both other corners known (open space nobody sensed), or
//! - has a corner nobody has looked at: not known, and no vertex next to it
//!   visited (had one been, its sensing would have made the corner known
//!   were the edge between them open). What lies there is unknown.
//!
//! An uncovered triangle whose other corners are known closed (unknown, but
//! a visited vertex next to them sensed no way in: a wall) makes no
//! frontier: the robot has no reason to think there is space there.
//!
//! So a robot that walks a row makes the next row's vertices frontiers
//! (their far side is unexplored) but, once the row after is walked, not
//! any more: rows may be skipped, as the oracle's plan skips them. Among
//! the nearest frontiers it prefers the one covering the most uncovered
//! triangles ([`gain`]), then draws at random, and takes a shortest path's
//! first step. `frontier-sensed-coord` instead takes the frontier of least
//! cost as `frontier-coord` does (distance plus the discount near the
//! neighbours' announced vertices), ties to the greatest gain.
//!
//! The search still ends only by the core's stop rule (every target found,
//! or every known vertex visited): when no frontier is left that the robot
//! can start towards, it behaves as `frontier` (nearest known unvisited
//! vertex, else a random step), so it keeps making progress towards that.

use super::coord::{discount, RANGE};
use super::frontier::Frontier;
use super::paths::Paths;
use super::{uniform, ChoiceRule, RuleRng, View};
use crate::grid::{Grid, VertexId, NONE};
use crate::map::Map;

/// The triangles `v` is a corner of: pairs of consecutive adjacency slots,
/// both inside the grid (on the triangular lattice, consecutive neighbours
/// are adjacent).
pub fn triangles(grid: &Grid, v: VertexId) -> impl Iterator<Item = (VertexId, VertexId)> + '_ {
    let deg = grid.degree();
    let n = &grid.neighbors(v)[..deg];
    (0..deg).map(move |d| (n[d], n[(d + 1) % deg])).filter(|&(a, b)| a != NONE && b != NONE)
}

/// Whether some robot has looked at `w`: `w` is known, or a vertex next to
/// it was visited (and so sensed whether `w` can be entered from there).
pub fn explored(grid: &Grid, map: &Map, w: VertexId) -> bool {
    map.known(w) || grid.neighbors(w)[..grid.degree()].iter().any(|&n| n != NONE && map.visited(n))
}

/// Whether the triangle at `v` with other corners `a`, `b` holds space
/// nobody sensed that is worth going to: no corner visited, and the other
/// corners both known open or one of them unexplored.
fn open_uncovered(grid: &Grid, map: &Map, v: VertexId, a: VertexId, b: VertexId) -> bool {
    if map.visited(v) || map.visited(a) || map.visited(b) {
        return false;
    }
    (map.known(a) && map.known(b)) || !explored(grid, map, a) || !explored(grid, map, b)
}

/// Whether `v` is a frontier: known, unvisited, and a corner of a triangle
/// of unsensed space (see the module's text).
pub fn is_frontier(grid: &Grid, map: &Map, v: VertexId) -> bool {
    map.known(v) && !map.visited(v) && triangles(grid, v).any(|(a, b)| open_uncovered(grid, map, v, a, b))
}

/// How many of `v`'s triangles standing on `v` would cover that hold
/// unsensed space worth going to.
pub fn gain(grid: &Grid, map: &Map, v: VertexId) -> usize {
    triangles(grid, v).filter(|&(a, b)| open_uncovered(grid, map, v, a, b)).count()
}

#[derive(Clone, Debug, Default)]
pub struct FrontierSensed {
    /// Whether to discount frontiers near the neighbours' announced
    /// vertices (`frontier-sensed-coord`).
    coordinated: bool,
    paths: Paths,
    others: Paths,
    found: Vec<(VertexId, u32)>,
    best: Vec<VertexId>,
    sources: Vec<VertexId>,
    closed: Vec<VertexId>,
    /// What to do when no frontier is within reach.
    fallback: Frontier,
}

/// A fresh `frontier-sensed`, for the registry.
pub fn new() -> Box<dyn ChoiceRule> {
    Box::<FrontierSensed>::default()
}

/// A fresh `frontier-sensed-coord`, for the registry.
pub fn new_coord() -> Box<dyn ChoiceRule> {
    Box::new(FrontierSensed { coordinated: true, ..Default::default() })
}

impl ChoiceRule for FrontierSensed {
    fn choose(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        let step = self.pick(view, rng);
        self.paths.release();
        self.others.release();
        step
    }

    /// It skips rows it counts as sensed, and heads for the nearest
    /// unvisited vertex itself when no frontier is left.
    fn passes_unvisited(&self) -> bool {
        true
    }
}

impl FrontierSensed {
    fn pick(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        super::close(view, &mut self.closed);
        let (g, map) = (view.grid, view.map);
        // The coordinated twin weighs frontiers up to RANGE moves past the
        // nearest; the plain rule only the nearest.
        let slack = if self.coordinated { RANGE } else { 0 };
        let near =
            self.paths.unvisited_within_where(g, map, view.position, &self.closed, slack, &mut self.found, |v, _| {
                is_frontier(g, map, v)
            });
        if near.is_none() {
            // No frontier the robot can start towards: head for the nearest
            // unvisited vertex as `frontier` does, so the core's stop rule
            // (every known vertex visited) is still reached.
            return self.fallback.choose(view, rng);
        }
        if self.coordinated {
            discount(view, &mut self.others, &mut self.sources, &self.found, &mut self.best);
        } else {
            self.best.clear();
            self.best.extend(self.found.iter().map(|f| f.0));
        }
        let best_gain = self.best.iter().map(|&v| gain(g, map, v)).max().unwrap_or(0);
        self.best.retain(|&v| gain(g, map, v) == best_gain);
        let t = uniform(rng, &self.best)?;
        let steps = self.paths.first_steps(view, t, &self.closed);
        if steps.is_empty() {
            // The way back from the frontier was not found (on the
            // honeycomb lattice an edge known from one end only can read
            // closed from the other): never stay for good on it.
            return self.fallback.choose(view, rng);
        }
        uniform(rng, &steps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use crate::lattice::{Coord, Lattice, LatticeKind};
    use rand::SeedableRng;

    fn grid() -> Grid {
        Grid::new(Lattice::new(LatticeKind::Triangular, 1.0), Point::new(-8.0, -6.0), Point::new(8.0, 6.0))
    }

    fn at(g: &Grid, i: i32, j: i32) -> VertexId {
        g.id_of(Coord::new(i, j)).unwrap()
    }

    /// A robot on `v` senses every edge open that leads to a vertex for
    /// which `open` holds.
    fn sense(g: &Grid, map: &mut Map, v: VertexId, open: impl Fn(Coord) -> bool) {
        let mut mask = 0u8;
        for (d, &n) in g.neighbors(v)[..g.degree()].iter().enumerate() {
            if n != NONE && open(g.coord(n)) {
                mask |= 1 << d;
            }
        }
        map.record_sensing(g, v, mask);
    }

    #[test]
    fn in_the_open_a_row_walked_two_rows_on_leaves_the_row_between_sensed() {
        let g = &grid();
        let mut map = Map::new(g.len());
        // Row 0 walked, from i = -4 to 4; everything around is open.
        for i in -4..=4 {
            sense(g, &mut map, at(g, i, 0), |_| true);
        }
        // Row 1 is known, and its far side nobody has looked at.
        assert!(map.known(at(g, 0, 1)) && !map.known(at(g, 0, 2)));
        assert!(is_frontier(g, &map, at(g, 0, 1)));
        // Standing there would sense its three triangles towards row 2.
        assert_eq!(gain(g, &map, at(g, 0, 1)), 3);
        assert!(!is_frontier(g, &map, at(g, 0, 0)), "visited");
        assert!(!is_frontier(g, &map, at(g, 0, 2)), "unknown");
        // Row 2 walked (from i = -5, above row 0's i = -4): row 1 between
        // i = -4 and 3 has every triangle covered, though nobody stood there.
        for i in -5..=3 {
            sense(g, &mut map, at(g, i, 2), |_| true);
        }
        for i in -4..=3 {
            assert!(!map.visited(at(g, i, 1)) && !is_frontier(g, &map, at(g, i, 1)), "row 1, i = {i}");
        }
        // Past the walked part of row 2 it still is (what lies beyond
        // (5, 1) nobody has looked at), and so is row 3.
        assert!(is_frontier(g, &map, at(g, 4, 1)));
        assert!(is_frontier(g, &map, at(g, 0, 3)));
    }

    #[test]
    fn a_corridor_one_row_wide_is_sensed_by_every_other_vertex() {
        let g = &grid();
        let mut map = Map::new(g.len());
        // Only row 0 is open: every edge off it is closed.
        let row0 = |c: Coord| c.j == 0;
        sense(g, &mut map, at(g, 0, 0), row0);
        // Past (1, 0) the corridor goes on, unexplored: a frontier.
        assert!(is_frontier(g, &map, at(g, 1, 0)));
        sense(g, &mut map, at(g, 2, 0), row0);
        // Between two visited vertices, with walls known on both sides:
        // nothing of it is unsensed.
        assert!(!is_frontier(g, &map, at(g, 1, 0)));
        assert_eq!(gain(g, &map, at(g, 1, 0)), 0);
        assert!(is_frontier(g, &map, at(g, 3, 0)));
    }

    #[test]
    fn a_robot_skips_a_sensed_row_for_the_frontier_beyond() {
        let g = &grid();
        let mut map = Map::new(g.len());
        for i in -5..=5 {
            sense(g, &mut map, at(g, i, 0), |_| true);
        }
        for i in -6..=4 {
            sense(g, &mut map, at(g, i, 2), |_| true);
        }
        // On row 2, the robot has row 1's unvisited vertices next to it
        // (where `frontier` would step) and row 3's, the frontier.
        let me = at(g, 0, 2);
        let candidates: Vec<VertexId> = g.neighbors(me)[..g.degree()].to_vec();
        let view = View::of(g, &map, me, &candidates, &[]);
        assert!(candidates.iter().any(|&c| g.coord(c).j == 1 && !map.visited(c)));
        for rule in [new as fn() -> Box<dyn ChoiceRule>, new_coord] {
            for seed in 0..20 {
                let step = rule().choose(&view, &mut RuleRng::seed_from_u64(seed)).unwrap();
                assert_eq!(g.coord(step).j, 3, "seed {seed}");
            }
        }
    }

    #[test]
    fn with_no_frontier_left_it_heads_for_the_nearest_unvisited_vertex() {
        let g = &grid();
        let mut map = Map::new(g.len());
        // A corridor along row 0 walked on every other vertex: (1, 0) and
        // (3, 0) are unvisited and no frontier, so only the fallback goes there.
        let row0 = |c: Coord| c.j == 0 && (0..=4).contains(&c.i);
        for i in [0, 2, 4] {
            sense(g, &mut map, at(g, i, 0), row0);
        }
        assert!(!is_frontier(g, &map, at(g, 1, 0)) && !is_frontier(g, &map, at(g, 3, 0)));
        let me = at(g, 4, 0);
        let candidates = [at(g, 3, 0)];
        let view = View::of(g, &map, me, &candidates, &[]);
        let step = FrontierSensed::default().choose(&view, &mut RuleRng::seed_from_u64(1));
        assert_eq!(step, Some(at(g, 3, 0)));
    }
}
