//! Which items can be near a point, without testing them all: a grid of
//! cells over a box, each listing the items (obstacles, area edges,
//! targets) whose box, grown by a margin, overlaps it. Building a world
//! asks this for every vertex and edge; a 400 x 400 m map has about a
//! million vertices and may have thousands of obstacles and a thousand
//! area corners, and testing every one of them took minutes.
//!
//! A cell's list is a superset of what matters (exact tests follow), in
//! ascending item order, so that results built from it are those of
//! testing every item.

use crate::geometry::Point;

pub(crate) struct Buckets {
    lo: Point,
    /// Cell sides along x and y.
    side: (f64, f64),
    nx: usize,
    ny: usize,
    /// Items of cell `k` are `items[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Buckets {
    /// Cells of `side` over `[lo, hi]`; item `k` is listed in every cell its
    /// box `boxes[k]` grown by `margin` overlaps (points outside the box
    /// belong to the nearest cell, so queries never fall off the grid).
    pub(crate) fn new(lo: Point, hi: Point, side: (f64, f64), boxes: &[(Point, Point)], margin: f64) -> Self {
        let count = |extent: f64, s: f64| ((extent / s).floor().max(0.0) as usize).saturating_add(1).min(1 << 20);
        let (nx, ny) = (count(hi.x - lo.x, side.0), count(hi.y - lo.y, side.1));
        let mut b = Buckets { lo, side, nx, ny, start: vec![0; nx * ny + 1], items: Vec::new() };
        // Rounding in the cell arithmetic must never drop an item.
        let m = margin * (1.0 + 1e-9) + 1e-9 * (side.0 + side.1);
        let ranges: Vec<(usize, usize, usize, usize)> = boxes.iter().map(|bx| b.range(bx, m)).collect();
        // Counting sort into compressed rows: items stay in ascending order.
        for &(x0, x1, y0, y1) in &ranges {
            for y in y0..=y1 {
                for x in x0..=x1 {
                    b.start[y * nx + x + 1] += 1;
                }
            }
        }
        for k in 0..nx * ny {
            b.start[k + 1] += b.start[k];
        }
        let mut fill = b.start.clone();
        b.items = vec![0; b.start[nx * ny] as usize];
        for (k, &(x0, x1, y0, y1)) in ranges.iter().enumerate() {
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let c = y * nx + x;
                    b.items[fill[c] as usize] = k as u32;
                    fill[c] += 1;
                }
            }
        }
        b
    }

    /// The cells `(x0, x1, y0, y1)`, inclusive, that the box grown by `m` overlaps.
    fn range(&self, (a, z): &(Point, Point), m: f64) -> (usize, usize, usize, usize) {
        let (x0, y0) = self.cell(Point::new(a.x - m, a.y - m));
        let (x1, y1) = self.cell(Point::new(z.x + m, z.y + m));
        (x0, x1, y0, y1)
    }

    /// Calls `f(i, j, first)`, `i < j`, for every two items listed in a
    /// common cell, cell by cell (not in item order), until `f` returns
    /// false. `first` is true in the first cell the two ranges share only,
    /// so a pair of items spread over many cells is handled once, though
    /// looked at (and paid for) in each. `boxes` and `margin` must be those
    /// the buckets were made with.
    pub(crate) fn pairs(&self, boxes: &[(Point, Point)], margin: f64, mut f: impl FnMut(u32, u32, bool) -> bool) {
        let m = margin * (1.0 + 1e-9) + 1e-9 * (self.side.0 + self.side.1);
        for y in 0..self.ny {
            for x in 0..self.nx {
                let k = y * self.nx + x;
                let items = &self.items[self.start[k] as usize..self.start[k + 1] as usize];
                for (n, &i) in items.iter().enumerate() {
                    let (ix, _, iy, _) = self.range(&boxes[i as usize], m);
                    for &j in &items[n + 1..] {
                        let (jx, _, jy, _) = self.range(&boxes[j as usize], m);
                        if !f(i, j, (ix.max(jx), iy.max(jy)) == (x, y)) {
                            return;
                        }
                    }
                }
            }
        }
    }

    fn cell(&self, p: Point) -> (usize, usize) {
        let idx = |v: f64, o: f64, s: f64, n: usize| (((v - o) / s).floor().max(0.0) as usize).min(n - 1);
        (idx(p.x, self.lo.x, self.side.0, self.nx), idx(p.y, self.lo.y, self.side.1, self.ny))
    }

    /// Every item whose grown box contains `p` (and maybe others), ascending.
    pub(crate) fn near(&self, p: Point) -> &[u32] {
        let (x, y) = self.cell(p);
        let k = y * self.nx + x;
        &self.items[self.start[k] as usize..self.start[k + 1] as usize]
    }
}
