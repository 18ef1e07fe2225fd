//! A run's directory: every file one search leaves behind, written by one
//! function whichever engine ran it (`simulate` in-process, `run` with one
//! process per robot), so that the two engines' directories can be compared
//! file by file and the replay page reads the same files from either.
//!
//! Files: `summary.json`, `trajectories.jsonl`, `routes.svg` (as before),
//! `world.json` (enough to rebuild the [`World`] exactly), `rounds.csv` (the
//! simulated clock round by round, when the engine reports it) and
//! `replay.html` (built from the files just written, see [`crate::replay`]).

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use gridswarm::geometry::{Point, Polygon, Shape};
use gridswarm::grid::VertexId;
use gridswarm::lattice::LatticeKind;
use gridswarm::lfp::LfpParams;
use gridswarm::outcome::RunResult;
use gridswarm::params::Params;
use gridswarm::scenario::Scenario;
use gridswarm::world::World;
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

use crate::error::{Error, Result};
use crate::staging::Staging;
use crate::{figures, output, replay, routes};

/// Names of the files in a run directory.
pub const SUMMARY: &str = "summary.json";
pub const TRAJECTORIES: &str = "trajectories.jsonl";
pub const ROUTES: &str = "routes.svg";
pub const WORLD: &str = "world.json";
pub const ROUNDS: &str = "rounds.csv";
pub const REPLAY: &str = "replay.html";

/// What `world.json` holds. The numbers are the scenario's own `f64`s
/// written in their shortest round-trip form, so [`WorldFile::world`]
/// rebuilds the same `World` bit for bit (same grid, same accessible
/// vertices and edges) without the scenario file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldFile {
    /// `gridswarm-world 1`; a later layout would change the number.
    pub format: String,
    pub scenario: String,
    pub grid: LatticeKind,
    pub situation: u8,
    pub params: Params,
    /// Corners of the area polygon.
    pub area: Vec<[f64; 2]>,
    pub obstacles: Vec<ObstacleFile>,
    pub targets: Vec<[f64; 2]>,
    /// Lattice coordinates `[i, j]` of each robot's start vertex, robot `k` at index `k`.
    pub starts: Vec<[i32; 2]>,
}

/// An obstacle as the scenario format writes it: exactly one of the two.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum ObstacleFile {
    Polygon(Vec<[f64; 2]>),
    Circle { center: [f64; 2], radius: f64 },
}

pub const WORLD_FORMAT: &str = "gridswarm-world 1";

fn pair(p: Point) -> [f64; 2] {
    [p.x, p.y]
}

fn point(p: [f64; 2]) -> Point {
    Point::new(p[0], p[1])
}

impl WorldFile {
    pub fn new(scenario: &Scenario, world: &World, starts: &[VertexId]) -> Self {
        WorldFile {
            format: WORLD_FORMAT.to_string(),
            scenario: scenario.name.clone(),
            grid: world.grid.lattice.kind,
            situation: scenario.situation.number(),
            params: world.params,
            area: world.area.points.iter().map(|&p| pair(p)).collect(),
            obstacles: world
                .obstacles
                .iter()
                .map(|o| match o {
                    Shape::Polygon(p) => ObstacleFile::Polygon(p.points.iter().map(|&q| pair(q)).collect()),
                    Shape::Circle(c) => ObstacleFile::Circle { center: pair(c.center), radius: c.radius },
                })
                .collect(),
            targets: world.targets.iter().map(|&p| pair(p)).collect(),
            starts: starts
                .iter()
                .map(|&v| {
                    let c = world.grid.coord(v);
                    [c.i, c.j]
                })
                .collect(),
        }
    }

    /// The ground truth again, exactly as the run had it.
    pub fn world(&self) -> World {
        let obstacles = self
            .obstacles
            .iter()
            .map(|o| match o {
                ObstacleFile::Polygon(pts) => Shape::Polygon(Polygon::new(pts.iter().map(|&p| point(p)).collect())),
                ObstacleFile::Circle { center, radius } => {
                    Shape::Circle(gridswarm::geometry::Circle { center: point(*center), radius: *radius })
                }
            })
            .collect();
        World::new(
            Polygon::new(self.area.iter().map(|&p| point(p)).collect()),
            obstacles,
            self.targets.iter().map(|&p| point(p)).collect(),
            self.params,
            self.grid,
        )
    }

    /// One top-level key per line, each value compact: readable, and short
    /// even for a map with hundreds of corners.
    pub fn to_text(&self) -> String {
        let v = serde_json::to_value(self).expect("a world file serialises");
        let map = v.as_object().expect("a struct serialises to an object");
        let mut s = String::from("{\n");
        // Declaration order, not the map's (sorted) order.
        let keys = ["format", "scenario", "grid", "situation", "params", "area", "obstacles", "targets", "starts"];
        debug_assert_eq!(keys.len(), map.len());
        for (n, k) in keys.iter().enumerate() {
            let sep = if n + 1 < keys.len() { "," } else { "" };
            let _ = writeln!(s, "  {}: {}{sep}", json!(k), map[*k]);
        }
        s.push_str("}\n");
        s
    }

    /// Reads and checks `world.json`; errors name the file.
    pub fn read(path: &Path) -> Result<WorldFile> {
        let text = read_text(path)?;
        let w: WorldFile = serde_json::from_str(&text).map_err(|e| Error::Read {
            path: path.to_path_buf(),
            message: format!("not a gridswarm world file: {e}"),
        })?;
        if w.format != WORLD_FORMAT {
            return Err(Error::Read {
                path: path.to_path_buf(),
                message: format!("format is `{}`, expected `{WORLD_FORMAT}`", w.format),
            });
        }
        if w.area.len() < 3 {
            return Err(Error::Read { path: path.to_path_buf(), message: "the area needs at least 3 corners".into() });
        }
        Ok(w)
    }
}

/// Reads a whole file, naming it in the error (and saying when it is missing).
pub fn read_text(path: &Path) -> Result<String> {
    fs::read_to_string(path).map_err(|e| Error::Read {
        path: path.to_path_buf(),
        message: if e.kind() == std::io::ErrorKind::NotFound { "no such file".to_string() } else { e.to_string() },
    })
}

/// One finished run, as any engine reports it, for [`write_run_dir`].
pub struct RunRecord<'a> {
    pub scenario: &'a Scenario,
    pub world: &'a World,
    /// Start vertex of each robot, robot `k` at index `k`.
    pub starts: &'a [VertexId],
    pub lfp: &'a LfpParams,
    /// With its trajectories recorded, and the simulated time at the end
    /// of each round in `round_end_times_s` (element `k` ends round `k`);
    /// when that is empty the replay spreads the run's total evenly over
    /// its rounds and says so.
    pub result: &'a RunResult,
    /// More fields for `summary.json`, merged over the common ones (a JSON
    /// object, or `null` for none): `max_rounds`, and from the distributed
    /// engine `failures_detected` and `refused_moves`, which the replay
    /// marks (shapes in [`crate::replay`]).
    pub extra: Value,
}

impl RunRecord<'_> {
    /// `summary.json`: [`output::run_summary`], the protocol's figures
    /// ([`figures::summary_fields`]), `extra`, and the start vertices.
    pub fn summary(&self) -> Value {
        let mut summary = output::run_summary(self.scenario, self.lfp, self.result);
        if let Value::Object(protocol) = figures::summary_fields(self.result) {
            for (k, v) in protocol {
                summary[k] = v;
            }
        }
        if let Value::Object(extra) = &self.extra {
            for (k, v) in extra {
                summary[k] = v.clone();
            }
        }
        summary["starts"] = json!(self
            .starts
            .iter()
            .map(|&v| {
                let c = self.world.grid.coord(v);
                [c.i, c.j]
            })
            .collect::<Vec<_>>());
        summary
    }

    /// The one-line description that heads the route map and the replay.
    pub fn title(&self) -> String {
        let r = self.result;
        format!(
            "{}: {} ({}), {} robots, seed {}: {} rounds, {:.1} s, {}/{} targets",
            crate::output::shown(&self.scenario.name),
            r.algorithm.name(),
            r.algorithm.paper_label(),
            r.robots,
            r.seed,
            r.rounds,
            r.search_time_s,
            r.targets_found,
            r.targets_total
        )
    }
}

/// `rounds.csv`: `round,end_time_s,collisions`, one line per round played
/// (without the last column when the engine did not count per round).
pub fn rounds_csv(round_end_times_s: &[f64], round_collisions: &[u32]) -> String {
    let counted = round_collisions.len() == round_end_times_s.len();
    let mut s = String::from(if counted { "round,end_time_s,collisions\n" } else { "round,end_time_s\n" });
    for (k, t) in round_end_times_s.iter().enumerate() {
        let _ = write!(s, "{k},{}", output::fixed(*t));
        let _ = if counted { writeln!(s, ",{}", round_collisions[k]) } else { writeln!(s) };
    }
    s
}

/// Writes every file of a run into the staging folder `stage`, puts it in
/// place and returns the files' final paths.
pub fn write_staged(stage: Staging, run: &RunRecord) -> Result<Vec<PathBuf>> {
    let written = write_run_dir(stage.path(), run)?;
    let target = stage.target().to_path_buf();
    stage.commit()?;
    Ok(written.iter().filter_map(|p| Some(target.join(p.file_name()?))).collect())
}

/// Writes every file of a run into `dir` (created if missing) and returns
/// their paths in the order written. `replay.html` comes last and is built
/// by reading the others back, exactly as `gridswarm replay DIR` does.
pub fn write_run_dir(dir: &Path, run: &RunRecord) -> Result<Vec<PathBuf>> {
    output::create_dir(dir)?;
    let mut written = Vec::new();
    let path = dir.join(SUMMARY);
    let summary = run.summary();
    output::write_json(&path, &summary)?;
    written.push(path);
    let path = dir.join(TRAJECTORIES);
    output::write_file(&path, |w| output::write_trajectories(w, &run.result.trajectories))?;
    written.push(path);
    let path = dir.join(ROUTES);
    let notes = routes::Notes::of(&run.title(), &summary);
    output::write_text(&path, &routes::routes_svg(run.world, &run.result.trajectories, &notes))?;
    written.push(path);
    let path = dir.join(WORLD);
    output::write_text(&path, &WorldFile::new(run.scenario, run.world, run.starts).to_text())?;
    written.push(path);
    let rounds_path = dir.join(ROUNDS);
    let times = &run.result.round_end_times_s;
    if times.is_empty() {
        // A stale one from an earlier run in the same directory would lie.
        let _ = fs::remove_file(&rounds_path);
    } else {
        output::write_text(&rounds_path, &rounds_csv(times, &run.result.round_collisions))?;
        written.push(rounds_path);
    }
    written.push(replay::write(dir)?);
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridswarm::scenario::BUILTIN;

    #[test]
    fn world_file_rebuilds_every_builtin_world_exactly() {
        for name in BUILTIN {
            let scenario = Scenario::builtin(name).unwrap();
            let world = scenario.world();
            let starts = scenario.start_vertices(&world, scenario.robots).unwrap();
            let file = WorldFile::new(&scenario, &world, &starts);
            let back: WorldFile = serde_json::from_str(&file.to_text()).unwrap();
            assert_eq!(back, file, "{name}");
            let again = back.world();
            assert_eq!(again.area, world.area, "{name}");
            assert_eq!(again.obstacles, world.obstacles, "{name}");
            assert_eq!(again.targets, world.targets, "{name}");
            assert_eq!(again.params, world.params, "{name}");
            assert_eq!(again.grid.len(), world.grid.len(), "{name}");
            for v in 0..world.grid.len() as VertexId {
                assert_eq!(again.is_accessible(v), world.is_accessible(v), "{name} vertex {v}");
                assert_eq!(again.open_mask(v), world.open_mask(v), "{name} vertex {v}");
            }
            for (k, s) in back.starts.iter().enumerate() {
                let v = again.grid.id_of(gridswarm::lattice::Coord::new(s[0], s[1])).unwrap();
                assert_eq!(v, starts[k]);
            }
        }
    }

    #[test]
    fn world_file_text_is_one_key_per_line() {
        let scenario = Scenario::builtin("paper").unwrap();
        let world = scenario.world();
        let text = WorldFile::new(&scenario, &world, &[]).to_text();
        assert_eq!(text.lines().count(), 11, "{text}");
        assert!(text.lines().nth(1).unwrap().starts_with("  \"format\": \"gridswarm-world 1\""));
    }

    #[test]
    fn rounds_csv_lines() {
        assert_eq!(rounds_csv(&[5.85, 11.7], &[0, 2]), "round,end_time_s,collisions\n0,5.850000,0\n1,11.700000,2\n");
        assert_eq!(rounds_csv(&[5.85, 11.7], &[]), "round,end_time_s\n0,5.850000\n1,11.700000\n");
    }
}
