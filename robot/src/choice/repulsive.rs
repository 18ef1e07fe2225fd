//! The paper's (1),(2)&(3): rule (1) (unvisited first, uniformly) when the
//! robot has no searching neighbour, rule (2) (repulsion) otherwise.

use super::{uniform, ChoiceRule, RuleRng, Slots, View};
use crate::geometry::Point;
use crate::grid::VertexId;

/// Distances within this are equal when rule (2) looks for the farthest candidate.
pub(crate) const TIE: f64 = 1e-9;

#[derive(Clone, Copy, Debug, Default)]
pub struct Repulsive;

impl ChoiceRule for Repulsive {
    fn choose(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        repel(view, &view.unvisited_first(), rng)
    }
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
