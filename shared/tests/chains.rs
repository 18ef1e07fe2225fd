//! Chains of waits under the paper's order (issue 37, points 2 and 7). A
//! fixed slot holds a chain of a few links of radio delay; robots further
//! down once waited on a live chain until the slot was nearly over, chose
//! too late for their acknowledgements to come back, and stayed, slot
//! after slot: 60 robots with 800 ms of delay, inside the bound, never
//! ended a search their fault-free twin ends in 19 rounds. Each case here
//! must end complete within 5 times its fault-free twin's rounds. Each
//! prints the command that replays it.

use gridswarm::engine;
use gridswarm::outcome::{RunConfig, RunResult};
use gridswarm::params::{Order, Situation, SlotRule};
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;
use gridswarm::sim::{Fault, FaultKind, Radio};

/// `frontier` on `paper`, situation 2, fixed slot, the paper's order, with
/// `delay_ms` of radio delay on every delivery (0: the fault-free twin).
fn run(robots: usize, seed: u64, delay_ms: u64, max_rounds: u32) -> RunResult {
    let mut sc = Scenario::builtin("paper").unwrap();
    sc.params.slot = SlotRule::Fixed;
    sc.params.order = Order::Paper;
    let world = sc.world();
    let starts = sc.start_vertices(&world, robots).unwrap();
    let mut cfg = RunConfig::new(Policy::Frontier, seed, Situation::Two);
    cfg.max_rounds = max_rounds;
    cfg.measure_coverage = false;
    cfg.record_trajectories = false;
    cfg.radio = Radio { delay: delay_ms * 1000, ..Radio::default() };
    engine::run(&world, &starts, &cfg)
}

/// The case with `delay_ms` of delay ends complete, by a stop, with no
/// collision, within 5 times its fault-free twin's rounds.
fn ends_near_twin(robots: usize, seed: u64, delay_ms: u64) {
    let twin = run(robots, seed, 0, 2000);
    assert!(twin.complete, "the fault-free twin of {robots} robots, seed {seed} ends");
    let limit = 5 * twin.rounds;
    let r = run(robots, seed, delay_ms, limit);
    let p = &r.protocol;
    let what = format!(
        "ended by {} at round {} (twin: {}), {} unsure stays, {} collisions\n  replay: gridswarm simulate --scenario paper --robots {robots} --algorithm frontier --seed {seed} --situation 2 --slot fixed --order paper --max-rounds {limit} --delay {delay_ms}",
        p.ended_by, r.rounds, twin.rounds, p.unsure, r.collisions
    );
    assert!(r.complete && p.ended_by == "stop" && r.rounds <= limit, "{what}");
    assert_eq!((r.collisions, p.forced_slots), (0, 0), "{what}");
}

/// Issue 37's reproducer: 60 robots, 800 ms of delay.
#[test]
fn a_chain_longer_than_the_fixed_slot_still_moves() {
    ends_near_twin(60, 110298310943876802, 800);
}

/// 40 and 60 robots, 700 and 1,000 ms of delay (the bound is the widest
/// window, 1.05 s), three seeds each.
#[test]
fn chains_under_delay_inside_the_bound_end() {
    for robots in [40, 60] {
        for delay_ms in [700, 1000] {
            for seed in 1..=3 {
                ends_near_twin(robots, seed, delay_ms);
            }
        }
    }
}

/// Point 7: a robot with more than one reason to stay unsure in a slot
/// (deaf to a radio slower than its widest window, and too slow for it)
/// counted the stay twice: 4,404 unsure stays in 4,403 robot-rounds. A
/// stay is one robot-round, whatever its reasons.
#[test]
fn an_unsure_stay_counts_once() {
    let sc = Scenario::builtin("paper").unwrap();
    let world = sc.world();
    let starts = sc.start_vertices(&world, 13).unwrap();
    let mut cfg = RunConfig::new(Policy::Sequential, 8642353540196803369, Situation::Two);
    cfg.max_rounds = 400;
    cfg.measure_coverage = false;
    cfg.record_trajectories = false;
    cfg.radio = Radio { delay: 1_500_000, ..Radio::default() };
    cfg.faults = vec![Fault { robot: 8, round: 3, offset: 61_018, kind: FaultKind::Crash }];
    let r = engine::run(&world, &starts, &cfg);
    let p = &r.protocol;
    assert!(
        p.unsure > 0 && p.unsure <= r.robot_rounds,
        "{} unsure stays in {} robot-rounds\n  replay: gridswarm simulate --scenario paper --robots 13 --algorithm sequential --seed 8642353540196803369 --max-rounds 400 --delay 1500:0 --kill 8@3+0.061018",
        p.unsure,
        r.robot_rounds
    );
}
