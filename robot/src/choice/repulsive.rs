//! The paper's (1),(2)&(3): rule (1) (unvisited first, uniformly) when the
//! robot has no searching neighbour, rule (2) (repulsion) otherwise.

use super::{uniform, ChoiceRule, RuleRng, Slots, View};
use rand::Rng;

use crate::geometry::Point;
use crate::grid::VertexId;
use crate::params::VisitedChoice;

/// Distances within this are equal when rule (2) looks for the farthest candidate.
pub(crate) const TIE: f64 = 1e-9;

#[derive(Clone, Copy, Debug, Default)]
pub struct Repulsive;

impl ChoiceRule for Repulsive {
    fn choose(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        let (unvisited, visited) = view.split();
        if !unvisited.is_empty() {
            return repel(view, &unvisited, rng);
        }
        match view.visited_choice {
            VisitedChoice::Farthest => repel(view, &visited, rng),
            VisitedChoice::Uniform => uniform(rng, &visited),
            VisitedChoice::RandomBiased => biased(view, &visited, rng),
        }
    }
}

/// Rule (2) over visited vertices as Theorem 4.1's proof reads it
/// ("robots will randomly choose"), with the repulsion as a bias: one
/// fair draw from the robot's generator, then with probability 1/2
/// [`repel`]'s choice, else one of `set` uniformly. Every candidate thus
/// has probability at least `1 / (2 |set|)`, so no deterministic cycle can
/// hold a team for ever. Without searching neighbours it is rule (1),
/// uniform, as [`repel`]; a single candidate draws nothing.
fn biased(view: &View<'_>, set: &[VertexId], rng: &mut RuleRng) -> Option<VertexId> {
    if set.len() <= 1 || centre(view).is_none() || rng.random_bool(0.5) {
        return repel(view, set, rng);
    }
    uniform(rng, set)
}

/// Rule (2) over `set`: the vertices farthest from the mean of the
/// searching neighbours' next positions (announced choices of earlier
/// choosers, current positions of later ones), one at random; rule (1)
/// (uniform over `set`) without searching neighbours. Robots that stopped
/// are obstacles, not repellers: being pushed from one would keep this
/// robot from passing it.
/// The mean of the searching neighbours' next positions (announced
/// choices of earlier choosers, current positions of later ones); `None`
/// without searching neighbours. Summing integer lattice coordinates keeps
/// it independent of order.
pub fn centre(view: &View<'_>) -> Option<Point> {
    let (mut si, mut sj, mut live) = (0i64, 0i64, 0i64);
    for nb in view.neighbours.iter().filter(|n| n.searching) {
        let c = view.grid.coord(nb.choice.unwrap_or(nb.at));
        si += c.i as i64;
        sj += c.j as i64;
        live += 1;
    }
    (live > 0).then(|| view.grid.lattice.position_of(si as f64 / live as f64, sj as f64 / live as f64))
}

pub fn repel(view: &View<'_>, set: &[VertexId], rng: &mut RuleRng) -> Option<VertexId> {
    if set.is_empty() {
        return None;
    }
    let Some(ave) = centre(view) else {
        return uniform(rng, set);
    };
    let mut best = Slots::default();
    let mut best_d = f64::NEG_INFINITY;
    for &c in set {
        let d = (view.grid.position(c) - ave).norm();
        if d > best_d + TIE {
            best_d = d;
            best.clear();
        }
        if d >= best_d - TIE {
            best.push(c);
        }
    }
    uniform(rng, &best)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::choice::NeighbourView;
    use crate::grid::Grid;
    use crate::lattice::{Coord, Lattice, LatticeKind};
    use crate::map::Map;
    use rand::SeedableRng;

    /// How often each of the six visited candidates around the origin is
    /// chosen in 6,000 draws, with one searching neighbour two steps east
    /// (so the farthest candidate is the one west).
    fn counts(visited_choice: VisitedChoice) -> (Vec<usize>, usize) {
        let g = &Grid::new(Lattice::new(LatticeKind::Triangular, 1.0), Point::new(-6.0, -6.0), Point::new(6.0, 6.0));
        let at = |i, j| g.id_of(Coord::new(i, j)).unwrap();
        let mut map = Map::new(g.len());
        for v in 0..g.len() as VertexId {
            map.set_known(v, true);
            map.set_visited(v, true);
        }
        let me = at(0, 0);
        let candidates: Vec<VertexId> = g.neighbors(me)[..g.degree()].to_vec();
        let others = [NeighbourView { id: 1, at: at(2, 0), choice: None, searching: true }];
        let view = View { visited_choice, ..View::of(g, &map, me, &candidates, &others) };
        let mut rng = RuleRng::seed_from_u64(7);
        let mut n = vec![0; candidates.len()];
        for _ in 0..6000 {
            let c = Repulsive.choose(&view, &mut rng).unwrap();
            n[candidates.iter().position(|&x| x == c).unwrap()] += 1;
        }
        (n, candidates.iter().position(|&x| x == at(-1, 0)).unwrap())
    }

    #[test]
    fn the_texts_visited_choice_is_the_farthest_every_time() {
        let (n, west) = counts(VisitedChoice::Farthest);
        assert_eq!(n[west], 6000, "{n:?}");
    }

    #[test]
    fn random_biased_takes_the_farthest_half_the_time_and_any_candidate_otherwise() {
        // 1/2 + 1/12 for the farthest, 1/12 for each other: 3,500 and 500
        // (4 standard deviations: 150 and 85).
        let (n, west) = counts(VisitedChoice::RandomBiased);
        for (k, &c) in n.iter().enumerate() {
            let (expected, within) = if k == west { (3500.0, 150.0) } else { (500.0, 85.0) };
            assert!((c as f64 - expected).abs() < within, "candidate {k}: {c} of 6000, {n:?}");
        }
        let (n, _) = counts(VisitedChoice::Uniform);
        assert!(n.iter().all(|&c| (c as f64 - 1000.0).abs() < 120.0), "{n:?}");
    }
}
