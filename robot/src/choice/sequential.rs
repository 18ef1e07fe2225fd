//! (1)&(3): the sequential collision-free choice with rule (1) alone:
//! an unvisited candidate uniformly, else a visited one.

use super::{uniform, ChoiceRule, RuleRng, View};
use crate::grid::VertexId;

#[derive(Clone, Copy, Debug, Default)]
pub struct Sequential;

impl ChoiceRule for Sequential {
    fn choose(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        uniform(rng, &view.unvisited_first())
    }
}
