//! `gridswarm check`: loads a scenario, places its robots and reports which
//! of the paper's assumptions hold on it. Also the warning the other
//! subcommands print when they run a scenario that breaks an assumption
//! (READING.md: such a scenario may run, but the tool must say so).

use std::fmt::Write as _;

use crate::contract::{self, Report};
use crate::error::Result;

/// What `check` found: the printed text, and whether every assumption holds.
pub struct CheckOutcome {
    pub text: String,
    pub report: Report,
}

impl CheckOutcome {
    pub fn all_hold(&self) -> bool {
        self.report.all_hold()
    }

    /// The ids of the failing assumptions, comma-separated.
    pub fn failing_ids(&self) -> String {
        self.report.failures().map(|c| c.id).collect::<Vec<_>>().join(", ")
    }
}

pub fn check(scenario_name: &str) -> Result<CheckOutcome> {
    let scenario = contract::load_scenario(scenario_name)?;
    let world = scenario.world();
    let starts = contract::start_vertices(&scenario, &world, scenario.robots)?;
    let report = contract::check_assumptions(&scenario, &world, &starts);
    let va = world.reachable_from(&starts).iter().filter(|&&b| b).count();
    let p = &scenario.params;
    let mut text = String::new();
    let _ = writeln!(
        text,
        "scenario {}: {} grid, a = {} m, {} targets, {} obstacles, {} robots, situation {}",
        scenario.name,
        scenario.grid.name(),
        p.a,
        scenario.targets.len(),
        scenario.obstacles.len(),
        scenario.robots,
        scenario.situation.number()
    );
    let _ = writeln!(
        text,
        "ranges: r_rob {} r_safe {} r_so {} r_st {} r_c {} (m); times: t_rot {} t_trans {} t_choice {} (s)",
        p.r_rob, p.r_safe, p.r_so, p.r_st, p.r_c, p.t_rot, p.t_trans, p.t_choice
    );
    let _ = writeln!(
        text,
        "grid: {} frame vertices, {} accessible, |Va| = {} from the start vertices",
        world.grid.len(),
        world.accessible_vertices().count(),
        va
    );
    let _ = writeln!(text, "assumptions:");
    let _ = write!(text, "{report}");
    Ok(CheckOutcome { text, report })
}

/// One `warning:` line per failing assumption, for stderr.
pub fn warnings(report: &Report) -> Vec<String> {
    report.failures().map(|c| format!("warning: {} ({}) does not hold: {}", c.id, c.title, c.detail)).collect()
}
