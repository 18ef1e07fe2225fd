//! Writers for a run's files, shared by every engine: the in-process one
//! here and the distributed one later write the same bytes for the same
//! run, so their outputs can be compared with `cmp`.

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use gridswarm::lfp::LfpParams;
use gridswarm::outcome::{Pose, RunResult};
use gridswarm::scenario::Scenario;
use serde_json::{json, Value};

use crate::error::{Error, Result};

/// `s` for a terminal or a page's title: every control character (an
/// escape sequence, a newline that would fake an `error:` line) escaped as
/// `\u{1b}`, `\n`, ... A scenario's name is the user's text; the JSON
/// files keep it as it is (JSON escapes it itself).
pub fn shown(s: &str) -> std::borrow::Cow<'_, str> {
    if !s.chars().any(char::is_control) {
        return s.into();
    }
    s.chars().map(|c| if c.is_control() { c.escape_default().to_string() } else { c.to_string() }).collect()
}

/// Fixed-precision float for files meant to be compared byte for byte.
/// Negative zero is written as zero: two engines may reach the same
/// position by different float paths, and only the sign of zero differs.
pub fn fixed(x: f64) -> String {
    let s = format!("{x:.6}");
    if s.starts_with('-') && s[1..].bytes().all(|b| b == b'0' || b == b'.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// Writes `trajectories.jsonl`: one line per robot per round, round-major
/// then robot order, `{"round":k,"robot":r,"vertex":[i,j]|null,"x":..,"y":..}`.
/// `trajectories[r][k]` is robot `r` at the start of round `k`. Robots with
/// shorter records (a stopped or failed robot in some engine) simply end.
pub fn write_trajectories<W: Write>(mut w: W, trajectories: &[Vec<Pose>]) -> io::Result<()> {
    let rounds = trajectories.iter().map(Vec::len).max().unwrap_or(0);
    for k in 0..rounds {
        for (r, poses) in trajectories.iter().enumerate() {
            let Some(p) = poses.get(k) else { continue };
            let vertex = match p.vertex {
                Some(c) => format!("[{},{}]", c.i, c.j),
                None => "null".to_string(),
            };
            writeln!(
                w,
                "{{\"round\":{k},\"robot\":{r},\"vertex\":{vertex},\"x\":{},\"y\":{}}}",
                fixed(p.position.x),
                fixed(p.position.y)
            )?;
        }
    }
    w.flush()
}

/// The summary of one run: its result, and the scenario and parameters
/// that produced it, so a summary alone says how to reproduce it.
pub fn run_summary(scenario: &Scenario, lfp: &LfpParams, result: &RunResult) -> Value {
    json!({
        "scenario": scenario.name,
        "grid": scenario.grid.name(),
        "algorithm": result.algorithm.name(),
        "label": result.algorithm.paper_label(),
        "robots": result.robots,
        "seed": result.seed,
        "situation": result.situation,
        "rounds": result.rounds,
        "search_time_s": result.search_time_s,
        "targets_found": result.targets_found,
        "targets_total": result.targets_total,
        "collisions": result.collisions,
        "coverage": result.coverage,
        "complete": result.complete,
        "robot_rounds": result.robot_rounds,
        "params": scenario.params,
        "lfp": lfp,
    })
}

/// Creates `dir` and its parents if missing.
pub fn create_dir(dir: &Path) -> Result<()> {
    fs::create_dir_all(dir).map_err(|source| Error::OutDir { path: dir.to_path_buf(), source })
}

/// Writes a file through a buffer, naming the file in any error.
pub fn write_file(path: &Path, body: impl FnOnce(&mut BufWriter<fs::File>) -> io::Result<()>) -> Result<()> {
    let run = || -> io::Result<()> {
        let mut w = BufWriter::new(fs::File::create(path)?);
        body(&mut w)?;
        w.flush()
    };
    run().map_err(Error::write(path))
}

/// Writes a JSON value, pretty-printed, with a final newline.
pub fn write_json(path: &Path, value: &Value) -> Result<()> {
    write_file(path, |w| {
        serde_json::to_writer_pretty(&mut *w, value)?;
        writeln!(w)
    })
}

pub fn write_text(path: &Path, text: &str) -> Result<()> {
    write_file(path, |w| w.write_all(text.as_bytes()))
}

/// A CSV cell for an optional number: empty when there is none.
pub fn csv_num(x: Option<f64>) -> String {
    x.map(|v| format!("{v:.6}")).unwrap_or_default()
}

/// The lines that open a run's report on the terminal, for either engine:
/// what was run, then how it ended (the engine's own `ended_by`, never a
/// guess), then for grid policies the protocol's counts and one line per
/// injected failure with its detection delay. `engine` follows the first
/// line (e.g. ": one process per robot"); `extra` goes before the coverage.
pub fn headline(scenario: &Scenario, result: &RunResult, engine: &str, extra: &str) -> String {
    let ended = &result.protocol.ended_by;
    // A collision its algorithm promises against outweighs a complete search.
    let how = match (crate::error::collided(result), result.complete) {
        (true, true) => "COLLIDED, search complete",
        (true, false) => "COLLIDED, search INCOMPLETE",
        (false, true) => "complete",
        (false, false) => "INCOMPLETE",
    };
    let mut s = format!(
        "scenario {} ({} grid), algorithm {} [{}], {} robots, seed {}, situation {}{engine}\n\
         {how} ({}: {}) after {} rounds: {:.1} s simulated search time; targets {}/{}; collisions {}; {extra}coverage {}\n",
        shown(&scenario.name),
        scenario.grid.name(),
        result.algorithm.name(),
        result.algorithm.paper_label(),
        result.robots,
        result.seed,
        result.situation,
        if ended.is_empty() { "-" } else { ended.as_str() },
        crate::figures::ended_text(&result.protocol),
        result.rounds,
        result.search_time_s,
        result.targets_found,
        result.targets_total,
        result.collisions,
        result.coverage.map(|c| format!("{c:.4}")).unwrap_or_else(|| "not measured".into())
    );
    if result.algorithm.on_grid() {
        s += &crate::figures::protocol_line(result);
        s += &crate::figures::failure_lines(result);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridswarm::geometry::Point;
    use gridswarm::lattice::Coord;

    fn pose(v: Option<(i32, i32)>, x: f64, y: f64) -> Pose {
        Pose { vertex: v.map(|(i, j)| Coord::new(i, j)), position: Point::new(x, y) }
    }

    #[test]
    fn trajectories_round_major() {
        let t = vec![
            vec![pose(Some((0, 0)), 0.0, 0.0), pose(Some((1, 0)), 1.0, 0.0)],
            vec![pose(None, 2.5, -1e-9), pose(None, 1.0 / 3.0, 0.866_025_403_8)],
        ];
        let mut out = Vec::new();
        write_trajectories(&mut out, &t).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(
            text,
            "{\"round\":0,\"robot\":0,\"vertex\":[0,0],\"x\":0.000000,\"y\":0.000000}\n\
             {\"round\":0,\"robot\":1,\"vertex\":null,\"x\":2.500000,\"y\":0.000000}\n\
             {\"round\":1,\"robot\":0,\"vertex\":[1,0],\"x\":1.000000,\"y\":0.000000}\n\
             {\"round\":1,\"robot\":1,\"vertex\":null,\"x\":0.333333,\"y\":0.866025}\n"
        );
        for line in text.lines() {
            let v: Value = serde_json::from_str(line).unwrap();
            assert!(v["round"].is_u64() && v["x"].is_f64());
        }
    }

    #[test]
    fn ragged_records_end_early() {
        let t =
            vec![vec![pose(Some((0, 0)), 0.0, 0.0)], vec![pose(Some((1, 0)), 1.0, 0.0), pose(Some((2, 0)), 2.0, 0.0)]];
        let mut out = Vec::new();
        write_trajectories(&mut out, &t).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(text.lines().count(), 3);
        assert!(text.lines().last().unwrap().starts_with("{\"round\":1,\"robot\":1,"));
    }

    #[test]
    fn fixed_formats() {
        assert_eq!(fixed(-0.0), "0.000000");
        assert_eq!(fixed(-1e-12), "0.000000");
        assert_eq!(fixed(-0.5), "-0.500000");
        assert_eq!(fixed(12.3456789), "12.345679");
    }
}
