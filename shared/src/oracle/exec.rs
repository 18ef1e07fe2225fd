//! Carrying out the oracle's plan in lock-step rounds, one edge per robot
//! per round, the way the world moves robots: collisions are avoided by
//! waiting. Each round the robots with the most route left go first; a move
//! that would end on a vertex another robot holds or will hold, or come
//! within `2 r_safe` of another robot's motion, waits a round; one in the
//! way only of robots not decided yet is decided after them, so a robot
//! follows another through a corridor without a gap. A robot
//! blocked for [`DETOUR_AFTER`] rounds takes a shortest path around the
//! robots in its way, if there is one, or has the robot in its way step
//! aside; a robot done with its route steps aside at once. Robots kept
//! waiting go first. One with no less route left after [`SWAP_AFTER`]
//! rounds (blocked, or pushed to and fro), held up by a robot standing
//! where it must go (head-on in a corridor, or a parked
//! robot with nowhere to step) trades the rest of its route with that
//! robot's instead of moving: the robots are alike, so each carries on
//! with the other's work from where it stands, and no move is forced. Only
//! one blocked for [`FORCE_AFTER`] rounds moves anyway, counted as a
//! collision; the tests run hundreds of searches without one.
//!
//! A round lasts `t_rot` longer if any robot turns, so turns wait for one
//! another: a robot whose next move is a turn stands in a round nobody must
//! turn in, while so few want to that the rest's moves are worth more than
//! the `t_rot` saved ([`Exec::turning`] says when one must), and in a round
//! someone turns in, every robot standing turns to face its next move.

use crate::bitset::Bitset;
use crate::geometry::swept_min_distance;
use crate::grid::VertexId;
use crate::world::World;

use super::plan::{next_hop, Dist, Route};

const DETOUR_AFTER: u32 = 2;
const SWAP_AFTER: u32 = 20;
const FORCE_AFTER: u32 = 100;
/// The most rounds in a row a robot waits to turn (see [`Exec::turning`]).
const TURN_WAIT_MAX: u32 = 4;

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
    /// The least route left it had, and the rounds since it had less:
    /// robots pushed to and fro reset `blocked`, not this.
    best: u32,
    stalled: u32,
    /// A path around blocking robots, followed before the route resumes.
    detour: Vec<u32>,
    /// Rounds in a row this robot stood because its next move is a turn
    /// and nobody turned.
    turn_wait: u32,
    /// Moves made, and turns to a new direction (with a move or on the
    /// spot).
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
    /// Whether turns wait for rounds others turn in ([`Exec::turning`]);
    /// off, every robot turns when its route does (the tests compare).
    pub plan_turns: bool,
}

/// A robot at its route's start, about to follow it.
/// A walker on `route`, with the heading, moves and turns it had so far.
fn walker(d: &Dist, route: Route, (heading, moves, turns): (Option<(i32, i32)>, u32, u32)) -> Walker {
    let mut tail = vec![0u32; route.stops.len()];
    for p in (0..route.stops.len().saturating_sub(1)).rev() {
        tail[p] = tail[p + 1] + d.get(route.stops[p], route.stops[p + 1]);
    }
    Walker {
        at: route.start,
        heading,
        route,
        next: 0,
        tail,
        blocked: 0,
        best: u32::MAX,
        stalled: 0,
        detour: Vec::new(),
        turn_wait: 0,
        moves,
        turns,
    }
}

impl<'a> Exec<'a> {
    pub fn new(world: &'a World, d: &'a Dist, routes: Vec<Route>) -> Self {
        let mut visited = Bitset::new(world.grid.len());
        for r in &routes {
            visited.set(d.verts[r.start as usize] as usize);
        }
        let walkers = routes.into_iter().map(|route| walker(d, route, (None, 0, 0))).collect();
        Exec { world, d, walkers, visited, plan_turns: true }
    }

    /// New routes from where the robots stand (route `k`'s start is robot
    /// `k`'s vertex), headings, visits and counts kept.
    pub fn replan(&mut self, routes: Vec<Route>) {
        let kept: Vec<_> = self.walkers.iter().map(|w| (w.heading, w.moves, w.turns)).collect();
        self.walkers = routes.into_iter().zip(kept).map(|(r, k)| walker(self.d, r, k)).collect();
        for k in 0..self.walkers.len() {
            self.skip_visited(k);
        }
    }

    /// Robot `k`'s vertex, compact.
    pub fn at(&self, k: usize) -> u32 {
        self.walkers[k].at
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
        for &k in &order {
            let left = self.remaining(k);
            let w = &mut self.walkers[k];
            if left < w.best {
                (w.best, w.stalled) = (left, 0);
            } else {
                w.stalled += 1;
            }
        }
        // Robots kept waiting go first (no robot starves behind a stream),
        // then those with the most left (the makespan's).
        order.sort_by_key(|&k| (std::cmp::Reverse(self.walkers[k].blocked), std::cmp::Reverse(self.remaining(k)), k));
        let turning = self.turning(&order);
        let mut end: Vec<Option<u32>> = vec![None; n];
        let mut round = Round::default();
        // A robot whose move meets only robots not decided yet is decided
        // after the others, once: a robot following another through a
        // corridor takes the vertex the other leaves in the same round
        // instead of waiting a round behind it (robots go in order of route
        // left, and the follower often has more).
        let mut queue: Vec<(usize, bool)> = order.iter().map(|&k| (k, true)).collect();
        let mut next = 0;
        while let Some(&(k, first)) = queue.get(next) {
            next += 1;
            if end[k].is_some() {
                // Pushed aside by a robot that went before it.
                continue;
            }
            let Some(to) = self.wish(k) else { continue };
            if !turning && self.turns(k, to) {
                end[k] = Some(self.walkers[k].at);
                round.waited = true;
                let w = &mut self.walkers[k];
                w.turn_wait += 1;
                // Standing on purpose is not being held up: no trade for it.
                w.stalled = w.stalled.saturating_sub(1);
                continue;
            }
            let mut clashes = self.clashes(k, to, &end);
            if clashes > 0 && first && self.undecided_in_way(k, to, &end) {
                queue.push((k, false));
                continue;
            }
            if clashes > 0 && self.step_aside(to, k, &mut end) {
                clashes = self.clashes(k, to, &end);
            }
            if clashes == 0 || self.walkers[k].blocked >= FORCE_AFTER {
                round.forced += clashes;
                end[k] = Some(to);
                self.walkers[k].blocked = 0;
            } else if self.walkers[k].stalled >= SWAP_AFTER && self.trade(k, to, &end) {
                end[k] = Some(self.walkers[k].at);
                round.waited = true;
            } else {
                end[k] = Some(self.walkers[k].at);
                round.waited = true;
                self.walkers[k].blocked += 1;
                if self.walkers[k].blocked == DETOUR_AFTER {
                    self.plan_detour(k);
                }
            }
        }
        let mut stood = Vec::new();
        for (k, to) in end.into_iter().enumerate() {
            if let Some(to) = to {
                if to == self.walkers[k].at {
                    stood.push(k);
                }
                self.advance(k, to, &mut round);
            }
        }
        if round.rotated && self.plan_turns {
            // The round lasts `t_rot` longer anyway: robots standing turn
            // on the spot to face their next move, which then needs no turn.
            for k in stood {
                if let Some(to) = self.wish(k) {
                    let dir = Some(self.direction(self.walkers[k].at, to));
                    let w = &mut self.walkers[k];
                    // A turn on the spot is a rotation too (the metrics).
                    w.turns += u32::from(w.heading != dir);
                    w.heading = dir;
                }
            }
        }
        round
    }

    /// A move's direction in lattice coordinates.
    fn direction(&self, from: u32, to: u32) -> (i32, i32) {
        let grid = &self.world.grid;
        let (a, b) = (grid.coord(self.d.verts[from as usize]), grid.coord(self.d.verts[to as usize]));
        (b.i - a.i, b.j - a.j)
    }

    /// Whether robot `k`'s move to `to` is a turn (a rotation, charged `t_rot`).
    fn turns(&self, k: usize, to: u32) -> bool {
        let w = &self.walkers[k];
        w.heading != Some(self.direction(w.at, to))
    }

    /// Whether robots may turn this round. A round lasts `t_trans`, plus
    /// `t_rot` if any robot turns, so a robot turns in the same round as
    /// others where it can and otherwise waits for one: robots wanting to
    /// turn stand (at most [`TURN_WAIT_MAX`] rounds in a row) in a round
    /// nobody must turn in. The rule, by the team's moves per second: of
    /// `n` robots with a route, `m` wanting to turn, a round without turns
    /// makes `n - m` moves in `t_trans` against `n` in `t_trans + t_rot`,
    /// and pays only while `m (t_trans + t_rot) < n t_rot`: with the
    /// default times `m <= 2` of 13, `m <= 1` of 7, never for one robot
    /// alone. A robot must turn (and so all may) when standing would cost
    /// more than that: it has the most route left (the makespan's); a
    /// robot wants its vertex (it would hold a follower up too); it is
    /// blocked or on a detour (it is being held up already); or it has
    /// waited [`TURN_WAIT_MAX`] rounds (so every robot moves again).
    /// Without the makespan's robot the rule cost 5% on `open` at 7 robots;
    /// without the follower's, 5% on `cave` at 13 (200 runs each).
    fn turning(&self, order: &[usize]) -> bool {
        if !self.plan_turns {
            return true;
        }
        let wishes: Vec<Option<u32>> = order.iter().map(|&k| self.wish(k)).collect();
        let most = order.iter().map(|&k| self.remaining(k)).max().unwrap_or(0);
        let mut want = 0usize;
        for (&k, &to) in order.iter().zip(&wishes) {
            let Some(to) = to else { continue };
            if !self.turns(k, to) {
                continue;
            }
            let w = &self.walkers[k];
            if w.blocked > 0
                || !w.detour.is_empty()
                || w.turn_wait >= TURN_WAIT_MAX
                || self.remaining(k) >= most
                || wishes.contains(&Some(w.at))
            {
                return true;
            }
            want += 1;
        }
        let p = &self.world.params;
        want as f64 * (p.t_trans + p.t_rot) >= order.len() as f64 * p.t_rot
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

    /// Whether a robot with a route, not decided yet this round, stands
    /// where the move of `k` to `to` would meet it. Every move is checked
    /// against every decided one when it is made, so deciding `k` later is
    /// as safe as deciding it now.
    fn undecided_in_way(&self, k: usize, to: u32, end: &[Option<u32>]) -> bool {
        let from = self.walkers[k].at;
        self.walkers.iter().enumerate().any(|(j, w)| {
            j != k
                && end[j].is_none()
                && self.busy(j)
                && (w.at == to || (w.at != from && self.meets(from, to, w.at, w.at)))
        })
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

    /// Robot `k` trades the rest of its route with the robot standing on
    /// `to` (not moving this round), which has been in its way; both start
    /// afresh. Whether there was one.
    fn trade(&mut self, k: usize, to: u32, end: &[Option<u32>]) -> bool {
        let standing =
            (0..self.walkers.len()).find(|&j| j != k && self.walkers[j].at == to && end[j].is_none_or(|e| e == to));
        let Some(j) = standing else { return false };
        let (a, b) = if k < j { (k, j) } else { (j, k) };
        let (left, right) = self.walkers.split_at_mut(b);
        let (x, y) = (&mut left[a], &mut right[0]);
        std::mem::swap(&mut x.route.stops, &mut y.route.stops);
        std::mem::swap(&mut x.next, &mut y.next);
        std::mem::swap(&mut x.tail, &mut y.tail);
        for w in [x, y] {
            w.detour.clear();
            (w.blocked, w.best, w.stalled) = (0, u32::MAX, 0);
        }
        // A waypoint of the other's route may be where this one stands.
        self.skip_visited(a);
        self.skip_visited(b);
        true
    }

    /// Moves robot `k`'s next waypoint past those visited already.
    fn skip_visited(&mut self, k: usize) {
        let (verts, visited) = (&self.d.verts, &self.visited);
        let w = &mut self.walkers[k];
        while w.route.stops.get(w.next).is_some_and(|&s| visited.get(verts[s as usize] as usize)) {
            w.next += 1;
            w.detour.clear();
        }
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
            w.turn_wait = 0;
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
        self.skip_visited(k);
    }
}
