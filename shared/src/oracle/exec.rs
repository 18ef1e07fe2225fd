//! Carrying out the oracle's plan in lock-step rounds, one edge per robot
//! per round, the way the world moves robots: collisions are avoided by
//! waiting. Each round the robots with the most route left go first; a move
//! that would end on a vertex another robot holds or will hold, or come
//! within `2 r_safe` of another robot's motion, waits a round. A robot
//! blocked for [`DETOUR_AFTER`] rounds takes a shortest path around the
//! robots in its way, if there is one, or has the robot in its way step
//! aside; a robot done with its route steps aside at once. Robots kept
//! waiting go first. One still blocked after [`FORCE_AFTER`] rounds moves
//! anyway, and that move is counted as a collision (never seen on the
//! built-in maps).

use crate::bitset::Bitset;
use crate::geometry::swept_min_distance;
use crate::grid::VertexId;
use crate::world::World;

use super::plan::{next_hop, Dist, Route};

const DETOUR_AFTER: u32 = 2;
const FORCE_AFTER: u32 = 20;

/// One robot following its route.
#[derive(Clone, Debug)]
struct Walker {
    at: u32,
    /// The last move's direction in lattice coordinates.
    heading: Option<(i32, i32)>,
    route: Route,
    /// Index of the next waypoint in `route.stops`.
    next: usize,
    /// Moves of the route left after the next waypoint.
    tail: Vec<u32>,
    /// Rounds in a row this robot was blocked.
    blocked: u32,
    /// A path around blocking robots, followed before the route resumes.
    detour: Vec<u32>,
    /// Moves made, and turns to a new direction among them.
    moves: u32,
    turns: u32,
}

/// What one round did.
#[derive(Clone, Debug, Default)]
pub(super) struct Round {
    pub rotated: bool,
    pub translated: bool,
    pub waited: bool,
    pub forced: u32,
}

/// The robots and the ground truth of where they stand.
pub(super) struct Exec<'a> {
    world: &'a World,
    d: &'a Dist,
    walkers: Vec<Walker>,
    pub visited: Bitset,
}

impl<'a> Exec<'a> {
    pub fn new(world: &'a World, d: &'a Dist, routes: Vec<Route>) -> Self {
        let mut visited = Bitset::new(world.grid.len());
        let walkers = routes
            .into_iter()
            .map(|route| {
                visited.set(d.verts[route.start as usize] as usize);
                let mut tail = vec![0u32; route.stops.len()];
                for p in (0..route.stops.len().saturating_sub(1)).rev() {
                    tail[p] = tail[p + 1] + d.get(route.stops[p], route.stops[p + 1]);
                }
                Walker {
                    at: route.start,
                    heading: None,
                    route,
                    next: 0,
                    tail,
                    blocked: 0,
                    detour: Vec::new(),
                    moves: 0,
                    turns: 0,
                }
            })
            .collect();
        Exec { world, d, walkers, visited }
    }

    pub fn position(&self, k: usize) -> VertexId {
        self.d.verts[self.walkers[k].at as usize]
    }

    /// Robot `k`'s moves so far, and its turns among them.
    pub fn moves_and_turns(&self, k: usize) -> (u32, u32) {
        (self.walkers[k].moves, self.walkers[k].turns)
    }

    /// Whether robot `k` has waypoints left.
    pub fn busy(&self, k: usize) -> bool {
        self.walkers[k].next < self.walkers[k].route.stops.len()
    }

    fn remaining(&self, k: usize) -> u32 {
        let w = &self.walkers[k];
        match w.route.stops.get(w.next) {
            Some(&goal) => self.d.get(w.at, goal) + w.tail[w.next] + w.detour.len() as u32,
            None => 0,
        }
    }

    /// The vertex robot `k` wants to move to this round, if any.
    fn wish(&self, k: usize) -> Option<u32> {
        let w = &self.walkers[k];
        if let Some(&v) = w.detour.last() {
            return Some(v);
        }
        let goal = *w.route.stops.get(w.next)?;
        let ahead = w.heading.and_then(|(di, dj)| {
            let c = self.world.grid.coord(self.d.verts[w.at as usize]);
            let v = self.world.grid.id_of(crate::lattice::Coord::new(c.i + di, c.j + dj))?;
            let a = self.d.index[v as usize];
            (a != u32::MAX).then_some(a)
        });
        Some(next_hop(self.d, w.at, goal, ahead))
    }

    /// One round: every robot moves one edge along its route or waits.
    pub fn step(&mut self) -> Round {
        let n = self.walkers.len();
        let mut order: Vec<usize> = (0..n).filter(|&k| self.busy(k)).collect();
        // Robots kept waiting go first (no robot starves behind a stream),
        // then those with the most left (the makespan's).
        order.sort_by_key(|&k| (std::cmp::Reverse(self.walkers[k].blocked), std::cmp::Reverse(self.remaining(k)), k));
        let mut end: Vec<Option<u32>> = vec![None; n];
        let mut round = Round::default();
        for &k in &order {
            if end[k].is_some() {
                // Pushed aside by a robot that went before it.
                continue;
            }
            let Some(to) = self.wish(k) else { continue };
            let mut clashes = self.clashes(k, to, &end);
            if clashes > 0 && self.step_aside(to, k, &mut end) {
                clashes = self.clashes(k, to, &end);
            }
            if clashes == 0 || self.walkers[k].blocked >= FORCE_AFTER {
                round.forced += clashes;
                end[k] = Some(to);
                self.walkers[k].blocked = 0;
            } else {
                end[k] = Some(self.walkers[k].at);
                round.waited = true;
                self.walkers[k].blocked += 1;
                if self.walkers[k].blocked == DETOUR_AFTER {
                    self.plan_detour(k);
                }
            }
        }
        for (k, to) in end.into_iter().enumerate() {
            if let Some(to) = to {
                self.advance(k, to, &mut round);
            }
        }
        round
    }

    /// Whether moves `a0 -> a1` and `b0 -> b1`, made together, come within `2 r_safe`.
    fn meets(&self, a0: u32, a1: u32, b0: u32, b1: u32) -> bool {
        let pos = |c: u32| self.world.grid.position(self.d.verts[c as usize]);
        swept_min_distance(pos(a0), pos(a1), pos(b0), pos(b1)) < 2.0 * self.world.params.r_safe
    }

    /// How many robots the move of `k` to `to` would meet, given the moves
    /// decided so far (`end`) and the others standing where they are.
    fn clashes(&self, k: usize, to: u32, end: &[Option<u32>]) -> u32 {
        let from = self.walkers[k].at;
        let mut count = 0;
        for (j, w) in self.walkers.iter().enumerate() {
            if j == k {
                continue;
            }
            let there = end[j].unwrap_or(w.at);
            // Robots already stacked (after a forced move) part without meeting again.
            let stacked = w.at == from;
            if there == to || (!stacked && self.meets(from, to, w.at, there)) {
                count += 1;
            }
        }
        count
    }

    /// The robot standing on `v`, where robot `k` wants to go, moves to a
    /// free adjacent vertex if it can without meeting anyone: at once if it
    /// is done with its route (a parked robot must not wall off a passage),
    /// after [`DETOUR_AFTER`] rounds otherwise (robots head-on).
    fn step_aside(&self, v: u32, k: usize, end: &mut [Option<u32>]) -> bool {
        let patient = self.walkers[k].blocked < DETOUR_AFTER;
        let standing = (0..self.walkers.len())
            .find(|&j| j != k && end[j].is_none() && self.walkers[j].at == v && !(patient && self.busy(j)));
        let Some(j) = standing else { return false };
        let held = |u: u32| self.walkers.iter().enumerate().any(|(m, w)| m != j && end[m].unwrap_or(w.at) == u);
        let free = self.d.adj[v as usize].iter().copied().find(|&u| {
            u != self.walkers[k].at
                && !held(u)
                && self.clashes(j, u, end) == 0
                && !self.meets(self.walkers[k].at, v, v, u)
        });
        end[j] = free;
        free.is_some()
    }

    /// A shortest path from robot `k` to its next waypoint that avoids the
    /// vertices other robots stand on, stored backwards in its detour.
    fn plan_detour(&mut self, k: usize) {
        let w = &self.walkers[k];
        let Some(&goal) = w.route.stops.get(w.next) else { return };
        let n = self.d.len();
        let mut blocked = vec![false; n];
        for (j, o) in self.walkers.iter().enumerate() {
            if j != k && o.at != goal {
                blocked[o.at as usize] = true;
            }
        }
        let mut parent = vec![u32::MAX; n];
        parent[w.at as usize] = w.at;
        let mut queue = vec![w.at];
        let mut head = 0;
        while head < queue.len() && parent[goal as usize] == u32::MAX {
            let u = queue[head];
            head += 1;
            for &v in &self.d.adj[u as usize] {
                if parent[v as usize] == u32::MAX && !blocked[v as usize] {
                    parent[v as usize] = u;
                    queue.push(v);
                }
            }
        }
        if parent[goal as usize] == u32::MAX {
            return;
        }
        let mut path = Vec::new();
        let mut v = goal;
        while v != w.at {
            path.push(v);
            v = parent[v as usize];
        }
        self.walkers[k].detour = path;
    }

    fn advance(&mut self, k: usize, to: u32, round: &mut Round) {
        let grid = &self.world.grid;
        let w = &mut self.walkers[k];
        if to != w.at {
            let (a, b) = (grid.coord(self.d.verts[w.at as usize]), grid.coord(self.d.verts[to as usize]));
            let dir = (b.i - a.i, b.j - a.j);
            round.translated = true;
            round.rotated |= w.heading != Some(dir);
            w.turns += u32::from(w.heading != Some(dir));
            w.moves += 1;
            w.heading = Some(dir);
            w.at = to;
            if w.detour.last() == Some(&to) {
                w.detour.pop();
            } else {
                // A move off the detour (none is planned) voids it.
                w.detour.clear();
            }
            self.visited.set(self.d.verts[to as usize] as usize);
        }
        while w.route.stops.get(w.next).is_some_and(|&s| self.visited.get(self.d.verts[s as usize] as usize)) {
            w.next += 1;
            w.detour.clear();
        }
    }
}
