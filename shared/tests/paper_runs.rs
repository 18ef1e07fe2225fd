//! The properties the issue asks of the policies, on the default `paper`
//! scenario across robot counts: the collision-free policies never collide
//! (at least 1,000 seeded runs each) and every policy ends within a bound.

use gridswarm::engine;
use gridswarm::outcome::RunConfig;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;

/// Far above any run seen (one robot needs a few hundred rounds on `paper`).
const BOUND: u32 = 20_000;

fn quick(policy: Policy, seed: u64, situation: Situation) -> RunConfig {
    let mut cfg = RunConfig::new(policy, seed, situation);
    cfg.max_rounds = BOUND;
    cfg.record_trajectories = false;
    cfg.measure_coverage = false;
    cfg
}

#[test]
fn collision_free_policies_never_collide_in_1000_runs() {
    let s = Scenario::load("paper").unwrap();
    let world = s.world();
    let all = s.start_vertices(&world, 13).unwrap();
    for policy in [Policy::Repulsive, Policy::Sequential, Policy::Escape] {
        let mut runs = 0;
        for robots in 1..=13 {
            for seed in 0..78 {
                let situation = if seed % 2 == 0 { Situation::One } else { Situation::Two };
                let r = engine::run(&world, &all[..robots], &quick(policy, seed, situation));
                assert_eq!(r.collisions, 0, "{policy} robots={robots} seed={seed} {situation:?}");
                assert!(r.complete && r.rounds < BOUND, "{policy} robots={robots} seed={seed} {situation:?}");
                runs += 1;
            }
        }
        assert!(runs >= 1000);
    }
}

#[test]
fn every_policy_terminates_within_the_bound() {
    let s = Scenario::load("paper").unwrap();
    let world = s.world();
    let all = s.start_vertices(&world, 13).unwrap();
    for policy in Policy::ALL {
        for robots in [1, 4, 9, 13] {
            for seed in 0..25 {
                let r = engine::run(&world, &all[..robots], &quick(policy, seed, Situation::One));
                assert!(r.complete, "{policy} robots={robots} seed={seed}: not done in {BOUND} rounds");
                assert_eq!(r.targets_found, r.targets_total);
            }
        }
    }
}

#[test]
fn situation_two_visits_every_vertex_of_va() {
    let s = Scenario::load("cave").unwrap();
    let world = s.world();
    let starts = s.start_vertices(&world, 5).unwrap();
    for policy in [Policy::Repulsive, Policy::Sequential, Policy::Escape, Policy::Ru] {
        let mut cfg = quick(policy, 3, Situation::Two);
        cfg.measure_coverage = true;
        let r = engine::run(&world, &starts, &cfg);
        assert!(r.complete, "{policy}");
        // Every vertex of Va visited means the whole of Ad is detected on the
        // triangular grid (the scenario's `coverage` assumption holds).
        assert!(r.coverage.unwrap() > 0.999, "{policy}: {:?}", r.coverage);
    }
}

#[test]
fn comb_loads_and_every_grid_rule_completes_it() {
    let s = Scenario::load("comb").unwrap();
    assert_eq!((s.name.as_str(), s.targets.len()), ("comb", 9));
    let world = s.world();
    let all = s.start_vertices(&world, 13).unwrap();
    for policy in (0..gridswarm::vopr::POLICIES.len()).map(gridswarm::vopr::policy) {
        for robots in [1, 5, 13] {
            for seed in 0..4 {
                let situation = if seed % 2 == 0 { Situation::One } else { Situation::Two };
                let mut cfg = quick(policy, seed, situation);
                cfg.measure_coverage = situation == Situation::Two;
                // The paper's random walk over visited vertices takes one
                // robot some 20,000 rounds out of the comb's teeth.
                cfg.max_rounds = 10 * BOUND;
                let r = engine::run(&world, &all[..robots], &cfg);
                let tag = format!("{policy} robots={robots} seed={seed} {situation:?}");
                assert!(r.complete, "{tag}");
                assert_eq!(r.targets_found, r.targets_total, "{tag}");
                if policy != Policy::Ru {
                    assert_eq!(r.collisions, 0, "{tag}");
                }
                if situation == Situation::Two {
                    assert!(r.coverage.unwrap() > 0.999, "{tag}: {:?}", r.coverage);
                }
            }
        }
    }
}

#[test]
fn the_named_frontier_rules_complete_on_every_lattice() {
    use gridswarm::lattice::LatticeKind;
    for grid in [LatticeKind::Triangular, LatticeKind::Square, LatticeKind::Hexagonal] {
        let mut s = Scenario::load("paper").unwrap();
        s.grid = grid;
        let world = s.world();
        let all = s.start_vertices(&world, 7).unwrap();
        for name in ["frontier-coord", "frontier-sensed", "frontier-sensed-coord"] {
            let policy: Policy = name.parse().unwrap();
            for seed in 0..4 {
                let situation = if seed % 2 == 0 { Situation::One } else { Situation::Two };
                let r = engine::run(&world, &all, &quick(policy, seed, situation));
                let tag = format!("{name} {grid:?} seed={seed} {situation:?}");
                assert!(r.complete && r.rounds < BOUND, "{tag}");
                assert_eq!(r.collisions, 0, "{tag}");
            }
        }
    }
}
