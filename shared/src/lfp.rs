//! LFP: Levy flight with an artificial potential field (Sutantyo et al.
//! 2010), the continuous-motion baseline of Fig. 7 (READING.md "The
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
//!   Mantegna's method with exponent `beta`, and a heading: uniform for the
//!   first flight, then the previous heading plus `N(0, turn_sigma)`. A new
//!   heading that points into a sensed obstacle (against the obstacle
//!   repulsion) is mirrored off it, so a robot stopped at a wall turns away.
//! - **Rounds.** Time advances in lock-step rounds. In each round every robot
//!   covers one sub-step of length `min(a, what is left of its flight)`, in
//!   `micro_steps` equal micro-steps (its control loop). Each micro-step goes
//!   in the direction `heading + F`, normalised, where `F` is the potential
//!   field at the robot's position at the start of the micro-step: for every
//!   other robot within `r_c` at distance `d`, `k_robot * (1/d - 1/r_c) / d^2`
//!   away from it; for every boundary edge, obstacle edge or obstacle circle
//!   within `r_so`, `k_obstacle * (1/d - 1/r_so) / d^2` away from its nearest
//!   point (Khatib's potential, which vanishes at the edge of the range). The
//!   field bends the path, not the flight: the heading stays the flight's
//!   own, so a robot slides along a wall or round a neighbour and carries on.
//!   A micro-step the field turns more than 90 degrees from the heading ends
//!   the flight with the round (the robot is pushed back; it takes a new
//!   flight instead of dithering in front of the obstacle). A robot knows
//!   the other robots' positions within `r_c` (Wi-Fi) and the obstacles
//!   within `r_so` (sonar); it never reads the map. The length of a flight
//!   is measured along the path.
//! - **Clearance.** A micro-step that would bring the robot within `r_safe`
//!   of an obstacle or the boundary is cut short at the last clear point
//!   (bisection to 1/1024 of the micro-step); the robot stops for the rest of
//!   the round and starts a new flight next round. With `r_so >= a + r_safe`
//!   (Assumption 2.4) the robot senses everything this check uses; with a
//!   shorter sonar the check still applies, because the ground truth does not
//!   let robots into walls.
//! - **Time** (READING.md "Time"). A round lasts `t_choice` (every robot
//!   computes its own move at once: one unit) plus `t_trans` (one sub-step of
//!   at most `a`), plus `t_rot` if any robot rotates on the spot: it starts a
//!   new flight, or its direction of motion changes by more than
//!   `max_steer` between two micro-steps (smaller bends are steering while
//!   driving). Each collision counted in the round adds one more
//!   `params.move_time()`, as the paper does for RU.
//! - **Collisions.** The referee counts a collision for every pair of robots
//!   that come closer than `2 * r_safe` at any moment of the round. All
//!   robots move through their micro-steps together and each micro-step is
//!   straight, so the closest approach within one is
//!   [`geometry::swept_min_distance`]. A pair counts at most once per round,
//!   and again in every round it is too close. The field makes collisions
//!   rare, not impossible (two robots just out of `r_c` close at up to `2a`
//!   per round).
//! - **Sensing and stop.** A target is found when it lies within `r_st` of a
//!   robot's position at the start of the run or at the end of a sub-step;
//!   found targets are broadcast to all. Situation 1 stops when every target
//!   of the world is found (rule 3). Situation 2: LFP keeps no map, so rule 4
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
mod sensing;

use std::sync::OnceLock;

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

use crate::geometry::{swept_min_distance, Point, Vector};
use crate::grid::{VertexId, NONE};
use crate::lattice::Coord;
use crate::outcome::{Pose, RunConfig, RunResult};
use crate::params::Situation;
use crate::policy::Policy;
use crate::rng;
use crate::world::{Raster, World};

use levy::Mantegna;
use sensing::Sensing;

/// LFP's constants. The paper gives none; these defaults are the project's
/// documented choice and every one can be set in a scenario's `[lfp]` table.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LfpParams {
    /// Levy exponent of Mantegna's method, meaningful in `(0, 2)`. Default
    /// 1.5: READING.md's suggestion and the common choice in Levy search.
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
    /// Standard deviation of the normally drawn turn between flights (rad).
    /// Default 0.5 (29 degrees): the project's choice; the heading forgets
    /// itself over about `2 / turn_sigma^2` = 8 flights. Search time is
    /// sensitive to it (one robot on a 20 x 16 m map with four obstacles:
    /// about 1900 s at 0.5, 2600 s at 1.0, 3700 s at pi/2, 4900 s at pi), so
    /// reports should state it.
    pub turn_sigma: f64,
    /// Gain of the repulsion from other robots within `r_c`. Default 1.0:
    /// the push equals the unit heading at about 0.85 m, i.e. before two
    /// robots are `2 * r_safe` apart.
    pub k_robot: f64,
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
            turn_sigma: 0.5,
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
    raster: OnceLock<Raster>,
}

impl<'w> LfpWorld<'w> {
    pub fn new(world: &'w World) -> Self {
        LfpWorld { world, sensing: Sensing::new(world), vertices: VertexTable::new(world), raster: OnceLock::new() }
    }

    pub fn world(&self) -> &'w World {
        self.world
    }

    fn raster(&self) -> &Raster {
        self.raster.get_or_init(|| self.world.raster(self.world.params.a / 10.0))
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

/// [`run`], also pushing onto `round_end_times` the simulated time at the
/// end of every round (for replays, which show the clock round by round).
pub fn run_timed(
    world: &World,
    starts: &[VertexId],
    cfg: &RunConfig,
    lfp: &LfpParams,
    round_end_times: &mut Vec<f64>,
) -> RunResult {
    run_inner(&LfpWorld::new(world), starts, cfg, lfp, Some(round_end_times))
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

/// Starts a flight for `r` at a point where the obstacles push with `f_obs`.
fn new_flight(r: &mut Robot, f_obs: Vector, levy: &Mantegna, lfp: &LfpParams, a: f64) {
    r.heading = if r.heading == Vector::zeros() {
        let (s, c) = (r.rng.random::<f64>() * std::f64::consts::TAU).sin_cos();
        Vector::new(c, s)
    } else {
        let turn: f64 = r.rng.sample::<f64, _>(StandardNormal) * lfp.turn_sigma;
        let (s, c) = turn.sin_cos();
        let h = r.heading;
        Vector::new(c * h.x - s * h.y, s * h.x + c * h.y)
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

/// [`run`] on a prepared world.
pub fn run_prepared(lw: &LfpWorld, starts: &[VertexId], cfg: &RunConfig, lfp: &LfpParams) -> RunResult {
    run_inner(lw, starts, cfg, lfp, None)
}

fn run_inner(
    lw: &LfpWorld,
    starts: &[VertexId],
    cfg: &RunConfig,
    lfp: &LfpParams,
    mut round_end_times: Option<&mut Vec<f64>>,
) -> RunResult {
    let world = lw.world;
    let prm = &world.params;
    let n = starts.len();
    let a = prm.a;
    let levy = Mantegna::new(lfp.beta);
    let cos_steer = lfp.max_steer.cos();
    let r_st2 = prm.r_st * prm.r_st;
    let r_c2 = prm.r_c * prm.r_c;
    let inv_rc = 1.0 / prm.r_c;
    let collide = 2.0 * prm.r_safe;
    let micro = lfp.micro_steps.max(1);
    // Two robots further apart than this cannot meet within one micro-step.
    let far2 = (collide + 2.0 * a / micro as f64).powi(2);
    let mut stamp = vec![u32::MAX; n * n.saturating_sub(1) / 2];

    let mut pos: Vec<Point> = starts.iter().map(|&v| world.grid.position(v)).collect();
    let mut next = pos.clone();
    let mut robots: Vec<Robot> = (0..n)
        .map(|k| Robot {
            heading: Vector::zeros(),
            facing: Vector::zeros(),
            rem: 0.0,
            step: 0.0,
            moving: false,
            repelled: false,
            rng: rng::robot_rng(cfg.seed, k as u16),
        })
        .collect();

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
    let mut visited: Vec<Point> = if cfg.measure_coverage { pos.clone() } else { Vec::new() };

    for &p in &pos {
        sense_targets(&mut missing, p);
        if situation2 {
            cover(&mut pending, &mut uncovered, p);
        }
    }
    let done = |missing: &Vec<u32>, uncovered: usize| if situation2 { uncovered == 0 } else { missing.is_empty() };

    let mut rounds = 0u32;
    let mut time = 0.0;
    let mut collisions = 0u32;
    let mut complete = done(&missing, uncovered);
    while !complete && n > 0 && rounds < cfg.max_rounds {
        let mut rotated = false;
        for (i, r) in robots.iter_mut().enumerate() {
            if r.rem <= 0.0 {
                new_flight(r, lw.sensing.sense(pos[i], prm.r_so, lfp.k_obstacle).0, &levy, lfp, a);
                rotated = true;
            }
            r.step = r.rem.min(a) / micro as f64;
            r.moving = true;
            r.repelled = false;
        }

        let mut round_collisions = 0u32;
        for _ in 0..micro {
            for (i, r) in robots.iter_mut().enumerate() {
                let p = pos[i];
                if !r.moving {
                    next[i] = p;
                    continue;
                }
                let (mut field, nearest) = lw.sensing.sense(p, prm.r_so, lfp.k_obstacle);
                if lfp.k_robot != 0.0 && prm.r_c > 0.0 {
                    for (j, &q) in pos.iter().enumerate() {
                        let v = p - q;
                        let d2 = v.norm_squared();
                        if j != i && d2 < r_c2 && d2 > 1e-18 {
                            let d = d2.sqrt();
                            field += v * (lfp.k_robot * (1.0 / d - inv_rc) / (d2 * d));
                        }
                    }
                }
                let bent = r.heading + field;
                let len = bent.norm();
                let dir = if len > 1e-12 { bent / len } else { r.heading };
                if dir.dot(&r.facing) < cos_steer {
                    rotated = true;
                }
                r.facing = dir;
                // Pushed back against its flight: the flight gives way to a new
                // one rather than dither in front of the obstacle or robot.
                if dir.dot(&r.heading) < 0.0 {
                    r.repelled = true;
                }
                // No feature nearer than r_safe + step can be reached this micro-step.
                let t = if nearest >= prm.r_safe + r.step { 1.0 } else { lw.sensing.clear_fraction(p, dir * r.step) };
                next[i] = p + dir * (r.step * t);
                if t < 1.0 {
                    r.rem = 0.0;
                    r.moving = false;
                } else {
                    r.rem -= r.step;
                }
            }
            // Each pair counts at most once per round, however many of the
            // round's micro-steps it spends too close.
            let mut pair = 0;
            for i in 0..n {
                for j in i + 1..n {
                    if stamp[pair] != rounds
                        && (pos[i] - pos[j]).norm_squared() <= far2
                        && swept_min_distance(pos[i], next[i], pos[j], next[j]) < collide
                    {
                        stamp[pair] = rounds;
                        round_collisions += 1;
                    }
                    pair += 1;
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

        for (k, &p) in pos.iter().enumerate() {
            sense_targets(&mut missing, p);
            if situation2 {
                cover(&mut pending, &mut uncovered, p);
            }
            if cfg.record_trajectories {
                trajectories[k].push(Pose { vertex: None, position: p });
            }
        }
        if cfg.measure_coverage {
            visited.extend_from_slice(&pos);
        }

        rounds += 1;
        collisions += round_collisions;
        time += prm.t_choice
            + prm.t_trans
            + if rotated { prm.t_rot } else { 0.0 }
            + round_collisions as f64 * prm.move_time();
        if let Some(t) = round_end_times.as_deref_mut() {
            t.push(time);
        }
        complete = done(&missing, uncovered);
    }

    let coverage = cfg.measure_coverage.then(|| lw.raster().detected_fraction(visited.iter().copied(), prm.r_st));
    RunResult {
        algorithm: Policy::Lfp,
        robots: n,
        seed: cfg.seed,
        situation: cfg.situation.number(),
        rounds,
        search_time_s: time,
        targets_found: world.targets.len() - missing.len(),
        targets_total: world.targets.len(),
        collisions,
        coverage,
        complete,
        robot_rounds: rounds as u64 * n as u64,
        trajectories,
        round_end_times_s: Vec::new(),
        protocol: crate::sim::ProtocolStats {
            ended_by: if complete { "stop" } else { "max_rounds" }.to_string(),
            ..Default::default()
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Circle, Polygon, Shape};
    use crate::lattice::LatticeKind;
    use crate::params::Params;

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Polygon {
        Polygon::new(vec![Point::new(x0, y0), Point::new(x1, y0), Point::new(x1, y1), Point::new(x0, y1)])
    }

    /// Nine targets evenly spread over a `w x h` area (Sec. 5).
    fn nine_targets(w: f64, h: f64) -> Vec<Point> {
        let mut t = Vec::new();
        for y in 0..3 {
            for x in 0..3 {
                t.push(Point::new(w * (2 * x + 1) as f64 / 6.0, h * (2 * y + 1) as f64 / 6.0));
            }
        }
        t
    }

    /// A paper-sized map: 20 x 16 m, two boxes and two discs, nine targets.
    fn paper_like() -> World {
        let obstacles = vec![
            Shape::Polygon(rect(4.0, 4.0, 7.0, 6.0)),
            Shape::Polygon(rect(12.0, 9.0, 15.0, 12.0)),
            Shape::Circle(Circle { center: Point::new(6.0, 11.0), radius: 1.5 }),
            Shape::Circle(Circle { center: Point::new(14.0, 4.0), radius: 1.2 }),
        ];
        World::new(
            rect(0.0, 0.0, 20.0, 16.0),
            obstacles,
            nine_targets(20.0, 16.0),
            Params::default(),
            LatticeKind::Triangular,
        )
    }

    fn open(w: f64, h: f64) -> World {
        World::new(rect(0.0, 0.0, w, h), vec![], nine_targets(w, h), Params::default(), LatticeKind::Triangular)
    }

    /// `n` neighbouring accessible vertices along the bottom border.
    fn border_starts(world: &World, n: usize) -> Vec<VertexId> {
        let s: Vec<VertexId> = world.accessible_vertices().take(n).collect();
        assert_eq!(s.len(), n);
        s
    }

    fn cfg(seed: u64, situation: Situation) -> RunConfig {
        RunConfig::new(Policy::Lfp, seed, situation)
    }

    fn quiet(seed: u64) -> RunConfig {
        RunConfig { measure_coverage: false, record_trajectories: false, ..cfg(seed, Situation::One) }
    }

    #[test]
    fn deterministic_for_a_seed() {
        let w = paper_like();
        let starts = border_starts(&w, 5);
        let a = run(&w, &starts, &cfg(42, Situation::One), &LfpParams::default());
        let b = run(&w, &starts, &cfg(42, Situation::One), &LfpParams::default());
        assert_eq!(a.rounds, b.rounds);
        assert_eq!(a.search_time_s, b.search_time_s);
        assert_eq!(a.collisions, b.collisions);
        assert_eq!(a.coverage, b.coverage);
        assert_eq!(a.trajectories, b.trajectories);
        // The prepared form is the same computation.
        let lw = LfpWorld::new(&w);
        let c = run_prepared(&lw, &starts, &cfg(42, Situation::One), &LfpParams::default());
        assert_eq!(a.trajectories, c.trajectories);
        assert_eq!(a.search_time_s, c.search_time_s);
    }

    #[test]
    fn different_seeds_differ() {
        let w = paper_like();
        let starts = border_starts(&w, 3);
        let runs: Vec<RunResult> =
            (0..4).map(|s| run(&w, &starts, &cfg(s, Situation::One), &LfpParams::default())).collect();
        for x in 0..runs.len() {
            for y in x + 1..runs.len() {
                assert_ne!(runs[x].trajectories, runs[y].trajectories, "seeds {x} and {y}");
            }
        }
        // Robots of one run do not share a stream.
        assert_ne!(runs[0].trajectories[0][1..3], runs[0].trajectories[1][1..3]);
    }

    #[test]
    fn result_fields_are_filled() {
        let w = paper_like();
        let starts = border_starts(&w, 4);
        let r = run(&w, &starts, &cfg(3, Situation::One), &LfpParams::default());
        assert_eq!(r.algorithm, Policy::Lfp);
        assert_eq!((r.robots, r.seed, r.situation), (4, 3, 1));
        assert!(r.complete);
        assert_eq!((r.targets_found, r.targets_total), (9, 9));
        assert_eq!(r.robot_rounds, 4 * r.rounds as u64);
        assert_eq!(r.trajectories.len(), 4);
        for (k, t) in r.trajectories.iter().enumerate() {
            assert_eq!(t.len(), r.rounds as usize + 1);
            assert_eq!(t[0].position, w.grid.position(starts[k]));
            assert!(t.iter().all(|p| p.vertex.is_none()));
            // No sub-step is longer than a.
            assert!(t.windows(2).all(|s| (s[1].position - s[0].position).norm() <= w.params.a + 1e-9));
        }
        let cov = r.coverage.unwrap();
        assert!(cov > 0.0 && cov <= 1.0, "{cov}");
        // Every round costs at least t_choice + t_trans, at most that plus
        // t_rot and the collision penalties.
        let p = w.params;
        let lo = r.rounds as f64 * (p.t_choice + p.t_trans);
        let hi = lo + r.rounds as f64 * p.t_rot + r.collisions as f64 * p.move_time();
        assert!(
            r.search_time_s >= lo - 1e-9 && r.search_time_s <= hi + 1e-9,
            "{} not in [{lo}, {hi}]",
            r.search_time_s
        );
        // The first round always rotates (every robot starts a flight).
        assert!(r.search_time_s >= lo + p.t_rot - 1e-9);
    }

    #[test]
    fn never_inside_an_obstacle_or_too_close_to_a_wall() {
        let w = paper_like();
        let r_safe = w.params.r_safe;
        for (robots, seed) in [(1, 0), (5, 1), (13, 2), (13, 3), (8, 4)] {
            let starts = border_starts(&w, robots);
            let c = RunConfig { max_rounds: 3000, ..cfg(seed, Situation::Two) };
            let r = run(&w, &starts, &c, &LfpParams::default());
            for t in &r.trajectories {
                for pose in t {
                    let p = pose.position;
                    assert!(w.area.contains(p), "{p:?} left the area");
                    assert!(w.area.boundary_distance(p) >= r_safe - 1e-9, "{p:?} too close to the boundary");
                    for o in &w.obstacles {
                        assert!(!o.contains(p) && o.distance(p) >= r_safe - 1e-9, "{p:?} too close to {o:?}");
                    }
                }
                // Nor on the way: every sub-step keeps the clearance.
                for s in t.windows(2) {
                    let (p, q) = (s[0].position, s[1].position);
                    assert!(w.area.boundary_segment_distance(p, q) >= r_safe - 1e-9);
                    assert!(w.obstacles.iter().all(|o| o.segment_distance(p, q) >= r_safe - 1e-9));
                }
            }
        }
    }

    #[test]
    fn finds_all_targets_on_an_open_rectangle() {
        let w = open(20.0, 16.0);
        for robots in [1, 5] {
            let starts = border_starts(&w, robots);
            for seed in 0..8 {
                let r = run(&w, &starts, &quiet(seed), &LfpParams::default());
                assert!(r.complete, "{robots} robots, seed {seed}: {} rounds", r.rounds);
                assert_eq!(r.targets_found, 9);
                let bound = if robots == 1 { 3000 } else { 800 };
                assert!(r.rounds <= bound, "{robots} robots, seed {seed}: {} rounds", r.rounds);
            }
        }
    }

    #[test]
    fn more_robots_search_faster_on_average() {
        let w = paper_like();
        let mean = |robots: usize| {
            let starts = border_starts(&w, robots);
            (0..40).map(|s| run(&w, &starts, &quiet(s), &LfpParams::default()).search_time_s).sum::<f64>() / 40.0
        };
        let (one, five) = (mean(1), mean(5));
        assert!(five < one, "1 robot {one} s, 5 robots {five} s");
    }

    #[test]
    fn situation_two_covers_va() {
        let w = open(8.0, 6.0);
        let starts = border_starts(&w, 3);
        let r = run(&w, &starts, &cfg(5, Situation::Two), &LfpParams::default());
        assert!(r.complete && r.situation == 2);
        let va = w.reachable_from(&starts);
        let ends: Vec<Point> = r.trajectories.iter().flatten().map(|p| p.position).collect();
        for v in w.accessible_vertices().filter(|&v| va[v as usize]) {
            let pv = w.grid.position(v);
            assert!(ends.iter().any(|&e| (e - pv).norm() <= 0.5 + 1e-9), "vertex at {pv:?} never passed");
        }
        // Nearly all of Ad is then detected; corners may keep a sliver.
        assert!(r.coverage.unwrap() > 0.99, "{:?}", r.coverage);
    }

    #[test]
    fn collisions_are_counted_when_forced() {
        let w = World::new(
            rect(0.0, 0.0, 4.0, 4.0),
            vec![],
            vec![Point::new(100.0, 100.0)],
            Params::default(),
            LatticeKind::Triangular,
        );
        let starts = border_starts(&w, 10);
        let c = RunConfig { max_rounds: 200, ..quiet(9) };
        let blind = LfpParams { k_robot: 0.0, ..LfpParams::default() };
        let r = run(&w, &starts, &c, &blind);
        assert!(!r.complete && r.rounds == 200 && r.targets_found == 0);
        assert!(r.collisions > 0);
        let p = w.params;
        let lo = 200.0 * (p.t_choice + p.t_trans) + r.collisions as f64 * p.move_time();
        assert!(r.search_time_s >= lo - 1e-9);
        // The potential field makes them rarer.
        let fielded = run(&w, &starts, &c, &LfpParams::default());
        assert!(fielded.collisions < r.collisions, "{} vs {}", fielded.collisions, r.collisions);
    }

    #[test]
    fn blind_robots_in_a_corridor_cannot_pass_unnoticed() {
        // The free band is 2 r_safe wide: two robots that do not repel cannot
        // pass each other without coming closer than 2 r_safe, and the
        // referee must see it.
        // A target nobody can reach keeps the run going.
        let w = World::new(
            rect(0.0, -0.6, 8.0, 0.6),
            vec![],
            vec![Point::new(50.0, 0.0)],
            Params::default(),
            LatticeKind::Square,
        );
        let row: Vec<VertexId> = w.accessible_vertices().collect();
        let starts = [row[0], row[row.len() - 1]];
        let blind = LfpParams { k_robot: 0.0, ..LfpParams::default() };
        for seed in 0..4 {
            let c = RunConfig { max_rounds: 1000, ..cfg(seed, Situation::One) };
            let r = run(&w, &starts, &c, &blind);
            let side = |k: usize| r.trajectories[0][k].position.x < r.trajectories[1][k].position.x;
            let passed = (0..=r.rounds as usize).any(|k| side(k) != side(0));
            assert!(passed, "seed {seed}: never passed in {} rounds", r.rounds);
            assert!(r.collisions > 0, "seed {seed}: passed without a collision");
        }
    }

    #[test]
    fn the_field_keeps_collisions_rare() {
        let w = paper_like();
        let starts = border_starts(&w, 13);
        let total: u32 = (0..30).map(|s| run(&w, &starts, &quiet(s), &LfpParams::default()).collisions).sum();
        assert!(total <= 15, "{total} collisions in 30 runs of 13 robots");
    }

    #[test]
    fn no_targets_means_done_at_once() {
        let w = World::new(rect(0.0, 0.0, 6.0, 6.0), vec![], vec![], Params::default(), LatticeKind::Triangular);
        let r = run(&w, &border_starts(&w, 2), &cfg(0, Situation::One), &LfpParams::default());
        assert!(r.complete);
        assert_eq!((r.rounds, r.search_time_s), (0, 0.0));
        assert_eq!(r.trajectories[0].len(), 1);
    }

    #[test]
    fn unreachable_target_ends_incomplete() {
        let w = World::new(
            rect(0.0, 0.0, 6.0, 6.0),
            vec![Shape::Circle(Circle { center: Point::new(3.0, 3.0), radius: 1.0 })],
            vec![Point::new(3.0, 3.0)],
            Params::default(),
            LatticeKind::Triangular,
        );
        let c = RunConfig { max_rounds: 300, ..cfg(1, Situation::One) };
        let r = run(&w, &border_starts(&w, 2), &c, &LfpParams::default());
        assert!(!r.complete && r.rounds == 300 && r.targets_found == 0);
    }

    #[test]
    fn other_lattices_run() {
        for kind in [LatticeKind::Square, LatticeKind::Hexagonal] {
            let w = World::new(rect(0.0, 0.0, 8.0, 6.0), vec![], nine_targets(8.0, 6.0), Params::default(), kind);
            let starts = border_starts(&w, 2);
            for situation in [Situation::One, Situation::Two] {
                let r = run(&w, &starts, &cfg(2, situation), &LfpParams::default());
                assert!(r.complete, "{kind:?} {situation:?}");
            }
        }
    }

    #[test]
    fn params_from_partial_tables() {
        let p: LfpParams = serde_json::from_str(r#"{"beta": 1.2, "k_robot": 0.0}"#).unwrap();
        assert_eq!(p, LfpParams { beta: 1.2, k_robot: 0.0, ..LfpParams::default() });
        assert!(serde_json::from_str::<LfpParams>(r#"{"gamma": 1.0}"#).is_err());
        let d: LfpParams = serde_json::from_str("{}").unwrap();
        assert_eq!(d, LfpParams::default());
    }
}
