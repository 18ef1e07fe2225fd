//! Breadth-first search on a robot's own map: through known vertices and
//! edges known traversable, never through blocked vertices (failed robots,
//! bodies). A search's space (four words a vertex) is needed only while
//! its robot chooses: a rule gives it back ([`Paths::release`]) to a
//! pool of its thread, where the next robot's search takes it, so a search
//! allocates only when the pool is empty, and 10,000 robots on a big map
//! share a few instead of holding 10,000 (gigabytes).

use std::cell::RefCell;

use crate::grid::{Grid, VertexId, NONE};
use crate::map::Map;

thread_local! {
    /// Released searches' space, for the next search of this thread.
    static SPARE: RefCell<Vec<Paths>> = const { RefCell::new(Vec::new()) };
}

#[derive(Clone, Debug, Default)]
pub struct Paths {
    /// `stamp[v] == generation` when `v` was reached by the current search.
    stamp: Vec<u32>,
    dist: Vec<u32>,
    /// The first step from the source of the path that reached `v`.
    first: Vec<VertexId>,
    queue: Vec<VertexId>,
    generation: u32,
}

impl Paths {
    /// Gives this search's space to the thread's pool; its results are
    /// gone (`dist` answers `None`).
    pub fn release(&mut self) {
        if !self.stamp.is_empty() {
            let space = std::mem::take(self);
            SPARE.with(|s| s.borrow_mut().push(space));
        }
    }

    /// Space for `n` vertices: the pool's, else new. The generation goes
    /// with the stamps, so space another robot used is as good as fresh.
    fn space(n: usize) -> Paths {
        let spare = SPARE.with(|s| {
            let mut s = s.borrow_mut();
            let k = s.iter().position(|p| p.stamp.len() == n)?;
            Some(s.swap_remove(k))
        });
        spare.unwrap_or_else(|| Paths {
            stamp: vec![0; n],
            dist: vec![0; n],
            first: vec![NONE; n],
            queue: Vec::with_capacity(n),
            generation: 0,
        })
    }

    /// Starts a search from `sources` (distance 0) with `blocked` closed.
    fn start(&mut self, n: usize, sources: &[VertexId], blocked: &[VertexId]) -> u32 {
        if self.stamp.len() != n {
            self.release();
            *self = Self::space(n);
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.stamp.iter_mut().for_each(|s| *s = 0);
            self.generation = 1;
        }
        let g = self.generation;
        self.queue.clear();
        for &b in blocked {
            self.stamp[b as usize] = g;
            self.dist[b as usize] = u32::MAX;
        }
        for &s in sources {
            self.stamp[s as usize] = g;
            self.dist[s as usize] = 0;
            self.first[s as usize] = NONE;
            self.queue.push(s);
        }
        g
    }

    /// Expands the search level by level until `done(v)` holds for a
    /// popped vertex; returns it, or `None` when the search is exhausted.
    fn run(
        &mut self,
        grid: &Grid,
        map: &Map,
        g: u32,
        mut done: impl FnMut(&Self, VertexId) -> bool,
    ) -> Option<VertexId> {
        let mut head = 0;
        while head < self.queue.len() {
            let v = self.queue[head];
            head += 1;
            if done(self, v) {
                return Some(v);
            }
            for (d, &w) in grid.neighbors(v)[..grid.degree()].iter().enumerate() {
                if w == NONE || self.stamp[w as usize] == g || !map.known(w) || !map.edge_open(grid, v, d) {
                    continue;
                }
                self.stamp[w as usize] = g;
                self.dist[w as usize] = self.dist[v as usize] + 1;
                self.first[w as usize] = if self.first[v as usize] == NONE { w } else { self.first[v as usize] };
                self.queue.push(w);
            }
        }
        None
    }

    /// The first step of a shortest path from `from` to the nearest known
    /// unvisited vertex (the first found in adjacency-slot order); `None`
    /// when none is reachable.
    pub fn step_to_unvisited(
        &mut self,
        grid: &Grid,
        map: &Map,
        from: VertexId,
        blocked: &[VertexId],
    ) -> Option<VertexId> {
        let g = self.start(grid.len(), &[from], blocked);
        let v = self.run(grid, map, g, |_, v| v != from && !map.visited(v))?;
        Some(self.first[v as usize])
    }

    /// Every known unvisited vertex at the least distance from `from`, in
    /// search order, into `out`; returns that distance (`None`: none is
    /// reachable).
    pub fn nearest_unvisited(
        &mut self,
        grid: &Grid,
        map: &Map,
        from: VertexId,
        blocked: &[VertexId],
        out: &mut Vec<VertexId>,
    ) -> Option<u32> {
        self.nearest_where(grid, map, from, blocked, out, |_, _| true)
    }

    /// [`Paths::nearest_unvisited`] among the unvisited vertices `v` at
    /// distance `d` for which `accept(v, d)` holds.
    pub fn nearest_where(
        &mut self,
        grid: &Grid,
        map: &Map,
        from: VertexId,
        blocked: &[VertexId],
        out: &mut Vec<VertexId>,
        accept: impl Fn(VertexId, u32) -> bool,
    ) -> Option<u32> {
        out.clear();
        let g = self.start(grid.len(), &[from], blocked);
        let mut level = None;
        self.run(grid, map, g, |s, v| {
            let d = s.dist[v as usize];
            if level.is_some_and(|l| d > l) {
                return true;
            }
            if v != from && !map.visited(v) && accept(v, d) {
                level = Some(d);
                out.push(v);
            }
            false
        });
        level
    }

    /// Every known unvisited vertex at most `slack` farther from `from`
    /// than the nearest, with its distance, in search order, into `out`;
    /// returns the nearest's distance (`None`: none is reachable).
    pub fn unvisited_within(
        &mut self,
        grid: &Grid,
        map: &Map,
        from: VertexId,
        blocked: &[VertexId],
        slack: u32,
        out: &mut Vec<(VertexId, u32)>,
    ) -> Option<u32> {
        self.unvisited_within_where(grid, map, from, blocked, slack, out, |_, _| true)
    }

    /// [`Paths::unvisited_within`] among the unvisited vertices `v` at
    /// distance `d` for which `accept(v, d)` holds.
    #[allow(clippy::too_many_arguments)]
    pub fn unvisited_within_where(
        &mut self,
        grid: &Grid,
        map: &Map,
        from: VertexId,
        blocked: &[VertexId],
        slack: u32,
        out: &mut Vec<(VertexId, u32)>,
        accept: impl Fn(VertexId, u32) -> bool,
    ) -> Option<u32> {
        out.clear();
        let g = self.start(grid.len(), &[from], blocked);
        let mut level = None;
        self.run(grid, map, g, |s, v| {
            let d = s.dist[v as usize];
            if level.is_some_and(|l: u32| d > l + slack) {
                return true;
            }
            if v != from && !map.visited(v) && accept(v, d) {
                level.get_or_insert(d);
                out.push((v, d));
            }
            false
        });
        level
    }

    /// Distances from the nearest of `sources` to every reachable vertex.
    pub fn distances_from(&mut self, grid: &Grid, map: &Map, sources: &[VertexId], blocked: &[VertexId]) {
        let g = self.start(grid.len(), sources, blocked);
        self.run(grid, map, g, |_, _| false);
    }

    /// Distances to `to` (edges are symmetric) of every vertex no farther
    /// from it than `from` is, read with [`Paths::dist`] until the next
    /// search: the search stops once it reaches `from`, when every vertex at
    /// `from`'s distance or less has its own (a farther one may read `None`).
    /// Robots ask about the way to a vertex near them, and a search of the
    /// whole map for each was most of what `escape` and `frontier` cost.
    pub fn distances_to(&mut self, grid: &Grid, map: &Map, to: VertexId, from: VertexId, blocked: &[VertexId]) {
        let g = self.start(grid.len(), &[to], blocked);
        self.run(grid, map, g, |_, v| v == from);
    }

    /// The distance the last search found for `v`; `None` if unreached or blocked.
    pub fn dist(&self, v: VertexId) -> Option<u32> {
        let k = v as usize;
        (k < self.stamp.len() && self.stamp[k] == self.generation && self.dist[k] != u32::MAX).then(|| self.dist[k])
    }
}

impl Paths {
    /// The candidates of `view` that start a shortest path from the robot
    /// to `to` (avoiding `blocked`), in slot order.
    pub fn first_steps(&mut self, view: &super::View<'_>, to: VertexId, blocked: &[VertexId]) -> super::Slots {
        let mut out = super::Slots::default();
        self.distances_to(view.grid, view.map, to, view.position, blocked);
        let Some(here) = self.dist(view.position) else {
            return out;
        };
        for &c in view.candidates {
            if self.dist(c).is_some_and(|d| d + 1 == here) {
                out.push(c);
            }
        }
        out
    }
}
