//! The oracle's plan: which vertices each robot visits, in which order.
//! Every waypoint (every vertex of `Va`, or in situation 1 those whose
//! sensing discs cover the area: [`super::cover`]) is a waypoint of
//! exactly one robot or a start; a route's
//! length is the sum of grid distances (breadth-first, over traversable
//! edges) between its consecutive waypoints, from the robot's start. The
//! plan minimizes the longest route (the makespan, in moves): a greedy
//! construction, then local search.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::grid::{VertexId, NONE};
use crate::world::World;

/// A distance no route may use (another connected component).
pub(super) const INF: u32 = u32::MAX / 4;

/// Moves evaluated by one local search before it settles for what it has.
/// The search converges within it on `paper`, `cave` and `open` (their
/// plans are the same at 2 M as at 50 M); on `large` each move misses the
/// cache (the distance table is tens of MB), and 5 M moves give makespans
/// within 3% of 50 M's at a fifth of the time (2026-12-01, 13 robots).
const BUDGET: u64 = 5_000_000;

/// Routes up to this many waypoints get full 2-opt; longer ones only
/// segments of [`WINDOW`] waypoints.
const FULL_TWO_OPT: usize = 1000;
const WINDOW: usize = 64;

/// The vertices of `Va` renumbered `0..n`, their adjacency over traversable
/// edges, and every pairwise distance.
#[derive(Clone, Debug)]
pub(super) struct Dist {
    /// Grid vertex of each compact index.
    pub verts: Vec<VertexId>,
    /// Compact index of each grid vertex, or `u32::MAX` outside `Va`.
    pub index: Vec<u32>,
    /// Neighbours of each compact vertex, in adjacency-slot order.
    pub adj: Vec<Vec<u32>>,
    d: Vec<u16>,
    /// Situation 1's waypoints ([`super::cover`]), made on first use.
    pub cover: std::sync::OnceLock<Vec<bool>>,
}

impl Dist {
    pub fn new(world: &World, va: &[bool]) -> Self {
        let grid = &world.grid;
        let verts: Vec<VertexId> = (0..grid.len() as VertexId).filter(|&v| va[v as usize]).collect();
        let mut index = vec![u32::MAX; grid.len()];
        for (k, &v) in verts.iter().enumerate() {
            index[v as usize] = k as u32;
        }
        let adj = verts
            .iter()
            .map(|&v| {
                grid.neighbors(v)[..grid.degree()]
                    .iter()
                    .filter(|&&n| n != NONE && index[n as usize] != u32::MAX && world.can_move(v, n))
                    .map(|&n| index[n as usize])
                    .collect()
            })
            .collect();
        let n = verts.len();
        let mut dist = Dist { verts, index, adj, d: vec![u16::MAX; n * n], cover: std::sync::OnceLock::new() };
        let mut queue = Vec::with_capacity(n);
        for s in 0..n {
            dist.bfs(s, &mut queue);
        }
        dist
    }

    fn bfs(&mut self, s: usize, queue: &mut Vec<u32>) {
        let n = self.verts.len();
        let row = &mut self.d[s * n..(s + 1) * n];
        queue.clear();
        queue.push(s as u32);
        row[s] = 0;
        let mut head = 0;
        while head < queue.len() {
            let u = queue[head] as usize;
            head += 1;
            for &w in &self.adj[u] {
                if row[w as usize] == u16::MAX {
                    row[w as usize] = row[u] + 1;
                    queue.push(w);
                }
            }
        }
    }

    pub fn len(&self) -> usize {
        self.verts.len()
    }

    /// Moves from `u` to `w` (compact), or [`INF`].
    pub fn get(&self, u: u32, w: u32) -> u32 {
        match self.d[u as usize * self.verts.len() + w as usize] {
            u16::MAX => INF,
            d => d as u32,
        }
    }
}

/// One robot's route: its start and its waypoints, compact indices.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Route {
    pub start: u32,
    pub stops: Vec<u32>,
}

impl Route {
    pub fn cost(&self, d: &Dist) -> u32 {
        let mut at = self.start;
        let mut c = 0u32;
        for &w in &self.stops {
            c = c.saturating_add(d.get(at, w)).min(INF);
            at = w;
        }
        c
    }

    /// The waypoint before position `p` (the start for `p = 0`).
    fn before(&self, p: usize) -> u32 {
        if p == 0 {
            self.start
        } else {
            self.stops[p - 1]
        }
    }
}

/// The plan for robots starting at `starts` (compact) to visit every
/// vertex `need` marks: the better of the greedy routes and one robot's
/// tour cut into consecutive shares, each improved by local search. The
/// shares bound the makespan by `ceil(tour / robots)` plus the farthest any
/// robot is from any vertex.
pub(super) fn plan(d: &Dist, starts: &[u32], need: &[bool], rng: &mut ChaCha8Rng) -> Vec<Route> {
    // Robot 0's tour first: it is then the one-robot plan of the same stream.
    let mut tour = greedy(d, &starts[..1], need, rng);
    improve(d, &mut tour);
    if starts.len() == 1 {
        return tour;
    }
    let mut routes = greedy(d, starts, need, rng);
    improve(d, &mut routes);
    {
        let mut shared = split(d, starts, &tour[0].stops);
        improve(d, &mut shared);
        if makespan(d, &shared) < makespan(d, &routes) {
            return shared;
        }
    }
    routes
}

pub(super) fn makespan(d: &Dist, routes: &[Route]) -> u32 {
    routes.iter().map(|r| r.cost(d)).max().unwrap_or(0)
}

/// One robot's tour cut into consecutive shares, robot `k` taking the
/// `k`-th, with the smallest makespan such cuts give (binary search).
/// Other robots' starts are covered already and leave the tour.
fn split(d: &Dist, starts: &[u32], tour: &[u32]) -> Vec<Route> {
    let tour: Vec<u32> = tour.iter().copied().filter(|w| !starts.contains(w)).collect();
    let cut = |limit: u32| -> Option<Vec<Route>> {
        let mut routes: Vec<Route> = starts.iter().map(|&s| Route { start: s, stops: Vec::new() }).collect();
        let mut p = 0;
        for r in routes.iter_mut() {
            let mut cost = 0u32;
            let mut at = r.start;
            while p < tour.len() && cost + d.get(at, tour[p]) <= limit {
                cost += d.get(at, tour[p]);
                at = tour[p];
                r.stops.push(at);
                p += 1;
            }
        }
        (p == tour.len()).then_some(routes)
    };
    let (mut lo, mut hi) = (0u32, Route { start: starts[0], stops: tour.clone() }.cost(d));
    let mut best = cut(hi).unwrap_or_else(|| vec![Route { start: starts[0], stops: tour.clone() }]);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        match cut(mid) {
            Some(r) => {
                best = r;
                hi = mid;
            }
            None => lo = mid + 1,
        }
    }
    best.resize(starts.len(), Route { start: 0, stops: Vec::new() });
    for (r, &s) in best.iter_mut().zip(starts) {
        r.start = s;
    }
    best
}

/// Robots extend their routes one nearest needed vertex at a time, the
/// robot whose route ends earliest first; needed vertices passed on the
/// way become waypoints too. Ties between nearest vertices are drawn from
/// `rng`.
fn greedy(d: &Dist, starts: &[u32], need: &[bool], rng: &mut ChaCha8Rng) -> Vec<Route> {
    let n = d.len();
    let mut covered: Vec<bool> = need.iter().map(|&x| !x).collect();
    let mut left = need.iter().filter(|&&x| x).count();
    for &s in starts {
        if !std::mem::replace(&mut covered[s as usize], true) {
            left -= 1;
        }
    }
    let mut routes: Vec<Route> = starts.iter().map(|&s| Route { start: s, stops: Vec::new() }).collect();
    let mut ends = starts.to_vec();
    let mut lens = vec![0u32; starts.len()];
    let mut stuck = vec![false; starts.len()];
    let mut ties = Vec::new();
    while left > 0 {
        let Some(k) = (0..routes.len()).filter(|&k| !stuck[k]).min_by_key(|&k| (lens[k], k)) else { break };
        let from = ends[k];
        ties.clear();
        let mut best = INF;
        for w in (0..n as u32).filter(|&w| !covered[w as usize]) {
            let dw = d.get(from, w);
            if dw < best {
                best = dw;
                ties.clear();
            }
            if dw == best && dw < INF {
                ties.push(w);
            }
        }
        if ties.is_empty() {
            stuck[k] = true;
            continue;
        }
        let goal = ties[rng.random_range(0..ties.len())];
        let mut at = from;
        while at != goal {
            at = next_hop(d, at, goal, None);
            if !std::mem::replace(&mut covered[at as usize], true) {
                left -= 1;
                routes[k].stops.push(at);
            }
        }
        lens[k] += best;
        ends[k] = goal;
    }
    routes
}

/// The neighbour of `at` one move closer to `goal`: the one straight ahead
/// of `ahead` (a compact vertex the robot would reach going on) if it is
/// closer, else the first in adjacency order.
pub(super) fn next_hop(d: &Dist, at: u32, goal: u32, ahead: Option<u32>) -> u32 {
    let want = d.get(at, goal) - 1;
    if let Some(a) = ahead {
        if d.adj[at as usize].contains(&a) && d.get(a, goal) == want {
            return a;
        }
    }
    *d.adj[at as usize].iter().find(|&&w| d.get(w, goal) == want).expect("a reachable goal has a closer neighbour")
}

/// Local search on the makespan: 2-opt within every route, and moving one
/// waypoint of the longest route to wherever it lengthens another least,
/// while that shortens the longer of the two. Each accepted move makes the
/// routes' lengths, sorted from longest, lexicographically smaller, so the
/// search ends.
fn improve(d: &Dist, routes: &mut [Route]) {
    let mut budget = BUDGET;
    while budget > 0 {
        for r in routes.iter_mut() {
            two_opt(d, r, &mut budget);
        }
        let costs: Vec<u32> = routes.iter().map(|r| r.cost(d)).collect();
        let Some(l) = (0..routes.len()).max_by_key(|&k| (costs[k], std::cmp::Reverse(k))) else { return };
        if !relocate_from(d, routes, &costs, l, &mut budget) {
            return;
        }
    }
}

/// Reverses segments of `r` while that shortens it (the route is open: its
/// end is free). Segments longer than [`WINDOW`] are not tried on routes
/// longer than that, which bounds the work on large maps.
fn two_opt(d: &Dist, r: &mut Route, budget: &mut u64) {
    let m = r.stops.len();
    let window = if m <= FULL_TWO_OPT { m } else { WINDOW };
    loop {
        let mut improved = false;
        for i in 0..m {
            if *budget == 0 {
                return;
            }
            *budget = budget.saturating_sub(window.min(m - i) as u64);
            let prev = r.before(i);
            for j in i + 1..m.min(i + window) {
                let (wi, wj) = (r.stops[i], r.stops[j]);
                let mut delta = d.get(prev, wj) as i64 - d.get(prev, wi) as i64;
                if j + 1 < m {
                    let next = r.stops[j + 1];
                    delta += d.get(wi, next) as i64 - d.get(wj, next) as i64;
                }
                if delta < 0 {
                    r.stops[i..=j].reverse();
                    improved = true;
                }
            }
        }
        if !improved {
            return;
        }
    }
}

/// What inserting `w` at position `q` of `r` adds to its length.
fn insertion(d: &Dist, r: &Route, q: usize, w: u32) -> u32 {
    let prev = r.before(q);
    let add = d.get(prev, w);
    match r.stops.get(q) {
        Some(&next) => (add + d.get(w, next)).saturating_sub(d.get(prev, next)),
        None => add,
    }
}

/// Moves one waypoint of route `l` (the longest) to its cheapest place in
/// any route if that shortens the longer of the two routes involved.
fn relocate_from(d: &Dist, routes: &mut [Route], costs: &[u32], l: usize, budget: &mut u64) -> bool {
    let cl = costs[l];
    let places: u64 = routes.iter().map(|r| r.stops.len() as u64 + 1).sum();
    for p in 0..routes[l].stops.len() {
        if *budget == 0 {
            return false;
        }
        *budget = budget.saturating_sub(places);
        let mut shorter = routes[l].clone();
        let w = shorter.stops.remove(p);
        let cl_new = shorter.cost(d);
        // (resulting longer length, route, position), best first.
        let mut best: Option<(u32, usize, usize)> = None;
        for (b, r) in routes.iter().enumerate() {
            let (base, route) = if b == l { (cl_new, &shorter) } else { (costs[b], r) };
            for q in 0..=route.stops.len() {
                let grown = base.saturating_add(insertion(d, route, q, w));
                let worst = if b == l { grown } else { grown.max(cl_new) };
                if worst < cl && best.is_none_or(|(x, _, _)| worst < x) {
                    best = Some((worst, b, q));
                }
            }
        }
        if let Some((_, b, q)) = best {
            if b == l {
                shorter.stops.insert(q, w);
            } else {
                routes[b].stops.insert(q, w);
            }
            routes[l] = shorter;
            return true;
        }
    }
    false
}
