//! Wrappers for the shared crate's scenario, assumption and engine entry
//! points (loading a scenario, placing starts, checking assumptions,
//! running a search), which also turn the shared crate's errors into the
//! command's. Not the only caller: other modules call the library directly
//! (`Scenario::parse` in `experiments/settings.rs` and
//! `provenance/rerun.rs`, `Scenario::world` in many places).

use gridswarm::grid::VertexId;
use gridswarm::lfp::LfpParams;
use gridswarm::outcome::{RunConfig, RunResult};
use gridswarm::scenario::{Scenario, StartRule};
use gridswarm::world::World;

pub use gridswarm::assumptions::{Check, Report};

use crate::error::{Error, Result};

/// A built-in scenario by name, or a TOML file or a map by path.
pub fn load_scenario(name_or_path: &str) -> Result<Scenario> {
    Scenario::load(name_or_path).map_err(|e| Error::Scenario(e.to_string()))
}

/// [`load_scenario`], and how reading a map changed it (`check` says so).
pub fn load_scenario_noted(name_or_path: &str) -> Result<(Scenario, Vec<String>)> {
    Scenario::load_noted(name_or_path).map_err(|e| Error::Scenario(e.to_string()))
}

/// Refuses a search in situation 1 of a scenario without targets: its stop
/// rule (every target found) holds before the first move, so it would end
/// "complete" after one round having searched nothing. `name` is what the
/// command was given (`--scenario`), to say where targets go.
pub fn needs_targets(scenario: &Scenario, name: &str) -> Result<()> {
    if scenario.situation != gridswarm::params::Situation::One || !scenario.targets.is_empty() {
        return Ok(());
    }
    let add = if gridswarm::scenario::occupancy::is_map(name) {
        let side = gridswarm::scenario::occupancy::sidecar_path(std::path::Path::new(name));
        format!("add `targets = [[x, y], ...]` to its sidecar {}", side.display())
    } else {
        format!("add `targets = [[x, y], ...]` to `{}`", crate::output::shown(name))
    };
    Err(Error::Scenario(format!(
        "situation 1 needs targets: scenario `{}` has none, so a search would end at once as complete; {add}, \
         or use --situation 2 (search until every reachable vertex is visited)",
        crate::output::shown(&scenario.name)
    )))
}

/// The start vertices of `robots` robots in `world`, robot `k` at index `k`.
pub fn start_vertices(scenario: &Scenario, world: &World, robots: usize) -> Result<Vec<VertexId>> {
    scenario.start_vertices(world, robots).map_err(|e| Error::Scenario(e.to_string()))
}

/// The start vertices of a run with seed `seed` under `rule` (the fixed
/// layout of [`start_vertices`], or one drawn from the seed).
pub fn starts(scenario: &Scenario, world: &World, robots: usize, rule: StartRule, seed: u64) -> Result<Vec<VertexId>> {
    scenario.starts_by(world, robots, rule, seed).map_err(|e| Error::Scenario(e.to_string()))
}

/// LFP's constants as the scenario sets them.
pub fn lfp_params(scenario: &Scenario) -> LfpParams {
    scenario.lfp
}

/// The paper's assumptions checked on `scenario` with robots at `starts`.
pub fn check_assumptions(scenario: &Scenario, world: &World, starts: &[VertexId]) -> Report {
    gridswarm::assumptions::check(scenario, world, starts)
}

/// One search of a grid policy shown to `watch` as it goes (`--mcap`, `--live`).
pub fn run_grid_watched(
    world: &World,
    starts: &[VertexId],
    cfg: &RunConfig,
    watch: &mut dyn gridswarm::sim::watch::Watch<std::rc::Rc<gridswarm::protocol::Frame>>,
) -> RunResult {
    gridswarm::engine::run_grid_watched(world, starts, cfg, watch)
}

/// Runs searches on one world, reusing whatever the engine can precompute
/// for it (the sweep runs thousands of searches on the same world).
pub struct Runner<'w> {
    prepared: gridswarm::engine::Prepared<'w>,
    lfp: LfpParams,
}

impl<'w> Runner<'w> {
    pub fn new(world: &'w World, lfp: LfpParams) -> Self {
        Runner { prepared: gridswarm::engine::Prepared::new(world), lfp }
    }

    pub fn world(&self) -> &World {
        self.prepared.world()
    }

    pub fn run(&self, starts: &[VertexId], cfg: &RunConfig) -> RunResult {
        // The scenario's LFP constants reach the engine here and only here.
        self.prepared.run(starts, cfg, &self.lfp)
    }
}
