//! Rules (1) and (2) and the waiting of step 5 on hand-made situations,
//! driving one robot's decision core directly.

use std::collections::BTreeSet;

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
    let area = Polygon::new(vec![Point::new(-10.0, -10.0), Point::new(10.0, -10.0), Point::new(10.0, 10.0), Point::new(-10.0, 10.0)]);
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
    let mut m = Map::new(grid.len(), 0);
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
    m.visited.set(v as usize);
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
        r.receive_map(1, at(g, -2, 0), &Map::new(g.len(), 0), false);
        assert!(r.ready(), "a lower-priority neighbour is not waited for");
        assert_eq!(r.choose(), Some(at(g, 1, 0)));
    }
    // A higher-priority neighbour two steps right that stays: go left.
    let mut r = robot(g, Policy::Repulsive, 3, 0, v);
    r.sense(0, &Sensing { open: ALL_OPEN, occupied: 0, targets: &[] });
    r.receive_map(1, at(g, 2, 0), &Map::new(g.len(), 0), false);
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
        r.receive_map(1, at(g, -1, 2), &Map::new(g.len(), 0), false);
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
        r.receive_map(1, j_at, &Map::new(g.len(), 0), false);
        r.receive_map(2, left, &Map::new(g.len(), 0), false);
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
        r.receive_map(1, j_at, &Map::new(g.len(), 0), false);
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
        r.receive_map(1, j_at, &Map::new(g.len(), 0), false);
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
        r.receive_map(1, j_at, &Map::new(g.len(), 0), true);
        assert!(r.ready());
        assert_ne!(r.choose(), Some(j_at));
    }
}
