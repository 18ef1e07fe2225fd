//! The per-run metrics of issue 22, item 4, on `paper` for every policy of
//! the sweeps: plausible, and consistent with the run's own figures.

use gridswarm::engine;
use gridswarm::grid::VertexId;
use gridswarm::outcome::{RunConfig, RunResult};
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;
use gridswarm::world::coverage::LEVELS;
use gridswarm::world::World;

fn run(world: &World, starts: &[VertexId], policy: Policy, seed: u64, situation: Situation) -> RunResult {
    let mut cfg = RunConfig::new(policy, seed, situation);
    cfg.max_rounds = 20_000;
    engine::run(world, starts, &cfg)
}

/// The detected fraction by the end's raster pass over every place the
/// trajectories hold, as engines measured it before it was marked as the
/// run went.
fn raster_pass(world: &World, r: &RunResult) -> f64 {
    let points = r.trajectories.iter().flatten().map(|p| p.position);
    let h = if r.algorithm == Policy::Lfp { world.params.a / 10.0 } else { 0.1 * world.params.a };
    world.raster(h).detected_fraction(points, world.params.r_st)
}

fn check(world: &World, r: &RunResult) {
    let what = format!("{} robots={} seed={}", r.algorithm, r.robots, r.seed);
    let m = &r.metrics;
    let coverage = r.coverage.expect("measured");
    assert_eq!(coverage, raster_pass(world, r), "{what}: coverage as it went is the end's pass");
    // The curve: nondecreasing, from the start, each level once, up to the run's coverage.
    let last = r.round_end_times_s.last().copied().unwrap_or(0.0);
    assert!(m.coverage_s.windows(2).all(|w| w[0] <= w[1]), "{what}: {:?}", m.coverage_s);
    assert!(m.coverage_s.iter().all(|&t| (0.0..=last).contains(&t)), "{what}");
    assert!(!m.coverage_s.is_empty() && m.coverage_s[0] == 0.0, "{what}: the starts detect 1% of `paper`");
    let levels = m.coverage_s.len() as f64 / LEVELS as f64;
    assert!(coverage >= levels - 1e-12 && coverage < levels + 1.0 / LEVELS as f64, "{what}: {coverage} {levels}");
    // Targets: one time each, in order, no later than the search's end.
    assert_eq!(m.targets_s.len(), r.targets_found, "{what}");
    assert!(m.targets_s.windows(2).all(|w| w[0] <= w[1]), "{what}: {:?}", m.targets_s);
    assert!(m.targets_s.iter().all(|&t| t >= 0.0 && t <= r.search_time_s), "{what}: {:?}", m.targets_s);
    // Per robot: distance and turns, and radio traffic for the grid policies.
    assert_eq!((m.distance_m.len(), m.rotations.len()), (r.robots, r.robots), "{what}");
    let a = world.params.a;
    let distance: f64 = m.distance_m.iter().sum();
    let turns: u32 = m.rotations.iter().sum();
    if matches!(r.algorithm, Policy::Lfp | Policy::Oracle) {
        assert!(m.frames.is_empty() && m.bytes.is_empty(), "{what}: no radio");
        // Every robot moves, and turns to its first move; no more than an edge a round.
        assert!(m.rotations.iter().all(|&t| t >= 1 && t <= r.rounds), "{what}: {:?}", m.rotations);
        assert!(m.distance_m.iter().all(|&d| d > 0.0 && d <= a * r.rounds as f64 + 1e-9), "{what}");
    } else {
        let moves = r.protocol.moves as f64;
        assert!(distance >= moves * a - 1e-9, "{what}: {distance} m for {moves} moves");
        if r.collisions == 0 {
            assert!((distance - moves * a).abs() < 1e-9, "{what}: no back-off, a leg a move");
        }
        assert!(turns as f64 <= moves && turns >= 1, "{what}: {turns} turns, {moves} moves");
        assert_eq!(m.frames.len(), r.robots, "{what}");
        assert_eq!(m.frames.iter().sum::<u64>(), r.protocol.frames, "{what}");
        // A map a robot a slot, of a few hundred vertices: a byte each at least.
        let bytes: u64 = m.bytes.iter().sum();
        assert!(bytes > r.protocol.frames * 10, "{what}: {bytes} bytes for {} frames", r.protocol.frames);
        assert!(m.frames.iter().all(|&f| f >= r.rounds as u64 / 2), "{what}: a map a slot, {:?}", m.frames);
    }
}

#[test]
fn every_policy_measures_its_run_plausibly() {
    let s = Scenario::load("paper").unwrap();
    let world = s.world();
    let all = s.start_vertices(&world, 13).unwrap();
    for policy in [Policy::Lfp, Policy::Ru, Policy::Sequential, Policy::Repulsive, Policy::Oracle] {
        for robots in [1, 5, 13] {
            for seed in 0..3 {
                let r = run(&world, &all[..robots], policy, seed, Situation::One);
                assert!(r.complete);
                check(&world, &r);
            }
        }
    }
}

/// In situation 1 a lone robot ends the search when it finds the last
/// target: the grid policies at the end of that slot's exchange, LFP and
/// the oracle at once. (In a team the robot that finds it may not yet know
/// the others' finds, so the search may end later.)
#[test]
fn the_last_target_ends_the_search_in_situation_one() {
    let s = Scenario::load("paper").unwrap();
    let world = s.world();
    let all = s.start_vertices(&world, 13).unwrap();
    for policy in [Policy::Repulsive, Policy::Sequential, Policy::Ru, Policy::Lfp, Policy::Oracle] {
        for seed in 0..5 {
            let r = run(&world, &all[..1], policy, seed, Situation::One);
            let last = *r.metrics.targets_s.last().expect("targets found");
            assert_eq!(r.metrics.targets_s.len(), r.targets_total);
            let slack = r.search_time_s - last;
            // A grid robot senses at the slot's start and stops at its exchange's end.
            let wait = if policy.on_grid() { world.params.t_exchange } else { 0.0 };
            assert!(
                (slack - wait).abs() < 1e-6,
                "{policy} seed={seed}: last target at {last}, search {}",
                r.search_time_s
            );
        }
    }
}

/// Coverage is measured only when asked for, and measuring it changes nothing else.
#[test]
fn measuring_changes_no_run() {
    let s = Scenario::load("paper").unwrap();
    let world = s.world();
    let all = s.start_vertices(&world, 13).unwrap();
    for policy in [Policy::Lfp, Policy::Ru, Policy::Repulsive, Policy::Oracle] {
        let mut cfg = RunConfig::new(policy, 4, Situation::One);
        let with = engine::run(&world, &all[..6], &cfg);
        cfg.measure_coverage = false;
        let without = engine::run(&world, &all[..6], &cfg);
        assert!(without.coverage.is_none() && without.metrics.coverage_s.is_empty());
        assert_eq!(with.trajectories, without.trajectories, "{policy}");
        assert_eq!(with.search_time_s, without.search_time_s, "{policy}");
        assert_eq!(
            (with.metrics.targets_s.clone(), with.metrics.distance_m.clone(), with.metrics.bytes.clone()),
            (without.metrics.targets_s, without.metrics.distance_m, without.metrics.bytes)
        );
    }
}
