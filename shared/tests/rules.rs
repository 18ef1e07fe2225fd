//! Rules (1) and (2), the waiting of step 5, the other choice rules
//! (escape, frontier, a registered one) and the choices-update-maps
//! reading on hand-made situations, driving one robot's decision core
//! directly.

use std::collections::BTreeSet;

use gridswarm::choice::{self, registry, ChoiceRule, RuleRng, View};
use gridswarm::geometry::{Point, Polygon};
use gridswarm::grid::{Grid, VertexId};
use gridswarm::lattice::{Coord, LatticeKind};
use gridswarm::map::Map;
use gridswarm::params::{Params, Situation};
use gridswarm::policy::Policy;
use gridswarm::robot::{Robot, RobotConfig, Sensing};
use gridswarm::world::World;

const ALL_OPEN: u8 = 0b11_1111;

fn world() -> World {
    let area = Polygon::new(vec![
        Point::new(-10.0, -10.0),
        Point::new(10.0, -10.0),
        Point::new(10.0, 10.0),
        Point::new(-10.0, 10.0),
    ]);
    World::new(area, vec![], vec![], Params::default(), LatticeKind::Triangular)
}

fn at(grid: &Grid, i: i32, j: i32) -> VertexId {
    grid.id_of(Coord::new(i, j)).unwrap()
}

fn robot(grid: &Grid, policy: Policy, seed: u64, id: u16, v: VertexId) -> Robot<'_> {
    Robot::new(grid, RobotConfig::new(id, policy, Situation::Two, 0, 0.3, seed), v)
}

/// The neighbour of `v` in slot `d`.
fn slot(grid: &Grid, v: VertexId, d: usize) -> VertexId {
    grid.neighbors(v)[d]
}

fn visited_map(grid: &Grid, vs: &[VertexId]) -> Map {
    let mut m = Map::new(grid.len());
    for &v in vs {
        m.record_sensing(grid, v, ALL_OPEN);
    }
    m
}

#[test]
fn rule_1_prefers_unvisited_uniformly() {
    let w = world();
    let g = &w.grid;
    let v = at(g, 0, 0);
    // Slots 0, 1 and 2 visited by someone (robot 9, a neighbour this round).
    let visited: Vec<_> = (0..3).map(|d| slot(g, v, d)).collect();
    let mut seen = BTreeSet::new();
    let mut m = visited_map(g, &visited);
    m.set_visited(v, true);
    for seed in 0..200 {
        // (1)&(3) uses rule (1) whatever its neighbours; robot 9 only brings the map.
        let mut r = robot(g, Policy::Sequential, seed, 0, v);
        r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
        assert!(r.receive_map(9, at(g, -8, 0), &m, false));
        let c = r.choose().unwrap();
        assert!(!visited.contains(&c) && c != v, "seed {seed}: chose visited {c}");
        seen.insert(c);
    }
    let unvisited: BTreeSet<_> = (3..6).map(|d| slot(g, v, d)).collect();
    assert_eq!(seen, unvisited, "every unvisited candidate is drawn");
}

#[test]
fn rule_1_falls_back_to_visited_then_stays() {
    let w = world();
    let g = &w.grid;
    let v = at(g, 0, 0);
    let around: Vec<_> = (0..6).map(|d| slot(g, v, d)).collect();
    let m = visited_map(g, &around);
    let mut seen = BTreeSet::new();
    for seed in 0..100 {
        let mut r = robot(g, Policy::Sequential, seed, 0, v);
        // Only slots 0 and 4 are open.
        r.sense(0, &Sensing { open: 0b01_0001, occupied: 0, targets: &[] });
        r.receive_map(9, at(g, -8, 0), &m, false);
        seen.insert(r.choose().unwrap());
    }
    assert_eq!(seen, [slot(g, v, 0), slot(g, v, 4)].into_iter().collect());
    let mut r = robot(g, Policy::Sequential, 1, 0, v);
    r.sense(0, &Sensing { open: 0, occupied: 0, targets: &[] });
    assert_eq!(r.choose(), Some(v), "no candidates: stay");
}

#[test]
fn rule_2_moves_away_from_the_mean() {
    let w = world();
    let g = &w.grid;
    let v = at(g, 0, 0);
    // A lower-priority neighbour two steps to the left: the farthest unvisited
    // candidate from it is the right-hand vertex, uniquely.
    for seed in 0..50 {
        let mut r = robot(g, Policy::Repulsive, seed, 0, v);
        r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
        r.receive_map(1, at(g, -2, 0), &Map::new(g.len()), false);
        assert!(r.ready(), "a lower-priority neighbour is not waited for");
        assert_eq!(r.choose(), Some(at(g, 1, 0)));
    }
    // A higher-priority neighbour two steps right that stays: go left.
    let mut r = robot(g, Policy::Repulsive, 3, 0, v);
    r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
    r.receive_map(1, at(g, 2, 0), &Map::new(g.len()), false);
    assert!(!r.ready(), "waits for the higher-priority neighbour");
    assert_eq!(r.choose(), None);
    r.receive_choice(1, at(g, 2, 0), at(g, 2, 0));
    assert_eq!(r.choose(), Some(at(g, -1, 0)));
}

#[test]
fn rule_2_ties_are_drawn_uniformly() {
    let w = world();
    let g = &w.grid;
    let v = at(g, 0, 0);
    // Neighbour straight above at two rows: the two lower vertices tie.
    let mut seen = BTreeSet::new();
    for seed in 0..100 {
        let mut r = robot(g, Policy::Repulsive, seed, 0, v);
        r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
        r.receive_map(1, at(g, -1, 2), &Map::new(g.len()), false);
        r.receive_choice(1, at(g, -1, 2), at(g, -1, 2));
        seen.insert(r.choose().unwrap());
    }
    assert_eq!(seen, [at(g, 0, -1), at(g, 1, -1)].into_iter().collect());
}

#[test]
fn earlier_choices_exclude_vertices_and_colliding_moves() {
    let w = world();
    let g = &w.grid;
    let v = at(g, 0, 0);
    let j_at = at(g, 1, 0); // adjacent, higher priority
    let j_to = at(g, 0, 1); // turns 120 degrees into i's slot 1
    let left = at(g, -1, 0); // lower-priority neighbour
    for seed in 0..100 {
        let mut r = robot(g, Policy::Sequential, seed, 0, v);
        r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0b00_1001, targets: &[] });
        r.receive_map(1, j_at, &Map::new(g.len()), false);
        r.receive_map(2, left, &Map::new(g.len()), false);
        r.receive_choice(1, j_at, j_to);
        let c = r.choose().unwrap();
        assert_ne!(c, j_to, "chosen by an earlier robot");
        assert_ne!(c, j_at, "following a 120-degree turn collides");
        assert_ne!(c, left, "held by a robot that has not chosen");
    }
    // Following straight on into the vacated vertex is allowed.
    let mut ok = false;
    for seed in 0..100 {
        let mut r = robot(g, Policy::Sequential, seed, 0, v);
        r.sense(0, &Sensing { open: 0b00_0001, occupied: 0b00_0001, targets: &[] });
        r.receive_map(1, j_at, &Map::new(g.len()), false);
        r.receive_choice(1, j_at, at(g, 2, 0));
        ok |= r.choose() == Some(j_at);
    }
    assert!(ok);
}

#[test]
fn a_failed_neighbour_is_not_waited_for_and_stays_blocked() {
    let w = world();
    let g = &w.grid;
    let v = at(g, 0, 0);
    let j_at = at(g, 1, 0);
    for seed in 0..50 {
        let mut r = robot(g, Policy::Repulsive, seed, 0, v);
        r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0b00_0001, targets: &[] });
        r.receive_map(1, j_at, &Map::new(g.len()), false);
        assert!(!r.ready(), "waits for the higher-priority neighbour's choice");
        r.declare_failed(1, j_at, 0);
        assert!(r.ready());
        let c = r.choose().unwrap();
        assert_ne!(c, j_at);
        assert!(r.map().is_failed(1), "the failure goes out with the map");
    }
}

#[test]
fn arrival_order_does_not_matter() {
    let w = world();
    let g = &w.grid;
    let v = at(g, 0, 0);
    let m1 = visited_map(g, &[at(g, 1, 1), at(g, 0, 1)]);
    let m2 = visited_map(g, &[at(g, -1, -1)]);
    for seed in 0..50 {
        let run = |first: bool| {
            let mut r = robot(g, Policy::Repulsive, seed, 0, v);
            r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
            if first {
                r.receive_map(1, at(g, 2, 0), &m1, false);
                r.receive_map(2, at(g, -2, 1), &m2, false);
            } else {
                r.receive_map(2, at(g, -2, 1), &m2, false);
                r.receive_map(1, at(g, 2, 0), &m1, false);
            }
            r.receive_choice(1, at(g, 2, 0), at(g, 2, -1));
            (r.choose(), r.map().clone())
        };
        assert_eq!(run(true), run(false));
    }
}

#[test]
fn maps_from_itself_or_off_the_grid_have_no_effect() {
    let w = world();
    let g = &w.grid;
    let v = at(g, 0, 0);
    let mut r = robot(g, Policy::Repulsive, 1, 0, v);
    r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
    let before = r.map().clone();
    assert!(!r.receive_map(0, at(g, 1, 0), &visited_map(g, &[at(g, 3, 3)]), false));
    assert!(!r.receive_map(5, g.len() as VertexId, &visited_map(g, &[at(g, 3, 3)]), false));
    assert!(!r.receive_choice(5, at(g, 1, 1), g.len() as VertexId));
    assert_eq!(r.map(), &before);
    assert!(r.ready(), "nobody heard, nobody waited for");
}

#[test]
fn a_halted_neighbour_is_not_waited_for_and_never_vacates() {
    let w = world();
    let g = &w.grid;
    let v = at(g, 0, 0);
    let j_at = at(g, 1, 0);
    for seed in 0..50 {
        let mut r = robot(g, Policy::Repulsive, seed, 0, v);
        r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0b00_0001, targets: &[] });
        r.receive_map(1, j_at, &Map::new(g.len()), true);
        assert!(r.ready());
        assert_ne!(r.choose(), Some(j_at));
    }
}

/// A map in which robots stood on `stood` and sensed only the edges
/// between listed vertices (`edges`, both ways).
fn corridor_map(grid: &Grid, stood: &[VertexId], edges: &[(VertexId, VertexId)]) -> Map {
    let mut m = Map::new(grid.len());
    for &v in stood {
        let mut open = 0u8;
        for &(a, b) in edges {
            let other = if a == v {
                b
            } else if b == v {
                a
            } else {
                continue;
            };
            open |= 1 << grid.slot_of(v, other).unwrap();
        }
        m.record_sensing(grid, v, open);
    }
    m
}

/// The open mask of `v` for the edges to `to`.
fn open_to(grid: &Grid, v: VertexId, to: &[VertexId]) -> u8 {
    to.iter().fold(0, |m, &t| m | 1 << grid.slot_of(v, t).unwrap())
}

/// A straight corridor along j = 0 from `lo` to `hi`, visited from
/// `lo + 1` to `hi - 1`: its two ends are the only unvisited vertices.
fn straight(g: &Grid, lo: i32, hi: i32) -> Map {
    let stood: Vec<_> = (lo + 1..hi).map(|i| at(g, i, 0)).collect();
    let edges: Vec<_> = (lo..hi).map(|i| (at(g, i, 0), at(g, i + 1, 0))).collect();
    corridor_map(g, &stood, &edges)
}

#[test]
fn escape_and_frontier_head_for_the_nearest_unvisited_vertex() {
    let w = world();
    let g = &w.grid;
    let v = at(g, 0, 0);
    // Ends at (3, 0) and (-5, 0): the right one is nearer.
    let m = straight(g, -5, 3);
    for policy in [Policy::Escape, Policy::Frontier] {
        for seed in 0..30 {
            let mut r = robot(g, policy, seed, 0, v);
            r.sense(0, &Sensing { open: open_to(g, v, &[at(g, 1, 0), at(g, -1, 0)]), occupied: 0, targets: &[] });
            r.receive_map(9, at(g, -8, 3), &m, false);
            assert_eq!(r.choose(), Some(at(g, 1, 0)), "{policy} seed {seed}");
        }
    }
}

#[test]
fn nearest_ties_are_drawn_at_random_and_escape_keeps_its_target() {
    let w = world();
    let g = &w.grid;
    let v = at(g, 0, 0);
    // Ends at (3, 0) and (-3, 0), equally near.
    let m = straight(g, -3, 3);
    let open = open_to(g, v, &[at(g, 1, 0), at(g, -1, 0)]);
    for policy in [Policy::Escape, Policy::Frontier] {
        let mut seen = BTreeSet::new();
        for seed in 0..40 {
            let mut r = robot(g, policy, seed, 0, v);
            r.sense(0, &Sensing { open, occupied: 0, targets: &[] });
            // From a robot that stopped: no searching neighbour to spread from.
            r.receive_map(9, at(g, -8, 3), &m, true);
            let first = r.choose().unwrap();
            seen.insert(first);
            if policy == Policy::Escape {
                // It did not get to move: the next rounds it heads the same way.
                for round in 1..4 {
                    r.sense(round, &Sensing { open, occupied: 0, targets: &[] });
                    assert_eq!(r.choose(), Some(first), "seed {seed} round {round}: the target is kept");
                }
            }
        }
        assert_eq!(seen, [at(g, 1, 0), at(g, -1, 0)].into_iter().collect(), "{policy}: no side is favoured");
    }
}

#[test]
fn escape_takes_another_shortest_path_when_the_first_step_is_blocked() {
    let w = world();
    let g = &w.grid;
    let (v, right, up, left, goal) = (at(g, 0, 0), at(g, 1, 0), at(g, 0, 1), at(g, -1, 0), at(g, 1, 1));
    // (1, 1) is the one unvisited vertex, two steps away through (1, 0) or (0, 1).
    let m = corridor_map(g, &[v, right, up, left], &[(v, right), (v, up), (v, left), (right, goal), (up, goal)]);
    for seed in 0..40 {
        let mut r = robot(g, Policy::Escape, seed, 0, v);
        r.sense(
            0,
            &Sensing { open: open_to(g, v, &[right, up, left]), occupied: open_to(g, v, &[right]), targets: &[] },
        );
        r.receive_map(1, right, &m, false);
        // The higher-priority robot on (1, 0) stays there.
        r.receive_choice(1, right, right);
        // Rule (2) would go left, away from it; the other shortest path goes up.
        assert_eq!(r.choose(), Some(up), "seed {seed}");
    }
}

/// A claim dropped takes back only what the claim added: a map merged
/// after it that sensed an open edge into the claimed vertex keeps it
/// known, and the sender's next map, merged after the drop, agrees.
#[test]
fn a_claim_dropped_keeps_what_a_map_merged_over_it_sensed() {
    let w = world();
    let g = &w.grid;
    let (v, j_at, j_to, t_at) = (at(g, 0, 0), at(g, 2, 0), at(g, 3, 0), at(g, 4, 0));
    let mut t = Map::new(g.len());
    t.record_sensing(g, t_at, ALL_OPEN);
    let mut r = robot(g, Policy::Sequential, 1, 0, v);
    r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
    r.receive_choice(1, j_at, j_to);
    // Late, after the claim: robot 2's map, which knows j_to.
    r.receive_map(2, t_at, &t.send_copy(0, None), false);
    r.sense(1, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
    assert!(r.map().known(j_to) && !r.map().visited(j_to), "the dropped claim took back only the visit");
    let next = t.send_copy(1, None);
    assert_eq!((next.base, next.cells().changes()), (Some(0), 0), "nothing changed since");
    r.receive_map(2, t_at, &next, false);
    assert!(r.map().known(j_to) && !r.map().visited(j_to), "robot 2's next map agrees");
}

#[test]
fn a_heard_choice_marks_its_vertex_visited_for_the_round() {
    let w = world();
    let g = &w.grid;
    let v = at(g, 0, 0);
    let (j_at, j_to) = (at(g, 2, 0), at(g, 3, 0));
    for on in [true, false] {
        let mut cfg = RobotConfig::new(0, Policy::Sequential, Situation::Two, 0, 0.3, 1);
        cfg.choices_update_maps = on;
        let mut r = Robot::new(g, cfg, v);
        r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
        r.receive_map(1, j_at, &Map::new(g.len()), false);
        r.receive_choice(1, j_at, j_to);
        assert_eq!(r.map().visited(j_to), on, "marked only with the reading on");
        r.choose().unwrap();
        // Next round: nobody sensed there (the chooser's map has not come),
        // so the claim is dropped and the vertex is unvisited again.
        r.sense(1, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
        assert!(!r.map().visited(j_to));
        assert!(!r.map().known(j_to), "it was not known before the claim");
    }
    // A claim the chooser's own map confirms within the round stays.
    let mut r = robot(g, Policy::Sequential, 1, 0, v);
    r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
    r.receive_choice(1, j_at, j_to);
    r.receive_map(1, j_at, &visited_map(g, &[j_to]), false);
    r.sense(1, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
    assert!(r.map().visited(j_to));
    // RU exchanges no choices: nothing to mark.
    let mut r = robot(g, Policy::Ru, 1, 0, v);
    r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
    r.receive_choice(1, j_at, j_to);
    assert!(!r.map().visited(j_to));
}

/// A registered rule: always the last candidate.
struct Last;

impl ChoiceRule for Last {
    fn choose(&mut self, view: &View<'_>, _rng: &mut RuleRng) -> Option<VertexId> {
        view.candidates.last().copied()
    }
}

#[test]
fn a_registered_rule_is_a_policy_by_name() {
    let p = choice::register("last-candidate", || Box::new(Last)).unwrap();
    assert_eq!(p.name(), "last-candidate");
    assert_eq!("last-candidate".parse::<Policy>(), Ok(p));
    assert!(p.on_grid() && p.sequential() && p.collision_free());
    let json = serde_json::to_string(&p).unwrap();
    assert_eq!(json, "\"last-candidate\"");
    assert_eq!(serde_json::from_str::<Policy>(&json).unwrap(), p);
    let w = world();
    let g = &w.grid;
    let v = at(g, 0, 0);
    let mut r = robot(g, p, 1, 0, v);
    r.sense(0, &Sensing { open: 0b00_0110, occupied: 0, targets: &[] });
    assert_eq!(r.choose(), Some(slot(g, v, 2)), "the rule decides");

    for bad in ["escape", "Upper", "1st", "", "a b"] {
        assert!(choice::register(bad, || Box::new(Last)).is_err(), "`{bad}` accepted");
    }
    let err = "no-such-rule".parse::<Policy>().unwrap_err();
    assert!(
        err.contains("unknown algorithm `no-such-rule`") && err.contains("frontier") && err.contains("last-candidate"),
        "{err}"
    );
    // Read from a file, a name passes; only building its robots needs the rule.
    let far: Policy = serde_json::from_str("\"elsewhere\"").unwrap();
    assert_eq!(far.name(), "elsewhere");
    assert!(registry::runnable(far).unwrap_err().contains("not registered"));
    assert!(registry::runnable(Policy::Lfp).is_err());
    assert!(serde_json::from_str::<Policy>("\"Bad Name\"").is_err());
}
