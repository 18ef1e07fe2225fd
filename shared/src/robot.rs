//! The decision core: one robot's side of a round (READING.md "One round"),
//! as a state machine with no I/O. Both engines drive it the same way:
//!
//! 1. [`Robot::sense`] with what the robot's sensors and radio report (steps 1-2),
//!    then [`Robot::learn_targets`] for targets broadcast by others;
//! 2. [`Robot::map`] goes to every communication neighbour, whose maps come
//!    back through [`Robot::receive_map`] (step 3); [`Robot::stop_rule`] is
//!    then the stop test (rules 3/4);
//! 3. [`Robot::receive_choice`] for each announced choice, [`Robot::declare_failed`]
//!    for neighbours that will never answer; once [`Robot::ready`], [`Robot::choose`]
//!    decides (steps 4-5) and the choice is announced;
//! 4. [`Robot::moved`] once the world has executed the move (step 6).
//!
//! A decision depends only on the set of inputs received, never on their
//! arrival order: maps merge by union, choices wait for every higher-priority
//! neighbour, and the repulsion centre is summed in exact lattice coordinates.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::geometry::swept_min_distance;
use crate::grid::{Grid, VertexId, NONE};
use crate::lattice::MAX_DEGREE;
use crate::map::{Map, RobotId};
use crate::params::Situation;
use crate::policy::Policy;
use crate::rng::robot_rng;

/// Distances within this are equal when rule (2) looks for the farthest candidate.
const TIE: f64 = 1e-9;

/// What a robot needs to know about itself and the run.
#[derive(Clone, Copy, Debug)]
pub struct RobotConfig {
    pub id: RobotId,
    pub policy: Policy,
    pub situation: Situation,
    pub targets_total: usize,
    pub r_safe: f64,
    pub seed: u64,
}

/// One round's readings from the robot's own sensors and radio.
#[derive(Clone, Copy, Debug)]
pub struct Sensing<'a> {
    /// Adjacency slots whose edge is free of obstacles and boundary (sonar).
    pub open: u8,
    /// Adjacency slots whose vertex holds another robot (sonar).
    pub occupied: u8,
    /// Targets within `r_st` (laser).
    pub targets: &'a [u16],
    /// Robots within `r_c` this round (radio), excluding this robot.
    pub neighbours: &'a [RobotId],
}

/// Why a robot stops.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// Rule (3): every target is known.
    AllTargets,
    /// Rule (4): the map has no unvisited accessible vertex. In situation 1
    /// this also ends the search (nothing is left to find), incomplete.
    MapComplete,
}

#[derive(Clone, Copy, Debug)]
struct Neighbour {
    id: RobotId,
    at: VertexId,
    key: (i64, i64),
    map_in: bool,
    choice: Option<VertexId>,
    failed: bool,
}

/// Scratch space for the escape policy's breadth-first search, kept between
/// rounds so the search never allocates.
#[derive(Clone, Debug, Default)]
struct Bfs {
    stamp: Vec<u32>,
    first: Vec<VertexId>,
    queue: Vec<VertexId>,
    generation: u32,
}

#[derive(Clone, Debug)]
pub struct Robot<'g> {
    grid: &'g Grid,
    cfg: RobotConfig,
    rng: ChaCha8Rng,
    pos: VertexId,
    round: u32,
    map: Map,
    nbrs: Vec<Neighbour>,
    open_now: u8,
    occupied_now: u8,
    next: Option<VertexId>,
    bfs: Bfs,
}

impl<'g> Robot<'g> {
    pub fn new(grid: &'g Grid, cfg: RobotConfig, start: VertexId) -> Self {
        Robot {
            grid,
            rng: robot_rng(cfg.seed, cfg.id),
            cfg,
            pos: start,
            round: 0,
            map: Map::new(grid.len(), cfg.targets_total),
            nbrs: Vec::with_capacity(16),
            open_now: 0,
            occupied_now: 0,
            next: None,
            bfs: Bfs::default(),
        }
    }

    pub fn id(&self) -> RobotId {
        self.cfg.id
    }

    pub fn position(&self) -> VertexId {
        self.pos
    }

    pub fn round(&self) -> u32 {
        self.round
    }

    pub fn map(&self) -> &Map {
        &self.map
    }

    /// The choice made this round, once [`Robot::choose`] has run.
    pub fn choice(&self) -> Option<VertexId> {
        self.next
    }

    /// Steps 1-2: start round `round` with this round's readings.
    pub fn sense(&mut self, round: u32, s: &Sensing) {
        self.round = round;
        self.next = None;
        self.open_now = s.open;
        self.occupied_now = s.occupied;
        self.map.record_sensing(self.grid, self.pos, s.open);
        for &t in s.targets {
            self.map.targets.set(t as usize);
        }
        self.nbrs.clear();
        for &id in s.neighbours {
            if id == self.cfg.id || self.nbrs.iter().any(|n| n.id == id) {
                continue;
            }
            let failed = self.map.is_failed(id);
            self.nbrs.push(Neighbour { id, at: NONE, key: (0, 0), map_in: false, choice: None, failed });
        }
        // Sorted by id so every later pass visits neighbours in one fixed order.
        self.nbrs.sort_unstable_by_key(|n| n.id);
    }

    /// Step 1 of others: targets they broadcast to every robot.
    pub fn learn_targets(&mut self, targets: &[u16]) {
        for &t in targets {
            if (t as usize) < self.cfg.targets_total {
                self.map.targets.set(t as usize);
            }
        }
    }

    /// Step 3: a neighbour's map as it was when it sensed this round, and where
    /// it stands. Returns false (and changes nothing) when `from` is not a
    /// communication neighbour this round.
    pub fn receive_map(&mut self, from: RobotId, at: VertexId, map: &Map) -> bool {
        let Some(k) = self.nbrs.iter().position(|n| n.id == from) else {
            return false;
        };
        if (at as usize) >= self.grid.len() {
            return false;
        }
        self.map.merge(map);
        let key = self.grid.priority_key(at);
        let n = &mut self.nbrs[k];
        n.at = at;
        n.key = key;
        n.map_in = true;
        // A merged map may carry news of this neighbour's failure.
        for n in self.nbrs.iter_mut() {
            if self.map.is_failed(n.id) {
                n.failed = true;
            }
        }
        true
    }

    /// Steps 7 (rules 3/4), evaluated once the maps are exchanged.
    pub fn stop_rule(&mut self) -> Option<Stop> {
        if self.cfg.situation == Situation::One && self.map.targets.count() >= self.cfg.targets_total {
            return Some(Stop::AllTargets);
        }
        if !self.map.has_unvisited() {
            return Some(Stop::MapComplete);
        }
        // Sec. 4.2: a failed robot blocks its vertex for good, so it can cut
        // unvisited vertices off; those can never be visited and must not
        // keep the search going. Only with failures, so a failure-free run
        // decides exactly as before.
        if !self.map.failed.is_empty() && self.step_to_unvisited().is_none() {
            return Some(Stop::MapComplete);
        }
        None
    }

    /// Sec. 4.2: robot `id`, standing on `at`, will never answer. It is no
    /// longer waited for and its vertex stays blocked.
    pub fn declare_failed(&mut self, id: RobotId, at: VertexId) {
        if id == self.cfg.id || (at as usize) >= self.grid.len() {
            return;
        }
        self.map.add_failed(id, at);
        if let Some(n) = self.nbrs.iter_mut().find(|n| n.id == id) {
            n.failed = true;
        }
    }

    /// Step 5 of a neighbour: its announced next vertex. Ignored from robots
    /// that are not neighbours this round.
    pub fn receive_choice(&mut self, from: RobotId, next: VertexId) -> bool {
        match self.nbrs.iter_mut().find(|n| n.id == from) {
            Some(n) if (next as usize) < self.grid.len() => {
                n.choice = Some(next);
                true
            }
            _ => false,
        }
    }

    fn sequential(&self) -> bool {
        self.cfg.policy != Policy::Ru
    }

    fn key(&self) -> (i64, i64) {
        self.grid.priority_key(self.pos)
    }

    /// Neighbours this robot still waits for: missing maps, then (for the
    /// sequential policies) higher-priority neighbours that have not chosen.
    pub fn waiting_for(&self) -> impl Iterator<Item = RobotId> + '_ {
        let all_maps = self.nbrs.iter().all(|n| n.map_in || n.failed);
        let me = self.key();
        let seq = self.sequential();
        self.nbrs
            .iter()
            .filter(move |n| {
                !n.failed && (!n.map_in || (all_maps && seq && n.key > me && n.choice.is_none()))
            })
            .map(|n| n.id)
    }

    /// Whether every input step 5 needs has arrived.
    pub fn ready(&self) -> bool {
        self.next.is_none() && self.waiting_for().next().is_none()
    }

    /// Whether `nb` chose before this robot (step 4's order).
    fn chose_earlier(&self, nb: &Neighbour) -> bool {
        self.sequential() && nb.key > self.key()
    }

    /// Steps 4-5: the next vertex (the current one to stay). `None` while
    /// [`Robot::ready`] is false.
    pub fn choose(&mut self) -> Option<VertexId> {
        if !self.ready() {
            return None;
        }
        let grid = self.grid;
        let here = grid.position(self.pos);
        let two_safe = 2.0 * self.cfg.r_safe;
        let mut cands = [NONE; MAX_DEGREE];
        let mut nc = 0;
        'slot: for (d, &n) in grid.neighbors(self.pos)[..grid.degree()].iter().enumerate() {
            if n == NONE || self.open_now >> d & 1 == 0 {
                continue;
            }
            if self.cfg.policy == Policy::Ru {
                // Particles: RU ignores other robots altogether.
                cands[nc] = n;
                nc += 1;
                continue;
            }
            let there = grid.position(n);
            for &(_, at) in &self.map.failed {
                let p = grid.position(at);
                if at == n || swept_min_distance(here, there, p, p) < two_safe {
                    continue 'slot;
                }
            }
            let mut vacated = false;
            for nb in self.nbrs.iter().filter(|nb| !nb.failed && nb.map_in) {
                let from = grid.position(nb.at);
                if self.chose_earlier(nb) {
                    let c = nb.choice.expect("ready() waits for every earlier choice");
                    if c == n || swept_min_distance(here, there, from, grid.position(c)) < two_safe {
                        continue 'slot;
                    }
                    vacated |= nb.at == n;
                } else if nb.at == n || swept_min_distance(here, there, from, from) < two_safe {
                    continue 'slot;
                }
            }
            // A robot on that vertex that has not announced leaving it blocks it.
            if self.occupied_now >> d & 1 == 1 && !vacated {
                continue;
            }
            cands[nc] = n;
            nc += 1;
        }
        let cands = &cands[..nc];
        let next = self.pick(cands).unwrap_or(self.pos);
        self.next = Some(next);
        Some(next)
    }

    /// Rules (1) and (2), and the escape policy's breadth-first step.
    fn pick(&mut self, cands: &[VertexId]) -> Option<VertexId> {
        let mut unvisited = [NONE; MAX_DEGREE];
        let mut visited = [NONE; MAX_DEGREE];
        let (mut nu, mut nv) = (0, 0);
        for &c in cands {
            if self.map.visited.get(c as usize) {
                visited[nv] = c;
                nv += 1;
            } else {
                unvisited[nu] = c;
                nu += 1;
            }
        }
        if nu == 0 && self.cfg.policy == Policy::Escape {
            if let Some(step) = self.step_to_unvisited() {
                if cands.contains(&step) {
                    return Some(step);
                }
            }
        }
        let set = if nu > 0 { &unvisited[..nu] } else { &visited[..nv] };
        if set.is_empty() {
            return None;
        }
        let repulsive = matches!(self.cfg.policy, Policy::Repulsive | Policy::Escape);
        let live = self.nbrs.iter().filter(|n| !n.failed && n.map_in).count();
        if !repulsive || live == 0 {
            return Some(self.uniform(set));
        }
        // Rule (2): farthest from the mean of the earlier choosers' next
        // positions and the later choosers' current positions.
        let (mut si, mut sj) = (0i64, 0i64);
        for nb in self.nbrs.iter().filter(|n| !n.failed && n.map_in) {
            let v = if self.chose_earlier(nb) { nb.choice.unwrap_or(nb.at) } else { nb.at };
            let c = self.grid.coord(v);
            si += c.i as i64;
            sj += c.j as i64;
        }
        // Summing integer coordinates keeps the mean independent of order.
        let ave = self.grid.lattice.position_of(si as f64 / live as f64, sj as f64 / live as f64);
        let mut best = [NONE; MAX_DEGREE];
        let mut nb = 0;
        let mut best_d = f64::NEG_INFINITY;
        for &c in set {
            let d = (self.grid.position(c) - ave).norm();
            if d > best_d + TIE {
                best_d = d;
                nb = 0;
            }
            if d >= best_d - TIE {
                best[nb] = c;
                nb += 1;
            }
        }
        Some(self.uniform(&best[..nb]))
    }

    fn uniform(&mut self, set: &[VertexId]) -> VertexId {
        if set.len() == 1 {
            set[0]
        } else {
            set[self.rng.random_range(0..set.len())]
        }
    }

    /// The first step of a shortest path on the robot's own map to the
    /// nearest known unvisited vertex, avoiding failed robots; `None` when no
    /// unvisited vertex is reachable.
    fn step_to_unvisited(&mut self) -> Option<VertexId> {
        let grid = self.grid;
        let n = grid.len();
        let bfs = &mut self.bfs;
        if bfs.stamp.len() != n {
            bfs.stamp = vec![0; n];
            bfs.first = vec![NONE; n];
            bfs.queue = Vec::with_capacity(n);
        }
        bfs.generation = bfs.generation.wrapping_add(1);
        if bfs.generation == 0 {
            bfs.stamp.iter_mut().for_each(|s| *s = 0);
            bfs.generation = 1;
        }
        let g = bfs.generation;
        bfs.queue.clear();
        bfs.stamp[self.pos as usize] = g;
        bfs.queue.push(self.pos);
        for &(_, at) in &self.map.failed {
            bfs.stamp[at as usize] = g;
        }
        let mut head = 0;
        while head < bfs.queue.len() {
            let v = bfs.queue[head];
            head += 1;
            if v != self.pos && !self.map.visited.get(v as usize) {
                return Some(bfs.first[v as usize]);
            }
            for (d, &w) in grid.neighbors(v)[..grid.degree()].iter().enumerate() {
                if w == NONE || bfs.stamp[w as usize] == g || !self.map.known.get(w as usize) || !self.map.edge_open(grid, v, d)
                {
                    continue;
                }
                bfs.stamp[w as usize] = g;
                bfs.first[w as usize] = if v == self.pos { w } else { bfs.first[v as usize] };
                bfs.queue.push(w);
            }
        }
        None
    }

    /// Step 6 done: the world moved this robot to `to`.
    pub fn moved(&mut self, to: VertexId) {
        self.pos = to;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Point, Polygon};
    use crate::lattice::{Coord, LatticeKind};
    use crate::params::Params;
    use crate::world::World;

    #[test]
    fn vertices_cut_off_by_failed_robots_do_not_keep_the_search_going() {
        let area = Polygon::new(vec![Point::new(-5.0, -5.0), Point::new(5.0, -5.0), Point::new(5.0, 5.0), Point::new(-5.0, 5.0)]);
        let w = World::new(area, vec![], vec![], Params::default(), LatticeKind::Triangular);
        let g = &w.grid;
        let v = g.id_of(Coord::new(0, 0)).unwrap();
        let cfg = RobotConfig { id: 0, policy: Policy::Repulsive, situation: Situation::Two, targets_total: 0, r_safe: 0.3, seed: 1 };
        let mut r = Robot::new(g, cfg, v);
        // Only the edge in slot 0 is open: its far end is the one unvisited vertex.
        r.sense(0, &Sensing { open: 1, occupied: 0, targets: &[], neighbours: &[] });
        assert_eq!(r.stop_rule(), None);
        // A failed robot elsewhere changes nothing.
        r.declare_failed(4, g.neighbors(v)[3]);
        assert_eq!(r.stop_rule(), None);
        // One standing on that vertex blocks it for good: nothing is left.
        r.declare_failed(5, g.neighbors(v)[0]);
        assert_eq!(r.stop_rule(), Some(Stop::MapComplete));
    }
}
