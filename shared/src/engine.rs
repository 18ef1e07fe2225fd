//! The in-process engine: every robot's decision core driven in lock-step
//! rounds in one thread, with the [`Referee`] as the physical world. Messages
//! are delivered as direct calls, in the order that makes every robot ready
//! when its turn comes; because no decision depends on arrival order, the
//! result equals what separate processes exchanging the same messages get.

use crate::geometry::Point;
use crate::grid::VertexId;
use crate::lfp::{self, LfpParams};
use crate::map::{Map, RobotId};
use crate::outcome::{Pose, RunConfig, RunResult};
use crate::params::Situation;
use crate::policy::Policy;
use crate::referee::{longest_wait_chain, priority_order, round_time, Referee};
use crate::robot::{Robot, RobotConfig, Sensing, Stop};
use crate::world::World;

/// Side of a raster cell for the detected fraction, in units of `a`.
pub const RASTER_CELL: f64 = 0.1;

/// Runs one search with robots starting at `starts` (robot `k` at
/// `starts[k]`), LFP with its default constants.
pub fn run(world: &World, starts: &[VertexId], cfg: &RunConfig) -> RunResult {
    run_with_lfp(world, starts, cfg, &LfpParams::default())
}

/// [`run`] with LFP's constants given (they matter only to LFP).
pub fn run_with_lfp(world: &World, starts: &[VertexId], cfg: &RunConfig, lfp: &LfpParams) -> RunResult {
    match cfg.policy {
        Policy::Lfp => lfp::run(world, starts, cfg, lfp),
        _ => run_grid(world, starts, cfg, None),
    }
}

/// [`run_with_lfp`], also returning the simulated time at the end of every
/// round (element `k` ends round `k`): a replay shows the clock round by
/// round, which the run's total alone cannot give.
pub fn run_with_round_times(
    world: &World,
    starts: &[VertexId],
    cfg: &RunConfig,
    lfp: &LfpParams,
) -> (RunResult, Vec<f64>) {
    let mut times = Vec::new();
    let result = match cfg.policy {
        Policy::Lfp => lfp::run_timed(world, starts, cfg, lfp, &mut times),
        _ => run_grid(world, starts, cfg, Some(&mut times)),
    };
    (result, times)
}

fn run_grid(
    world: &World,
    starts: &[VertexId],
    cfg: &RunConfig,
    mut round_end_times: Option<&mut Vec<f64>>,
) -> RunResult {
    let n = starts.len();
    let params = world.params;
    let mut referee = Referee::new(world, starts);
    let mut robots: Vec<Robot> = (0..n)
        .map(|k| {
            let rc = RobotConfig {
                id: k as RobotId,
                policy: cfg.policy,
                situation: cfg.situation,
                targets_total: world.targets.len(),
                r_safe: params.r_safe,
                seed: cfg.seed,
            };
            Robot::new(&world.grid, rc, starts[k])
        })
        .collect();
    let mut snapshots: Vec<Map> = robots.iter().map(|r| r.map().clone()).collect();
    let mut neighbours: Vec<Vec<RobotId>> = vec![Vec::with_capacity(8); n];
    let mut order: Vec<usize> = (0..n).collect();
    let mut chain = vec![0u32; n];
    let mut next = vec![0 as VertexId; n];
    let mut round_targets: Vec<u16> = Vec::new();
    let mut trajectories: Vec<Vec<Pose>> = if cfg.record_trajectories { vec![Vec::new(); n] } else { Vec::new() };
    let record = |trajectories: &mut Vec<Vec<Pose>>, referee: &Referee| {
        for (k, t) in trajectories.iter_mut().enumerate() {
            let v = referee.position(k);
            t.push(Pose { vertex: Some(world.grid.coord(v)), position: world.grid.position(v) });
        }
    };
    record(&mut trajectories, &referee);

    let mut rounds = 0u32;
    let mut time = 0.0;
    let mut collisions = 0u32;
    let stop = loop {
        // Steps 1-2: sense; found targets go to every robot (a broadcast).
        round_targets.clear();
        for k in 0..n {
            referee.radio(k, |_| true, &mut neighbours[k]);
            let (open, occupied) = referee.sonar(k);
            let targets = referee.laser(k);
            round_targets.extend_from_slice(targets);
            robots[k].sense(rounds, &Sensing { open, occupied, targets, neighbours: &neighbours[k] });
        }
        if cfg.situation == Situation::One && !round_targets.is_empty() {
            round_targets.sort_unstable();
            round_targets.dedup();
            for r in robots.iter_mut() {
                r.learn_targets(&round_targets);
            }
        }
        // Step 3: exchange the maps as they were after sensing.
        for k in 0..n {
            snapshots[k].copy_from(robots[k].map());
        }
        for k in 0..n {
            for &j in &neighbours[k] {
                robots[k].receive_map(j, referee.position(j as usize), &snapshots[j as usize]);
            }
        }
        // Step 7: one robot's stop is broadcast to all (step 8).
        let stop = robots.iter_mut().find_map(|r| r.stop_rule());
        if stop.is_some() || rounds >= cfg.max_rounds {
            break stop;
        }
        // Steps 4-5: in descending priority every robot finds its
        // higher-priority neighbours' choices already announced.
        priority_order(&world.grid, referee.positions(), &mut order);
        for &k in &order {
            let v = robots[k].choose().expect("every earlier neighbour has chosen");
            next[k] = v;
            if cfg.policy != Policy::Ru {
                for &j in &neighbours[k] {
                    robots[j as usize].receive_choice(k as RobotId, v);
                }
            }
        }
        // RU robots choose at once; the others wait along chains.
        let longest = match cfg.policy {
            Policy::Ru => 1,
            _ => longest_wait_chain(&world.grid, referee.positions(), &neighbours, &order, &mut chain),
        };
        // Step 6.
        let report = referee.execute(&next);
        collisions += report.collisions;
        time += round_time(&params, longest, &report);
        if let Some(t) = round_end_times.as_deref_mut() {
            t.push(time);
        }
        for k in 0..n {
            robots[k].moved(referee.position(k));
        }
        rounds += 1;
        record(&mut trajectories, &referee);
    };

    let found = referee.found().count();
    let complete = match (cfg.situation, stop) {
        (Situation::One, Some(Stop::AllTargets)) => true,
        (Situation::Two, Some(_)) => {
            let va = world.reachable_from(starts);
            (0..world.grid.len()).all(|v| !va[v] || referee.visited().get(v))
        }
        _ => false,
    };
    let coverage = cfg.measure_coverage.then(|| {
        let centres: Vec<Point> = referee.visited().iter().map(|v| world.grid.position(v as VertexId)).collect();
        world.raster(RASTER_CELL * params.a).detected_fraction(centres, params.r_st)
    });
    RunResult {
        algorithm: cfg.policy,
        robots: n,
        seed: cfg.seed,
        situation: cfg.situation.number(),
        rounds,
        search_time_s: time,
        targets_found: found,
        targets_total: world.targets.len(),
        collisions,
        coverage,
        complete,
        robot_rounds: rounds as u64 * n as u64,
        trajectories,
    }
}
