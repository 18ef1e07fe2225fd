//! The detected fraction of `Ad` as a run goes (issue 22, item 4): each
//! place a robot stands on marks the raster cells within `r_st` once, so
//! the fraction is known after every round for the cost of the new places
//! only, and the run's `coverage` is its last value: the cells
//! [`Raster::detected_fraction`] counts, to the bit.
//!
//! Cheap enough for every run of a sweep. The raster's cells are bits in
//! tiles of 8 x 8 (a word each), so a disc of radius `r_st` is a score of
//! words. What a disc covers is worked out once per world and kept
//! ([`Footprints`], shared by threads): for every vertex, one after another
//! in one table, the first time a run stands on one; for a point off the
//! grid (LFP), by the class of its
//! place within a tile and a half of a cell, as the cells surely
//! within `r_st` wherever in that half it lies, and the few cells at the
//! rim that depend on where, tested one by one (256 shapes, about 100 KB:
//! quarters made 1,024 and missed the cache more often than halves test
//! rims). Marking disc by disc a row at a time instead, with no table,
//! took ten times as long. The curve is kept as the
//! times the fraction first reached each hundredth ([`LEVELS`]), not a
//! value per round.

use std::sync::OnceLock;

use super::Raster;
use crate::bitset::Bitset;
use crate::geometry::Point;
use crate::grid::VertexId;
use crate::world::World;

/// Steps of the coverage curve: a run records when its detected fraction
/// first reached `1 / LEVELS`, `2 / LEVELS`, ..., 1.
pub const LEVELS: usize = 100;

/// A tile's side in cells (a tile is one word).
const T: i64 = 8;
/// A point's place within its cell, in steps of `1 / Q` of a side: a
/// point's rim is a band about `1.4 / Q` of a cell wide.
const Q: i64 = 2;
/// Distances within this of `r` are left to the exact test: far above the
/// rounding of coordinates, far below a cell.
const SLACK: f64 = 1e-9;

/// What a point's class covers, a tile at a time: for the tile `dx, dy`
/// tiles from its own (`dt` words on), the cells within `r` wherever in
/// its class the point lies (`sure`), and those within `r` for some places
/// of the class only (`rim`). Apart, so that the loop over a place's
/// tiles reads the offsets and masks it needs and no more.
#[derive(Debug)]
struct Shape {
    dt: Box<[i32]>,
    masks: Box<[(u64, u64)]>,
    dxy: Box<[(i16, i16)]>,
    /// A row of tiles at a time, `(dt, tiles, entries)`: the row's tiles
    /// from `dt` words on, `tiles` of them side by side, hold the entries
    /// `entries` (in order of `dt`). A row none of whose tiles has a cell
    /// left open is passed over with a word or two of [`Coverage`]'s
    /// tiles left open, not a word a tile.
    rows: Box<[(i32, u32, std::ops::Range<u32>)]>,
}

/// Whether any of the bits `from .. from + len` (`len > 0`) is set.
#[inline]
fn any_in(bits: &[u64], from: usize, len: usize) -> bool {
    let last = from + len - 1;
    let (mut w, end) = (from / 64, last / 64);
    let mut mask = !0u64 << (from % 64);
    loop {
        if w == end {
            return bits[w] & mask & (!0u64 >> (63 - last % 64)) != 0;
        }
        if bits[w] & mask != 0 {
            return true;
        }
        w += 1;
        mask = !0;
    }
}

/// Every vertex's footprint, the tiles of its cells of `Ad` within `r`
/// with their bits, one after another: vertex `v`'s are
/// `tiles[at[v]..at[v + 1]]`.
#[derive(Debug)]
struct VertexPrints {
    at: Vec<u32>,
    tiles: Vec<(u32, u64)>,
}

/// What every run on one world shares to measure its coverage: the raster
/// of `Ad` as bits, each vertex's footprint (the tiles of the cells of `Ad`
/// within `r_st` of it, with their bits) and each class of points' shape,
/// both made on first use.
#[derive(Debug)]
pub struct Footprints {
    raster: Raster,
    /// Tiles in a row and in a column, `pad` of them on every side beyond
    /// the raster's (none of `Ad`), so that a disc about any point of the
    /// raster lies on tiles.
    tx: i64,
    ty: i64,
    pad: i64,
    /// Tile `t`'s cells of `Ad`: bit `8 (y % 8) + x % 8` of `inside[t]`.
    inside: Vec<u64>,
    /// A bit a tile: whether it has a cell of `Ad`.
    live: Vec<u64>,
    r: f64,
    /// Made on first use, all at once (LFP's runs never ask).
    vertices: OnceLock<VertexPrints>,
    shapes: Vec<OnceLock<Shape>>,
}

/// `floor(u)` without a call to libm's.
#[inline]
fn floor(u: f64) -> i64 {
    let t = u as i64;
    t - i64::from(t as f64 > u)
}

impl Footprints {
    /// Footprints on `raster`, sensing range `r` (the vertices' those of
    /// the world the runs pass to [`Coverage::on`]).
    pub fn new(raster: Raster, r: f64) -> Self {
        let pad = Self::reach(r, raster.h);
        let tx = raster.nx.div_ceil(T as usize) as i64 + 2 * pad;
        let ty = raster.ny.div_ceil(T as usize) as i64 + 2 * pad;
        let shapes = (0..T * T * Q * Q).map(|_| OnceLock::new()).collect();
        let inside = vec![0; (tx * ty) as usize];
        let live = vec![0; (tx * ty) as usize / 64 + 1];
        let mut f = Footprints { raster, tx, ty, pad, inside, live, r, vertices: OnceLock::new(), shapes };
        for k in (0..f.raster.inside.len()).filter(|&k| f.raster.inside[k]) {
            let (t, bit) = f.tile_bit((k % f.raster.nx) as i64, (k / f.raster.nx) as i64);
            f.inside[t] |= bit;
            f.live[t / 64] |= 1 << (t % 64);
        }
        f
    }

    /// Cells within `span` of a point's, and tiles within `reach` of its tile.
    fn span(r: f64, h: f64) -> i64 {
        (r / h).ceil() as i64 + 1
    }

    fn reach(r: f64, h: f64) -> i64 {
        Self::span(r, h) / T + 2
    }

    /// The raster's cells of `Ad`.
    pub fn samples(&self) -> usize {
        self.raster.count
    }

    /// Cell `(x, y)`'s tile and bit (a cell of the raster).
    #[inline]
    fn tile_bit(&self, x: i64, y: i64) -> (usize, u64) {
        (((y / T + self.pad) * self.tx + x / T + self.pad) as usize, 1 << ((y % T) * T + x % T))
    }

    /// Whether cell `(x, y)` lies within `r` of `c`: [`Raster::mark`]'s
    /// test, the same operations in the same order.
    fn within(&self, x: i64, y: i64, c: Point) -> bool {
        let (o, h) = (self.raster.origin, self.raster.h);
        let p = Point::new(o.x + (x as f64 + 0.5) * h, o.y + (y as f64 + 0.5) * h);
        (p - c).norm() <= self.r
    }

    /// Whether cell `(x, y)` is a cell of the raster in `Ad`.
    #[inline]
    fn in_ad(&self, x: i64, y: i64) -> bool {
        let (nx, ny) = (self.raster.nx as i64, self.raster.ny as i64);
        (0..nx).contains(&x) && (0..ny).contains(&y) && self.raster.inside[(y * nx + x) as usize]
    }

    /// Vertex `v`'s footprint (every vertex's made the first time one is
    /// asked for).
    #[inline]
    fn of(&self, world: &World, v: VertexId) -> &[(u32, u64)] {
        let p = self.vertices.get_or_init(|| self.vertex_prints(world));
        &p.tiles[p.at[v as usize] as usize..p.at[v as usize + 1] as usize]
    }

    fn vertex_prints(&self, world: &World) -> VertexPrints {
        let mut at = Vec::with_capacity(world.grid.len() + 1);
        let mut tiles: Vec<(u32, u64)> = Vec::new();
        at.push(0);
        for v in 0..world.grid.len() as VertexId {
            let c = world.grid.position(v);
            let (o, h, r) = (self.raster.origin, self.raster.h, self.r);
            let (x0, x1) = (floor((c.x - r - o.x) / h) - 1, floor((c.x + r - o.x) / h) + 1);
            let (y0, y1) = (floor((c.y - r - o.y) / h) - 1, floor((c.y + r - o.y) / h) + 1);
            let first = tiles.len();
            for y in y0..=y1 {
                for x in (x0..=x1).filter(|&x| self.in_ad(x, y) && self.within(x, y, c)) {
                    let (t, bit) = self.tile_bit(x, y);
                    match tiles[first..].iter_mut().find(|e| e.0 == t as u32) {
                        Some(e) => e.1 |= bit,
                        None => tiles.push((t as u32, bit)),
                    }
                }
            }
            at.push(u32::try_from(tiles.len()).expect("footprints in range"));
        }
        VertexPrints { at, tiles }
    }

    /// The shape of the points in cell `(ci, cj)` of their tile whose place
    /// in the cell is `[qx, qx + 1] / Q` by `[qy, qy + 1] / Q`: a cell is
    /// surely within `r` if its farthest distance to that box is `SLACK`
    /// under `r`, and on the rim if its nearest is not `SLACK` over it
    /// (rounding moves a point or a distance by far less).
    fn shape(&self, ci: i64, cj: i64, qx: i64, qy: i64) -> Shape {
        let (h, r) = (self.raster.h, self.r);
        let span = Self::span(r, h);
        // The nearest and farthest offsets of a cell's centre from the
        // point over the box, in metres, squared.
        let range = |d: i64, q: i64| {
            let (a, b) = (d as f64 + 0.5 - (q + 1) as f64 / Q as f64, d as f64 + 0.5 - q as f64 / Q as f64);
            let near = if a <= 0.0 && b >= 0.0 { 0.0 } else { a.abs().min(b.abs()) * h };
            let far = a.abs().max(b.abs()) * h;
            (near * near, far * far)
        };
        let (inner, outer) = ((r - SLACK).powi(2), (r + SLACK).powi(2));
        // Tiles from (-w, -w) to (w, w) of the point's own, as `(sure, rim)`.
        let w = self.pad;
        let mut grid = vec![(0u64, 0u64); ((2 * w + 1) * (2 * w + 1)) as usize];
        for dy in -span..=span {
            let (ny, fy) = range(dy, qy);
            let y = cj + dy;
            for dx in -span..=span {
                let (nx, fx) = range(dx, qx);
                if nx + ny > outer {
                    continue;
                }
                let x = ci + dx;
                let cell = &mut grid[((y.div_euclid(T) + w) * (2 * w + 1) + x.div_euclid(T) + w) as usize];
                let bit = 1u64 << (y.rem_euclid(T) * T + x.rem_euclid(T));
                if fx + fy < inner {
                    cell.0 |= bit;
                } else {
                    cell.1 |= bit;
                }
            }
        }
        let side = 2 * w + 1;
        let used: Vec<i64> = (0..grid.len() as i64).filter(|&k| grid[k as usize] != (0, 0)).collect();
        let dxy: Vec<(i64, i64)> = used.iter().map(|&k| (k % side - w, k / side - w)).collect();
        let dts: Vec<i32> =
            dxy.iter().map(|&(dx, dy)| i32::try_from(dy * self.tx + dx).expect("a map of tiles in range")).collect();
        // `used` goes a row at a time, left to right.
        let mut rows: Vec<(i32, u32, std::ops::Range<u32>)> = Vec::new();
        for (e, (&(_, dy), &dt)) in dxy.iter().zip(&dts).enumerate() {
            match rows.last_mut() {
                Some(row) if e > 0 && dxy[e - 1].1 == dy => {
                    row.1 = (dt - row.0 + 1) as u32;
                    row.2.end = e as u32 + 1;
                }
                _ => rows.push((dt, 1, e as u32..e as u32 + 1)),
            }
        }
        Shape {
            rows: rows.into_boxed_slice(),
            dt: dts.into_boxed_slice(),
            masks: used.iter().map(|&k| grid[k as usize]).collect(),
            dxy: dxy.iter().map(|&(dx, dy)| (dx as i16, dy as i16)).collect(),
        }
    }

    /// Clears in `open` (a run's cells of `Ad` not detected yet) the
    /// cells within `r` of the point `c`, returning how many: its class's
    /// sure cells a tile at a time, then its rim cell by cell with the
    /// exact test.
    fn mark_point(&self, open: &mut [u64], live: &mut [u64], c: Point) -> usize {
        let (o, h) = (self.raster.origin, self.raster.h);
        let (u, v) = ((c.x - o.x) / h, (c.y - o.y) / h);
        let (i, j) = (floor(u), floor(v));
        let q = |f: f64| ((f * Q as f64) as i64).clamp(0, Q - 1);
        let (qx, qy) = (q(u - i as f64), q(v - j as f64));
        let (ci, cj) = (i.rem_euclid(T), j.rem_euclid(T));
        let class = (((cj * T + ci) * Q + qy) * Q + qx) as usize;
        let shape = self.shapes[class].get_or_init(|| self.shape(ci, cj, qx, qy));
        let (ti, tj) = (i.div_euclid(T), j.div_euclid(T));
        let open = &mut open[..self.inside.len()];
        let mut new = 0;
        let inner = self.tx - 2 * self.pad;
        if (0..inner).contains(&ti) && (0..self.ty - 2 * self.pad).contains(&tj) {
            // The point is over the raster: its disc lies on tiles.
            let base = (tj + self.pad) * self.tx + ti + self.pad;
            for (dt, tiles, entries) in shape.rows.iter() {
                // Late in a run most rows are done with.
                if !any_in(live, (base + *dt as i64) as usize, *tiles as usize) {
                    continue;
                }
                let entries = entries.start as usize..entries.end as usize;
                for (&dt, &(sure, rim)) in shape.dt[entries.clone()].iter().zip(&shape.masks[entries]) {
                    let t = (base + dt as i64) as usize;
                    let o = open[t];
                    // Most places add nothing: the rest out of this loop's way.
                    if (sure | rim) & o != 0 {
                        new += self.add(open, live, t, sure & o, rim & o, c);
                    }
                }
            }
            return new;
        }
        for (&(dx, dy), &(sure, rim)) in shape.dxy.iter().zip(shape.masks.iter()) {
            let (a, b) = (ti + self.pad + dx as i64, tj + self.pad + dy as i64);
            if a < 0 || b < 0 || a >= self.tx || b >= self.ty {
                continue;
            }
            let t = (b * self.tx + a) as usize;
            let o = open[t];
            if (sure | rim) & o != 0 {
                new += self.add(open, live, t, sure & o, rim & o, c);
            }
        }
        new
    }

    /// Clears in tile `t` the cells `sure` and those of `rim` within `r`
    /// of `c`, all open; returns how many.
    #[inline(never)]
    fn add(&self, open: &mut [u64], live: &mut [u64], t: usize, sure: u64, rim: u64, c: Point) -> usize {
        let (x, y) = ((t as i64 % self.tx - self.pad) * T, (t as i64 / self.tx - self.pad) * T);
        let mut fresh = sure;
        let mut left = rim;
        while left != 0 {
            let bit = left.trailing_zeros() as i64;
            left &= left - 1;
            if self.within(x + bit % T, y + bit / T, c) {
                fresh |= 1 << bit;
            }
        }
        clear(open, live, t, fresh);
        fresh.count_ones() as usize
    }
}

/// Clears the cells `fresh` of tile `t` in `open`, and the tile's bit in
/// `live` once it has none left.
#[inline]
fn clear(open: &mut [u64], live: &mut [u64], t: usize, fresh: u64) {
    open[t] &= !fresh;
    if open[t] == 0 {
        live[t / 64] &= !(1 << (t % 64));
    }
}

/// One run's detected fraction as it goes, and the times it first reached
/// each level of its curve.
#[derive(Debug)]
pub struct Coverage<'w> {
    world: &'w World,
    prints: &'w Footprints,
    /// The cells of `Ad` not detected yet, as [`Footprints::inside`], and
    /// a bit a tile: whether it has any.
    open: Vec<u64>,
    live: Vec<u64>,
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
            open: prints.inside.clone(),
            live: prints.live.clone(),
            stood: Bitset::new(world.grid.len()),
            detected: 0,
            reached: Vec::new(),
        }
    }

    /// A robot stands on vertex `v`.
    #[inline]
    pub fn stand(&mut self, v: VertexId) {
        if !self.stood.get(v as usize) {
            self.mark(v);
        }
    }

    /// Marks vertex `v`'s footprint, the first time a robot stands there.
    fn mark(&mut self, v: VertexId) {
        self.stood.set(v as usize);
        for &(t, bits) in self.prints.of(self.world, v) {
            let fresh = bits & self.open[t as usize];
            if fresh != 0 {
                self.detected += fresh.count_ones() as usize;
                clear(&mut self.open, &mut self.live, t as usize, fresh);
            }
        }
    }

    /// A robot stands at `p`, off the grid.
    pub fn pass(&mut self, p: Point) {
        self.detected += self.prints.mark_point(&mut self.open, &mut self.live, p);
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

    /// Points anywhere in and around the area, some on cells' rows and
    /// columns and at `r` from them, and the vertices: both ways of marking
    /// give exactly the cells of the raster's own test.
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
            let snap = |x: f64, o: f64| o + ((x - o) / raster.h).round() * raster.h + 0.5 * raster.h;
            for k in 0..5000 {
                let p = if k % 3 == 0 {
                    let v = rng.random_range(0..world.grid.len() as VertexId);
                    cov.stand(v);
                    world.grid.position(v)
                } else {
                    let (x, y) = (rng.random_range(lo.x - 2.0..hi.x + 2.0), rng.random_range(lo.y - 2.0..hi.y + 2.0));
                    let mut p = Point::new(x, y);
                    if k % 5 == 0 {
                        p.y = snap(p.y, raster.origin.y);
                    }
                    if k % 7 == 0 {
                        p.x = snap(p.x, raster.origin.x) + r;
                    }
                    if k % 11 == 0 {
                        p = Point::new(snap(p.x, raster.origin.x), snap(p.y, raster.origin.y));
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
    fn any_in_reads_exactly_its_range() {
        for bit in [0usize, 5, 63, 64, 100, 127, 128, 191] {
            let mut bits = [0u64; 3];
            bits[bit / 64] |= 1 << (bit % 64);
            for from in 0..180 {
                for len in 1..(192 - from).min(70) {
                    assert_eq!(any_in(&bits, from, len), (from..from + len).contains(&bit), "{bit} in {from} + {len}");
                }
            }
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
