//! `gridswarm map-setup MAP.yaml --robot-radius R`: a map's sidecar sized
//! for a robot, by one stated rule (docs/scenario-format.md "Sizing a map
//! for a robot"), never by the results of runs: `r_safe` is the default
//! parameters' share of the robot's radius, `a` the smallest whole
//! centimetre at which robots on the lattice keep `2 r_safe` apart (S0),
//! and the ranges the equality cases of their assumptions. It says which
//! passages the robot cannot take on that grid, reads the map as the
//! sidecar will have it read, checks it, and writes the sidecar whole or
//! not at all, never over an existing file unless asked.

use std::fs::{self, OpenOptions};
use std::io::Write as _;
use std::path::{Path, PathBuf};

use gridswarm::assumptions::{self, Spacing};
use gridswarm::lattice::{Lattice, LatticeKind};
use gridswarm::scenario::{limits, occupancy, Scenario};

use crate::check;
use crate::error::{Error, Result};
use crate::output::shown;

/// `r_safe / r_rob` of the default parameters (0.30 / 0.25): the margin
/// for every error (localisation, control) the paper folds into `r_safe`.
pub const SAFE_PER_RADIUS: f64 = 1.2;

/// Passages listed by name; the rest are counted.
const LISTED: usize = 20;

/// What `map-setup` was asked.
pub struct MapSetupOptions {
    pub map: String,
    pub robot_radius: f64,
    /// [default: the sidecar the map reads, `NAME.gridswarm.toml`].
    pub out: Option<PathBuf>,
    pub force: bool,
}

/// The lengths a robot of radius `r_rob` asks for (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sizes {
    pub r_rob: f64,
    pub r_safe: f64,
    pub a: f64,
    pub r_so: f64,
    pub r_st: f64,
    pub r_c: f64,
}

/// `x` to whole micrometres, never below it (past the checks' slack).
fn up_um(x: f64) -> f64 {
    let v = (x * 1e6).round() / 1e6;
    if v < x - 1e-12 {
        v + 1e-6
    } else {
        v
    }
}

/// The rule: `r_safe = SAFE_PER_RADIUS r_rob`; `a` the smallest whole
/// centimetre at which S0's nearest approach on `kind` exceeds `2 r_safe`
/// (`sqrt(3)/2 a` on the triangular grid: a robot passing another along an
/// edge); `r_so = r_st = a + r_safe` (2.4, 3.1.1) and
/// `r_c = 2a + r_safe - r_rob` (2.5), each the least its assumption allows.
pub fn sizes(r_rob: f64, kind: LatticeKind) -> std::result::Result<Sizes, String> {
    let r_safe = up_um(SAFE_PER_RADIUS * r_rob);
    let per_side = Spacing::of(Lattice::new(kind, 1.0)).nearest().0;
    let mut cm = (2.0 * r_safe / per_side * 100.0 + 1e-9).floor() + 1.0;
    // Rounding: the lattice's own distances decide, as the check's do.
    while Spacing::of(Lattice::new(kind, cm / 100.0)).nearest().0 <= 2.0 * r_safe + 1e-9 {
        cm += 1.0;
    }
    let a = cm / 100.0;
    if !(limits::MIN_A..=limits::MAX_A).contains(&a) {
        return Err(format!(
            "--robot-radius {r_rob} asks for a grid side a = {a} m, outside MIN_A = {} to MAX_A = {} m",
            limits::MIN_A,
            limits::MAX_A
        ));
    }
    let r_so = up_um(a + r_safe);
    Ok(Sizes { r_rob, r_safe, a, r_so, r_st: r_so, r_c: up_um(2.0 * a + r_safe - r_rob) })
}

/// The sizes with the ranges `base`'s `[params]` gives where they reach
/// farther than the assumptions ask: a range is the robot's sensor's or
/// radio's, which map-setup never shortens.
fn keep_ranges(base: &toml::Table, mut s: Sizes) -> Sizes {
    let given = |k: &str| base.get("params").and_then(|p| p.get(k)).and_then(toml::Value::as_float);
    for (k, v) in [("r_so", &mut s.r_so), ("r_st", &mut s.r_st), ("r_c", &mut s.r_c)] {
        if let Some(g) = given(k).filter(|g| g.is_finite() && *g > *v) {
            *v = g;
        }
    }
    s
}

/// The sidecar to write: the map's own sidecar (every key it has: targets,
/// starts, robots, name, `[map]`), with the sizes in `[params]` and
/// `[map] sliver` set; situation 2 when it names no target (situation 1
/// would have nothing to find).
fn sidecar_text(base: &toml::Table, s: &Sizes, sliver: Option<f64>, header: &str) -> String {
    let mut t = base.clone();
    let params = t.entry("params").or_insert_with(|| toml::Value::Table(toml::Table::new()));
    if let toml::Value::Table(p) = params {
        for (k, v) in
            [("a", s.a), ("r_rob", s.r_rob), ("r_safe", s.r_safe), ("r_so", s.r_so), ("r_st", s.r_st), ("r_c", s.r_c)]
        {
            p.insert(k.into(), toml::Value::Float(v));
        }
    }
    let map = t.entry("map").or_insert_with(|| toml::Value::Table(toml::Table::new()));
    if let toml::Value::Table(m) = map {
        match sliver {
            Some(w) => m.insert("sliver".into(), toml::Value::Float(w)),
            None => m.remove("sliver"),
        };
        if m.is_empty() {
            t.remove("map");
        }
    }
    let no_targets = t.get("targets").and_then(toml::Value::as_array).is_none_or(|a| a.is_empty());
    if no_targets {
        t.insert("situation".into(), toml::Value::Integer(2));
    }
    let mut text: String = header.lines().map(|l| format!("# {l}\n")).collect();
    if no_targets {
        text += "# No targets: situation 2 searches until every reachable vertex is visited; add\n\
                 # targets = [[x, y], ...] and situation = 1 to search for them.\n";
    }
    text + &toml::to_string(&t).expect("a TOML table serialises")
}

/// The map's sidecar as a table (empty when it has none).
fn base_sidecar(map: &str) -> Result<toml::Table> {
    let side = occupancy::sidecar_path(Path::new(map));
    if fs::symlink_metadata(&side).is_err() {
        return Ok(toml::Table::new());
    }
    let shown_side = side.display().to_string();
    let text =
        gridswarm::scenario::read_file(&shown_side).map_err(|e| Error::Scenario(format!("`{shown_side}`: {e}")))?;
    text.parse::<toml::Table>().map_err(|e| Error::Scenario(format!("`{shown_side}`: {e}")))
}

/// The map read with sidecar `text`, as a scenario, and how it was read.
fn read(map: &str, out: &Path, text: &str) -> Result<(Scenario, Vec<String>)> {
    let name = out.display().to_string();
    occupancy::load_with(map, Some((&name, text)))
        .map(|c| (c.scenario, c.notes))
        .map_err(|e| Error::Scenario(e.to_string()))
}

/// The passages narrower than `W_pass` in `s`, one line each.
fn narrow(s: &Scenario) -> Vec<String> {
    let w = s.world();
    let p = w.params;
    let w_pass = p.a + 2.0 * p.r_safe;
    let found = match assumptions::measured_passages(&w) {
        Ok(found) => found,
        Err(at) => return vec![format!("not measured: obstacles crowd near ({:.2}, {:.2})", at.x, at.y)],
    };
    let narrow: Vec<_> = found.into_iter().filter(|g| g.width < w_pass - 1e-9).collect();
    let mut lines: Vec<String> = narrow
        .iter()
        .take(LISTED)
        .map(|g| {
            let why = if g.width <= 2.0 * p.r_safe {
                "the robot does not fit (2 r_safe)"
            } else {
                "the robot fits, the grid need not pass"
            };
            format!("{} near ({:.2}, {:.2}): {:.3} m, {why}", g.between, g.at.x, g.at.y, g.width)
        })
        .collect();
    if narrow.len() > LISTED {
        lines.push(format!("and {} more", narrow.len() - LISTED));
    }
    lines
}

/// Writes `text` to `path` through a new file beside it (created
/// exclusively) renamed into place; without `force`, never over a file.
fn write_new(path: &Path, text: &str, force: bool) -> Result<()> {
    let name = path.file_name().ok_or_else(|| Error::Usage(format!("--out `{}` is not a file", path.display())))?;
    let tmp = path.with_file_name(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
    let mut f = OpenOptions::new().write(true).create_new(true).open(&tmp).map_err(Error::write(&tmp))?;
    let written = f.write_all(text.as_bytes()).and_then(|()| f.sync_all());
    drop(f);
    // Without --force, a hard link is the rename that never replaces.
    let placed = written.and_then(|()| if force { fs::rename(&tmp, path) } else { fs::hard_link(&tmp, path) });
    let _ = fs::remove_file(&tmp);
    placed.map_err(|e| match e.kind() {
        std::io::ErrorKind::AlreadyExists => exists(path),
        _ => Error::write(path)(e),
    })
}

fn exists(path: &Path) -> Error {
    Error::Input(format!(
        "`{}` exists: map-setup replaces a sidecar only with --force (keeping its targets, starts and other keys), \
         or writes elsewhere with --out FILE",
        path.display()
    ))
}

/// Sizes, reads, checks and writes; the text for stdout, and whether every
/// assumption holds with the sidecar written.
pub fn run(opts: &MapSetupOptions) -> Result<(String, bool)> {
    if !occupancy::is_map(&opts.map) {
        return Err(Error::Usage(format!("`{}` is not a map (NAME.yaml)", shown(&opts.map))));
    }
    let out = opts.out.clone().unwrap_or_else(|| occupancy::sidecar_path(Path::new(&opts.map)));
    if !opts.force && fs::symlink_metadata(&out).is_ok() {
        return Err(exists(&out));
    }
    let base = base_sidecar(&opts.map)?;
    let kind = match base.get("grid").and_then(toml::Value::as_str) {
        Some(g) => g.parse::<LatticeKind>().map_err(Error::Scenario)?,
        None => LatticeKind::Triangular,
    };
    let s = keep_ranges(&base, sizes(opts.robot_radius, kind).map_err(Error::Usage)?);
    let w_pass = up_um(s.a + 2.0 * s.r_safe);
    // The map's file name only: the same sidecar wherever the map lies.
    let file = Path::new(&opts.map).file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
    let header = format!(
        "written by gridswarm map-setup {} --robot-radius {}: r_safe = {SAFE_PER_RADIUS} r_rob, a the smallest\n\
         whole centimetre meeting S0, r_so = r_st = a + r_safe, r_c = 2a + r_safe - r_rob (or the sidecar's\n\
         own where farther), [map] sliver = W_pass = a + 2 r_safe (docs/scenario-format.md \"Sizing a map\n\
         for a robot\")",
        shown(&file),
        opts.robot_radius
    );
    // The passages as the robot's width alone would leave them.
    let (open, _) = read(&opts.map, &out, &sidecar_text(&base, &s, None, ""))?;
    let narrow = narrow(&open);
    let text = sidecar_text(&base, &s, Some(w_pass), &header);
    let (scenario, notes) = read(&opts.map, &out, &text)?;
    let world = scenario.world();
    let starts = crate::contract::start_vertices(&scenario, &world, scenario.robots)?;
    let report = crate::contract::check_assumptions(&scenario, &world, &starts);
    write_new(&out, &text, opts.force)?;

    let mut t = format!(
        "map {} for a robot of radius {} m: r_safe {} a {} r_so {} r_st {} r_c {} (m); W_pass = a + 2 r_safe = {w_pass}\n",
        shown(&opts.map),
        s.r_rob,
        s.r_safe,
        s.a,
        s.r_so,
        s.r_st,
        s.r_c
    );
    if narrow.is_empty() {
        t += "passages the robot cannot take: none narrower than W_pass\n";
    } else {
        t += &format!("passages the robot cannot take (narrower than W_pass, closed by [map] sliver = {w_pass}):\n");
        narrow.iter().for_each(|l| t += &format!("  {l}\n"));
    }
    t += "map as read with the sidecar:\n";
    notes.iter().for_each(|n| t += &format!("  {n}\n"));
    t += &format!("assumptions:\n{report}");
    for c in report.failures() {
        t += &format!("fix {:<8} {}\n", c.id, check::hint(c.id));
    }
    t += &format!("wrote {}\n", out.display());
    Ok((t, report.all_hold()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rule_sizes_a_turtlebot_and_the_defaults_robot() {
        // TurtleBot3 Burger, 0.105 m: r_safe 0.126, a > 4 r_safe / sqrt(3) = 0.291.
        let s = sizes(0.105, LatticeKind::Triangular).unwrap();
        assert_eq!((s.r_safe, s.a), (0.126, 0.3), "{s:?}");
        assert_eq!((s.r_so, s.r_st, s.r_c), (0.426, 0.426, 0.621), "{s:?}");
        // The default robot (0.25 m) gets r_safe 0.30, and a = 0.70: the
        // defaults' a = 1 is more than S0 needs.
        let d = sizes(0.25, LatticeKind::Triangular).unwrap();
        assert_eq!((d.r_safe, d.a), (0.3, 0.7), "{d:?}");
        // On the square grid the nearest approach is a itself.
        assert_eq!(sizes(0.25, LatticeKind::Square).unwrap().a, 0.61);
        assert!(sizes(1e6, LatticeKind::Triangular).unwrap_err().contains("MAX_A"));
    }

    #[test]
    fn every_size_meets_the_assumptions_it_comes_from() {
        for r in [0.01, 0.05, 0.1, 0.105, 0.17, 0.2, 0.25, 0.33, 0.5, 1.0] {
            for kind in LatticeKind::ALL {
                let s = sizes(r, kind).unwrap();
                let near = Spacing::of(Lattice::new(kind, s.a)).nearest().0;
                assert!(near > 2.0 * s.r_safe, "{r} {kind:?}: {s:?}");
                // The smallest such centimetre.
                let less = Spacing::of(Lattice::new(kind, s.a - 0.01)).nearest().0;
                assert!(less <= 2.0 * s.r_safe + 1e-9, "{r} {kind:?}: {s:?}");
                // The checks' slack is 1e-9 (assumptions.rs).
                let slack = 1e-12;
                assert!(s.r_safe > s.r_rob && s.r_so >= s.a + s.r_safe - slack, "{s:?}");
                assert!(s.r_c >= 2.0 * s.a + s.r_safe - s.r_rob - slack, "{s:?}");
            }
        }
    }
}
