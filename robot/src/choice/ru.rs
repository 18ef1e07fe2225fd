//! RU: rule (1) over every open adjacent vertex. The core gives RU robots
//! no collision avoidance (`Policy::sequential` is false for it): their
//! candidates ignore other robots, and they choose all at once.

use super::{uniform, ChoiceRule, RuleRng, View};
use crate::grid::VertexId;

#[derive(Clone, Copy, Debug, Default)]
pub struct Ru;

impl ChoiceRule for Ru {
    fn choose(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        uniform(rng, &view.unvisited_first())
    }
}
