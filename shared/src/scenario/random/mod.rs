//! Random maps: `random:SEED[,size=WxH][,density=F][,passage=M][,targets=N]
//! [,robots=N][,break=ID]` names a scenario generated from the seed alone.
//!
//! Reject and redraw: attempt `k` draws a whole map from its own stream
//! (`derive(seed, k)`), builds its world, places robots and targets, and
//! runs every assumption check ([`crate::assumptions::check`]); the first
//! attempt whose failing checks are exactly the ones asked for (none, or
//! those of `break=ID`) is the map. The attempts are bounded, so a map that
//! cannot be had (a density out of reach at that passage width) is a clear
//! error, never a hang. The same text gives the same map on every machine
//! and in every process, which is how `gridswarm run`'s world-server gets
//! the map the orchestrator checked: it generates it again.
//!
//! What a map has: a rectilinear area of about `size` with notches (walls
//! snapped to the lattice, see [`shapes`]); convex obstacles covering about
//! `density` of it, every gap between them and to the walls at least
//! `passage` (default 2 m, above `W_pass` = 1.6 m); `targets` targets (9,
//! situation 1, as `paper`) spread over the reachable vertices, each within
//! half a grid side of one; `robots` robots on the border from the
//! bottom-left corner; the default parameters (Table 1 as docs/paper.md
//! restores it).
//!
//! What `break=ID` changes: `2.4`, `2.5` and `3.1.1` lower `r_so`, `r_c` and
//! `r_st` below their bounds (by `0.3`, `0.5` and `0.1` m); `3.1.2` adds a
//! bay with an 18 degree apex no vertex sees (which also leaves part of `Ad`
//! uncovered: `coverage` fails with it); `3.1.3` puts one obstacle `passage`
//! (default 1 m) from a wall, the other gaps staying at least 2 m.

mod shapes;
mod spec;

pub use spec::{w_pass, Break, Spec, PREFIX, SYNTAX};

use rand::Rng;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::{Scenario, ScenarioError, Starts};
use crate::assumptions;
use crate::geometry::{Point, Shape, Vector};
use crate::grid::VertexId;
use crate::lattice::LatticeKind;
use crate::lfp::LfpParams;
use crate::params::{Params, Situation};
use crate::rng::derive;
use crate::spot::Spot;
use crate::world::World;

/// Attempts before giving up. At the defaults the first attempt passes in
/// most seeds; a limit this high only matters for options near the edge.
pub const MAX_ATTEMPTS: u64 = 40;
/// Every gap but the narrow one, when 3.1.3 is broken.
const WIDE_PASSAGE: f64 = 2.0;

/// A generated map and how many attempts it took.
#[derive(Clone, Debug)]
pub struct Generated {
    pub scenario: Scenario,
    /// 1 when the first draw passed.
    pub attempts: u64,
}

/// Whether `name` asks for a random map.
pub fn is_random(name: &str) -> bool {
    name.starts_with(PREFIX)
}

/// The scenario `text` (`random:...`) names.
pub fn load(text: &str) -> Result<Scenario, ScenarioError> {
    generate(&Spec::parse(text)?).map(|g| g.scenario)
}

/// The parameters of a map breaking `b` (or none).
fn params(b: Option<Break>) -> Params {
    let mut p = Params::default();
    match b {
        Some(Break::Sonar) => p.r_so = p.a + p.r_safe - 0.3,
        Some(Break::Radio) => p.r_c = 2.0 * p.a + p.r_safe - p.r_rob - 0.5,
        Some(Break::Laser) => p.r_st = p.a + p.r_safe - 0.1,
        _ => {}
    }
    p
}

/// The map `spec` names, or why none of [`MAX_ATTEMPTS`] draws would do.
pub fn generate(spec: &Spec) -> Result<Generated, ScenarioError> {
    let mut last = String::new();
    for k in 0..MAX_ATTEMPTS {
        let mut rng = ChaCha8Rng::seed_from_u64(derive(spec.seed, k));
        match attempt(spec, &mut rng) {
            Ok(scenario) => {
                super::limits::admit(&scenario)?;
                return Ok(Generated { scenario, attempts: k + 1 });
            }
            Err(why) => last = why,
        }
    }
    let asked = spec
        .breaks
        .map_or("every check to pass".to_string(), |b| format!("only {} to fail", b.failing().join(" and ")));
    Err(ScenarioError::new(
        &spec.name(),
        None,
        "",
        format!(
            "no map in {MAX_ATTEMPTS} attempts had {asked}; the last: {last}. \
             Try another seed, a lower density or a narrower passage"
        ),
    ))
}

/// One draw: `Ok` if its checks fail exactly as asked, else why not.
fn attempt(spec: &Spec, rng: &mut ChaCha8Rng) -> Result<Scenario, String> {
    let params = params(spec.breaks);
    let area = shapes::area(rng, spec.size, params.a, spec.breaks == Some(Break::Pocket));
    let mut placed = Vec::new();
    let gap = if spec.breaks == Some(Break::Passage) {
        placed.push(shapes::narrow_obstacle(rng, &area, spec.passage).ok_or("no spot for the narrow passage")?);
        WIDE_PASSAGE
    } else {
        spec.passage
    };
    let obstacles = shapes::obstacles(rng, &area, placed, spec.density, gap).map_err(|reached| {
        format!("obstacles covered only {:.0}% of the area with every cell used", 100.0 * reached)
    })?;
    let mut sc = Scenario {
        name: spec.name(),
        area: area.polygon,
        obstacles,
        targets: Vec::new(),
        starts: Starts::Border { from: area.corner },
        robots: spec.robots,
        params,
        grid: LatticeKind::Triangular,
        situation: Situation::One,
        lfp: LfpParams::default(),
    };
    let bare = sc.world();
    let starts = sc.start_vertices(&bare, spec.robots).map_err(|e| e.message)?;
    sc.targets = targets(rng, &bare, &starts, spec.targets);
    if sc.targets.len() < spec.targets {
        return Err(format!("only {} targets found places of their own", sc.targets.len()));
    }
    let report = assumptions::check(&sc, &sc.world(), &starts);
    let mut failing: Vec<&str> = report.failures().map(|c| c.id).collect();
    let mut wanted: Vec<&str> = spec.breaks.map_or(&[][..], Break::failing).to_vec();
    failing.sort_unstable();
    wanted.sort_unstable();
    if failing == wanted {
        Ok(sc)
    } else if failing.is_empty() {
        Err("every check passed".into())
    } else {
        let why: Vec<String> = report.failures().map(|c| format!("{} ({})", c.id, c.detail)).collect();
        Err(format!("failed {}", why.join("; ")))
    }
}

/// `n` targets spread over `Va` (best of a few candidates: the vertex
/// farthest from the targets already placed, Mitchell's rule), each moved
/// up to half a grid side off its vertex, staying in `Ad`: every target is
/// detectable from `Va`, and targets are "evenly separated" as in Sec. 5.
fn targets(rng: &mut ChaCha8Rng, w: &World, starts: &[VertexId], n: usize) -> Vec<Point> {
    let va = w.reachable_from(starts);
    let pool: Vec<Point> =
        (0..w.grid.len() as VertexId).filter(|&v| va[v as usize]).map(|v| w.grid.position(v)).collect();
    let mut out: Vec<Point> = Vec::with_capacity(n);
    if pool.is_empty() {
        return out;
    }
    const CANDIDATES: usize = 8;
    let spot = |p: Point| Spot::at(p, w.params.a);
    // A laser tells targets apart by position only: a draw on the spot of
    // one placed is drawn again (a map too small to hold `n` apart is
    // left short, and `attempt` draws another map).
    let mut draws = 0;
    while out.len() < n && draws < 1000 * n {
        draws += 1;
        let far = |p: &Point| out.iter().map(|t| (t - p).norm()).fold(f64::INFINITY, f64::min);
        let v = (0..CANDIDATES)
            .map(|_| pool[rng.random_range(0..pool.len())])
            .max_by(|p, q| far(p).total_cmp(&far(q)))
            .expect("at least one candidate");
        let t = rng.random_range(0.0..std::f64::consts::TAU);
        let d = rng.random_range(0.0..=0.5 * w.params.a);
        let moved = v + Vector::new(t.cos(), t.sin()) * d;
        let moved = Point::new(shapes::mm(moved.x), shapes::mm(moved.y));
        let p = if w.in_ad(moved) { moved } else { Point::new(shapes::mm(v.x), shapes::mm(v.y)) };
        if !out.iter().any(|&q| spot(q) == spot(p)) {
            out.push(p);
        }
    }
    out
}

/// The area under the obstacles of `s` (m²), to compare with the area's.
pub fn obstacle_area(s: &Scenario) -> f64 {
    s.obstacles
        .iter()
        .map(|o| match o {
            Shape::Polygon(p) => p.signed_area().abs(),
            Shape::Circle(c) => std::f64::consts::PI * c.radius * c.radius,
        })
        .sum()
}
