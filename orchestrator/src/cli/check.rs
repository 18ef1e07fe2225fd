//! `gridswarm check`: loads a scenario, places its robots and reports which
//! of the paper's assumptions hold on it (and, for a map, how reading it
//! changed it). Also the warning the other
//! subcommands print when they run a scenario that breaks an assumption
//! (docs/paper.md: such a scenario may run, but the tool must say so).

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
    let (scenario, notes) = contract::load_scenario_noted(scenario_name)?;
    let world = scenario.world();
    let starts = contract::start_vertices(&scenario, &world, scenario.robots)?;
    let report = contract::check_assumptions(&scenario, &world, &starts);
    let va = world.reachable_from(&starts).iter().filter(|&&b| b).count();
    let p = &scenario.params;
    let mut text = String::new();
    let _ = writeln!(
        text,
        "scenario {}: {} grid, a = {} m, {} targets, {} obstacles, {} robots, situation {}",
        crate::output::shown(&scenario.name),
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
    if !notes.is_empty() {
        let _ = writeln!(text, "map {}, as read:", crate::output::shown(scenario_name));
        for n in &notes {
            let _ = writeln!(text, "  {n}");
        }
    }
    let _ = writeln!(text, "assumptions:");
    let _ = write!(text, "{report}");
    for c in report.failures() {
        let _ = writeln!(text, "fix {:<8} {}", c.id, hint(c.id));
    }
    Ok(CheckOutcome { text, report })
}

/// How to make a failing assumption hold, in the scenario file's terms.
pub fn hint(id: &str) -> &'static str {
    match id {
        "2.4" => "raise `r_so` in [params] to at least a + r_safe (or drop it: the default is that bound)",
        "2.5" => "raise `r_c` in [params] to at least 2a + r_safe - r_rob (or drop it: the default is that bound)",
        "r_safe" => "make `r_safe` larger than `r_rob` in [params]",
        "S0" => {
            "raise `a` or lower `r_safe` in [params] until the named distance exceeds 2 r_safe \
                 (on the triangular grid: r_safe below sqrt(3)/4 a = 0.433 a)"
        }
        "3.1.1" => "raise `r_st` in [params] to at least a + r_safe (or drop it: the default is that bound)",
        "3.1.2" => "open the named corner (a wider angle), move it nearer the accessible grid, or raise `r_st`",
        "3.1.3" => "move the named obstacle or wall apart to at least W_pass = a + 2 r_safe, or close the gap entirely",
        "Va" => "join the unreachable part to the rest with a passage at least a + 2 r_safe wide, or add a start there",
        "starts" => "give each robot its own start point inside the accessible area ([starts] points), or fewer robots",
        "targets" => {
            "move each named target within r_st of an accessible vertex, or raise `r_st`; with none, add \
             `targets = [[x, y], ...]` (a map's sidecar) or set `situation = 2`"
        }
        "coverage" => "widen the narrow parts near the named points, or raise `r_st` so their walls are in range",
        _ => "see docs/paper.md \"The world\" for what the assumption asks",
    }
}

/// Refuses a search under `policy` when its parameters let robots collide
/// where the policy promises they never do (S0): such a run would count
/// collisions and might still read as complete. RU (particles, charged
/// for each collision) and LFP (off the lattice) run with the warning.
pub fn refuse(report: &Report, policy: gridswarm::policy::Policy) -> Result<()> {
    match report.get("S0") {
        Some(c) if !c.holds && policy.collision_free() => Err(crate::error::Error::Collision(format!(
            "refused: S0 ({}) does not hold: {}; `{policy}` promises no collision, so a run would only count \
             them; fix: {}",
            c.title,
            c.detail,
            hint("S0")
        ))),
        _ => Ok(()),
    }
}

/// One `warning:` line per failing assumption, for stderr.
pub fn warnings(report: &Report) -> Vec<String> {
    report.failures().map(|c| format!("warning: {} ({}) does not hold: {}", c.id, c.title, c.detail)).collect()
}
