//! The oracle: a centralized planner that knows the whole map (the
//! accessible vertices and traversable edges, not the targets) and gives
//! each algorithm a reference time (issue 8, point 3). It is not a robot
//! program: it runs in-process only, and `run` refuses it.
//!
//! - **Waypoints**: in situation 2 every vertex of `Va`, as the robots'
//!   rule 4 must visit them all; in situation 1 a set of vertices whose
//!   sensing discs cover the area ([`cover`]), planned again for the rest
//!   of `Va` should targets be missing once they are all visited. It is a
//!   reference, not a lower bound: the routes are planned in moves, not
//!   turns (`crate::bound` has a lower bound).
//! - **Plan** ([`plan`]): every waypoint is assigned to one robot. A greedy
//!   multi-robot tour (the
//!   robot whose route ends earliest extends it to its nearest unassigned
//!   vertex, by grid distance; ties drawn from the run's seed), improved by
//!   local search (2-opt within routes, relocating waypoints off the longest
//!   route) on the makespan in moves.
//! - **Execution** ([`exec`]): real trajectories, one traversable edge per
//!   robot per round, all robots at once. Collisions are avoided in the
//!   plan's execution by waiting a round (robots kept waiting, then those
//!   with the most left, go first; a robot in the way only of robots not
//!   decided yet goes after them, so followers close up), with detours,
//!   robots in the way stepping aside, and a robot blocked for 20 rounds
//!   by another trading
//!   the rest of its route with it; only a robot blocked for 100 rounds
//!   would move anyway, counted as a collision (none in the tests' runs on
//!   the built-in and random maps). Turns are planned across the team:
//!   a robot whose next move is a turn stands in a round nobody must turn
//!   in, when that makes the team's moves per second higher, and robots
//!   standing in a round someone turns in turn on the spot to face their
//!   next move (`Exec::turning`).
//! - **Time**: motion only, per the params' move model as the world charges
//!   it: a round lasts `t_trans` if any robot translates (or waits for
//!   another), plus `t_rot` if any robot turns; no radio protocol, no
//!   choice time. Situation 1 ends at the end of the round in which the
//!   last target is detected (within `r_st` of a robot's vertex), situation
//!   2 when every vertex of `Va` has been visited.

mod cover;
mod exec;
mod plan;
#[cfg(test)]
mod tests;

use std::sync::{Arc, Mutex};

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::bitset::Bitset;
use crate::grid::VertexId;
use crate::outcome::{Pose, RunConfig, RunMetrics, RunResult};
use crate::params::Situation;
use crate::policy::Policy;
use crate::rng;
use crate::sim::ProtocolStats;
use crate::world::coverage::Coverage;
use crate::world::World;

use exec::Exec;

/// The label of the oracle's random stream (tie-breaks of the greedy plan).
const STREAM: u64 = 0x0AC1E;

/// Runs the oracle's search: robot `k` starts at `starts[k]`.
pub fn run(world: &World, starts: &[VertexId], cfg: &RunConfig) -> RunResult {
    run_prepared(&OracleWorld::new(world), starts, cfg)
}

/// Distance tables kept per world: a sweep's runs share their accessible
/// part `Va`, and building its table (a breadth-first search from every
/// vertex, |Va|^2 entries) costs more than planning on `large`.
const TABLES_KEPT: usize = 4;

/// What the oracle precomputes of a world: the distance table of each
/// accessible part it was asked about (the last [`TABLES_KEPT`]). Build once
/// per world, share across threads, and call [`run_prepared`].
pub struct OracleWorld<'w> {
    world: &'w World,
    tables: Mutex<Vec<(Vec<bool>, Arc<plan::Dist>)>>,
}

impl<'w> OracleWorld<'w> {
    pub fn new(world: &'w World) -> Self {
        OracleWorld { world, tables: Mutex::new(Vec::new()) }
    }

    fn table(&self, va: &[bool]) -> Arc<plan::Dist> {
        let kept = |t: &Vec<(Vec<bool>, Arc<plan::Dist>)>| t.iter().find(|(v, _)| v == va).map(|(_, d)| d.clone());
        // A poisoned lock only means another run panicked; the tables are intact.
        if let Some(d) = kept(&self.tables.lock().unwrap_or_else(|e| e.into_inner())) {
            return d;
        }
        // Built outside the lock: two threads may build the same table once.
        let d = Arc::new(plan::Dist::new(self.world, va));
        let mut tables = self.tables.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(d) = kept(&tables) {
            return d;
        }
        if tables.len() == TABLES_KEPT {
            tables.remove(0);
        }
        tables.push((va.to_vec(), d.clone()));
        d
    }
}

/// [`run`] on a prepared world.
pub fn run_prepared(ow: &OracleWorld, starts: &[VertexId], cfg: &RunConfig) -> RunResult {
    let world = ow.world;
    let va = world.reachable_from(starts);
    let d = ow.table(&va);
    let compact: Vec<u32> = starts.iter().map(|&s| d.index[s as usize]).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(rng::derive(cfg.seed, STREAM));
    let every;
    let need: &[bool] = match cfg.situation {
        Situation::One => d.cover.get_or_init(|| cover::waypoints(world, &d)),
        Situation::Two => {
            every = vec![true; d.len()];
            &every
        }
    };
    let routes = plan::plan(&d, &compact, need, &mut rng);
    Search::new(world, &d, starts, cfg, routes, rng).run()
}

/// The execution's bookkeeping: what is found, the clock, the records.
struct Search<'a> {
    world: &'a World,
    d: &'a plan::Dist,
    cfg: &'a RunConfig,
    exec: Exec<'a>,
    /// The plan's stream, for planning again.
    rng: ChaCha8Rng,
    found: Bitset,
    /// `|Va|`; robots move only within it.
    va_len: usize,
    robots: usize,
    rounds: u32,
    time: f64,
    collisions: u32,
    moves: u64,
    robot_rounds: u64,
    round_end_times: Vec<f64>,
    round_collisions: Vec<u32>,
    trajectories: Vec<Vec<Pose>>,
    coverage: Option<Coverage<'a>>,
    targets_s: Vec<f64>,
}

impl<'a> Search<'a> {
    fn new(
        world: &'a World,
        d: &'a plan::Dist,
        starts: &[VertexId],
        cfg: &'a RunConfig,
        routes: Vec<plan::Route>,
        rng: ChaCha8Rng,
    ) -> Self {
        let exec = Exec::new(world, d, routes);
        let mut s = Search {
            world,
            d,
            cfg,
            exec,
            rng,
            found: Bitset::new(world.targets.len()),
            va_len: d.len(),
            robots: starts.len(),
            rounds: 0,
            time: 0.0,
            collisions: 0,
            moves: 0,
            robot_rounds: 0,
            round_end_times: Vec::new(),
            round_collisions: Vec::new(),
            trajectories: if cfg.record_trajectories { vec![Vec::new(); starts.len()] } else { Vec::new() },
            coverage: cfg.measure_coverage.then(|| Coverage::new(world)),
            targets_s: Vec::new(),
        };
        s.sense();
        s
    }

    /// Lasers at every robot's vertex, and the poses of the round's start.
    fn sense(&mut self) {
        let grid = &self.world.grid;
        for k in 0..self.robots {
            let v = self.exec.position(k);
            for &t in self.world.targets_near(v) {
                if !self.found.get(t as usize) {
                    self.found.set(t as usize);
                    self.targets_s.push(self.time);
                }
            }
            if let Some(c) = self.coverage.as_mut() {
                c.stand(v);
            }
            if let Some(t) = self.trajectories.get_mut(k) {
                t.push(Pose { vertex: Some(grid.coord(v)), position: grid.position(v) });
            }
        }
        if let Some(c) = self.coverage.as_mut() {
            c.at(self.time);
        }
    }

    fn done(&self) -> bool {
        match self.cfg.situation {
            Situation::One => self.found.count() == self.world.targets.len(),
            Situation::Two => self.exec.visited.count() == self.va_len,
        }
    }

    fn run(mut self) -> RunResult {
        let n = self.robots;
        while !self.done() && self.rounds < self.cfg.max_rounds && (self.busy() || self.replan()) {
            let busy = (0..n).filter(|&k| self.exec.busy(k)).count() as u64;
            let before: Vec<VertexId> = (0..n).map(|k| self.exec.position(k)).collect();
            let round = self.exec.step();
            self.moves += (0..n).filter(|&k| self.exec.position(k) != before[k]).count() as u64;
            self.robot_rounds += busy;
            self.collisions += round.forced;
            let p = &self.world.params;
            if round.translated || round.waited {
                self.time += p.t_trans;
            }
            if round.rotated {
                self.time += p.t_rot;
            }
            self.rounds += 1;
            self.round_end_times.push(self.time);
            self.round_collisions.push(round.forced);
            self.sense();
        }
        self.finish(n)
    }

    fn busy(&self) -> bool {
        (0..self.robots).any(|k| self.exec.busy(k))
    }

    /// Every waypoint visited and targets still missing (the sampled cover
    /// missed a sliver): a plan for the vertices of `Va` not visited yet.
    /// Whether any robot has somewhere to go.
    fn replan(&mut self) -> bool {
        let d = self.d;
        let need: Vec<bool> = d.verts.iter().map(|&v| !self.exec.visited.get(v as usize)).collect();
        if !need.contains(&true) {
            return false;
        }
        let at: Vec<u32> = (0..self.robots).map(|k| self.exec.at(k)).collect();
        let routes = plan::plan(d, &at, &need, &mut self.rng);
        self.exec.replan(routes);
        self.busy()
    }

    fn finish(self, n: usize) -> RunResult {
        let world = self.world;
        let complete = self.done();
        let ended = if complete {
            "stop"
        } else if self.rounds >= self.cfg.max_rounds {
            "max_rounds"
        } else {
            "no_robots"
        };
        let mut cov = self.coverage;
        // The cells `World::detected_fraction_of` counts, marked as the run went.
        let coverage = cov.as_ref().map(|c| c.fraction());
        let a = world.params.a;
        let (distance_m, rotations) = (0..n)
            .map(|k| {
                let (moves, turns) = self.exec.moves_and_turns(k);
                (f64::from(moves) * a, turns)
            })
            .unzip();
        let metrics = RunMetrics {
            coverage_s: cov.take().map(|c| c.curve()).unwrap_or_default(),
            targets_s: self.targets_s,
            distance_m,
            rotations,
            frames: Vec::new(),
            bytes: Vec::new(),
        };
        RunResult {
            algorithm: Policy::Oracle,
            robots: n,
            seed: self.cfg.seed,
            situation: self.cfg.situation.number(),
            rounds: self.rounds,
            search_time_s: self.time,
            targets_found: self.found.count(),
            targets_total: world.targets.len(),
            collisions: self.collisions,
            coverage,
            complete,
            cut_off_early: false,
            robot_rounds: self.robot_rounds,
            trajectories: self.trajectories,
            round_end_times_s: self.round_end_times,
            round_collisions: self.round_collisions,
            protocol: ProtocolStats { ended_by: ended.to_string(), moves: self.moves, ..Default::default() },
            metrics,
        }
    }
}
