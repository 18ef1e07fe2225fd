//! Admission limits: what a scenario may ask of the machine, checked while
//! it is read and before anything is allocated or computed in proportion to
//! it (issue 11). A file of a few bytes can name a billion grid vertices
//! (`a = 0.01`), a laser that sees every target from every vertex
//! (`r_st = 1e300`) or a move that lasts longer than the clock can count
//! (`t_rot = 1e308`); each such request is refused here with the field, the
//! value and the limit, instead of running out of memory or time later.
//!
//! The limits are generous: every built-in, every example of
//! docs/scenario-format.md and every `random:` map its options accept pass,
//! and `MAX_ROBOTS` leaves room for 10,000 robots (issue 10). The derived
//! ones bound products that the world build and the assumption checks pay
//! for: vertices times the pieces each vertex is tested against, robots
//! times the vertices each robot's map holds. docs/scenario-format.md lists
//! every constant.

use super::{Scenario, ScenarioError};
use crate::geometry::{Polygon, Shape};
use crate::lattice::LatticeKind;

/// Largest |x| or |y| of any point (m): keeps lattice coordinates
/// (position / a) far inside `i32` and products of coordinates exact enough.
pub const MAX_COORD: f64 = 1e5;
/// Smallest grid side `a` (m).
pub const MIN_A: f64 = 1e-3;
/// Largest grid side `a` (m).
pub const MAX_A: f64 = 1e3;
/// Largest robot, safety, sonar and laser range, in grid sides: the
/// coverage check stamps a disc of `r_st` around every vertex and LFP's
/// sensing index one of `r_so` around every wall.
pub const MAX_SENSING_SIDES: f64 = 20.0;
/// Largest radio range `r_c`, in grid sides. The radio's cost grows with
/// the robots in range, not the range, so this only keeps it finite.
pub const MAX_RADIO_SIDES: f64 = 1000.0;
/// Smallest positive time (s): the simulated clock counts microseconds, so
/// a shorter `t_exchange`, `t_hop` or `t_wait` would round to nothing.
pub const MIN_TIME: f64 = 1e-6;
/// Largest time parameter (s). Sums of them over 10^5 rounds stay exact in
/// microseconds and finite in seconds (`t_rot = t_trans = 1e308` made the
/// search time NaN).
pub const MAX_TIME: f64 = 3600.0;
/// Corners of one polygon (area or obstacle): simplicity and the passages
/// across a polygon's own concavities are quadratic in them, and every
/// vertex is tested against every edge of the area.
pub const MAX_CORNERS: usize = 1000;
/// Corners of the area and every polygon obstacle together (a 400 x 400 m
/// random map has some 30,000).
pub const MAX_TOTAL_CORNERS: usize = 100_000;
/// Obstacles (a 400 x 400 m random map holds several thousand).
pub const MAX_OBSTACLES: usize = 20_000;
/// Targets.
pub const MAX_TARGETS: usize = 10_000;
/// Robots, from the file or the command line: a robot id is 16 bits on the
/// radio ([`crate::protocol::MAX_ROBOTS`]).
pub const MAX_ROBOTS: usize = crate::protocol::MAX_ROBOTS;
/// Lattice vertices in the frame, the area's bounding box (counted from its
/// extent and `a`, before any is made).
pub const MAX_FRAME_VERTICES: f64 = 1e6;
/// Cells of the coverage raster (side `a / 10` over the area's bounding box).
pub const MAX_RASTER_CELLS: f64 = 4e7;
/// Frame vertices times (AREA_CORNER_WEIGHT x area corners + obstacles +
/// targets): what building and checking a world would test if every vertex
/// met every edge of the area, obstacle and target. World::new looks only
/// at those listed near each vertex, so at the limit `check` takes a few
/// seconds (900 x 900 m, 3,844 obstacles: 3.5 s of CPU, 2026-12-02); the
/// bound stays for the checks that still pair items.
pub const MAX_VERTEX_WORK: f64 = 4e9;
/// What one area corner costs per vertex against one obstacle (measured:
/// about 240 ns against 12 ns).
pub const AREA_CORNER_WEIGHT: usize = 20;
/// Robots times frame vertices: every robot's map holds about 1.25 bytes
/// per frame vertex.
pub const MAX_ROBOT_VERTICES: f64 = 4e8;
/// Perimeter of the area and every obstacle together, in grid sides `a`
/// (a circle's is `2 pi r`). The coverage check samples every edge each
/// `a/20` and the raster of `Ad` crosses every edge once a row of side
/// `a/10`: 8,000 thin quads 600 m long made 9.5 million sides, 25 s of
/// `check` (issue 23). A 400 x 400 m `random:` map has some 43,000.
pub const MAX_PERIMETER_SIDES: f64 = 2e5;
/// Obstacle boxes, each grown by `2a + 2 r_safe` and counted in `a^2`,
/// times (corners + 1): about how many edge tests building the world may
/// make, since it tests each vertex and edge against the obstacles whose
/// boxes are near it. A long thin diagonal obstacle has a box far bigger
/// than itself: 450 of them 212 m long took 8 s of `check`; 80 (9.6e6)
/// take 1.6 s. A 400 x 400 m `random:` map comes to about 1.4e6.
pub const MAX_COVER_WORK: f64 = 1e7;
/// Segment tests of the gaps between pieces near one another (boxes within
/// `3a`): obstacle to obstacle and to the area's edges, and every
/// polygon against itself, as admission and Assumption 3.1.3 measure them
/// ([`crate::scenario::pairs`]). 8,000 quads 3 cm apart are 32 million
/// pairs; ten interleaved zigzags of 1,000 corners 25 million tests.
pub const MAX_PAIR_WORK: f64 = 5e7;
/// Largest LFP gain or length scale (`scale`, `k_robot`, `k_obstacle`):
/// larger ones overflow the potential field to infinity.
pub const MAX_LFP_GAIN: f64 = 1e6;
/// Longest LFP flight, `max_step`, in grid sides.
pub const MAX_FLIGHT_SIDES: f64 = 1e4;
/// Largest LFP turn sigma (rad); beyond a few radians a turn is uniform anyway.
pub const MAX_TURN_SIGMA: f64 = 100.0;
/// LFP micro-steps per sub-step: every one is a pass over all robots.
pub const MAX_MICRO_STEPS: u32 = 1000;

/// Rounds a run lasts at most when nobody says otherwise (`RunConfig::new`,
/// `experiment`), and the most the work budget grants `simulate`.
pub const DEFAULT_MAX_ROUNDS: u32 = 100_000;
/// Search work a scenario may ask of one `simulate` without `--max-rounds`,
/// in map passes ([`round_work`]): every round each robot copies its map
/// and merges the map of every robot it hears, each a pass over the
/// frame's tiles, and answers each of them. Measured at about 2.8e-11 s of
/// CPU a unit (10,000 robots on a 180 x 180 m map: 0.37 s a round; 3
/// robots on 400 x 400 m: 17 us; 500 robots that all hear each other on
/// 100 x 100 m: 2.2 s), this is a second or two of rounds: the default
/// round limit is lowered to fit it ([`round_limit`]), and only the command
/// line (`--max-rounds N`) may ask for more.
pub const MAX_SEARCH_WORK: f64 = 1e11;
/// What a pair of robots in range costs a round beyond the map passes, per
/// robot heard, in [`MAX_SEARCH_WORK`]'s units: every frame is looked up
/// among those already heard, so a robot that hears `k` others pays about
/// `k^2` (500 robots in one radio range took 2.2 s a round).
pub const HEARD_PAIR_WORK: f64 = 400.0;

/// How many times dearer a frame between robots in range is when the radio
/// is impaired (`--loss`, `--delay`, `--dup`), per `1 + dup`: measured on
/// `large` with `r_c = 1000` (50 robots that all hear each other, 1,493
/// rounds), 3.1 s of CPU on a perfect radio, 7.6 s at `--loss 0.1`, 18 s
/// at `--delay 5:5` and 25 s at `--dup 0.5`, against the 2.8 s the budget
/// granted each (issue 23).
pub const IMPAIRED_FRAME_WORK: f64 = 6.0;

/// What a frame costs against a perfect radio's: 1, or
/// [`IMPAIRED_FRAME_WORK`] x (1 + `dup`) on an impaired radio.
pub fn frame_factor(perfect: bool, dup: f64) -> f64 {
    if perfect {
        1.0
    } else {
        IMPAIRED_FRAME_WORK * (1.0 + dup.clamp(0.0, 1.0))
    }
}

/// What a pair of robots costs an LFP round, in [`MAX_SEARCH_WORK`]'s
/// units: LFP robots do not talk, but every micro-step looks at every pair
/// (10,000 robots on 180 x 180 m: about 1.4 s of CPU a round).
pub const LFP_PAIR_WORK: f64 = 500.0;

/// Grid side of the coverage raster, in `a` (assumptions.rs, `coverage`).
const RASTER_SIDES: f64 = 0.1;

/// How a scenario's size is reported when it breaks a derived limit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extent {
    /// Width and height of the area's bounding box (m).
    pub width: f64,
    pub height: f64,
    pub a: f64,
    pub kind: LatticeKind,
}

impl Extent {
    /// An upper bound on the lattice vertices in the bounding box: rows
    /// times vertices per row, each rounded up (computed in `f64`, so a huge
    /// box cannot overflow the count).
    pub fn frame_vertices(&self) -> f64 {
        let row = match self.kind {
            LatticeKind::Square => self.a,
            _ => self.a * 3f64.sqrt() / 2.0,
        };
        (self.width / self.a + 1.0).floor().max(1.0) * (self.height / row + 1.0).floor().max(1.0)
    }

    /// Cells of the coverage raster.
    pub fn raster_cells(&self) -> f64 {
        let h = RASTER_SIDES * self.a;
        (self.width / h).ceil().max(1.0) * (self.height / h).ceil().max(1.0)
    }
}

/// A number as a person would write it: `1e300`, not three hundred digits.
pub fn show(v: f64) -> String {
    if v != 0.0 && v.is_finite() && (v.abs() >= 1e16 || v.abs() < 1e-4) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// A limit broken: `what` (a noun phrase) is `value`, above `limit`.
pub(crate) fn over(value: impl std::fmt::Display, name: &str, limit: impl std::fmt::Display) -> String {
    format!("{value} is above the limit {name} = {limit}")
}

/// `Err(message)` when a count exceeds its limit.
pub(crate) fn count(what: &str, n: usize, name: &str, limit: usize) -> Result<(), String> {
    if n > limit {
        Err(format!("{what}: {}", over(n, name, limit)))
    } else {
        Ok(())
    }
}

/// `Err(message)` unless `v` is a finite number within `[lo, hi]`; the
/// message names both bounds and where they come from.
pub(crate) fn within(v: f64, lo: f64, hi: f64, why: &str) -> Result<f64, String> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(format!("must be from {} to {} ({why}), got {}", show(lo), show(hi), show(v)))
    }
}

/// What every vertex is tested against, in [`MAX_VERTEX_WORK`]'s units.
pub fn pieces(area_corners: usize, obstacles: usize, targets: usize) -> usize {
    AREA_CORNER_WEIGHT * area_corners + obstacles + targets
}

/// The size limits of one area at one grid: frame vertices, raster cells,
/// and the work they multiply; `pieces` comes from [`pieces`].
pub fn check_size(e: &Extent, pieces: usize) -> Result<(), String> {
    let frame = e.frame_vertices();
    let at = format!("the area's {} x {} m bounding box at a = {} m", e.width, e.height, e.a);
    if frame > MAX_FRAME_VERTICES {
        return Err(format!(
            "{at} holds about {frame:.0} frame vertices, above the limit MAX_FRAME_VERTICES = {MAX_FRAME_VERTICES:.0} \
             (raise a or shrink the area)"
        ));
    }
    let cells = e.raster_cells();
    if cells > MAX_RASTER_CELLS {
        return Err(format!(
            "{at} needs {cells:.0} coverage raster cells of side a/10, above the limit MAX_RASTER_CELLS = {MAX_RASTER_CELLS:.0}"
        ));
    }
    let work = frame * pieces as f64;
    if work > MAX_VERTEX_WORK {
        return Err(format!(
            "{frame:.0} frame vertices times {pieces} (area corners x {AREA_CORNER_WEIGHT} + obstacles + targets) = \
             {work:.3e}, above the limit MAX_VERTEX_WORK = {MAX_VERTEX_WORK:.0e}"
        ));
    }
    Ok(())
}

/// `robots` robots on a world of `frame_vertices` vertices: the file's
/// count, and again a count given after the scenario was read (`--robots`).
pub fn check_robots(robots: usize, frame_vertices: f64) -> Result<(), String> {
    count("robots", robots, "MAX_ROBOTS", MAX_ROBOTS)?;
    let maps = robots as f64 * frame_vertices;
    if maps > MAX_ROBOT_VERTICES {
        return Err(format!(
            "{robots} robots times {frame_vertices:.0} frame vertices = {maps:.3e}, above the limit \
             MAX_ROBOT_VERTICES = {MAX_ROBOT_VERTICES:.0e} (every robot holds a map of the frame)"
        ));
    }
    Ok(())
}

/// The most robots one robot can hear: every robot on a lattice vertex
/// within `r_c` (an upper bound: the disc grown by a side, over the area a
/// vertex stands for), and never more than the others.
pub fn hearable(robots: usize, r_c: f64, a: f64, kind: LatticeKind) -> f64 {
    let per_vertex = match kind {
        LatticeKind::Square => a * a,
        LatticeKind::Triangular => a * a * 3f64.sqrt() / 2.0,
        LatticeKind::Hexagonal => a * a * 3.0 * 3f64.sqrt() / 4.0,
    };
    let disc = std::f64::consts::PI * (r_c.max(0.0) + a).powi(2) / per_vertex;
    disc.min(robots.saturating_sub(1) as f64)
}

/// What one round of `robots` robots, each hearing at most `hearable`
/// others, costs in [`MAX_SEARCH_WORK`]'s units: robots x (1 + heard) x
/// frame vertices for the maps, robots x heard^2 x [`HEARD_PAIR_WORK`] x
/// `frames` (from [`frame_factor`]) for the frames.
pub fn round_work(robots: usize, frame_vertices: f64, hearable: f64, frames: f64) -> f64 {
    let maps = (1.0 + hearable) * frame_vertices.max(1.0);
    robots as f64 * (maps + hearable * hearable * HEARD_PAIR_WORK * frames)
}

/// What one LFP round of `robots` robots costs, in [`MAX_SEARCH_WORK`]'s
/// units: robots^2 x [`LFP_PAIR_WORK`].
pub fn lfp_round_work(robots: usize) -> f64 {
    (robots as f64).powi(2) * LFP_PAIR_WORK
}

/// The round limit of a run nobody gave one: [`DEFAULT_MAX_ROUNDS`], or
/// fewer if that many rounds of `round_work` would pass
/// [`MAX_SEARCH_WORK`]; an error if not even one round fits.
pub fn round_limit(round_work: f64) -> Result<u32, String> {
    let fits = (MAX_SEARCH_WORK / round_work.max(1.0)).floor();
    if fits >= DEFAULT_MAX_ROUNDS as f64 {
        Ok(DEFAULT_MAX_ROUNDS)
    } else if fits >= 1.0 {
        Ok(fits as u32)
    } else {
        Err(format!(
            "one round would cost {round_work:.3e}, above the work budget MAX_SEARCH_WORK = {MAX_SEARCH_WORK:e} \
             (as docs/scenario-format.md counts it): use fewer robots or a shorter r_c, \
             or ask for rounds anyway with --max-rounds N"
        ))
    }
}

/// The shape limits of a map ([`MAX_PERIMETER_SIDES`], [`MAX_COVER_WORK`],
/// [`MAX_PAIR_WORK`]), computed from its pieces before any of the work
/// they bound, with the pairs worth measuring (boxes within `3a`) when
/// they fit.
pub(crate) fn check_geometry(
    area: &Polygon,
    obstacles: &[Shape],
    a: f64,
    r_safe: f64,
) -> Result<super::pairs::Near, String> {
    let edges = |p: &Polygon| p.edges().map(|(u, v)| (v - u).norm()).sum::<f64>();
    let length = |s: &Shape| match s {
        Shape::Polygon(p) => edges(p),
        Shape::Circle(c) => 2.0 * std::f64::consts::PI * c.radius,
    };
    let sides = (edges(area) + obstacles.iter().map(length).sum::<f64>()) / a;
    if sides > MAX_PERIMETER_SIDES {
        return Err(format!(
            "the area's and the obstacles' edges are {sides:.0} grid sides long in all, above the limit \
             MAX_PERIMETER_SIDES = {MAX_PERIMETER_SIDES:e} (fewer or shorter obstacles, or a larger a)"
        ));
    }
    let g = 2.0 * a + 2.0 * r_safe;
    let cover: f64 = obstacles
        .iter()
        .map(|o| {
            let (lo, hi) = o.bounding_box();
            (super::pairs::weight(o) + 1.0) * (hi.x - lo.x + 2.0 * g) * (hi.y - lo.y + 2.0 * g) / (a * a)
        })
        .sum();
    if cover > MAX_COVER_WORK {
        return Err(format!(
            "the obstacles' bounding boxes (grown by 2a + 2 r_safe, in a^2) times their corners + 1 come to \
             {cover:.3e}, above the limit MAX_COVER_WORK = {MAX_COVER_WORK:e}: every vertex in an obstacle's box is \
             tested against it (long thin diagonal obstacles have boxes far bigger than themselves)"
        ));
    }
    let selves: f64 = std::iter::once(area)
        .chain(obstacles.iter().filter_map(|o| match o {
            Shape::Polygon(p) => Some(p),
            Shape::Circle(_) => None,
        }))
        .map(super::pairs::self_work)
        .sum();
    let wide = PASSAGE_SIDES * a + 1e-9;
    let crowded = |c: super::pairs::Crowded| {
        format!(
            "obstacles crowd too close to measure: their gaps up to {PASSAGE_SIDES}a and their own edges take more than \
             {:.3e} segment tests (the last near ({:.2}, {:.2})), above the limit MAX_PAIR_WORK = {MAX_PAIR_WORK:e} \
             (spread them, or merge near ones into one)",
            c.work + selves,
            c.at.x,
            c.at.y
        )
    };
    if selves > MAX_PAIR_WORK {
        let at = area.points[0];
        return Err(crowded(super::pairs::Crowded { work: 0.0, at }));
    }
    super::pairs::near(area, obstacles, wide, wide, MAX_PAIR_WORK - selves).map_err(crowded)
}

/// The widest gap Assumption 3.1.3 measures as a passage, in grid sides
/// (wider is open space).
pub(crate) const PASSAGE_SIDES: f64 = 3.0;

/// Builds the error of a broken limit for `file`.
pub(crate) fn error(file: &str, field: &str, message: String) -> ScenarioError {
    ScenarioError::new(file, None, field, message)
}

/// The count and size limits of a scenario already built in code (a
/// `random:` map), the same that [`Scenario::parse`] applies to a file.
pub fn admit(s: &Scenario) -> Result<(), ScenarioError> {
    let err = |field: &str, m: String| error(&s.name, field, m);
    let corners = |shape: &Shape| match shape {
        Shape::Polygon(p) => p.points.len(),
        Shape::Circle(_) => 0,
    };
    let total = s.area.points.len() + s.obstacles.iter().map(corners).sum::<usize>();
    let counts = [
        ("area.polygon", "corners", s.area.points.len(), "MAX_CORNERS", MAX_CORNERS),
        ("obstacles", "obstacles", s.obstacles.len(), "MAX_OBSTACLES", MAX_OBSTACLES),
        ("obstacles", "polygon corners", total, "MAX_TOTAL_CORNERS", MAX_TOTAL_CORNERS),
        ("targets", "targets", s.targets.len(), "MAX_TARGETS", MAX_TARGETS),
        ("robots", "robots", s.robots, "MAX_ROBOTS", MAX_ROBOTS),
    ];
    for (field, what, n, name, max) in counts {
        count(what, n, name, max).map_err(|m| err(field, m))?;
    }
    let (lo, hi) = s.area.bounding_box();
    let extent = Extent { width: hi.x - lo.x, height: hi.y - lo.y, a: s.params.a, kind: s.grid };
    let pieces = pieces(s.area.points.len(), s.obstacles.len(), s.targets.len());
    check_size(&extent, pieces).map_err(|m| err("area.polygon", m))?;
    check_robots(s.robots, extent.frame_vertices()).map_err(|m| err("robots", m))?;
    check_geometry(&s.area, &s.obstacles, s.params.a, s.params.r_safe).map_err(|m| err("obstacles", m))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_vertices_bound_the_grid_built() {
        use crate::geometry::Point;
        use crate::lattice::Lattice;
        for kind in LatticeKind::ALL {
            for (w, h, a) in [(20.0, 16.0, 1.0), (7.3, 2.9, 0.37), (1.0, 1.0, 3.0)] {
                let e = Extent { width: w, height: h, a, kind };
                let built =
                    Lattice::new(kind, a).coords_in_box(Point::new(0.1, 0.2), Point::new(0.1 + w, 0.2 + h)).len();
                assert!(built as f64 <= e.frame_vertices(), "{kind:?} {w}x{h} a={a}: {built} > {}", e.frame_vertices());
                assert!(e.frame_vertices() <= 2.0 * built as f64 + 8.0, "{kind:?} {w}x{h}: loose bound");
            }
        }
    }

    #[test]
    fn a_hundredth_of_a_metre_on_the_paper_map_is_refused() {
        let e = Extent { width: 20.0, height: 16.0, a: 0.01, kind: LatticeKind::Triangular };
        let m = check_size(&e, 10).unwrap_err();
        assert!(m.contains("MAX_FRAME_VERTICES = 1000000") && m.contains("a = 0.01"), "{m}");
        let ok = Extent { a: 1.0, ..e };
        check_size(&ok, 10).unwrap();
    }

    #[test]
    fn the_biggest_random_map_fits() {
        // size=400x400 at a = 1, up to 1000 robots and targets, thousands
        // of obstacles (random/spec.rs bounds its options by these).
        let e = Extent { width: 402.0, height: 402.0, a: 1.0, kind: LatticeKind::Triangular };
        check_size(&e, pieces(60, 10_000, 1000)).unwrap();
        check_robots(1000, e.frame_vertices()).unwrap();
        check_robots(10_000, 40_000.0).unwrap();
        assert!(check_robots(5000, e.frame_vertices()).unwrap_err().contains("MAX_ROBOT_VERTICES"));
        assert!(check_robots(MAX_ROBOTS + 1, 10.0).unwrap_err().contains("MAX_ROBOTS = 65535"));
    }

    #[test]
    fn the_work_budget_spares_the_paper_and_cuts_big_maps_and_teams() {
        let paper = Extent { width: 20.0, height: 16.0, a: 1.0, kind: LatticeKind::Triangular };
        let r_c = 2.1;
        let rounds = |robots: usize, e: &Extent| {
            round_limit(round_work(robots, e.frame_vertices(), hearable(robots, r_c, e.a, e.kind), 1.0)).unwrap()
        };
        // Fig. 7's counts on the paper map keep the whole default.
        assert_eq!(rounds(13, &paper), DEFAULT_MAX_ROUNDS);
        let big = Extent { width: 402.0, height: 402.0, ..paper };
        assert_eq!(rounds(1, &big), DEFAULT_MAX_ROUNDS);
        let three = rounds(3, &big);
        assert!(three < DEFAULT_MAX_ROUNDS && three > 10_000, "{three}");
        let team = Extent { width: 182.0, height: 182.0, ..paper };
        let many = rounds(10_000, &team);
        assert!((1..10).contains(&many), "{many}");
        // Everyone in one radio range: the frames, not the maps, cost.
        let field = Extent { width: 100.0, height: 100.0, ..paper };
        let one_range = |robots| {
            round_limit(round_work(robots, field.frame_vertices(), hearable(robots, 300.0, 1.0, field.kind), 1.0))
        };
        // 100 robots: 0.035 s a round, measured.
        assert!(one_range(100).is_ok_and(|n| n < 300), "{:?}", one_range(100));
        assert_eq!(one_range(500), Ok(1));
        // 2,000 robots in one range took 23 s for one round: refused.
        assert!(one_range(2000).is_err_and(|e| e.contains("MAX_SEARCH_WORK") && e.contains("--max-rounds")));
        // A robot hears at most those within r_c, and never more than the others.
        assert_eq!(hearable(1, r_c, 1.0, LatticeKind::Triangular), 0.0);
        let disc = hearable(10_000, r_c, 1.0, LatticeKind::Triangular);
        assert!(disc >= 18.0 && disc < 40.0, "{disc}");
        assert!(round_limit(f64::INFINITY).is_err());
        // LFP: Fig. 7's 13 robots keep the default, 10,000 get a round or two.
        assert_eq!(round_limit(lfp_round_work(13)), Ok(DEFAULT_MAX_ROUNDS));
        assert!(round_limit(lfp_round_work(10_000)).is_ok_and(|n| n <= 2));
    }
}
