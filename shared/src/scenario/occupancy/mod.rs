//! Occupancy-grid maps: a ROS map_server map (`NAME.yaml` naming a PGM or
//! PNG image) read as a scenario, and any scenario written as one.
//!
//! The image is read as map_server reads it ([`image`]), in cells of whole
//! pixels ([`outline`]): the largest free region is the area, every blocked
//! region inside it an obstacle. What a map cannot say (targets, where the
//! robots start, the robots' parameters) comes from an optional sidecar
//! beside it, `NAME.gridswarm.toml`: a scenario file without `[area]` and
//! `[[obstacles]]`, plus a `[map]` table (`cell`, `unknown`). The same
//! path gives the same scenario in every process, which is how `gridswarm
//! run`'s world and robots agree on it (`crate::agreement`).
//!
//! Never: write a file while reading, or read a file that is not regular
//! or beyond its limit ([`MAX_IMAGE_PIXELS`], `MAX_IMAGE_BYTES`).

mod export;
mod image;
mod outline;
mod yaml;

pub use export::{write_map, DEFAULT_RESOLUTION_SIDES};
pub use image::MAX_IMAGE_PIXELS;

use std::path::{Path, PathBuf};

use super::file::{self, MAX_IMAGE_BYTES};
use super::locate::Node;
use super::raw::{Ctx, RawSidecar};
use super::{limits, Scenario, ScenarioError};
use crate::geometry::{Point, Polygon, Shape};
use crate::params::Params;
use image::Class;
use outline::{Frame, Outline};

/// Whether `name` names a map_server map (`.yaml` or `.yml`).
pub fn is_map(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    lower.ends_with(".yaml") || lower.ends_with(".yml")
}

/// The sidecar of map `yaml`: `NAME.gridswarm.toml` beside `NAME.yaml`.
pub fn sidecar_path(yaml: &Path) -> PathBuf {
    let stem = yaml.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    yaml.with_file_name(format!("{stem}.gridswarm.toml"))
}

/// A map read as a scenario, and what the reading changed, one line each.
#[derive(Clone, Debug)]
pub struct Converted {
    pub scenario: Scenario,
    pub notes: Vec<String>,
}

/// The map at `path` as a scenario, with its sidecar if it has one.
pub fn load(path: &str) -> Result<Converted, ScenarioError> {
    let side = sidecar_path(Path::new(path));
    let side_shown = side.display().to_string();
    if std::fs::symlink_metadata(&side).is_err() {
        return load_with(path, None);
    }
    let text =
        file::read(&side_shown).map_err(|e| ScenarioError::new(path, None, "", format!("`{side_shown}`: {e}")))?;
    load_with(path, Some((&side_shown, &text)))
}

/// The map at `path` as a scenario, with `sidecar` (its name as errors
/// show it, and its text) in place of whatever sidecar lies beside it:
/// how `gridswarm map-setup` tries a sidecar before writing it.
pub fn load_with(path: &str, sidecar: Option<(&str, &str)>) -> Result<Converted, ScenarioError> {
    let fail = |field: &str, m: String| ScenarioError::new(path, None, field, m);
    let text = file::read(path).map_err(|e| fail("", e.replace("scenario file", "map file")))?;
    let meta = yaml::parse(&text).map_err(|(f, m, line)| ScenarioError::new(path, line.map(|l| (l, 1)), f, m))?;
    let image_path = Path::new(path).parent().unwrap_or(Path::new("")).join(&meta.image);
    let shown = image_path.display().to_string();
    let bytes = file::read_bytes(&shown, "map image", MAX_IMAGE_BYTES, "MAX_IMAGE_BYTES")
        .map_err(|e| fail("image", format!("`{shown}`: {e}")))?;
    let raster = image::decode(&bytes, &meta).map_err(|e| fail("image", format!("`{shown}` {e}")))?;

    let has_side = sidecar.is_some();
    let (side_shown, side_text) = sidecar.unwrap_or((path, ""));
    let ctx = Ctx { text: side_text, file: side_shown, tree: toml::from_str::<Node>(side_text).ok() };
    let sidecar = RawSidecar::parse(&ctx)?;
    let unknown_free = match sidecar.map.unknown.as_deref() {
        None | Some("blocked") => false,
        Some("free") => true,
        Some(other) => return Err(ctx.err("map.unknown", format!("must be \"blocked\" or \"free\", got `{other}`"))),
    };
    let mut sizes = Sizes::of(&sidecar);
    let a = sizes.a;
    match sidecar.map.sliver {
        None => {}
        Some(w) if w.is_finite() && (0.0..=a * limits::MAX_SENSING_SIDES).contains(&w) => sizes.sliver = w,
        Some(w) => {
            return Err(ctx
                .err("map.sliver", format!("must be a width from 0 to {} m, got {w}", a * limits::MAX_SENSING_SIDES)))
        }
    }
    let frame = Frame { origin: meta.origin, resolution: meta.resolution };
    let first = match sidecar.map.cell {
        None => ((a * DEFAULT_CELL_SIDES / meta.resolution).floor() as usize).max(1),
        Some(c) if c.is_finite() && c >= meta.resolution && c <= a => (c / meta.resolution).round() as usize,
        Some(c) => {
            let m = format!(
                "must be from the image's resolution {} m to the grid side a = {a} m, got {c}",
                meta.resolution
            );
            return Err(ctx.err("map.cell", m));
        }
    };
    let (k, map, grown) =
        read_cells(&raster, frame, first, unknown_free, sizes).map_err(|e| fail("image", format!("`{shown}` {e}")))?;
    let stem = Path::new(path).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let scenario = sidecar.into_scenario(&ctx, &stem, &map.area, &map.obstacles).map_err(|mut e| {
        // The area and the obstacles come from the image, not the sidecar.
        if e.field.starts_with("area") || e.field.starts_with("obstacles") {
            (e.file, e.at) = (path.to_string(), None);
        }
        e
    })?;
    let read = Reading { raster: &raster, resolution: meta.resolution, k, first, grown, unknown_free, sizes };
    let mut notes = read.notes(&map);
    notes.push(if has_side {
        format!("targets, starts and parameters from {side_shown}")
    } else {
        let side = sidecar_path(Path::new(path));
        format!("no sidecar {}: no targets, the robots start along the border, default parameters", side.display())
    });
    Ok(Converted { scenario, notes })
}

/// The default cell side, in grid sides: the coverage check's raster is
/// as fine (assumptions.rs), so finer cells would only add corners.
const DEFAULT_CELL_SIDES: f64 = 0.1;

/// The lengths reading a map depends on: the grid side, the robot's and
/// the safety radius, as the sidecar asks for them, or the defaults where
/// it gives none or nonsense (its own checks report that later).
#[derive(Clone, Copy, Debug)]
struct Sizes {
    a: f64,
    r_safe: f64,
    /// Free parts narrower than this are blocked: the robot's width
    /// `2 r_rob`, or `[map] sliver`.
    sliver: f64,
}

impl Sizes {
    fn of(sidecar: &RawSidecar) -> Sizes {
        let d = Params::default();
        let ok = |v: Option<f64>, dflt: f64| v.filter(|v| v.is_finite() && *v > 0.0).unwrap_or(dflt);
        let (a, r_rob, r_safe) = sidecar.sizes();
        let a = ok(a, d.a).clamp(limits::MIN_A, limits::MAX_A);
        Sizes { a, r_safe: ok(r_safe, d.r_safe), sliver: 2.0 * ok(r_rob, d.r_rob) }
    }

    /// Cells of side `cell` that the sliver width spans.
    fn sliver(&self, cell: f64) -> usize {
        ((self.sliver / cell - 1e-9).ceil() as usize).max(1)
    }
}

/// The image read in cells of `first` pixels, or twice as many as often as
/// the outline breaks a limit while a cell stays within a grid side and
/// the free region keeps at least [`KEPT_WHEN_GROWN`] of its first area:
/// the pixels per cell, the outline, and the limit that made it grow.
fn read_cells(
    raster: &image::Raster,
    frame: Frame,
    first: usize,
    unknown_free: bool,
    sizes: Sizes,
) -> Result<(usize, Outline, Option<String>), String> {
    let (mut k, a) = (first, sizes.a);
    let area = |k: usize, map: &Outline| map.free_cells as f64 * (k * k) as f64;
    let mut grown: Option<(String, f64)> = None;
    loop {
        let sliver = sizes.sliver(k as f64 * frame.resolution);
        let cell = k as f64 * frame.resolution;
        let map = outline::outline(raster, frame, k, sliver, unknown_free);
        if let Some((why, before)) = &grown {
            // Coarse cells block every cell a wall pixel or speck touches:
            // a building's doors close and its rooms become pockets.
            if map.as_ref().map_or(true, |m| area(k, m) < KEPT_WHEN_GROWN * before) {
                let first = first as f64 * frame.resolution;
                return Err(format!(
                    "read in cells of {first} m: {why}; in cells of {cell} m it would lose most of its free \
                     region, so it is not grown: crop the image, or choose `[map] cell` in the sidecar"
                ));
            }
        }
        let map = map?;
        let Err(why) = fits(&map, a, sizes.r_safe) else {
            return Ok((k, map, grown.map(|(why, _)| why)));
        };
        let larger = 2 * k;
        if larger as f64 * frame.resolution > a.max(cell) || larger > raster.width.max(raster.height) {
            return Err(format!(
                "read in cells of {cell} m: {why}, and larger cells would pass the grid side a = {a} m"
            ));
        }
        grown = Some(grown.unwrap_or_else(|| (why, area(k, &map))));
        k = larger;
    }
}

/// The share of the first reading's free area a grown reading must keep.
const KEPT_WHEN_GROWN: f64 = 0.5;

/// Whether an outline fits the scenario limits that the cell size drives.
fn fits(map: &Outline, a: f64, r_safe: f64) -> Result<(), String> {
    let corners = map.area.len() + map.obstacles.iter().map(Vec::len).sum::<usize>();
    let biggest = map.obstacles.iter().map(Vec::len).chain([map.area.len()]).max().unwrap_or(0);
    limits::count("the largest outline's corners", biggest, "MAX_CORNERS", limits::MAX_CORNERS)?;
    limits::count("corners", corners, "MAX_TOTAL_CORNERS", limits::MAX_TOTAL_CORNERS)?;
    limits::count("obstacles", map.obstacles.len(), "MAX_OBSTACLES", limits::MAX_OBSTACLES)?;
    let poly = |pts: &[(f64, f64)]| Polygon::new(pts.iter().map(|&(x, y)| Point::new(x, y)).collect());
    let obstacles: Vec<Shape> = map.obstacles.iter().map(|o| Shape::Polygon(poly(o))).collect();
    limits::check_geometry(&poly(&map.area), &obstacles, a, r_safe).map(|_| ())
}

/// How an image was read, for the notes.
struct Reading<'a> {
    raster: &'a image::Raster,
    resolution: f64,
    k: usize,
    first: usize,
    grown: Option<String>,
    unknown_free: bool,
    sizes: Sizes,
}

impl Reading<'_> {
    fn notes(&self, map: &Outline) -> Vec<String> {
        let r = self.raster;
        let count = |c: Class| r.cells.iter().filter(|&&x| x == c).count();
        let unknown = if self.unknown_free { "free" } else { "blocked" };
        let mut notes = vec![format!(
            "image {} x {} pixels of {} m: {} free, {} occupied, {} unknown (read as {unknown})",
            r.width,
            r.height,
            self.resolution,
            count(Class::Free),
            count(Class::Occupied),
            count(Class::Unknown)
        )];
        let cell = self.k as f64 * self.resolution;
        let mut line =
            format!("read in cells of {cell} m ({0} x {0} pixels, a cell blocked if any pixel is occupied)", self.k);
        if let Some(why) = &self.grown {
            let first = self.first as f64 * self.resolution;
            line.push_str(&format!("; grown from {first} m, where {why}"));
        }
        notes.push(line);
        let corners: usize = map.obstacles.iter().map(Vec::len).sum();
        notes.push(format!(
            "{} blocked cells merged into {} obstacles ({corners} corners); {} free cells in an area of {} corners",
            map.obstacle_cells,
            map.obstacles.len(),
            map.free_cells,
            map.area.len()
        ));
        if map.sliver_cells > 0 {
            let s = self.sizes.sliver(cell);
            notes.push(format!(
                "{} free cells in slivers narrower than {s} cells ({} m: [map] sliver, default the robot's width \
                 2 r_rob) read as blocked",
                map.sliver_cells, self.sizes.sliver
            ));
        }
        if map.pockets > 0 {
            notes.push(format!(
                "{} free pockets apart from the largest free region ({} cells) read as blocked",
                map.pockets, map.pocket_cells
            ));
        }
        if map.pinch_cells > 0 {
            notes.push(format!(
                "{} free cells blocked where free cells touched only at a corner (an outline may not touch itself)",
                map.pinch_cells
            ));
        }
        notes
    }
}
