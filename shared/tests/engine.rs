//! Engine properties on hand-made worlds: no collisions for the
//! collision-free policies, termination, reproducibility.

use gridswarm::engine;
use gridswarm::geometry::{Circle, Point, Polygon, Shape};
use gridswarm::grid::VertexId;
use gridswarm::lattice::LatticeKind;
use gridswarm::outcome::RunConfig;
use gridswarm::params::{Params, Situation};
use gridswarm::policy::Policy;
use gridswarm::world::World;

fn small_world() -> World {
    let area =
        Polygon::new(vec![Point::new(0.0, 0.0), Point::new(12.0, 0.0), Point::new(12.0, 9.0), Point::new(0.0, 9.0)]);
    let obstacles = vec![
        Shape::Circle(Circle { center: Point::new(6.0, 4.5), radius: 1.2 }),
        Shape::Polygon(Polygon::new(vec![Point::new(2.0, 6.0), Point::new(4.0, 6.0), Point::new(3.0, 7.5)])),
    ];
    let targets = vec![Point::new(2.0, 2.0), Point::new(10.0, 2.0), Point::new(10.0, 7.5), Point::new(1.5, 8.0)];
    World::new(area, obstacles, targets, Params::default(), LatticeKind::Triangular)
}

fn starts(world: &World, n: usize) -> Vec<VertexId> {
    // A row of neighbouring vertices along the bottom border.
    let mut v: Vec<VertexId> = world.accessible_vertices().filter(|&v| world.grid.position(v).y < 1.0).collect();
    v.truncate(n);
    assert_eq!(v.len(), n);
    v
}

#[test]
fn collision_free_policies_never_collide_and_finish() {
    let world = small_world();
    for policy in [Policy::Repulsive, Policy::Sequential, Policy::Escape] {
        for situation in [Situation::One, Situation::Two] {
            for robots in [1, 3, 7, 10] {
                for seed in 0..30 {
                    let mut cfg = RunConfig::new(policy, seed, situation);
                    cfg.max_rounds = 20_000;
                    cfg.record_trajectories = false;
                    cfg.measure_coverage = false;
                    let r = engine::run(&world, &starts(&world, robots), &cfg);
                    assert_eq!(r.collisions, 0, "{policy} {situation:?} n={robots} seed={seed}");
                    assert!(r.complete, "{policy} {situation:?} n={robots} seed={seed}: {r:?}");
                }
            }
        }
    }
}

#[test]
fn ru_finishes_and_counts_collisions() {
    let world = small_world();
    let mut total = 0;
    for seed in 0..50 {
        let cfg = RunConfig::new(Policy::Ru, seed, Situation::One);
        let r = engine::run(&world, &starts(&world, 10), &cfg);
        assert!(r.complete);
        total += r.collisions;
    }
    assert!(total > 0, "ten particles on a small map should collide sometimes");
}

#[test]
fn same_seed_same_trajectories() {
    let world = small_world();
    let cfg = RunConfig::new(Policy::Repulsive, 7, Situation::One);
    let a = engine::run(&world, &starts(&world, 5), &cfg);
    let b = engine::run(&world, &starts(&world, 5), &cfg);
    assert_eq!(a.trajectories, b.trajectories);
    let c = engine::run(&world, &starts(&world, 5), &RunConfig::new(Policy::Repulsive, 8, Situation::One));
    assert_ne!(a.trajectories, c.trajectories);
}

#[test]
fn print_some_runs() {
    let world = small_world();
    for policy in [Policy::Repulsive, Policy::Sequential, Policy::Ru, Policy::Escape] {
        for n in [1, 5, 10] {
            let mut cfg = RunConfig::new(policy, 3, Situation::One);
            cfg.record_trajectories = false;
            let r = engine::run(&world, &starts(&world, n), &cfg);
            println!(
                "{policy} n={n} rounds={} t={:.1} found={}/{} coll={} cov={:?} complete={}",
                r.rounds, r.search_time_s, r.targets_found, r.targets_total, r.collisions, r.coverage, r.complete
            );
        }
    }
}

/// Target ids are 32-bit: with more than 65,535 targets every one is still
/// detectable (a 16-bit id once made target 65,536 alias target 0, and the
/// run never completed).
#[test]
fn more_than_65535_targets_are_all_found() {
    let area =
        Polygon::new(vec![Point::new(0.0, 0.0), Point::new(6.0, 0.0), Point::new(6.0, 5.0), Point::new(0.0, 5.0)]);
    let n = 65_537;
    // A dense spiral of distinct points over the area's middle.
    let targets: Vec<Point> = (0..n)
        .map(|k| {
            let f = k as f64 / n as f64;
            let a = k as f64 * 0.618_033_988_75 * std::f64::consts::TAU;
            Point::new(3.0 + 1.8 * f.sqrt() * a.cos(), 2.5 + 1.8 * f.sqrt() * a.sin())
        })
        .collect();
    let world = World::new(area, vec![], targets, Params::default(), LatticeKind::Triangular);
    let s = starts(&world, 2);
    for policy in [Policy::Repulsive, Policy::Lfp] {
        let r = engine::run(&world, &s, &RunConfig::new(policy, 3, Situation::One));
        assert_eq!((r.targets_total, r.targets_found), (n, n), "{policy}");
        assert!(r.complete, "{policy}: {} rounds, ended by {}", r.rounds, r.protocol.ended_by);
    }
}

/// One robot: RU, (1)&(3) and (1),(2)&(3) choose alike (unvisited first,
/// uniformly, from the same stream), so they must be the same run, to the
/// microsecond: the claims skip the count where they coincide run for run.
/// RU's first round once lasted 1 s less, the fresh listen being skipped.
#[test]
fn a_lone_robot_is_the_same_run_under_ru_and_the_sequential_rules() {
    let world = small_world();
    for seed in 0..20 {
        let runs: Vec<_> = [Policy::Ru, Policy::Sequential, Policy::Repulsive]
            .into_iter()
            .map(|p| {
                let r = engine::run(&world, &starts(&world, 1), &RunConfig::new(p, seed, Situation::One));
                (r.round_end_times_s, r.trajectories, r.search_time_s)
            })
            .collect();
        assert_eq!(runs[0], runs[1], "RU and (1)&(3), seed {seed}");
        assert_eq!(runs[1], runs[2], "(1)&(3) and (1),(2)&(3), seed {seed}");
    }
}
