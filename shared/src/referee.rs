//! The bodies' side of a slot, for the world ([`crate::sim`]): where every
//! robot really is, what its sonar and laser report, executing all moves at
//! once and counting collisions. It never decides for a robot.
//!
//! Under the default collision reading ([`RuCollisions::PerEvent`]) a
//! collision is an event: a pair that meets is counted once, and robots
//! that end on one vertex stay there, uncharged until they have been
//! apart; under [`RuCollisions::PerPair`] such a pair is counted again
//! every round. Under [`RuCollisions::BackOff`] a collision is physical: robots that meet drive back to where they came
//! from, so the next slot's readings show them there; but of each group of
//! robots that met, one, drawn from the run's seed, gets through (it got
//! there first), or two RU robots with one unvisited vertex between them
//! would meet and back off forever. A robot whose
//! destination is taken by one backing off would meet it too, and backs off
//! as well (counted as one more collision). Robots that stand stacked on one
//! vertex (they started so) separate to free adjacent vertices. Backing off
//! and separating happen within the penalty's extra move time; their paths
//! are not checked against other robots' (the penalty is the model).

use crate::bitset::Bitset;
use crate::geometry::{swept_min_distance, Point};
use crate::grid::{VertexId, NONE};
use crate::lattice::Coord;
use crate::near::Cells;
use crate::params::RuCollisions;
use crate::world::World;

const EMPTY: u16 = u16::MAX;

/// The outcome of executing one round's moves.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RoundReport {
    /// Collisions counted: pairs of robots that came closer than `2 r_safe`
    /// or shared a vertex (under [`RuCollisions::PerEvent`], only pairs that
    /// started the round apart).
    pub collisions: u32,
    /// Moves refused because they were not along a traversable edge.
    pub refused: u32,
    /// Whether any robot had to rotate, and whether any translated.
    pub rotated: bool,
    pub translated: bool,
}

/// Ground truth of robot positions on the grid.
#[derive(Clone, Debug)]
pub struct Referee<'w> {
    world: &'w World,
    pos: Vec<VertexId>,
    heading: Vec<Option<(i32, i32)>>,
    /// A robot on each vertex (any one of them if several), or `EMPTY`.
    occupant: Vec<u16>,
    visited: Bitset,
    /// Vertices first visited by a move (the starts not counted).
    visits: usize,
    found: Bitset,
    /// Where each robot ends this round; kept to avoid allocating per round.
    target: Vec<VertexId>,
    /// Robots in a counted collision this round.
    involved: Vec<bool>,
    /// Robots ending on each vertex, while backing off (all zero between rounds).
    ending: Vec<u16>,
    /// The pairs counted this round.
    pairs: Vec<(u16, u16)>,
    /// Robots' start points this round, in cells of the reach within
    /// which two can meet (many robots: not every pair is looked at).
    starts: Vec<Point>,
    cells: Cells,
    /// Draws who gets through a collision.
    seed: u64,
    round: u64,
    /// Targets found so far, and each robot's legs driven (a move, a
    /// return when backing off, a step aside) and turns made, for the
    /// run's metrics.
    found_count: usize,
    legs: Vec<u32>,
    turns: Vec<u32>,
    /// Where each robot was headed before backing off, kept to avoid allocating.
    planned: Vec<VertexId>,
}

impl<'w> Referee<'w> {
    pub fn new(world: &'w World, starts: &[VertexId]) -> Self {
        let mut r = Referee {
            world,
            pos: starts.to_vec(),
            heading: vec![None; starts.len()],
            occupant: vec![EMPTY; world.grid.len()],
            visited: Bitset::new(world.grid.len()),
            visits: 0,
            found: Bitset::new(world.targets.len()),
            target: Vec::with_capacity(starts.len()),
            involved: vec![false; starts.len()],
            ending: Vec::new(),
            pairs: Vec::new(),
            starts: Vec::new(),
            cells: Cells::new(Self::reach(world)),
            seed: 0,
            round: 0,
            found_count: 0,
            legs: vec![0; starts.len()],
            turns: vec![0; starts.len()],
            planned: Vec::new(),
        };
        for (k, &v) in starts.iter().enumerate() {
            r.occupant[v as usize] = k as u16;
            r.visited.set(v as usize);
        }
        r
    }

    /// The referee of a run with this seed (who gets through a collision).
    pub fn seeded(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    pub fn positions(&self) -> &[VertexId] {
        &self.pos
    }

    pub fn position(&self, robot: usize) -> VertexId {
        self.pos[robot]
    }

    /// Vertices robots have stood on.
    pub fn visited(&self) -> &Bitset {
        &self.visited
    }

    /// How many vertices moves have visited first (the starts not counted).
    pub fn visits(&self) -> usize {
        self.visits
    }

    /// How many targets were found so far, by anyone.
    pub fn found_count(&self) -> usize {
        self.found_count
    }

    /// Each robot's legs driven so far, one edge each: its moves, a return
    /// to where it came from when it backed off, a step aside off a shared
    /// vertex.
    pub fn legs(&self) -> &[u32] {
        &self.legs
    }

    /// Each robot's turns so far: moves in another direction than its last.
    pub fn turns(&self) -> &[u32] {
        &self.turns
    }

    /// Sonar: the open edge slots and the slots holding another robot.
    pub fn sonar(&self, robot: usize) -> (u8, u8) {
        let v = self.pos[robot];
        let grid = &self.world.grid;
        let mut occupied = 0u8;
        for (d, &n) in grid.neighbors(v)[..grid.degree()].iter().enumerate() {
            if n != NONE && self.occupant[n as usize] != EMPTY {
                occupied |= 1 << d;
            }
        }
        (self.world.open_mask(v), occupied)
    }

    /// Laser: targets within `r_st`; records them as found.
    pub fn laser(&mut self, robot: usize) -> &'w [u32] {
        let ts = self.world.targets_near(self.pos[robot]);
        for &t in ts {
            if !self.found.get(t as usize) {
                self.found.set(t as usize);
                self.found_count += 1;
            }
        }
        ts
    }

    /// Step 6 for everyone at once: every robot goes to `next[k]` (its own
    /// position to stay). A move that is not along a traversable edge is
    /// refused and the robot stays. Collisions are counted, not prevented;
    /// under [`RuCollisions::BackOff`] the robots in them back off.
    pub fn execute(&mut self, next: &[VertexId]) -> RoundReport {
        let grid = &self.world.grid;
        let mut report = RoundReport::default();
        let mut target = std::mem::take(&mut self.target);
        target.clear();
        for (k, &to) in next.iter().enumerate() {
            let from = self.pos[k];
            if to == from {
                target.push(from);
            } else if (to as usize) < grid.len() && self.world.can_move(from, to) {
                target.push(to);
            } else {
                report.refused += 1;
                target.push(from);
            }
        }
        report.collisions = self.count_collisions(&target);
        // Headings follow the planned moves: a robot that backs off turned
        // to its destination and reverses along the same edge.
        for (k, &to) in target.iter().enumerate() {
            let from = self.pos[k];
            if to == from {
                continue;
            }
            let (a, b) = (grid.coord(from), grid.coord(to));
            let dir = (b.i - a.i, b.j - a.j);
            report.translated = true;
            self.legs[k] += 1;
            if self.heading[k] != Some(dir) {
                report.rotated = true;
                self.turns[k] += 1;
            }
            self.heading[k] = Some(dir);
        }
        if self.world.params.ru_collisions == RuCollisions::BackOff && report.collisions > 0 {
            let mut planned = std::mem::take(&mut self.planned);
            planned.clear();
            planned.extend_from_slice(&target);
            report.collisions += self.back_off(&mut target);
            for (k, (&p, &t)) in planned.iter().zip(target.iter()).enumerate() {
                self.legs[k] += u32::from(p != t);
            }
            self.planned = planned;
        }
        self.round += 1;
        for &v in &self.pos {
            self.occupant[v as usize] = EMPTY;
        }
        for (k, &v) in target.iter().enumerate() {
            self.pos[k] = v;
            self.occupant[v as usize] = k as u16;
            if !self.visited.get(v as usize) {
                self.visits += 1;
                self.visited.set(v as usize);
            }
        }
        self.target = target;
        report
    }

    /// Sends every robot in a collision but one mover per group back to
    /// where it came from, then every robot whose destination a returning
    /// robot holds, until no two robots end on a vertex one of them moved
    /// to; robots left stacked separate. Returns the collisions the cascade
    /// added.
    fn back_off(&mut self, target: &mut [VertexId]) -> u32 {
        let mut ending = std::mem::take(&mut self.ending);
        ending.resize(self.world.grid.len(), 0);
        let through = self.through(target);
        for (k, t) in target.iter_mut().enumerate() {
            if self.involved[k] && !through[k] {
                *t = self.pos[k];
            }
        }
        for &t in target.iter() {
            ending[t as usize] += 1;
        }
        let mut added = 0;
        loop {
            let mut changed = false;
            for (k, t) in target.iter_mut().enumerate() {
                let (from, to) = (self.pos[k], *t);
                if to != from && ending[to as usize] > 1 {
                    ending[to as usize] -= 1;
                    ending[from as usize] += 1;
                    *t = from;
                    // A robot of a counted pair meeting it again is no new collision.
                    added += u32::from(!self.involved[k]);
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        self.separate(target, &mut ending);
        for &t in target.iter() {
            ending[t as usize] = 0;
        }
        self.ending = ending;
        added
    }

    /// One moving robot of each group of robots that met (linked by counted
    /// pairs), the one with the smallest draw from the seed and the round.
    fn through(&self, target: &[VertexId]) -> Vec<bool> {
        let n = target.len();
        let mut group: Vec<usize> = (0..n).collect();
        fn root(g: &mut [usize], mut k: usize) -> usize {
            while g[k] != k {
                g[k] = g[g[k]];
                k = g[k];
            }
            k
        }
        for &(i, j) in &self.pairs {
            let (a, b) = (root(&mut group, i as usize), root(&mut group, j as usize));
            group[a.max(b)] = a.min(b);
        }
        let draw = |k: usize| crate::rng::derive(crate::rng::derive(self.seed, self.round), k as u64);
        let mut best: Vec<Option<(u64, usize)>> = vec![None; n];
        for k in (0..n).filter(|&k| self.involved[k] && target[k] != self.pos[k]) {
            let g = root(&mut group, k);
            let d = (draw(k), k);
            if best[g].is_none_or(|b| d < b) {
                best[g] = Some(d);
            }
        }
        let mut through = vec![false; n];
        for (_, k) in best.into_iter().flatten() {
            through[k] = true;
        }
        through
    }

    /// Robots still sharing a vertex (they stood there together): the lowest
    /// id stays, each other one in id order moves to the first free vertex
    /// across a traversable edge, in adjacency order, or stays if none is.
    fn separate(&mut self, target: &mut [VertexId], ending: &mut [u16]) {
        let grid = &self.world.grid;
        for k in 0..target.len() {
            let v = target[k];
            if ending[v as usize] <= 1 || !(0..k).any(|j| target[j] == v) {
                continue;
            }
            let free = grid.neighbors(v)[..grid.degree()]
                .iter()
                .copied()
                .find(|&n| n != NONE && ending[n as usize] == 0 && self.world.can_move(v, n));
            if let Some(n) = free {
                ending[v as usize] -= 1;
                ending[n as usize] += 1;
                target[k] = n;
                let (a, b) = (grid.coord(v), grid.coord(n));
                self.heading[k] = Some((b.i - a.i, b.j - a.j));
            }
        }
    }

    /// Two robots further apart than this at the start of a move cannot meet.
    fn reach(world: &World) -> f64 {
        2.0 * world.params.a + 2.0 * world.params.r_safe
    }

    /// Pairs closer than `2 r_safe` at any moment of the simultaneous moves,
    /// or ending on one vertex; marks the robots in them in `involved`.
    /// Under [`RuCollisions::PerEvent`] a pair that starts the round in
    /// contact (stacked since it collided) is in the collision already
    /// counted: only pairs that start apart make a new one.
    fn count_collisions(&mut self, target: &[VertexId]) -> u32 {
        let grid = &self.world.grid;
        let params = &self.world.params;
        let limit = 2.0 * params.r_safe;
        let events = params.ru_collisions == RuCollisions::PerEvent;
        let reach2 = Self::reach(self.world).powi(2);
        self.involved.clear();
        self.involved.resize(target.len(), false);
        self.pairs.clear();
        let mut cells = std::mem::take(&mut self.cells);
        let mut starts = std::mem::take(&mut self.starts);
        starts.clear();
        starts.extend(self.pos.iter().map(|&v| grid.position(v)));
        let few = target.len() <= 64;
        if !few {
            cells.fill(&starts);
        }
        let mut count = 0;
        for i in 0..target.len() {
            let (p0, p1) = (starts[i], grid.position(target[i]));
            let mut test = |j: usize| {
                let q0 = starts[j];
                let d2 = (q0 - p0).norm_squared();
                if j <= i || d2 > reach2 || (events && d2 < limit * limit) {
                    return;
                }
                let q1 = grid.position(target[j]);
                if target[i] == target[j] || swept_min_distance(p0, p1, q0, q1) < limit {
                    count += 1;
                    self.involved[i] = true;
                    self.involved[j] = true;
                    self.pairs.push((i as u16, j as u16));
                }
            };
            if few {
                (i + 1..target.len()).for_each(&mut test);
            } else {
                cells.around(p0, |j| test(j as usize));
            }
        }
        self.cells = cells;
        self.starts = starts;
        count
    }

    pub fn coord(&self, robot: usize) -> Coord {
        self.world.grid.coord(self.pos[robot])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Point, Polygon};
    use crate::lattice::LatticeKind;
    use crate::params::Params;

    fn world(mode: RuCollisions) -> World {
        let area = Polygon::new(vec![
            Point::new(-5.0, -5.0),
            Point::new(5.0, -5.0),
            Point::new(5.0, 5.0),
            Point::new(-5.0, 5.0),
        ]);
        let params = Params { ru_collisions: mode, ..Params::default() };
        World::new(area, vec![], vec![], params, LatticeKind::Triangular)
    }

    fn v(w: &World, i: i32, j: i32) -> VertexId {
        w.grid.id_of(Coord::new(i, j)).unwrap()
    }

    #[test]
    fn a_head_on_pair_backs_off_and_is_not_charged_again() {
        let w = world(RuCollisions::BackOff);
        let (a, b) = (v(&w, 0, 0), v(&w, 1, 0));
        let mut r = Referee::new(&w, &[a, b]);
        let rep = r.execute(&[b, a]);
        assert_eq!(rep.collisions, 1);
        assert_eq!(r.positions(), &[a, b]);
        // Neither reached the other's vertex.
        assert!(!r.visited().get(v(&w, 2, 0) as usize));
        assert_eq!(r.execute(&[a, b]).collisions, 0);
    }

    #[test]
    fn of_robots_heading_into_one_vertex_one_gets_there() {
        let w = world(RuCollisions::BackOff);
        let (a, b, t) = (v(&w, 0, 0), v(&w, 2, 0), v(&w, 1, 0));
        let mut winners = [0; 2];
        for seed in 0..40 {
            let mut r = Referee::new(&w, &[a, b]).seeded(seed);
            assert_eq!(r.execute(&[t, t]).collisions, 1);
            let p = r.positions();
            let k = usize::from(p[1] == t);
            assert_eq!(p, if k == 0 { [t, b] } else { [a, t] }, "seed {seed}");
            winners[k] += 1;
        }
        assert!(winners[0] > 5 && winners[1] > 5, "the seed draws who gets through: {winners:?}");
    }

    #[test]
    fn stacked_robots_separate_under_back_off_and_stay_charged_per_pair() {
        let w = world(RuCollisions::BackOff);
        let a = v(&w, 0, 0);
        let mut r = Referee::new(&w, &[a, a, a]);
        assert_eq!(r.execute(&[a, a, a]).collisions, 3);
        let p = r.positions().to_vec();
        assert_eq!(p[0], a, "the lowest id keeps the vertex");
        assert!(p[1] != a && p[2] != a && p[1] != p[2], "{p:?}");
        assert!(w.can_move(a, p[1]) && w.can_move(a, p[2]));
        for _ in 0..3 {
            assert_eq!(r.execute(&p).collisions, 0, "standing apart costs nothing");
        }

        let w = world(RuCollisions::PerPair);
        let mut r = Referee::new(&w, &[a, a]);
        for _ in 0..3 {
            assert_eq!(r.execute(&[a, a]).collisions, 1);
            assert_eq!(r.positions(), &[a, a]);
        }
    }

    #[test]
    fn a_stacked_pair_is_charged_once_per_event() {
        let w = world(RuCollisions::PerEvent);
        let (a, b, t) = (v(&w, 0, 0), v(&w, 2, 0), v(&w, 1, 0));
        let mut r = Referee::new(&w, &[a, b]);
        assert_eq!(r.execute(&[t, t]).collisions, 1, "meeting on one vertex is a collision");
        assert_eq!(r.positions(), &[t, t], "no backing off: they stay stacked");
        for _ in 0..3 {
            assert_eq!(r.execute(&[t, t]).collisions, 0, "standing stacked is the same collision");
        }
        // Moving off together (never apart) is still that collision, and
        // so is one of them stepping away.
        let u = v(&w, 2, 0);
        assert_eq!(r.execute(&[u, u]).collisions, 0);
        assert_eq!(r.execute(&[u, t]).collisions, 0, "parting is no new collision");
        assert_eq!(r.positions(), &[u, t]);
        assert_eq!(w.params.collision_penalty(1), w.params.move_time(), "each event costs one move time");
    }

    #[test]
    fn a_pair_that_separates_and_meets_again_is_charged_twice() {
        let w = world(RuCollisions::PerEvent);
        let (a, b, t) = (v(&w, 0, 0), v(&w, 2, 0), v(&w, 1, 0));
        let mut r = Referee::new(&w, &[a, b]);
        let mut charged = r.execute(&[t, t]).collisions;
        charged += r.execute(&[a, t]).collisions;
        assert_eq!(r.positions(), &[a, t], "apart again");
        charged += r.execute(&[a, t]).collisions;
        charged += r.execute(&[t, t]).collisions;
        assert_eq!(charged, 2, "two meetings, two collisions");
        // Head-on along one edge is a collision too, from apart.
        let mut r = Referee::new(&w, &[a, t]);
        assert_eq!(r.execute(&[t, a]).collisions, 1);
        assert_eq!(r.execute(&[a, t]).collisions, 1, "swapped back: they met again");
        // Per pair, the same stacked pair is charged every round.
        let w = world(RuCollisions::PerPair);
        let mut r = Referee::new(&w, &[a, b]);
        let charged: u32 = (0..4).map(|_| r.execute(&[t, t]).collisions).sum();
        assert_eq!(charged, 4);
        assert_eq!(w.params.collision_penalty(4), 4.0 * w.params.move_time());
    }

    #[test]
    fn a_robot_whose_destination_is_taken_by_one_backing_off_backs_off_too() {
        let w = world(RuCollisions::BackOff);
        let (x, u, t) = (v(&w, -1, 0), v(&w, 0, 0), v(&w, 1, 0));
        // Robot 0 follows robot 1 along a line; robot 1 runs into robot 2.
        let mut r = Referee::new(&w, &[x, u, t]);
        let rep = r.execute(&[u, t, t]);
        assert_eq!(rep.collisions, 2, "the meeting and the cascade");
        assert_eq!(r.positions(), &[x, u, t]);
        // The same moves under per-pair: one collision, robots 1 and 2 stacked.
        let w = world(RuCollisions::PerPair);
        let mut r = Referee::new(&w, &[x, u, t]);
        assert_eq!(r.execute(&[u, t, t]).collisions, 1);
        assert_eq!(r.positions(), &[u, t, t]);
    }

    #[test]
    fn the_penalty_is_one_move_time_per_round_under_back_off() {
        let p = Params { ru_collisions: RuCollisions::BackOff, ..Params::default() };
        assert_eq!(p.collision_penalty(0), 0.0);
        assert_eq!(p.collision_penalty(1), p.move_time());
        assert_eq!(p.collision_penalty(5), p.move_time());
        let pp = Params { ru_collisions: RuCollisions::PerPair, ..p };
        assert_eq!(pp.collision_penalty(5), 5.0 * p.move_time());
    }

    #[test]
    fn ru_never_stands_stacked_under_back_off() {
        use crate::outcome::RunConfig;
        use crate::params::Situation;
        use crate::policy::Policy;
        let mut s = crate::scenario::Scenario::load("paper").unwrap();
        s.params.ru_collisions = RuCollisions::BackOff;
        let w = s.world();
        let starts = s.start_vertices(&w, 13).unwrap();
        let mut collided = 0;
        for seed in 0..5 {
            let cfg = RunConfig { measure_coverage: false, ..RunConfig::new(Policy::Ru, seed, Situation::One) };
            let r = crate::engine::run(&w, &starts, &cfg);
            collided += r.collisions;
            for k in 0..=r.rounds as usize {
                let mut at: Vec<_> = r.trajectories.iter().map(|t| t[k].vertex.unwrap()).collect();
                at.sort_by_key(|c| (c.i, c.j));
                at.dedup();
                assert_eq!(at.len(), 13, "seed {seed}: robots stacked at the start of round {k}");
            }
            // Every round lasts at most one penalty more than its slot and move.
            let p = w.params;
            let slot = p.t_exchange + 4.0 * p.t_wait + p.t_choice + 20.0 * p.t_hop + p.move_time();
            let mut last = 0.0;
            for &t in &r.round_end_times_s {
                assert!(t - last <= slot + p.move_time() + 1e-6, "seed {seed}: a round of {} s", t - last);
                last = t;
            }
        }
        assert!(collided > 0, "the test must see collisions to mean anything");
    }
}
