//! Dense teams (issue 21, point 5). Under the paper's order step 4's
//! chains of waits grow with the team: no robot may time out on a live
//! neighbour for it. Under the local order they have bounded depth: a
//! round must not grow with the team. Simulated time is deterministic, so
//! both are properties of one seeded run, not timings.

use gridswarm::engine;
use gridswarm::outcome::{RunConfig, RunResult};
use gridswarm::params::Order;
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;

fn large(order: Order, robots: usize, policy: Policy) -> (RunResult, Scenario) {
    let mut sc = Scenario::builtin("large").unwrap();
    sc.params.order = order;
    let world = sc.world();
    let starts = sc.start_vertices(&world, robots).unwrap();
    let mut cfg = RunConfig::new(policy, 1, sc.situation);
    cfg.measure_coverage = false;
    (engine::run(&world, &starts, &cfg), sc)
}

fn mean_round_s(r: &RunResult) -> f64 {
    r.search_time_s / r.rounds as f64
}

/// 200 robots on `large`: chains of waits longer than `t_wait` covers
/// (before the robots told each other they still wait, 163 unsure stays
/// and 870 time-outs in this run).
#[test]
fn the_papers_order_never_times_out_on_a_live_neighbour() {
    for policy in [Policy::Repulsive, Policy::Sequential] {
        let (r, _) = large(Order::Paper, 200, policy);
        let p = &r.protocol;
        let what = format!("{policy}: {} unsure, {} time-outs, {} forced slots", p.unsure, p.timeouts, p.forced_slots);
        assert!(r.complete && p.ended_by == "stop", "{what}: ended by {}", p.ended_by);
        assert_eq!((p.unsure, p.timeouts, p.forced_slots, r.collisions), (0, 0, 0, 0), "{what}");
        assert_eq!(p.false_suspicions, 0, "{what}");
    }
}

/// 13 and 1,000 robots on `large`: at most one robot of each of the
/// lattice's 7 classes in a chain, so a round at 1,000 robots lasts at most
/// 1.2 times one at 13 (issue 21's goal), and no slot's decisions outlast
/// the exchange and 7 choices with their hops.
#[test]
fn the_local_order_keeps_rounds_as_short_in_a_dense_team() {
    let (small, _) = large(Order::Local, 13, Policy::Repulsive);
    let (dense, sc) = large(Order::Local, 1000, Policy::Repulsive);
    for r in [&small, &dense] {
        let p = &r.protocol;
        assert!(r.complete && p.ended_by == "stop", "{} robots: ended by {}", r.robots, p.ended_by);
        assert_eq!((p.unsure, p.timeouts, p.forced_slots, r.collisions), (0, 0, 0, 0), "{} robots", r.robots);
    }
    let ratio = mean_round_s(&dense) / mean_round_s(&small);
    assert!(ratio <= 1.2, "a round at 1,000 robots lasts {ratio:.3} times one at 13");
    let p = &sc.params;
    let decisions = p.t_exchange + 7.0 * (p.t_choice + p.t_hop) + 3.0 * p.t_hop;
    let longest = p.t_rot + p.t_trans + decisions;
    let ends = &dense.round_end_times_s;
    assert!(ends.len() >= dense.rounds as usize, "{} round ends for {} rounds", ends.len(), dense.rounds);
    let mut start = 0.0;
    for (k, &end) in ends.iter().enumerate() {
        assert!(end - start <= longest + 1e-9, "round {k} lasted {:.3} s, more than {longest:.3}", end - start);
        start = end;
    }
    // The paper's order, same team: its chains run across the team.
    let (paper, _) = large(Order::Paper, 1000, Policy::Repulsive);
    assert!(mean_round_s(&paper) > 1.5 * mean_round_s(&dense), "the paper's order: {:.3} s", mean_round_s(&paper));
}
