//! The in-process engine. OWNED BY THE LEAD: being written.

use crate::grid::VertexId;
use crate::outcome::{RunConfig, RunResult};
use crate::world::World;

/// Runs one search with robots starting at `starts` (robot `k` at `starts[k]`).
pub fn run(world: &World, starts: &[VertexId], cfg: &RunConfig) -> RunResult {
    let _ = (world, starts, cfg);
    unimplemented!("engine being written")
}
