//! The one place where the command calls the shared crate's scenario,
//! assumption and engine entry points. Those were written in parallel with
//! this crate; keeping every call here means a signature change touches one
//! file, and the rest of the command codes against these small wrappers,
//! which also turn the shared crate's errors into the command's.

use gridswarm::grid::VertexId;
use gridswarm::lfp::LfpParams;
use gridswarm::outcome::{RunConfig, RunResult};
use gridswarm::scenario::Scenario;
use gridswarm::world::World;

pub use gridswarm::assumptions::{Check, Report};

use crate::error::{Error, Result};

/// A built-in scenario by name, or a TOML file by path.
pub fn load_scenario(name_or_path: &str) -> Result<Scenario> {
    Scenario::load(name_or_path).map_err(|e| Error::Scenario(e.to_string()))
}

/// The start vertices of `robots` robots in `world`, robot `k` at index `k`.
pub fn start_vertices(scenario: &Scenario, world: &World, robots: usize) -> Result<Vec<VertexId>> {
    scenario.start_vertices(world, robots).map_err(|e| Error::Scenario(e.to_string()))
}

/// LFP's constants as the scenario sets them.
pub fn lfp_params(scenario: &Scenario) -> LfpParams {
    scenario.lfp
}

/// The paper's assumptions checked on `scenario` with robots at `starts`.
pub fn check_assumptions(scenario: &Scenario, world: &World, starts: &[VertexId]) -> Report {
    gridswarm::assumptions::check(scenario, world, starts)
}

/// Runs searches on one world, reusing whatever the engine can precompute
/// for it (the sweep runs thousands of searches on the same world).
pub struct Runner<'w> {
    world: &'w World,
    lfp: LfpParams,
}

impl<'w> Runner<'w> {
    pub fn new(world: &'w World, lfp: LfpParams) -> Self {
        Runner { world, lfp }
    }

    pub fn world(&self) -> &World {
        self.world
    }

    pub fn run(&self, starts: &[VertexId], cfg: &RunConfig) -> RunResult {
        // The scenario's LFP constants reach the engine here and only here.
        gridswarm::engine::run_with_lfp(self.world, starts, cfg, &self.lfp)
    }

    /// [`Runner::run`], also returning the simulated time at the end of every round.
    pub fn run_with_round_times(&self, starts: &[VertexId], cfg: &RunConfig) -> (RunResult, Vec<f64>) {
        let mut r = self.run(starts, cfg);
        let times = std::mem::take(&mut r.round_end_times_s);
        (r, times)
    }
}
