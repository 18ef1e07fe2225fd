//! Scenario files (TOML) and the built-in scenarios.
//!
//! A scenario is everything a run needs besides the algorithm and the seed:
//! the area, the obstacles, the targets, where the robots start, and the
//! parameters. The format, every key optional unless marked:
//!
//! ```toml
//! name = "paper"            # default: the file name without extension
//! robots = 3                # default robot count, >= 1 (default 3)
//! situation = 1             # 1: |T| known (rule 3), 2: unknown (rule 4)
//! grid = "triangular"       # triangular | square | hexagonal
//! targets = [[2, 2], [10, 2]]   # points of Ad; a top-level key, so before any [table]
//!
//! [params]                  # a, r_rob, r_safe default 1.0 / 0.25 / 0.30; r_so, r_st,
//! a = 1.0                   # r_c default to the equality case of their assumption
//! r_safe = 0.30             # (Params::derived); t_rot, t_trans, t_choice in seconds
//! ru_collisions = "per-event" # RU's collisions: per-event (default) | per-pair | back-off (RuCollisions)
//! visited_choice = "farthest" # rule (2) over visited vertices: farthest (default) | uniform | random-biased
//! slot = "adaptive"         # what ends a slot: adaptive (default) | fixed (SlotRule)
//! order = "paper"           # who waits for whose choice: paper (default) | local (Order)
//! broadcast = "controller"  # how found targets and the stop reach all robots: controller (default) | flood (Broadcast)
//!
//! [area]                    # required: a simple polygon, corners in either order
//! polygon = [[0, 0], [20, 0], [20, 16], [0, 16]]
//!
//! [[obstacles]]             # any number; each exactly one of polygon, circle, rect;
//! polygon = [[3, 3], [6, 3], [6, 5]]   # inside the area, clear of its boundary,
//! [[obstacles]]                        # not touching one another
//! circle = { center = [10, 8], radius = 1.5 }
//! [[obstacles]]
//! rect = { min = [14, 2], max = [16, 5] }
//!
//! [starts]                  # default: border from the area's first corner
//! border = { from = [0, 0] }           # neighbouring vertices along the border
//! # points = [[1, 1], [2, 1]]          # or: one point per robot, snapped to a vertex
//!
//! [lfp]                     # optional constants of the LFP baseline (LfpParams)
//! beta = 1.5
//! turn = 1.0                # turn sigma in radians (default the standard normal) | "uniform"
//! repel_range = "sonar"     # robots repel within r_so (default) | "radio": r_c
//! ```
//!
//! Errors are one line, `file:line:col: field.path: what is wrong`, for
//! syntax, unknown keys and wrong types (from toml) as for meaning (from
//! here): a degenerate or self-crossing polygon, an obstacle overlapping
//! another or leaving the area, a non-positive length, `r_safe <= r_rob`, a
//! target outside `Ad`, an inaccessible or shared start vertex, a situation
//! other than 1 or 2, zero robots, and anything beyond an admission limit
//! ([`limits`]: sizes, counts and ranges, checked before the world is
//! built). The assumptions of the paper are *not*
//! enforced: a scenario that breaks them still runs, and
//! [`crate::assumptions::check`] says which fail.
//!
//! Besides files and built-ins, `random:SEED[,options]` names a map
//! generated from the seed ([`random`]), and `NAME.yaml` a ROS map_server
//! occupancy grid ([`occupancy`]); [`Scenario::to_toml`] writes any
//! scenario back in this format, [`occupancy::write_map`] as a map.

mod file;
mod gaps;
pub mod limits;
mod locate;
pub mod occupancy;
mod pairs;
pub mod random;
mod raw;
mod starts;
mod write;

pub use starts::StartRule;

pub use file::{read as read_file, MAX_FILE_BYTES, MAX_IMAGE_BYTES};
pub(crate) use gaps::{boundary_gap_of, self_passages, shape_gap, Gap};
pub(crate) use pairs::near as near_pairs;

use crate::geometry::{Point, Polygon, Shape};
use crate::grid::VertexId;
use crate::lattice::LatticeKind;
use crate::lfp::LfpParams;
use crate::params::{Params, Situation};
use crate::world::World;

/// Where the robots start.
#[derive(Clone, Debug, PartialEq)]
pub enum Starts {
    /// Neighbouring accessible vertices along the area's border, beginning
    /// with the border vertex nearest to `from` (Assumption 2.2).
    Border { from: Point },
    /// Given points, each snapped to its nearest lattice vertex.
    Points(Vec<Point>),
}

/// A search problem: everything needed to build a [`World`] and place robots.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    pub name: String,
    pub area: Polygon,
    pub obstacles: Vec<Shape>,
    pub targets: Vec<Point>,
    pub starts: Starts,
    /// Robot count used when the command line does not give one.
    pub robots: usize,
    pub params: Params,
    pub grid: LatticeKind,
    pub situation: Situation,
    /// Constants of the LFP baseline, from the optional `[lfp]` table.
    pub lfp: LfpParams,
}

/// Why a scenario could not be read or placed, as one line naming the file,
/// the position when known, and the field.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{}", self.one_line())]
pub struct ScenarioError {
    /// The file name or path (or built-in name) the scenario came from.
    pub file: String,
    /// 1-based line and column, when the error has a place in the text.
    pub at: Option<(usize, usize)>,
    /// Dotted path of the field, e.g. `obstacles[1].circle.radius`; empty
    /// when the error is about no field (a syntax error, a missing file).
    pub field: String,
    pub message: String,
}

impl ScenarioError {
    pub(crate) fn new(
        file: &str,
        at: Option<(usize, usize)>,
        field: impl Into<String>,
        message: impl AsRef<str>,
    ) -> Self {
        // toml's messages may span lines; the error must stay one line.
        let message = message.as_ref().trim().replace('\n', "; ");
        ScenarioError { file: file.to_string(), at, field: field.into(), message }
    }

    /// The line of the error, when known.
    pub fn line(&self) -> Option<usize> {
        self.at.map(|(l, _)| l)
    }

    /// The error as one printable line: the file's own text (an unknown
    /// key, a name) may hold an escape sequence that would clear or
    /// rewrite the terminal, so every control character is shown escaped
    /// (`\u{1b}`), as the commands show a scenario's name.
    fn one_line(&self) -> String {
        let s = self.raw_line();
        if !s.chars().any(char::is_control) {
            return s;
        }
        s.chars().map(|c| if c.is_control() { c.escape_default().to_string() } else { c.to_string() }).collect()
    }

    fn raw_line(&self) -> String {
        let mut s = self.file.clone();
        if let Some((line, col)) = self.at {
            s.push_str(&format!(":{line}:{col}"));
        }
        if !self.field.is_empty() {
            s.push_str(": ");
            s.push_str(&self.field);
        }
        s.push_str(": ");
        s.push_str(&self.message);
        s
    }
}

/// Names of the built-in scenarios, the default first.
pub const BUILTIN: &[&str] = &["paper", "open", "cave", "large", "small", "comb"];

fn builtin_text(name: &str) -> Option<&'static str> {
    Some(match name {
        "paper" => include_str!("../scenarios/paper.toml"),
        "open" => include_str!("../scenarios/open.toml"),
        "cave" => include_str!("../scenarios/cave.toml"),
        "large" => include_str!("../scenarios/large.toml"),
        "small" => include_str!("../scenarios/small.toml"),
        "comb" => include_str!("../scenarios/comb.toml"),
        _ => return None,
    })
}

impl Scenario {
    /// The ground truth of this scenario on its own grid.
    pub fn world(&self) -> World {
        World::new(self.area.clone(), self.obstacles.clone(), self.targets.clone(), self.params, self.grid)
    }

    /// The scenario used when none is named.
    pub fn default_name() -> &'static str {
        BUILTIN[0]
    }

    /// Parses a scenario file; `source` names it in error messages.
    pub fn parse(text: &str, source: &str) -> Result<Scenario, ScenarioError> {
        // The spanned tree only locates errors; if even it fails the text is
        // not TOML and the typed parse below reports the syntax error.
        let tree = toml::from_str::<locate::Node>(text).ok();
        let ctx = raw::Ctx { text, file: source, tree };
        let raw: raw::RawScenario = toml::from_str(text).map_err(|e| ctx.toml_error(&e))?;
        raw.into_scenario(&ctx)
    }

    /// A built-in scenario by name (see [`BUILTIN`]).
    pub fn builtin(name: &str) -> Option<Scenario> {
        let text = builtin_text(name)?;
        // The built-ins are tested to parse; a failure here is a bug in them.
        Some(Scenario::parse(text, &format!("{name}.toml")).unwrap_or_else(|e| panic!("built-in scenario: {e}")))
    }

    /// A built-in scenario by name, a random map (`random:SEED[,options]`,
    /// see [`random`]), else a scenario file by path.
    pub fn load(name_or_path: &str) -> Result<Scenario, ScenarioError> {
        Scenario::load_noted(name_or_path).map(|(s, _)| s)
    }

    /// [`Scenario::load`], and for a map (`NAME.yaml`, [`occupancy`]) how
    /// reading it changed it, one line each (none for other scenarios).
    pub fn load_noted(name_or_path: &str) -> Result<(Scenario, Vec<String>), ScenarioError> {
        if let Some(s) = Scenario::builtin(name_or_path) {
            return Ok((s, Vec::new()));
        }
        if random::is_random(name_or_path) {
            return random::load(name_or_path).map(|s| (s, Vec::new()));
        }
        if occupancy::is_map(name_or_path) {
            return occupancy::load(name_or_path).map(|c| (c.scenario, c.notes));
        }
        let text = file::read(name_or_path).map_err(|e| {
            ScenarioError::new(
                name_or_path,
                None,
                "",
                format!(
                    "{e} (not a built-in scenario either; those are: {}; or a random map, {})",
                    BUILTIN.join(", "),
                    random::SYNTAX
                ),
            )
        })?;
        Scenario::parse(&text, name_or_path).map(|s| (s, Vec::new()))
    }

    /// Start vertices for `robots` robots on `world` (which must be this
    /// scenario's world), robot `k` at element `k`: the first `robots` points
    /// snapped to vertices, or a chain of neighbouring vertices along the
    /// border (see [`Starts::Border`]). Distinct and accessible, or an error.
    pub fn start_vertices(&self, world: &World, robots: usize) -> Result<Vec<VertexId>, ScenarioError> {
        let file = self.name.clone();
        if robots == 0 {
            return Err(ScenarioError::new(&file, None, "robots", "must be >= 1, got 0"));
        }
        // The count may come from the command line, past the file's checks.
        limits::check_robots(robots, world.grid.len() as f64).map_err(|m| limits::error(&file, "robots", m))?;
        match &self.starts {
            Starts::Border { from } => starts::border(world, *from, robots, &file),
            Starts::Points(pts) => starts::points(world, pts, robots, &file),
        }
    }

    /// Start vertices for `robots` robots of a run with seed `seed` under
    /// `rule`: [`Scenario::start_vertices`] when fixed; when random, drawn
    /// from the seed alone ([`StartRule::Random`]), with the same errors as
    /// the fixed layout (a count the map cannot hold).
    pub fn starts_by(
        &self,
        world: &World,
        robots: usize,
        rule: StartRule,
        seed: u64,
    ) -> Result<Vec<VertexId>, ScenarioError> {
        let fixed = self.start_vertices(world, robots)?;
        Ok(match rule {
            StartRule::Fixed => fixed,
            StartRule::Random => {
                let border = matches!(self.starts, Starts::Border { .. });
                starts::random(world, &fixed, robots, border, seed)
            }
        })
    }
}
