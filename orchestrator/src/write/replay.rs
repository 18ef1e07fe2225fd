//! `replay.html`: one self-contained page that plays a run back from its
//! directory's files, whichever engine wrote them (`gridswarm replay DIR`,
//! and the last step of [`crate::rundir::write_run_dir`]).
//!
//! What is cheaper in Rust than in the browser is done here, once: the
//! detected fraction round by round (incremental marking on the engine's own
//! raster, so the last value is the run's `coverage`), targets found round by
//! round, the collisions of every round (the referee's swept-distance test on
//! consecutive poses) and the simulated clock. The page gets compact arrays:
//! robot poses as vertex indices (grid policies) or 16-bit fixed point (LFP),
//! base64-encoded, and draws them on a canvas.
//!
//! Inputs read from the directory:
//! - `world.json` ([`WorldFile`]), `trajectories.jsonl` (one line per robot
//!   per round, as [`crate::output::write_trajectories`] writes it; a robot's
//!   record may end early, but may not skip a round) and `summary.json`.
//! - `rounds.csv` if present (`round,end_time_s[,collisions]`); else the
//!   clock is `search_time_s` spread evenly over the rounds, and the page
//!   says `~`. With the `collisions` column the page counts the engine's
//!   collisions, also those the poses cannot show (robots that back off
//!   end where they started); its marks are those the poses show.
//! - From `summary.json`, besides the run's numbers, two optional fields the
//!   distributed engine writes:
//!   - `failures_detected`: `[{"robot": r, "round": k, ...}, ...]`, robot ids
//!     from 0 as in `trajectories.jsonl`; other keys (`at`, `cause`,
//!     `detected_by`, `at_ms`: `gridswarm::ipc::Detection`) are ignored. The
//!     robot is drawn failed from round `k` on.
//!   - without it, `failures` (every run's summary): each entry with a
//!     `detected_round` is drawn failed from that round on.
//!   - `refused_moves`: either a count (shown as a total) or
//!     `[{"robot": r, "round": k}, ...]` (each marked at that robot in round `k`).
//!   - `failures`' `kind`, `round` and `thawed_s` (every run's summary):
//!     a crashed robot is drawn crashed from its round, a frozen one frozen
//!     until the first round past its thaw, whether declared or not.
//!   - `faults` and `radio` (and `retries`), shown in the side bar as
//!     [`crate::figures::settings_line`] words them.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use gridswarm::engine::RASTER_CELL;
use gridswarm::geometry::{swept_min_distance, Point};
use gridswarm::grid::{VertexId, NONE};
use gridswarm::lattice::Coord;
use gridswarm::world::World;
use serde::Deserialize;
use serde_json::{json, Value};

use crate::error::{Error, Result};
use crate::output;
use crate::rundir::{self, WorldFile};

const TEMPLATE: &str = include_str!("../../assets/replay.html");
const SCRIPT: &str = include_str!("../../assets/replay.js");

/// One robot's pose at the start of a round, as recorded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecPose {
    /// The grid vertex, for policies that stay on the grid.
    pub vertex: Option<VertexId>,
    pub position: Point,
}

/// A robot the world declared failed, from `round` on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
pub struct Failure {
    pub robot: usize,
    pub round: u32,
}

/// A move the world refused (the robot stayed), in `round`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
pub struct Refusal {
    pub robot: usize,
    pub round: u32,
}

/// Without `failures_detected`: the failures of `summary.json`'s
/// `failures` list that some robot declared, drawn failed from the round
/// of the first declaration (entries of another shape are skipped).
fn declared(summary: &Value) -> Vec<Failure> {
    let list = summary.get("failures").and_then(Value::as_array).map(Vec::as_slice).unwrap_or_default();
    list.iter()
        .filter_map(|f| {
            let robot = f.get("robot")?.as_u64()? as usize;
            let round = f.get("detected_round")?.as_u64()? as u32;
            Some(Failure { robot, round })
        })
        .collect()
}

/// A run directory's files, read and checked.
pub struct Recorded {
    pub world_file: WorldFile,
    pub world: World,
    /// `poses[r][k]`: robot `r` at the start of round `k`.
    pub poses: Vec<Vec<RecPose>>,
    pub summary: Value,
    pub round_end_times_s: Option<Vec<f64>>,
    /// The referee's collisions of every round, when `rounds.csv` has them.
    pub round_collisions: Option<Vec<u32>>,
    pub failures: Vec<Failure>,
    pub refused: Vec<Refusal>,
    /// The total of refused moves when `summary.json` gives only a count.
    pub refused_total: Option<u64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Line {
    round: usize,
    robot: usize,
    vertex: Option<[i32; 2]>,
    x: f64,
    y: f64,
}

impl Recorded {
    /// Rounds played: the longest record, less its starting pose.
    pub fn rounds(&self) -> usize {
        self.poses.iter().map(Vec::len).max().unwrap_or(1).saturating_sub(1)
    }

    /// Reads `dir`'s recorded files; every error names the file (and line).
    pub fn load(dir: &Path) -> Result<Recorded> {
        if !dir.is_dir() {
            return Err(Error::Read { path: dir.to_path_buf(), message: "not a directory".into() });
        }
        let world_file = WorldFile::read(&dir.join(rundir::WORLD))?;
        let world = world_file.world();

        let spath = dir.join(rundir::SUMMARY);
        let summary: Value = serde_json::from_str(&rundir::read_text(&spath)?)
            .map_err(|e| Error::Read { path: spath.clone(), message: format!("not JSON: {e}") })?;
        if !summary.is_object() {
            return Err(Error::Read { path: spath, message: "expected a JSON object".into() });
        }
        let bad = |message: String| Error::Read { path: spath.clone(), message };
        let failures: Vec<Failure> = match summary.get("failures_detected") {
            None | Some(Value::Null) => declared(&summary),
            Some(v) => Vec::deserialize(v).map_err(|e| {
                bad(format!("failures_detected: expected [{{\"robot\": r, \"round\": k, ...}}, ...]: {e}"))
            })?,
        };
        let (refused, refused_total) = match summary.get("refused_moves") {
            None | Some(Value::Null) => (Vec::new(), None),
            Some(Value::Number(n)) => {
                (Vec::new(), Some(n.as_u64().ok_or_else(|| bad("refused_moves: expected a count".into()))?))
            }
            Some(v) => {
                let r: Vec<Refusal> = Vec::deserialize(v).map_err(|e| {
                    bad(format!("refused_moves: expected a count or [{{\"robot\": r, \"round\": k}}, ...]: {e}"))
                })?;
                let total = r.len() as u64;
                (r, Some(total))
            }
        };

        let tpath = dir.join(rundir::TRAJECTORIES);
        let poses = read_trajectories(&tpath, &rundir::read_text(&tpath)?, &world)?;
        let n = poses.len();
        if let Some(f) = failures.iter().find(|f| f.robot >= n) {
            return Err(bad(format!("failures_detected: robot {} but the trajectories have {n} robots", f.robot)));
        }
        if let Some(f) = refused.iter().find(|f| f.robot >= n) {
            return Err(bad(format!("refused_moves: robot {} but the trajectories have {n} robots", f.robot)));
        }

        let mut rec = Recorded {
            world_file,
            world,
            poses,
            summary,
            round_end_times_s: None,
            round_collisions: None,
            failures,
            refused,
            refused_total,
        };
        let rpath = dir.join(rundir::ROUNDS);
        if rpath.exists() {
            let (times, collisions) = read_rounds(&rpath, rec.rounds())?;
            rec.round_end_times_s = Some(times);
            rec.round_collisions = collisions;
        }
        Ok(rec)
    }

    /// The page's title line, from the summary's numbers.
    pub fn title(&self) -> String {
        let s = &self.summary;
        let text = |k: &str| s.get(k).and_then(Value::as_str).unwrap_or("?").to_string();
        let num = |k: &str| s.get(k).map(|v| v.to_string()).unwrap_or_else(|| "?".into());
        format!(
            "{}: {} ({}), {} robots, seed {}: {} rounds, {:.1} s, {}/{} targets",
            self.world_file.scenario,
            text("algorithm"),
            text("label"),
            self.poses.len(),
            num("seed"),
            self.rounds(),
            s.get("search_time_s").and_then(Value::as_f64).unwrap_or(f64::NAN),
            num("targets_found"),
            num("targets_total"),
        )
    }
}

fn read_trajectories(path: &Path, text: &str, world: &World) -> Result<Vec<Vec<RecPose>>> {
    let mut poses: Vec<Vec<RecPose>> = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let at =
            |message: String| Error::Read { path: path.to_path_buf(), message: format!("line {}: {message}", n + 1) };
        if line.trim().is_empty() {
            continue;
        }
        let l: Line = serde_json::from_str(line).map_err(|e| at(e.to_string()))?;
        if l.robot >= u16::MAX as usize {
            return Err(at(format!("robot {} is out of range", l.robot)));
        }
        if poses.len() <= l.robot {
            poses.resize(l.robot + 1, Vec::new());
        }
        let record = &mut poses[l.robot];
        if l.round != record.len() {
            return Err(at(format!("robot {} round {} follows round {}", l.robot, l.round, record.len() as i64 - 1)));
        }
        let vertex = match l.vertex {
            None => None,
            Some([i, j]) => Some(world.grid.id_of(Coord::new(i, j)).ok_or_else(|| {
                at(format!("vertex [{i},{j}] is not in the grid of world.json (files from different runs?)"))
            })?),
        };
        if !(l.x.is_finite() && l.y.is_finite()) {
            return Err(at("x and y must be finite".into()));
        }
        record.push(RecPose { vertex, position: Point::new(l.x, l.y) });
    }
    if poses.is_empty() {
        return Err(Error::Read { path: path.to_path_buf(), message: "no poses".into() });
    }
    if let Some(r) = poses.iter().position(Vec::is_empty) {
        return Err(Error::Read { path: path.to_path_buf(), message: format!("robot {r} has no pose") });
    }
    Ok(poses)
}

/// `rounds.csv`: each round's end time, and its collisions when the file
/// has that column (files of older versions do not).
fn read_rounds(path: &Path, rounds: usize) -> Result<(Vec<f64>, Option<Vec<u32>>)> {
    let text = rundir::read_text(path)?;
    let mut lines = text.lines();
    let bad = |message: String| Error::Read { path: path.to_path_buf(), message };
    let counted = match lines.next().map(str::trim) {
        Some("round,end_time_s") => false,
        Some("round,end_time_s,collisions") => true,
        _ => return Err(bad("expected the header `round,end_time_s` or `round,end_time_s,collisions`".into())),
    };
    let (mut times, mut collisions) = (Vec::with_capacity(rounds), Vec::new());
    for (n, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let k = cells.first().and_then(|k| k.parse::<usize>().ok());
        let t = cells.get(1).and_then(|t| t.parse::<f64>().ok()).filter(|t| t.is_finite());
        let c = if counted { cells.get(2).and_then(|c| c.parse::<u32>().ok()) } else { Some(0) };
        match (k, t, c) {
            (Some(k), Some(t), Some(c)) if k == n && cells.len() == 2 + counted as usize => {
                times.push(t);
                collisions.push(c);
            }
            _ => {
                let want = if counted { format!("`{n},<seconds>,<collisions>`") } else { format!("`{n},<seconds>`") };
                return Err(bad(format!("line {}: expected {want}, got `{line}`", n + 2)));
            }
        }
    }
    if times.len() != rounds {
        return Err(bad(format!("{} rounds, but the trajectories have {rounds}", times.len())));
    }
    Ok((times, counted.then_some(collisions)))
}

/// Standard base64 with padding; the page decodes it with `atob`.
pub fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (b[0] as u32) << 16 | (b[1] as u32) << 8 | b[2] as u32;
        for k in 0..4 {
            if k <= chunk.len() {
                s.push(ABC[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// Little-endian integers of the narrowest of 16 or 32 bits that holds `max`.
fn pack(values: impl Iterator<Item = u32>, max: u32) -> (u32, String) {
    let mut bytes = Vec::new();
    let bits = if max <= u16::MAX as u32 { 16 } else { 32 };
    for v in values {
        if bits == 16 {
            bytes.extend_from_slice(&(v as u16).to_le_bytes());
        } else {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    (bits, base64(&bytes))
}

/// `x` rounded to `d` decimals, as a JSON number.
fn round(x: f64, d: i32) -> Value {
    let m = 10f64.powi(d);
    json!((x * m).round() / m)
}

fn flat(points: impl Iterator<Item = Point>) -> Vec<Value> {
    points.flat_map(|p| [round(p.x, 4), round(p.y, 4)]).collect()
}

/// The series the page shows round by round, index `k` = after `k` rounds.
pub struct Series {
    /// Fraction of `Ad` detected by the poses of rounds `0..=k`.
    pub detected: Vec<f64>,
    /// Targets found by then.
    pub found: Vec<u32>,
    /// The index at which each target was first within `r_st` of a robot.
    pub target_found_at: Vec<Option<usize>>,
    /// Simulated time at index `k`.
    pub time_s: Vec<f64>,
    /// Whether `time_s` is the engine's clock (else spread evenly).
    pub time_exact: bool,
    /// `(round, i, j)`: robots `i < j` came closer than `2 r_safe` (or met on
    /// one vertex) while moving in that round, as the referee counts them.
    pub collisions: Vec<(usize, usize, usize)>,
}

/// Computes [`Series`] from the recorded poses.
pub fn series(rec: &Recorded) -> Series {
    let world = &rec.world;
    let params = &world.params;
    let rounds = rec.rounds();
    let raster = world.raster(RASTER_CELL * params.a);
    let samples = raster.samples().max(1) as f64;
    let mut hit = raster.unmarked();
    let mut detected_count = 0usize;
    let mut seen_vertex = vec![false; world.grid.len()];
    let mut seen_xy: HashSet<(u64, u64)> = HashSet::new();
    let r_st2 = params.r_st * params.r_st;
    let mut target_found_at: Vec<Option<usize>> = vec![None; world.targets.len()];
    let mut found = 0u32;
    let (mut detected, mut found_series) = (Vec::with_capacity(rounds + 1), Vec::with_capacity(rounds + 1));
    for k in 0..=rounds {
        for record in &rec.poses {
            let Some(p) = record.get(k) else { continue };
            // A place already marked adds nothing: skip the raster pass.
            let new = match p.vertex {
                Some(v) => !std::mem::replace(&mut seen_vertex[v as usize], true),
                None => seen_xy.insert((p.position.x.to_bits(), p.position.y.to_bits())),
            };
            if !new {
                continue;
            }
            detected_count += raster.mark(&mut hit, p.position, params.r_st);
            let mut note = |t: usize| {
                if target_found_at[t].is_none() {
                    target_found_at[t] = Some(k);
                    found += 1;
                }
            };
            match p.vertex {
                Some(v) => world.targets_near(v).iter().for_each(|&t| note(t as usize)),
                None => {
                    for (t, q) in world.targets.iter().enumerate() {
                        if (q - p.position).norm_squared() <= r_st2 {
                            note(t);
                        }
                    }
                }
            }
        }
        detected.push(if raster.samples() == 0 { 1.0 } else { detected_count as f64 / samples });
        found_series.push(found);
    }

    let (time_s, time_exact) = match &rec.round_end_times_s {
        Some(t) => (std::iter::once(0.0).chain(t.iter().copied()).collect(), true),
        None => {
            let total = rec.summary.get("search_time_s").and_then(Value::as_f64).unwrap_or(0.0);
            let per = if rounds > 0 { total / rounds as f64 } else { 0.0 };
            ((0..=rounds).map(|k| per * k as f64).collect(), false)
        }
    };

    Series { detected, found: found_series, target_found_at, time_s, time_exact, collisions: collisions(rec) }
}

/// The referee's test (`Referee::count_collisions`) on consecutive recorded
/// poses: exact for grid policies, the round's net motion for LFP (whose
/// engine also tests the sub-steps in between). Per event, a pair that
/// starts the round in contact is the collision already marked.
fn collisions(rec: &Recorded) -> Vec<(usize, usize, usize)> {
    let params = &rec.world.params;
    let limit = 2.0 * params.r_safe;
    let events = params.ru_collisions == gridswarm::params::RuCollisions::PerEvent;
    let reach2 = (2.0 * params.a + limit).powi(2);
    let mut out = Vec::new();
    let mut moving: Vec<(usize, RecPose, RecPose)> = Vec::with_capacity(rec.poses.len());
    for k in 0..rec.rounds() {
        moving.clear();
        moving.extend(rec.poses.iter().enumerate().filter_map(|(r, p)| Some((r, *p.get(k)?, *p.get(k + 1)?))));
        for (a, &(i, p0, p1)) in moving.iter().enumerate() {
            for &(j, q0, q1) in &moving[a + 1..] {
                let d2 = (q0.position - p0.position).norm_squared();
                if d2 > reach2 || (events && d2 < limit * limit) {
                    continue;
                }
                let same_end = match (p1.vertex, q1.vertex) {
                    (Some(u), Some(v)) => u == v,
                    _ => p1.position == q1.position,
                };
                if same_end || swept_min_distance(p0.position, p1.position, q0.position, q1.position) < limit {
                    out.push((k, i, j));
                }
            }
        }
    }
    out
}

/// The injected faults for the page, `[robot, kind, round, thaw]` each:
/// kind 0 a crash, 1 a freeze; `thaw` the first round whose end is past
/// the thaw (-1: never), so the page draws it frozen until then.
fn faults(summary: &Value, time_s: &[f64]) -> Vec<[i64; 4]> {
    let list = summary.get("failures").and_then(Value::as_array).map(Vec::as_slice).unwrap_or_default();
    list.iter()
        .filter_map(|f| {
            let robot = f.get("robot")?.as_u64()? as i64;
            let round = f.get("round")?.as_u64()? as i64;
            let crash = f.get("kind")?.as_str()? == "crash";
            let thaw = f
                .get("thawed_s")
                .and_then(Value::as_f64)
                .map_or(-1, |t| time_s.iter().position(|&e| e >= t).unwrap_or(time_s.len()) as i64);
            Some([robot, i64::from(!crash), round, thaw])
        })
        .collect()
}

/// The page's data: everything the script draws, as one JSON object.
pub fn data(rec: &Recorded) -> Value {
    let world = &rec.world;
    let grid = &world.grid;
    let s = series(rec);
    let rounds = rec.rounds();

    // Vertex table: the accessible vertices, then any other vertex a robot
    // stood on (none in a valid run, but a replay should still show it).
    let mut index = vec![NONE; grid.len()];
    let mut table: Vec<VertexId> = world.accessible_vertices().collect();
    let accessible = table.len();
    for (k, &v) in table.iter().enumerate() {
        index[v as usize] = k as u32;
    }
    for p in rec.poses.iter().flatten() {
        if let Some(v) = p.vertex {
            if index[v as usize] == NONE {
                index[v as usize] = table.len() as u32;
                table.push(v);
            }
        }
    }
    let mut edges = Vec::new();
    for v in world.accessible_vertices() {
        for (d, &n) in grid.neighbors(v)[..grid.degree()].iter().enumerate() {
            if n != NONE && v < n && world.open_mask(v) >> d & 1 == 1 {
                edges.extend([index[v as usize], index[n as usize]]);
            }
        }
    }
    let vmax = table.len().saturating_sub(1) as u32;
    let (edge_bits, edge_data) = pack(edges.iter().copied(), vmax);

    let (lo, hi) = world.area.bounding_box();
    let on_grid = rec.poses.iter().flatten().all(|p| p.vertex.is_some());
    let lens: Vec<usize> = rec.poses.iter().map(Vec::len).collect();
    let traj = if on_grid {
        let (bits, data) = pack(rec.poses.iter().flatten().map(|p| index[p.vertex.unwrap() as usize]), vmax);
        json!({ "mode": "v", "bits": bits, "lens": lens, "data": data })
    } else {
        // 16-bit fixed point over the area's box (a pose outside it is clamped):
        // a 100 m map still resolves 1.5 mm.
        let (w, h) = ((hi.x - lo.x).max(1e-9), (hi.y - lo.y).max(1e-9));
        let q = |x: f64, lo: f64, w: f64| ((x - lo) / w * 65535.0).round().clamp(0.0, 65535.0) as u32;
        let values = rec.poses.iter().flatten().flat_map(|p| [q(p.position.x, lo.x, w), q(p.position.y, lo.y, h)]);
        let (bits, data) = pack(values, u16::MAX as u32);
        json!({ "mode": "xy", "bits": bits, "lens": lens, "data": data,
                "box": [lo.x, lo.y, w / 65535.0, h / 65535.0] })
    };

    let obstacles: Vec<Value> = rec
        .world_file
        .obstacles
        .iter()
        .map(|o| match o {
            rundir::ObstacleFile::Polygon(pts) => {
                json!({ "poly": flat(pts.iter().map(|p| Point::new(p[0], p[1]))) })
            }
            rundir::ObstacleFile::Circle { center, radius } => json!({ "circle": [center[0], center[1], radius] }),
        })
        .collect();
    let summary = &rec.summary;
    let pick = |k: &str| summary.get(k).cloned().unwrap_or(Value::Null);
    let p = &world.params;
    json!({
        "title": rec.title(),
        "meta": {
            "scenario": rec.world_file.scenario,
            "grid": rec.world_file.grid.name(),
            "algorithm": pick("algorithm"),
            "label": pick("label"),
            "robots": rec.poses.len(),
            "seed": pick("seed"),
            "situation": pick("situation"),
            "rounds": rounds,
            "search_time_s": pick("search_time_s"),
            "targets_found": pick("targets_found"),
            "targets_total": world.targets.len(),
            "collisions": pick("collisions"),
            "coverage": pick("coverage"),
            "complete": pick("complete"),
        },
        "params": { "a": p.a, "r_rob": p.r_rob, "r_safe": p.r_safe, "r_st": p.r_st, "r_c": p.r_c, "r_so": p.r_so },
        "bbox": [lo.x, lo.y, hi.x, hi.y],
        "area": flat(world.area.points.iter().copied()),
        "obstacles": obstacles,
        "targets": flat(world.targets.iter().copied()),
        "vertices": flat(table.iter().map(|&v| grid.position(v))),
        "accessible": accessible,
        "edges": { "bits": edge_bits, "data": edge_data },
        "traj": traj,
        "series": {
            "time_s": s.time_s.iter().map(|&t| round(t, 3)).collect::<Vec<_>>(),
            "time_exact": s.time_exact,
            "detected": s.detected.iter().map(|&d| round(d, 5)).collect::<Vec<_>>(),
            "found": s.found,
        },
        "target_found_at": s.target_found_at,
        "collisions": s.collisions.iter().flat_map(|&(k, i, j)| [k, i, j]).collect::<Vec<_>>(),
        "collision_counts": rec.round_collisions,
        "failures": rec.failures.iter().flat_map(|f| [f.robot as u64, f.round as u64]).collect::<Vec<_>>(),
        "faults": faults(summary, &s.time_s).into_iter().filter(|f| (f[0] as usize) < rec.poses.len()).collect::<Vec<_>>(),
        "settings": { "faults": crate::figures::faults_given(summary), "radio": crate::figures::radio_text(summary) },
        "palette": crate::write::palette::COLOURS,
        "target_colour": crate::write::palette::TARGET,
        "refused": rec.refused.iter().flat_map(|f| [f.robot as u64, f.round as u64]).collect::<Vec<_>>(),
        "refused_total": rec.refused_total,
    })
}

/// Fills `{{NAME}}` placeholders in one pass, so that no inserted text is
/// ever scanned for placeholders itself.
fn fill(template: &str, values: &[(&str, &str)]) -> String {
    let mut out = String::with_capacity(template.len() + values.iter().map(|(_, v)| v.len()).sum::<usize>());
    let mut rest = template;
    while let Some(start) = rest.find("{{") {
        let Some(len) = rest[start..].find("}}") else { break };
        let key = &rest[start + 2..start + len];
        out.push_str(&rest[..start]);
        match values.iter().find(|(k, _)| *k == key) {
            Some((_, v)) => out.push_str(v),
            None => out.push_str(&rest[start..start + len + 2]),
        }
        rest = &rest[start + len + 2..];
    }
    out.push_str(rest);
    out
}

/// Text safe inside a `<script>` element: JSON is unchanged by escaping
/// `<` as `\u003c`, and no `</script>` can end the element early.
fn script_safe_json(v: &Value) -> String {
    serde_json::to_string(v).expect("a JSON value serialises").replace('<', "\\u003c")
}

/// The replay page of a recorded run.
pub fn page(rec: &Recorded) -> String {
    let title = format!("gridswarm replay: {}", rec.title());
    fill(
        TEMPLATE,
        &[("TITLE", &crate::routes::xml_escape(&title)), ("DATA", &script_safe_json(&data(rec))), ("SCRIPT", SCRIPT)],
    )
}

/// (Re)writes `dir/replay.html` from `dir`'s recorded files; returns its path.
pub fn write(dir: &Path) -> Result<PathBuf> {
    let rec = Recorded::load(dir)?;
    let path = dir.join(rundir::REPLAY);
    output::write_text(&path, &page(&rec))?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_the_standard() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foo"), "Zm9v");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
        assert_eq!(base64(&[0xff, 0xfe, 0x00, 0x01]), "//4AAQ==");
    }

    #[test]
    fn fill_is_one_pass() {
        let t = "a {{X}} b {{Y}} c {{Z}}";
        assert_eq!(fill(t, &[("X", "{{Y}}"), ("Y", "2")]), "a {{Y}} b 2 c {{Z}}");
    }

    #[test]
    fn script_text_cannot_close_the_element() {
        let s = script_safe_json(&json!({ "title": "</script><b>" }));
        assert!(!s.contains("</"));
        assert_eq!(serde_json::from_str::<Value>(&s).unwrap()["title"], "</script><b>");
    }

    #[test]
    fn pack_widths() {
        assert_eq!(pack([1u32, 2].into_iter(), 65535), (16, base64(&[1, 0, 2, 0])));
        assert_eq!(pack([1u32].into_iter(), 65536), (32, base64(&[1, 0, 0, 0])));
    }
}
