//! Issue 21's reproducers, each a fixed case that must end as a complete
//! search: a robot late for its slot once stopped the search on its
//! neighbours' announced choices (claims), livelocked `frontier` behind
//! it, or made the world force a slot shut. Each prints the command that
//! replays it.

use gridswarm::engine;
use gridswarm::outcome::RunConfig;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;
use gridswarm::sim::{Fault, FaultKind, Radio};

/// Robot `robot`'s fault at `round` plus `offset_ms` into it.
fn at(robot: usize, round: u32, offset_ms: u64, kind: FaultKind) -> Fault {
    Fault { robot, round, offset: offset_ms * 1000, kind }
}

fn slow(ms: u64) -> FaultKind {
    FaultKind::Slow(ms * 1000)
}

/// Runs `cfg` on `cave` with `robots` robots and checks that the search
/// ended complete, by a stop, with no collision and no forced slot.
fn completes(robots: usize, cfg: RunConfig, replay: &str) {
    let sc = Scenario::builtin("cave").unwrap();
    let world = sc.world();
    let starts = sc.start_vertices(&world, robots).unwrap();
    let r = engine::run(&world, &starts, &cfg);
    let p = &r.protocol;
    let what = format!(
        "ended by {} at round {}, {} of {} targets, {} collisions, {} forced slots\n  replay: gridswarm simulate --scenario cave --robots {robots} {replay}",
        p.ended_by, r.rounds, r.targets_found, r.targets_total, r.collisions, p.forced_slots
    );
    assert!(r.complete && p.ended_by == "stop", "{what}");
    assert!(r.collisions == 0 && p.forced_slots == 0, "{what}");
}

fn config(policy: Policy, seed: u64, situation: Situation, faults: Vec<Fault>) -> RunConfig {
    let mut cfg = RunConfig::new(policy, seed, situation);
    cfg.faults = faults;
    cfg
}

#[test]
fn a_robot_slow_past_its_window_does_not_stop_the_search_on_claims() {
    let cfg = config(Policy::Repulsive, 27322287, Situation::One, vec![at(8, 0, 0, slow(951))]);
    completes(10, cfg, "--algorithm repulsive --seed 27322287 --situation 1 --slow 8@0:951");
    let cfg = config(Policy::Escape, 1014966717, Situation::Two, vec![at(2, 2, 0, slow(200))]);
    completes(13, cfg, "--algorithm escape --seed 1014966717 --situation 2 --slow 2@2:200");
}

#[test]
fn frontier_does_not_livelock_behind_a_slightly_slow_robot() {
    let cfg = config(Policy::Frontier, 3890665, Situation::Two, vec![at(12, 35, 1975, slow(55))]);
    completes(13, cfg, "--algorithm frontier --seed 3890665 --situation 2 --slow 12@35+1.975:55");
}

#[test]
fn a_robot_slow_by_seconds_does_not_force_a_slot_shut() {
    let faults = vec![
        at(3, 37, 260, FaultKind::Freeze),
        at(3, 40, 854, FaultKind::Thaw),
        at(1, 28, 290, FaultKind::Crash),
        at(2, 18, 2178, slow(4704)),
    ];
    let mut cfg = config(Policy::Frontier, 1081004315, Situation::Two, faults);
    cfg.radio = Radio { delay: 7_000, jitter: 33_000, ..Radio::default() };
    let replay = "--algorithm frontier --seed 1081004315 --situation 2 --freeze 3@37+0.260:40+0.854 \
                  --kill 1@28+0.290 --slow 2@18+2.178:4704 --delay 7:33";
    completes(8, cfg, replay);
}
