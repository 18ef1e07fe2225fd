//! A true lower bound on a run's search time, from the world and the
//! starts alone: no algorithm, centralized or not, can finish sooner
//! (docs/paper.md, "A lower bound"). It is the time the farthest thing
//! that must be reached takes from the nearest start at full speed, with
//! every round a move and nothing but the move charged:
//!
//! - **Grid algorithms** (the paper's, escape, frontier, the oracle) move
//!   one traversable edge a round, and a round lasts at least `t_trans`.
//!   Situation 1 ends once every target was within `r_st` of a robot's
//!   vertex, so the bound is the largest, over targets, of the fewest moves
//!   from any start to a vertex that detects it. Situation 2 ends when no
//!   robot's map has an unvisited vertex; a vertex is marked visited by
//!   standing on it or, blocked, from a neighbour, so every vertex of `Va`
//!   must come within one move of a robot: the farthest such vertex, less
//!   one move.
//! - **LFP** moves at most `a` a round along any path, and a round lasts at
//!   least `t_choice + t_trans`. Situation 1: the farthest target's
//!   straight-line distance from the nearest start, less `r_st`; situation
//!   2 (every vertex of `Va` within `a / 2` of a sub-step's end): the
//!   farthest vertex's, less `a / 2`.
//!
//! Both ignore that many targets or vertices must be reached and that
//! robots turn: they are weak where the area, not a far corner, is the
//! work, and never wrong.

use std::collections::VecDeque;

use crate::grid::{VertexId, NONE};
use crate::params::Situation;
use crate::policy::Policy;
use crate::world::World;

/// What the bound is, for summary.json.
pub const NOTE: &str = "the largest, over the targets (situation 2: the vertices of Va, less one move), of the \
    travel time from the nearest start at full speed: grid algorithms t_trans per move over traversable edges, \
    LFP t_choice + t_trans per a of straight line; no run of any algorithm ends sooner";

/// Slack for floating-point distances at the sensing edge.
const EPS: f64 = 1e-9;

/// The lower bound in seconds for `policy` from `starts`, or `None` when
/// the run cannot complete (a target no reachable vertex detects).
pub fn lower_bound(world: &World, starts: &[VertexId], situation: Situation, policy: Policy) -> Option<f64> {
    if policy == Policy::Lfp {
        lfp(world, starts, situation)
    } else {
        grid(world, starts, situation)
    }
}

/// The grid bound: moves times `t_trans`.
fn grid(world: &World, starts: &[VertexId], situation: Situation) -> Option<f64> {
    let d = moves_from(world, starts);
    let reached = |v: usize| d[v] != u32::MAX;
    let moves = match situation {
        Situation::One => {
            let mut best = vec![u32::MAX; world.targets.len()];
            for v in (0..d.len()).filter(|&v| reached(v)) {
                for &t in world.targets_near(v as VertexId) {
                    best[t as usize] = best[t as usize].min(d[v]);
                }
            }
            best.into_iter().try_fold(0u32, |m, b| (b != u32::MAX).then_some(m.max(b)))?
        }
        Situation::Two => (0..d.len()).filter(|&v| reached(v)).map(|v| d[v].saturating_sub(1)).max().unwrap_or(0),
    };
    Some(f64::from(moves) * world.params.t_trans)
}

/// Fewest moves over traversable edges from any start to every vertex
/// (`u32::MAX` where unreachable).
fn moves_from(world: &World, starts: &[VertexId]) -> Vec<u32> {
    let g = &world.grid;
    let mut d = vec![u32::MAX; g.len()];
    let mut queue = VecDeque::new();
    for &s in starts {
        if d[s as usize] == u32::MAX {
            d[s as usize] = 0;
            queue.push_back(s);
        }
    }
    while let Some(v) = queue.pop_front() {
        for &n in &g.neighbors(v)[..g.degree()] {
            if n != NONE && d[n as usize] == u32::MAX && world.can_move(v, n) {
                d[n as usize] = d[v as usize] + 1;
                queue.push_back(n);
            }
        }
    }
    d
}

/// The LFP bound: rounds of at most `a` each, times `t_choice + t_trans`.
fn lfp(world: &World, starts: &[VertexId], situation: Situation) -> Option<f64> {
    let p = &world.params;
    let at: Vec<_> = starts.iter().map(|&s| world.grid.position(s)).collect();
    let gap = |x: crate::geometry::Point, reach: f64| {
        let near = at.iter().map(|&s| (x - s).norm()).fold(f64::INFINITY, f64::min);
        (near - reach).max(0.0)
    };
    let far = match situation {
        Situation::One => world.targets.iter().map(|&t| gap(t, p.r_st)).fold(0.0, f64::max),
        Situation::Two => {
            let va = world.reachable_from(starts);
            let pos = |v: usize| world.grid.position(v as VertexId);
            (0..va.len()).filter(|&v| va[v]).map(|v| gap(pos(v), p.a / 2.0)).fold(0.0, f64::max)
        }
    };
    let rounds = (far / p.a - EPS).ceil().max(0.0);
    Some(rounds * (p.t_choice + p.t_trans))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::outcome::RunConfig;
    use crate::scenario::{Scenario, StartRule};

    /// Every algorithm, on built-in and random maps, fixed and random
    /// starts, both situations: no run ends before the bound (424 runs).
    #[test]
    fn no_run_beats_the_bound() {
        let algorithms =
            [Policy::Repulsive, Policy::Sequential, Policy::Ru, Policy::Escape, Policy::Frontier, Policy::Lfp];
        let mut runs = 0;
        let mut tight = 0.0f64;
        for name in ["paper", "cave", "small", "open", "random:3", "random:8"] {
            let sc = Scenario::load(name).unwrap();
            let w = sc.world();
            for (robots, rule, seed) in [(1, StartRule::Fixed, 1), (13, StartRule::Fixed, 2), (7, StartRule::Random, 3)]
            {
                let starts = sc.starts_by(&w, robots, rule, seed).unwrap();
                for situation in [Situation::One, Situation::Two] {
                    for &policy in algorithms.iter().chain(&[Policy::Oracle]) {
                        // The slow ones (one robot, situation 2 on cave) once.
                        if robots == 1 && (name == "cave" || situation == Situation::Two) && policy != Policy::Oracle {
                            continue;
                        }
                        let mut cfg = RunConfig::new(policy, seed, situation);
                        cfg.record_trajectories = false;
                        cfg.measure_coverage = false;
                        let r = crate::engine::run(&w, &starts, &cfg);
                        let b = lower_bound(&w, &starts, situation, policy).unwrap();
                        if r.complete {
                            assert!(
                                r.search_time_s >= b,
                                "{name} {policy:?} {robots} robots s{}: {} s < bound {b} s",
                                situation.number(),
                                r.search_time_s
                            );
                            if b > 0.0 {
                                tight = tight.max(b / r.search_time_s);
                            }
                            runs += 1;
                        }
                    }
                }
            }
        }
        assert!(runs >= 150, "{runs} completed runs");
        // The bound says something: some run comes within a factor of 4 of it.
        assert!(tight > 0.25, "tightest run at {tight} of its time");
    }

    #[test]
    fn the_grid_bound_is_the_farthest_target_from_the_nearest_start() {
        let sc = Scenario::load("paper").unwrap();
        let w = sc.world();
        let starts = sc.start_vertices(&w, 13).unwrap();
        let d = moves_from(&w, &starts);
        let far = (0..w.targets.len() as u32)
            .map(|t| (0..d.len()).filter(|&v| w.targets_near(v as VertexId).contains(&t)).map(|v| d[v]).min().unwrap())
            .max()
            .unwrap();
        assert!(far > 0);
        let b = lower_bound(&w, &starts, Situation::One, Policy::Escape).unwrap();
        assert_eq!(b, f64::from(far) * w.params.t_trans);
        // A target beside a start costs nothing: a run with robots on
        // every detecting vertex of every target.
        let all: Vec<VertexId> = (0..d.len() as VertexId).filter(|&v| !w.targets_near(v).is_empty()).collect();
        assert_eq!(lower_bound(&w, &all, Situation::One, Policy::Frontier), Some(0.0));
        // No target detectable from where the robots can go: no bound.
        let mut lone = w.clone();
        lone.targets.push(crate::geometry::Point::new(1e6, 1e6));
        let lone = World::new(lone.area, lone.obstacles, lone.targets, lone.params, lone.grid.lattice.kind);
        assert_eq!(lower_bound(&lone, &starts, Situation::One, Policy::Escape), None);
    }
}
