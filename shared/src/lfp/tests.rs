//! LFP's behaviour: determinism, clearance, stop rules, collisions.

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
    assert!(r.search_time_s >= lo - 1e-9 && r.search_time_s <= hi + 1e-9, "{} not in [{lo}, {hi}]", r.search_time_s);
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
    let lo = 200.0 * (p.t_choice + p.t_trans) + p.collision_penalty(r.collisions);
    assert!(r.search_time_s >= lo - 1e-9);
    // The potential field makes them rarer.
    let fielded = run(&w, &starts, &c, &LfpParams::default());
    assert!(fielded.collisions < r.collisions, "{} vs {}", fielded.collisions, r.collisions);
}

#[test]
fn a_pair_still_in_contact_is_charged_once_per_event() {
    // Blind robots crowded in a small box: pairs stay in contact across
    // rounds. The reading changes the count, never the motion.
    let box_with = |ru_collisions| {
        let params = Params { ru_collisions, ..Params::default() };
        World::new(rect(0.0, 0.0, 4.0, 4.0), vec![], vec![Point::new(100.0, 100.0)], params, LatticeKind::Triangular)
    };
    let (events, pairs) = (box_with(RuCollisions::PerEvent), box_with(RuCollisions::PerPair));
    let starts = border_starts(&events, 9);
    let blind = LfpParams { k_robot: 0.0, ..LfpParams::default() };
    let c = RunConfig { max_rounds: 200, ..cfg(3, Situation::One) };
    let (e, p) = (run(&events, &starts, &c, &blind), run(&pairs, &starts, &c, &blind));
    assert_eq!(e.trajectories, p.trajectories);
    assert!(0 < e.collisions && e.collisions < p.collisions, "events {}, pairs {}", e.collisions, p.collisions);
    let move_time = Params::default().move_time();
    let charged = |r: &RunResult| r.search_time_s - r.collisions as f64 * move_time;
    assert!((charged(&e) - charged(&p)).abs() < 1e-6, "only the charge differs");
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
    let count = |lfp: &LfpParams| (0..30).map(|s| run(&w, &starts, &quiet(s), lfp).collisions).sum::<u32>();
    let blind = count(&LfpParams { k_robot: 0.0, ..LfpParams::default() });
    // Sensing each other only by sonar (1.3 m), robots closing at up to
    // 2a a round meet about once a run; by radio (2.05 m) rarely.
    let sonar = count(&LfpParams::default());
    let radio = count(&LfpParams { repel_range: RepelRange::Radio, ..LfpParams::default() });
    eprintln!("collisions in 30 runs of 13 robots: blind {blind}, sonar {sonar}, radio {radio}");
    assert!(
        sonar <= 45 && radio <= 15 && radio < sonar && 5 * sonar < blind,
        "blind {blind}, sonar {sonar}, radio {radio}"
    );
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
    let p: LfpParams = serde_json::from_str(r#"{"turn_sigma": 0.5, "repel_range": "radio"}"#).unwrap();
    assert_eq!((p.turn, p.repel_range), (Turn::Sigma(0.5), RepelRange::Radio));
    let p: LfpParams = serde_json::from_str(r#"{"turn": "uniform"}"#).unwrap();
    assert_eq!(p.turn, Turn::Uniform);
    let e = serde_json::from_str::<LfpParams>(r#"{"turn": "normal"}"#).unwrap_err().to_string();
    assert!(e.contains("\"uniform\" or a turn sigma"), "{e}");
    assert!(serde_json::from_str::<LfpParams>(r#"{"repel_range": "wifi"}"#).is_err());
    // What is written reads back.
    for turn in [Turn::Uniform, Turn::Sigma(0.25)] {
        let p = LfpParams { turn, ..LfpParams::default() };
        assert_eq!(serde_json::from_str::<LfpParams>(&serde_json::to_string(&p).unwrap()).unwrap(), p);
    }
    let d: LfpParams = serde_json::from_str("{}").unwrap();
    assert_eq!(d, LfpParams::default());
}

/// Mean cosine of the angle between consecutive flights' headings, in open space.
fn mean_turn_cos(turn: Turn) -> f64 {
    use rand::SeedableRng;
    let lfp = LfpParams { turn, ..LfpParams::default() };
    let levy = Mantegna::new(lfp.beta);
    let mut r = Robot::new(ChaCha8Rng::seed_from_u64(11));
    new_flight(&mut r, Vector::zeros(), &levy, &lfp, 1.0);
    let n = 20_000;
    let mut sum = 0.0;
    for _ in 0..n {
        let before = r.heading;
        new_flight(&mut r, Vector::zeros(), &levy, &lfp, 1.0);
        assert!((r.heading.norm() - 1.0).abs() < 1e-9);
        sum += before.dot(&r.heading);
    }
    sum / n as f64
}

#[test]
fn uniform_turning_forgets_the_last_heading() {
    // Independent uniform headings: E[cos] = 0, sd 0.005 over 20,000 flights.
    let uniform = mean_turn_cos(Turn::Uniform);
    assert!(uniform.abs() < 0.03, "{uniform}");
    // The correlated walk keeps it: E[cos] = exp(-sigma^2 / 2) = 0.88 at 0.5.
    let walk = mean_turn_cos(Turn::Sigma(0.5));
    assert!((walk - (-0.125f64).exp()).abs() < 0.02, "{walk}");
}

#[test]
fn the_default_turn_is_the_standard_normal_and_keeps_the_stated_correlation() {
    // The rule docs/paper.md states: N(0, 1) in radians, so a flight's
    // heading keeps a mean cosine of exp(-1/2) = 0.61 with the last one
    // (sd about 0.003 over 20,000 flights), neither straight nor uniform.
    assert_eq!(LfpParams::default().turn, Turn::Sigma(1.0));
    let walk = mean_turn_cos(LfpParams::default().turn);
    assert!((walk - (-0.5f64).exp()).abs() < 0.02, "{walk}");
}

#[test]
fn robots_repel_within_sonar_range_by_default() {
    let p = Params::default();
    assert!(p.r_so < p.r_c);
    let d = (p.r_so + p.r_c) / 2.0;
    let pos = [Point::new(0.0, 0.0), Point::new(d, 0.0), Point::new(0.0, p.r_so / 2.0)];
    let sonar = Repulsion { range: RepelRange::Sonar.range(&p), k: 1.0 };
    let radio = Repulsion { range: RepelRange::Radio.range(&p), k: 1.0 };
    let field = |r: &Repulsion, pos: &[Point]| {
        let mut f = Vec::new();
        r.fields(pos, &mut f);
        f
    };
    // Robot 1 is out of sonar range of robot 0 but within radio range.
    assert_eq!(field(&sonar, &pos[..2]), [Vector::zeros(); 2]);
    let far = field(&radio, &pos[..2]);
    assert!(far[0].x < 0.0 && far[0].y == 0.0, "pushed away from robot 1: {:?}", far[0]);
    assert_eq!(far[1], -far[0], "and robot 1 from robot 0, as hard");
    // Robot 2 is within both: pushed down, away from it.
    assert!(field(&sonar, &pos)[0].y < 0.0);
    // The default run differs from the radio reading when robots meet.
    let w = paper_like();
    let starts = border_starts(&w, 8);
    let a = run(&w, &starts, &quiet(4), &LfpParams::default());
    let b = run(&w, &starts, &quiet(4), &LfpParams { repel_range: RepelRange::Radio, ..LfpParams::default() });
    assert_ne!(a.search_time_s, b.search_time_s);
}

#[test]
fn sensing_skips_only_features_that_cannot_matter() {
    let world = paper_like();
    let p = world.params.clone();
    let s = Sensing::new(&world);
    let mut compared = 0;
    for yi in 0..124 {
        for xi in 0..155 {
            let at = Point::new(0.13 * xi as f64, 0.13 * yi as f64);
            let (f_all, n_all) = s.sense(at, p.r_so, 1.0, f64::INFINITY);
            for care in [0.0, p.r_safe + p.a / 8.0, p.r_safe + p.a] {
                let (f, n) = s.sense(at, p.r_so, 1.0, care);
                assert_eq!(f, f_all, "the same push at {at:?}, bit for bit");
                for t in [care, care / 2.0, p.r_safe] {
                    if t <= care {
                        assert_eq!(n >= t, n_all >= t, "the same clearance answer at {at:?} for {t}");
                        compared += (n_all < t) as u32;
                    }
                }
            }
        }
    }
    assert!(compared > 100, "points near features were tested: {compared}");
}

#[test]
fn one_pass_over_pairs_finds_every_near_pair() {
    let p = Params::default();
    let mut rng = rng::robot_rng(7, 0);
    let pos: Vec<Point> = (0..13).map(|_| Point::new(rng.random::<f64>() * 5.0, rng.random::<f64>() * 4.0)).collect();
    let repel = Repulsion { range: RepelRange::Sonar.range(&p), k: 1.0 };
    let near2 = 1.2f64.powi(2);
    let (mut fields, mut near) = (Vec::new(), Vec::new());
    repel.fields_and_near(&pos, &mut fields, near2, &mut near);
    let mut expected = Vec::new();
    let mut pair = 0;
    for i in 0..pos.len() {
        for j in i + 1..pos.len() {
            if (pos[i] - pos[j]).norm_squared() <= near2 {
                expected.push((i as u32, j as u32, pair));
            }
            pair += 1;
        }
    }
    assert!(!expected.is_empty() && expected.len() < 78, "some pairs near, not all: {}", expected.len());
    assert_eq!(near, expected);
    let mut alone = Vec::new();
    repel.fields(&pos, &mut alone);
    assert_eq!(fields, alone, "the pushes do not depend on the pairs asked for");
    // No repulsion still lists the pairs.
    Repulsion { range: 0.0, k: 0.0 }.fields_and_near(&pos, &mut fields, near2, &mut near);
    assert_eq!(near, expected);
    assert!(fields.iter().all(|f| *f == Vector::zeros()));
}
