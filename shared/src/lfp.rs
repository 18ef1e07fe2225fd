//! LFP: Levy flight with an artificial potential field (Sutantyo et al.
//! 2010), the continuous-motion baseline of Fig. 7 (docs/paper.md "The
//! algorithms compared"). Robots leave the grid, know no map, and search by
//! heavy-tailed random flights bent by repulsion from each other and from
//! the obstacles they sense.
//!
//! # The model
//!
//! The paper gives none of LFP's constants or timing; this is the project's
//! reading, and every constant lives in [`LfpParams`].
//!
//! - **Flights.** A robot starts at its start vertex's position. A flight has
//!   a length `L = clamp(scale * a * s, a, max_step * a)` with `s` drawn by
//!   Mantegna's method with exponent `beta`, and a heading: uniform in
//!   `[0, 2 pi)` for the first flight, then the previous heading plus
//!   `N(0, sigma)` (the paper's normal turning law; sigma 1 by default, the
//!   standard normal, [`readings::DEFAULT_TURN_SIGMA`]), or with `turn = "uniform"` uniform
//!   for every flight ([`Turn`]). A new
//!   heading that points into a sensed obstacle (against the obstacle
//!   repulsion) is mirrored off it, so a robot stopped at a wall turns away.
//! - **Rounds.** Time advances in lock-step rounds. In each round every robot
//!   covers one sub-step of length `min(a, what is left of its flight)`, in
//!   `micro_steps` equal micro-steps (its control loop). Each micro-step goes
//!   in the direction `heading + F`, normalised, where `F` is the potential
//!   field at the robot's position at the start of the micro-step: for every
//!   other robot within `r` at distance `d`, `k_robot * (1/d - 1/r) / d^2`
//!   away from it; for every boundary edge, obstacle edge or obstacle circle
//!   within `r_so`, `k_obstacle * (1/d - 1/r_so) / d^2` away from its nearest
//!   point (Khatib's potential, which vanishes at the edge of the range). The
//!   field bends the path, not the flight: the heading stays the flight's
//!   own, so a robot slides along a wall or round a neighbour and carries on.
//!   A micro-step the field turns more than 90 degrees from the heading ends
//!   the flight with the round (the robot is pushed back; it takes a new
//!   flight instead of dithering in front of the obstacle). A robot knows
//!   the other robots' positions within `r` and the obstacles within `r_so`
//!   (sonar); it never reads the map. `r` is `r_so` by default: the robots
//!   "cannot communicate", so they sense each other by sonar
//!   ([`RepelRange`]; `repel_range = "radio"` gives `r_c`). The length of a flight
//!   is measured along the path.
//! - **Clearance.** A micro-step that would bring the robot within `r_safe`
//!   of an obstacle or the boundary is cut short at the last clear point
//!   (bisection to 1/1024 of the micro-step); the robot stops for the rest of
//!   the round and starts a new flight next round. With `r_so >= a + r_safe`
//!   (Assumption 2.4) the robot senses everything this check uses; with a
//!   shorter sonar the check still applies, because the ground truth does not
//!   let robots into walls.
//! - **Time** (docs/paper.md "Time"). A round lasts `t_choice` (every robot
//!   computes its own move at once: one unit) plus `t_trans` (one sub-step of
//!   at most `a`), plus `t_rot` if any robot rotates on the spot: it starts a
//!   new flight, or its direction of motion changes by more than
//!   `max_steer` between two micro-steps (smaller bends are steering while
//!   driving). Collisions add `params.collision_penalty`, the reading the
//!   world applies to RU ([`crate::params::RuCollisions`]): by default one
//!   move time per collision event.
//! - **Collisions.** The referee counts a collision for a pair of robots
//!   that come closer than `2 * r_safe`. All robots move through their
//!   micro-steps together and each micro-step is straight, so the closest
//!   approach within one is [`geometry::swept_min_distance`]. A pair counts
//!   at most once per round. By default (`per-event`, as the world counts
//!   RU's) only a pair that started the round at least `2 * r_safe` apart
//!   counts: one still in contact from the last round is in the collision
//!   already charged. Under `per-pair` and `back-off` a pair counts again
//!   in every round it is too close. The field makes collisions
//!   rare, not impossible (two robots just out of range close at up to `2a`
//!   per round).
//! - **Sensing and stop.** A target is found when it lies within `r_st` of a
//!   robot's position at the start of the run or at the end of a sub-step;
//!   found targets are broadcast to all. Situation 1 stops when every target
//!   of the world is found (rule 3). LFP's robots have no radio between
//!   them; under [`crate::params::Broadcast::Controller`] (the default)
//!   a find reaches every robot as it reaches the grid robots: a hop to the
//!   human controller and a hop back ([`crate::sim::controller`]). So a
//!   robot that finds the last target knows every target at once if it
//!   found all those of the last round itself, and two hops later if
//!   another robot found one of them in the same round; the search ends
//!   when it knows ([`last_news`]). Under `flood` every find is known to
//!   all at once, as before issue 36. Situation 2: LFP keeps no map, so rule 4
//!   is replaced by a ground-truth stand-in: stop once every vertex of `Va`
//!   ([`World::reachable_from`] the starts) has had some sub-step end within
//!   `a / 2` of it, i.e. a robot stood, to the grid's resolution, on every
//!   vertex the grid algorithms must visit. This is looser than a visit: at a
//!   corner, a robot `a / 2` off the corner vertex may leave a sliver of `Ad`
//!   undetected (an open 8 x 6 m rectangle ends at about 99.7 % coverage),
//!   which `RunResult::coverage` shows.
//! - **Randomness.** Robot `k` draws everything from its own stream,
//!   [`rng::robot_rng`]`(seed, k)` as the grid robots do, and every robot's
//!   micro-step is computed from the positions at the start of the
//!   micro-step, so a run does not depend on the order robots are processed
//!   in.
//!
//! [`run`] prepares the world's obstacle index and runs once; a sweep that
//! runs thousands of searches on one world builds an [`LfpWorld`] once and
//! calls [`run_prepared`].
//!
//! [`geometry::swept_min_distance`]: crate::geometry::swept_min_distance

mod levy;
mod readings;
mod sensing;

pub use readings::{RepelRange, Turn, DEFAULT_TURN_SIGMA};

use std::sync::OnceLock;

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

use crate::geometry::{swept_min_distance, Point, Vector};
use crate::grid::{VertexId, NONE};
use crate::lattice::Coord;
use crate::outcome::{Pose, RunConfig, RunMetrics, RunResult};
use crate::params::{RuCollisions, Situation};
use crate::policy::Policy;
use crate::rng;
use crate::world::coverage::{Coverage, Footprints};
use crate::world::World;

use levy::Mantegna;
use sensing::Sensing;

/// LFP's constants. The paper gives none; these defaults are the project's
/// documented choice and every one can be set in a scenario's `[lfp]` table.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LfpParams {
    /// Levy exponent of Mantegna's method, meaningful in `(0, 2)`. Default
    /// 1.5: docs/paper.md's suggestion and the common choice in Levy search.
    pub beta: f64,
    /// Flight lengths are `scale * a * s` for a Mantegna draw `s`, clamped to
    /// `[a, max_step * a]`. Default 1.0: `s` itself in grid sides, so with
    /// the other defaults two flights in three last one sub-step, the mean
    /// flight is 1.6 a and the heavy tail supplies the long relocations.
    pub scale: f64,
    /// Longest flight in grid sides. Default 20.0: about the larger side of
    /// a paper-sized 20 x 16 m area, where a longer flight would only run
    /// into a wall (0.5 % of draws reach it).
    pub max_step: f64,
    /// How each new flight's heading is drawn: a turn sigma in radians
    /// (default [`readings::DEFAULT_TURN_SIGMA`], the standard normal; `turn_sigma`
    /// is still read) or `"uniform"`. Search time is sensitive to it (one
    /// robot on a 20 x 16 m map with four obstacles: about 1900 s at 0.5,
    /// 2600 s at 1.0, 3700 s at pi/2, 4900 s at pi), so reports should
    /// state it.
    #[serde(alias = "turn_sigma")]
    pub turn: Turn,
    /// Gain of the repulsion from other robots within the repulsion range.
    /// Default 1.0: the push equals the unit heading at about 0.75 m within
    /// `r_so` (0.85 m within `r_c`), before two robots are `2 * r_safe` apart.
    pub k_robot: f64,
    /// Which robots repel: those within sonar range (default) or radio range.
    pub repel_range: RepelRange,
    /// Gain of the repulsion from obstacles and the boundary within `r_so`.
    /// Default 1.0: the push equals the unit heading at about 0.75 m, well
    /// before `r_safe`, so robots mostly turn before a wall cuts their flight.
    pub k_obstacle: f64,
    /// Largest change of the direction of motion between two micro-steps
    /// that counts as steering while driving (rad); a larger one is a
    /// rotation on the spot and costs `t_rot`. Default pi/4 (45 degrees).
    pub max_steer: f64,
    /// Micro-steps per sub-step: the field is re-evaluated, the clearance
    /// checked and the referee consulted this many times per round, i.e. the
    /// robot's control loop runs every `t_trans / micro_steps` (0.56 s by
    /// default). Default 8: a potential field sampled once per metre cannot
    /// steer robots that close at up to `2a` per round apart (13 robots on a
    /// 20 x 16 m map: about 56 collisions a run at 1, 4 at 4, 0.02 at 8),
    /// while a real APF loop runs faster than 2 Hz anyway.
    pub micro_steps: u32,
}

impl Default for LfpParams {
    fn default() -> Self {
        LfpParams {
            beta: 1.5,
            scale: 1.0,
            max_step: 20.0,
            turn: Turn::Sigma(readings::DEFAULT_TURN_SIGMA),
            repel_range: RepelRange::Sonar,
            k_robot: 1.0,
            k_obstacle: 1.0,
            max_steer: std::f64::consts::FRAC_PI_4,
            micro_steps: 8,
        }
    }
}

/// What LFP precomputes of a world: the obstacle index its sensing queries
/// use, a lattice-coordinate table for the Situation 2 stop test, and (on
/// first use) the coverage raster. Build once per world, share across
/// threads, and call [`run_prepared`].
#[derive(Debug)]
pub struct LfpWorld<'w> {
    world: &'w World,
    sensing: Sensing,
    vertices: VertexTable,
    raster: OnceLock<Footprints>,
}

impl<'w> LfpWorld<'w> {
    pub fn new(world: &'w World) -> Self {
        LfpWorld { world, sensing: Sensing::new(world), vertices: VertexTable::new(world), raster: OnceLock::new() }
    }

    pub fn world(&self) -> &'w World {
        self.world
    }

    /// LFP's raster for coverage (its cells of side `a / 10`, which may
    /// differ from the grid engines' `0.1 a` in the last bit).
    fn raster(&self) -> &Footprints {
        let w = self.world;
        self.raster.get_or_init(|| Footprints::new(w.raster(w.params.a / 10.0), w.params.r_st))
    }
}

/// Dense `Coord -> VertexId` lookup over the grid's coordinate box; the
/// grid's own index hashes, which the per-sub-step test should not.
#[derive(Clone, Debug)]
struct VertexTable {
    i0: i32,
    j0: i32,
    ni: usize,
    nj: usize,
    ids: Vec<VertexId>,
}

impl VertexTable {
    fn new(world: &World) -> Self {
        let g = &world.grid;
        let (mut i0, mut i1, mut j0, mut j1) = (i32::MAX, i32::MIN, i32::MAX, i32::MIN);
        for v in 0..g.len() as VertexId {
            let c = g.coord(v);
            (i0, i1, j0, j1) = (i0.min(c.i), i1.max(c.i), j0.min(c.j), j1.max(c.j));
        }
        if g.is_empty() {
            return VertexTable { i0: 0, j0: 0, ni: 0, nj: 0, ids: Vec::new() };
        }
        let (ni, nj) = ((i1 - i0 + 1) as usize, (j1 - j0 + 1) as usize);
        let mut ids = vec![NONE; ni * nj];
        for v in 0..g.len() as VertexId {
            let c = g.coord(v);
            ids[(c.j - j0) as usize * ni + (c.i - i0) as usize] = v;
        }
        VertexTable { i0, j0, ni, nj, ids }
    }

    fn get(&self, c: Coord) -> Option<VertexId> {
        let (di, dj) = (c.i - self.i0, c.j - self.j0);
        if di < 0 || dj < 0 || di as usize >= self.ni || dj as usize >= self.nj {
            return None;
        }
        let v = self.ids[dj as usize * self.ni + di as usize];
        (v != NONE).then_some(v)
    }
}

/// Runs one LFP search: robot `k` starts at the position of `starts[k]`.
pub fn run(world: &World, starts: &[VertexId], cfg: &RunConfig, lfp: &LfpParams) -> RunResult {
    run_prepared(&LfpWorld::new(world), starts, cfg, lfp)
}

struct Robot {
    /// The flight's heading, which the field bends but does not change.
    heading: Vector,
    /// The direction the robot last moved in (its body orientation).
    facing: Vector,
    /// Length left of the current flight; `0` means a new flight is due.
    rem: f64,
    /// Length of each micro-step this round.
    step: f64,
    /// Whether the robot still moves this round (a cut stops it).
    moving: bool,
    /// Whether the flight ends with this round (the field turned it back).
    repelled: bool,
    rng: ChaCha8Rng,
}

impl Robot {
    /// At rest, with a new flight due.
    fn new(rng: ChaCha8Rng) -> Self {
        Robot {
            heading: Vector::zeros(),
            facing: Vector::zeros(),
            rem: 0.0,
            step: 0.0,
            moving: false,
            repelled: false,
            rng,
        }
    }
}

/// Starts a flight for `r` at a point where the obstacles push with `f_obs`.
fn new_flight(r: &mut Robot, f_obs: Vector, levy: &Mantegna, lfp: &LfpParams, a: f64) {
    r.heading = match lfp.turn {
        Turn::Sigma(sigma) if r.heading != Vector::zeros() => {
            let turn: f64 = r.rng.sample::<f64, _>(StandardNormal) * sigma;
            let (s, c) = turn.sin_cos();
            let h = r.heading;
            Vector::new(c * h.x - s * h.y, s * h.x + c * h.y)
        }
        _ => {
            let (s, c) = (r.rng.random::<f64>() * std::f64::consts::TAU).sin_cos();
            Vector::new(c, s)
        }
    };
    let push = f_obs.norm();
    if push > 0.0 {
        let normal = f_obs / push;
        let into = r.heading.dot(&normal);
        if into < 0.0 {
            r.heading -= normal * (2.0 * into);
        }
    }
    let s = levy.sample(&mut r.rng);
    r.rem = (lfp.scale * a * s).clamp(a, (lfp.max_step * a).max(a));
    r.facing = r.heading;
}

/// The push other robots give robot `i` (Khatib's potential within `range`).
#[derive(Clone, Copy, Debug)]
struct Repulsion {
    range: f64,
    k: f64,
}

impl Repulsion {
    /// Every robot's push at once into `fields`: a pair's push is computed
    /// once and given to both robots with opposite signs (exactly: the
    /// vector negates, its length is the same), and each robot's sum runs
    /// over the others in ascending order, as one robot's sum alone would.
    #[cfg(test)]
    fn fields(&self, pos: &[Point], fields: &mut Vec<Vector>) {
        self.fields_and_near(pos, fields, -1.0, &mut Vec::new());
    }

    /// [`Self::fields`], and in the same pass over the pairs the pairs
    /// `(i, j, pair index)` at most `sqrt(near2)` apart, ascending: the
    /// referee's candidates, so that it need not go over every pair again.
    fn fields_and_near(&self, pos: &[Point], fields: &mut Vec<Vector>, near2: f64, near: &mut Vec<(u32, u32, u32)>) {
        fields.clear();
        fields.resize(pos.len(), Vector::zeros());
        near.clear();
        let repel = self.k != 0.0 && self.range > 0.0;
        let (r2, inv_r) = (self.range * self.range, 1.0 / self.range);
        let mut pair = 0u32;
        for i in 0..pos.len() {
            for j in i + 1..pos.len() {
                let v = pos[i] - pos[j];
                let d2 = v.norm_squared();
                if d2 <= near2 {
                    near.push((i as u32, j as u32, pair));
                }
                pair += 1;
                if repel && d2 < r2 && d2 > 1e-18 {
                    let d = d2.sqrt();
                    let push = v * (self.k * (1.0 / d - inv_r) / (d2 * d));
                    fields[i] += push;
                    fields[j] -= push;
                }
            }
        }
    }
}

/// [`run`] on a prepared world.
pub fn run_prepared(lw: &LfpWorld, starts: &[VertexId], cfg: &RunConfig, lfp: &LfpParams) -> RunResult {
    let world = lw.world;
    let prm = &world.params;
    let n = starts.len();
    let a = prm.a;
    let levy = Mantegna::new(lfp.beta);
    let cos_steer = lfp.max_steer.cos();
    let r_st2 = prm.r_st * prm.r_st;
    let repel = Repulsion { range: lfp.repel_range.range(prm), k: lfp.k_robot };
    let collide = 2.0 * prm.r_safe;
    let events = prm.ru_collisions == RuCollisions::PerEvent;
    let micro = lfp.micro_steps.max(1);
    // Two robots further apart than this cannot meet within one micro-step.
    let far2 = (collide + 2.0 * a / micro as f64).powi(2);
    let mut stamp = vec![u32::MAX; n * n.saturating_sub(1) / 2];
    // Where the robots stood when the round began (per-event collisions).
    let mut begun: Vec<Point> = Vec::new();

    let mut pos: Vec<Point> = starts.iter().map(|&v| world.grid.position(v)).collect();
    let mut next = pos.clone();
    let mut pushes = Vec::with_capacity(n);
    let mut near = Vec::new();
    let mut robots: Vec<Robot> = (0..n).map(|k| Robot::new(rng::robot_rng(cfg.seed, k as u16))).collect();

    // Found targets are broadcast, so one shared list of those still missing.
    let mut missing: Vec<u32> = (0..world.targets.len() as u32).collect();
    let sense_targets = |missing: &mut Vec<u32>, p: Point| {
        missing.retain(|&t| (world.targets[t as usize] - p).norm_squared() > r_st2);
    };

    // Situation 2: the vertices of Va not yet passed within a/2.
    let situation2 = cfg.situation == Situation::Two;
    let (mut pending, mut uncovered) = if situation2 {
        let va = world.reachable_from(starts);
        let count = va.iter().filter(|&&b| b).count();
        (va, count)
    } else {
        (Vec::new(), 0)
    };
    let half_a2 = 0.25 * a * a;
    let cover = |pending: &mut Vec<bool>, uncovered: &mut usize, p: Point| {
        if let Some(v) = lw.vertices.get(world.grid.lattice.nearest(p)) {
            if pending[v as usize] && (world.grid.position(v) - p).norm_squared() <= half_a2 {
                pending[v as usize] = false;
                *uncovered -= 1;
            }
        }
    };

    let mut trajectories: Vec<Vec<Pose>> = Vec::new();
    if cfg.record_trajectories {
        trajectories = pos.iter().map(|&p| vec![Pose { vertex: None, position: p }]).collect();
    }
    let mut coverage = cfg.measure_coverage.then(|| Coverage::on(world, lw.raster()));
    let mut targets_s = Vec::new();
    let mut distance = vec![0.0; n];
    let mut rotations = vec![0u32; n];
    let mut turned = vec![false; n];

    for &p in &pos {
        sense_targets(&mut missing, p);
        if situation2 {
            cover(&mut pending, &mut uncovered, p);
        }
        if let Some(c) = coverage.as_mut() {
            c.pass(p);
        }
    }
    targets_s.resize(world.targets.len() - missing.len(), 0.0);
    if let Some(c) = coverage.as_mut() {
        c.at(0.0);
    }
    let done = |missing: &Vec<u32>, uncovered: usize| if situation2 { uncovered == 0 } else { missing.is_empty() };

    let mut rounds = 0u32;
    let mut time = 0.0;
    // The clock at the end of every round (replays show it round by round).
    let mut round_end_times = Vec::new();
    let mut per_round_collisions = Vec::new();
    let mut collisions = 0u32;
    let mut complete = done(&missing, uncovered);
    // The targets still missing when the last round began.
    let mut was_missing = Vec::with_capacity(missing.len());
    while !complete && n > 0 && rounds < cfg.max_rounds {
        was_missing.clear();
        was_missing.extend_from_slice(&missing);
        let mut rotated = false;
        for (i, r) in robots.iter_mut().enumerate() {
            turned[i] = r.rem <= 0.0;
            if r.rem <= 0.0 {
                new_flight(r, lw.sensing.sense(pos[i], prm.r_so, lfp.k_obstacle, 0.0).0, &levy, lfp, a);
                rotated = true;
            }
            r.step = r.rem.min(a) / micro as f64;
            r.moving = true;
            r.repelled = false;
        }

        let mut round_collisions = 0u32;
        if events {
            begun.clone_from(&pos);
        }
        for _ in 0..micro {
            repel.fields_and_near(&pos, &mut pushes, far2, &mut near);
            for (i, r) in robots.iter_mut().enumerate() {
                let p = pos[i];
                if !r.moving {
                    next[i] = p;
                    continue;
                }
                let clear_beyond = prm.r_safe + r.step;
                let (mut field, nearest) = lw.sensing.sense(p, prm.r_so, lfp.k_obstacle, clear_beyond);
                field += pushes[i];
                let bent = r.heading + field;
                let len = bent.norm();
                let dir = if len > 1e-12 { bent / len } else { r.heading };
                if dir.dot(&r.facing) < cos_steer {
                    rotated = true;
                    turned[i] = true;
                }
                r.facing = dir;
                // Pushed back against its flight: the flight gives way to a new
                // one rather than dither in front of the obstacle or robot.
                if dir.dot(&r.heading) < 0.0 {
                    r.repelled = true;
                }
                // No feature nearer than r_safe + step can be reached this micro-step.
                let t = if nearest >= clear_beyond { 1.0 } else { lw.sensing.clear_fraction(p, dir * r.step) };
                next[i] = p + dir * (r.step * t);
                distance[i] += r.step * t;
                if t < 1.0 {
                    r.rem = 0.0;
                    r.moving = false;
                } else {
                    r.rem -= r.step;
                }
            }
            // Each pair counts at most once per round, however many of the
            // round's micro-steps it spends too close; per event, not at all
            // if it started the round in contact (the collision counted).
            for &(i, j, pair) in &near {
                let (i, j, pair) = (i as usize, j as usize, pair as usize);
                let fresh = stamp[pair] != rounds && !(events && (begun[i] - begun[j]).norm() < collide);
                if fresh && swept_min_distance(pos[i], next[i], pos[j], next[j]) < collide {
                    stamp[pair] = rounds;
                    round_collisions += 1;
                }
            }
            std::mem::swap(&mut pos, &mut next);
        }
        for r in robots.iter_mut() {
            // Float residue of the micro-steps is not a flight.
            if r.rem < 1e-9 * a || r.repelled {
                r.rem = 0.0;
            }
        }

        let missed = missing.len();
        for (k, &p) in pos.iter().enumerate() {
            sense_targets(&mut missing, p);
            if situation2 {
                cover(&mut pending, &mut uncovered, p);
            }
            if cfg.record_trajectories {
                trajectories[k].push(Pose { vertex: None, position: p });
            }
            if let Some(c) = coverage.as_mut() {
                c.pass(p);
            }
            rotations[k] += u32::from(turned[k]);
        }

        rounds += 1;
        collisions += round_collisions;
        time += prm.t_choice
            + prm.t_trans
            + if rotated { prm.t_rot } else { 0.0 }
            + prm.collision_penalty(round_collisions);
        round_end_times.push(time);
        per_round_collisions.push(round_collisions);
        targets_s.resize(targets_s.len() + missed - missing.len(), time);
        if let Some(c) = coverage.as_mut() {
            c.at(time);
        }
        complete = done(&missing, uncovered);
    }

    let relayed = prm.broadcast == crate::params::Broadcast::Controller;
    let search_time_s = if complete && !situation2 && relayed && !last_news(world, &was_missing, &pos, r_st2) {
        time + 2.0 * prm.t_hop
    } else {
        time
    };
    // The cells `Raster::detected_fraction` counts, marked as the run went.
    let fraction = coverage.as_ref().map(|c| c.fraction());
    let metrics = RunMetrics {
        coverage_s: coverage.map(|c| c.curve()).unwrap_or_default(),
        targets_s,
        distance_m: distance,
        rotations,
        frames: Vec::new(),
        bytes: Vec::new(),
    };
    RunResult {
        algorithm: Policy::Lfp,
        robots: n,
        seed: cfg.seed,
        situation: cfg.situation.number(),
        rounds,
        search_time_s,
        targets_found: world.targets.len() - missing.len(),
        targets_total: world.targets.len(),
        collisions,
        coverage: fraction,
        complete,
        cut_off_early: false,
        robot_rounds: rounds as u64 * n as u64,
        trajectories,
        round_end_times_s: round_end_times,
        round_collisions: per_round_collisions,
        protocol: crate::sim::ProtocolStats {
            ended_by: if complete { "stop" } else { "max_rounds" }.to_string(),
            ..Default::default()
        },
        metrics,
    }
}

/// Whether some robot, at `pos`, found itself every target of `found` (the
/// last round's finds): it then knows every target at once, the others
/// having reached it through the controller in earlier rounds.
fn last_news(world: &World, found: &[u32], pos: &[Point], r_st2: f64) -> bool {
    pos.iter().any(|&p| found.iter().all(|&t| (world.targets[t as usize] - p).norm_squared() <= r_st2))
}

#[cfg(test)]
mod tests;
