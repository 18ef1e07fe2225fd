//! The detected fraction of `Ad` as a run goes (issue 22, item 4): each
//! place a robot stands on marks the raster cells within `r_st` once, so
//! the fraction is known after every round for the cost of the new places
//! only, and the run's `coverage` is its last value: the cells
//! [`Raster::detected_fraction`] counts, to the bit.
//!
//! Cheap enough for every run of a sweep: the raster's cells are bits, a
//! vertex's cells within `r_st` are worked out the first time any run of the
//! world stands on it and kept ([`Footprints`], shared by threads), and a
//! point off the grid (LFP) marks a row of its disc a few words at a time.
//! The curve is kept as the times the fraction first reached each
//! hundredth ([`LEVELS`]), not a value per round.

use std::sync::OnceLock;

use super::Raster;
use crate::bitset::Bitset;
use crate::geometry::Point;
use crate::grid::VertexId;
use crate::world::World;

/// Steps of the coverage curve: a run records when its detected fraction
/// first reached `1 / LEVELS`, `2 / LEVELS`, ..., 1.
pub const LEVELS: usize = 100;

/// What every run on one world shares to measure its coverage: the raster
/// of `Ad` as bits, and each vertex's footprint (the words of the cells of
/// `Ad` within `r_st` of it, with their bits), made on first use.
#[derive(Debug)]
pub struct Footprints {
    raster: Raster,
    /// Cell `k` of `Ad` is bit `k % 64` of word `k / 64`.
    inside: Vec<u64>,
    r: f64,
    vertices: Vec<OnceLock<Box<[(u32, u64)]>>>,
}

impl Footprints {
    /// Footprints on `raster` of the vertices of `world`'s grid, sensing range `r`.
    pub fn new(world: &World, raster: Raster, r: f64) -> Self {
        let mut inside = vec![0u64; raster.inside.len().div_ceil(64)];
        for (k, _) in raster.inside.iter().enumerate().filter(|(_, &b)| b) {
            inside[k / 64] |= 1 << (k % 64);
        }
        let vertices = (0..world.grid.len()).map(|_| OnceLock::new()).collect();
        Footprints { raster, inside, r, vertices }
    }

    /// The raster's cells of `Ad`.
    pub fn samples(&self) -> usize {
        self.raster.count
    }

    /// The rows of cells a disc of radius `r` at `c` may touch, and their
    /// columns: the bounds [`Raster::mark`] loops over.
    fn bounds(&self, c: Point) -> (usize, usize, usize, usize) {
        let (o, h, r) = (self.raster.origin, self.raster.h, self.r);
        let x0 = (((c.x - r - o.x) / h).floor().max(0.0)) as usize;
        let y0 = (((c.y - r - o.y) / h).floor().max(0.0)) as usize;
        let x1 = (((c.x + r - o.x) / h).ceil().max(0.0) as usize).min(self.raster.nx);
        let y1 = (((c.y + r - o.y) / h).ceil().max(0.0) as usize).min(self.raster.ny);
        (x0, y0, x1, y1)
    }

    /// Whether cell `(x, y)` lies within `r` of `c`: [`Raster::mark`]'s test,
    /// the same operations in the same order.
    fn within(&self, x: usize, y: usize, c: Point) -> bool {
        let (o, h) = (self.raster.origin, self.raster.h);
        let p = Point::new(o.x + (x as f64 + 0.5) * h, o.y + (y as f64 + 0.5) * h);
        (p - c).norm() <= self.r
    }

    /// Vertex `v`'s footprint, made the first time it is asked for.
    fn of(&self, world: &World, v: VertexId) -> &[(u32, u64)] {
        self.vertices[v as usize].get_or_init(|| {
            let c = world.grid.position(v);
            let (x0, y0, x1, y1) = self.bounds(c);
            let mut words: Vec<(u32, u64)> = Vec::new();
            for y in y0..y1 {
                for x in (x0..x1).filter(|&x| self.within(x, y, c)) {
                    let k = y * self.raster.nx + x;
                    if !self.raster.inside[k] {
                        continue;
                    }
                    let w = (k / 64) as u32;
                    match words.last_mut() {
                        Some(last) if last.0 == w => last.1 |= 1 << (k % 64),
                        _ => words.push((w, 1 << (k % 64))),
                    }
                }
            }
            words.into_boxed_slice()
        })
    }

    /// Marks in `hit` the cells of `Ad` within `r` of the point `c`,
    /// returning how many were new. Each row's cells within `r` are a run
    /// of columns (the test is monotone in the column), found from the
    /// disc's width at the row; a row whose ends fall within a rounding
    /// error of a cell's centre is tested cell by cell, so the cells are
    /// exactly [`Raster::mark`]'s.
    fn mark_point(&self, hit: &mut [u64], c: Point) -> usize {
        let (o, h, r, nx) = (self.raster.origin, self.raster.h, self.r, self.raster.nx);
        let (x0, y0, x1, y1) = self.bounds(c);
        // Column units: a rounding error is some 1e-13 of them at most.
        const MARGIN: f64 = 1e-6;
        let mut new = 0;
        for y in y0..y1 {
            let dy = o.y + (y as f64 + 0.5) * h - c.y;
            let s = r * r - dy * dy;
            if s < -1e-9 * r * r {
                continue;
            }
            let (lo, hi) = if s > 1e-6 * r * r {
                let half = s.sqrt();
                let u0 = (c.x - half - o.x) / h - 0.5;
                let u1 = (c.x + half - o.x) / h - 0.5;
                let (a, b) = (u0.ceil(), u1.floor());
                let near = |f: f64| !(MARGIN..=1.0 - MARGIN).contains(&f);
                if near(a - u0) || near(u1 - b) {
                    self.exact_row(y, x0, x1, c)
                } else {
                    ((a.max(x0 as f64) as usize).max(x0), ((b + 1.0).max(0.0) as usize).min(x1))
                }
            } else {
                self.exact_row(y, x0, x1, c)
            };
            if lo < hi {
                new += self.fill(hit, y * nx + lo, y * nx + hi);
            }
        }
        new
    }

    /// The columns of row `y` within `r` of `c`, by testing each cell of the box.
    fn exact_row(&self, y: usize, x0: usize, x1: usize, c: Point) -> (usize, usize) {
        let mut cols = (x0..x1).filter(|&x| self.within(x, y, c));
        match cols.next() {
            Some(first) => (first, cols.last().unwrap_or(first) + 1),
            None => (0, 0),
        }
    }

    /// Marks cells `k0..k1` of `Ad` in `hit`, returning how many were new.
    fn fill(&self, hit: &mut [u64], k0: usize, k1: usize) -> usize {
        let (first, last) = (k0 / 64, (k1 - 1) / 64);
        let mut new = 0;
        for w in first..=last {
            let mut mask = !0u64;
            if w == first {
                mask &= !0u64 << (k0 % 64);
            }
            if w == last {
                mask &= !0u64 >> (63 - (k1 - 1) % 64);
            }
            let fresh = mask & self.inside[w] & !hit[w];
            new += fresh.count_ones() as usize;
            hit[w] |= fresh;
        }
        new
    }
}

/// One run's detected fraction as it goes, and the times it first reached
/// each level of its curve.
#[derive(Debug)]
pub struct Coverage<'w> {
    world: &'w World,
    prints: &'w Footprints,
    hit: Vec<u64>,
    /// Vertices already marked (each marks the same cells every time).
    stood: Bitset,
    detected: usize,
    reached: Vec<f64>,
}

impl<'w> Coverage<'w> {
    /// Nothing detected yet, on the world's own raster ([`World::footprints`]).
    pub fn new(world: &'w World) -> Self {
        Coverage::on(world, world.footprints())
    }

    /// Nothing detected yet, on `prints` (made for `world`).
    pub fn on(world: &'w World, prints: &'w Footprints) -> Self {
        Coverage {
            world,
            prints,
            hit: vec![0; prints.inside.len()],
            stood: Bitset::new(world.grid.len()),
            detected: 0,
            reached: Vec::new(),
        }
    }

    /// A robot stands on vertex `v`.
    #[inline]
    pub fn stand(&mut self, v: VertexId) {
        if self.stood.get(v as usize) {
            return;
        }
        self.stood.set(v as usize);
        for &(w, bits) in self.prints.of(self.world, v) {
            let fresh = bits & !self.hit[w as usize];
            self.detected += fresh.count_ones() as usize;
            self.hit[w as usize] |= fresh;
        }
    }

    /// A robot stands at `p`, off the grid.
    pub fn pass(&mut self, p: Point) {
        self.detected += self.prints.mark_point(&mut self.hit, p);
    }

    /// Everything marked so far was detected by simulated time `t`
    /// (nondecreasing from call to call): records the levels it reached.
    pub fn at(&mut self, t: f64) {
        let samples = self.prints.samples();
        while self.reached.len() < LEVELS && self.detected * LEVELS >= (self.reached.len() + 1) * samples {
            self.reached.push(t);
        }
    }

    /// The detected fraction of `Ad` so far (1 when the raster has no cell of it).
    pub fn fraction(&self) -> f64 {
        let samples = self.prints.samples();
        if samples == 0 {
            1.0
        } else {
            self.detected as f64 / samples as f64
        }
    }

    /// The times the fraction first reached each level, as far as it went.
    pub fn curve(self) -> Vec<f64> {
        self.reached
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::Scenario;
    use rand::{Rng, SeedableRng};

    /// Points anywhere in and around the area, and the vertices: both ways
    /// of marking give exactly the cells of the raster's own test.
    #[test]
    fn marks_the_cells_the_raster_counts() {
        for name in ["paper", "cave"] {
            let world = Scenario::builtin(name).unwrap().world();
            let raster = world.raster(crate::engine::RASTER_CELL * world.params.a);
            let r = world.params.r_st;
            let (lo, hi) = world.area.bounding_box();
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
            let mut cov = Coverage::new(&world);
            let mut hit = raster.unmarked();
            let mut expected = 0;
            for k in 0..3000 {
                let p = if k % 3 == 0 {
                    let v = rng.random_range(0..world.grid.len() as VertexId);
                    cov.stand(v);
                    world.grid.position(v)
                } else {
                    // Some on cell centres' rows and columns exactly.
                    let snap = |x: f64, o: f64| o + ((x - o) / raster.h).round() * raster.h + 0.5 * raster.h;
                    let mut p = Point::new(rng.random_range(lo.x - 2.0..hi.x + 2.0), rng.random_range(lo.y - 2.0..hi.y + 2.0));
                    if k % 5 == 0 {
                        p.y = snap(p.y, raster.origin.y);
                    }
                    if k % 7 == 0 {
                        p.x = snap(p.x, raster.origin.x) + r;
                    }
                    cov.pass(p);
                    p
                };
                expected += raster.mark(&mut hit, p, r);
                assert_eq!(cov.detected, expected, "{name}, point {k} at {p:?}");
            }
            assert_eq!(cov.fraction(), expected as f64 / raster.samples() as f64);
        }
    }

    #[test]
    fn levels_are_reached_in_order_and_once() {
        let world = Scenario::builtin("paper").unwrap().world();
        let mut cov = Coverage::new(&world);
        cov.at(0.0);
        assert!(cov.reached.is_empty());
        for (k, v) in world.accessible_vertices().enumerate() {
            cov.stand(v);
            cov.at(k as f64);
        }
        let f = cov.fraction();
        let curve = cov.curve();
        assert_eq!(curve.len(), (f * LEVELS as f64 + 1e-9).floor() as usize);
        assert!(curve.windows(2).all(|w| w[0] <= w[1]));
        assert!(f > 0.99, "every accessible vertex stood on detects nearly all: {f}");
    }
}
