//! What an LFP robot senses of the obstacles and the boundary, made cheap.
//!
//! The area's edges, the obstacle polygons' edges and the obstacle circles are
//! flattened into primitive features, and every cell of a coarse square index
//! lists the features that can matter to a robot standing in it: those within
//! `reach` of some point of the cell. `reach` covers both the sonar range
//! `r_so` (repulsion) and `a + r_safe` (a sub-step of length at most `a` is
//! checked for clearance), so a query never misses a feature that matters,
//! and in open space the list is empty and a query costs nothing.

use crate::geometry::{point_segment_distance, segment_segment_distance, Point, Shape, Vector};
use crate::world::World;

#[derive(Clone, Copy, Debug)]
enum Feature {
    Edge(Point, Point),
    Circle(Point, f64),
}

impl Feature {
    fn point_distance(&self, p: Point) -> f64 {
        match *self {
            Feature::Edge(a, b) => point_segment_distance(p, a, b),
            Feature::Circle(c, r) => ((p - c).norm() - r).max(0.0),
        }
    }

    /// Distance from the segment `[p, q]`; the same primitives as
    /// `Shape::segment_distance`, so the referee and the robot agree.
    fn segment_distance(&self, p: Point, q: Point) -> f64 {
        match *self {
            Feature::Edge(a, b) => segment_segment_distance(p, q, a, b),
            Feature::Circle(c, r) => (point_segment_distance(c, p, q) - r).max(0.0),
        }
    }

    /// Distance from `p` and the unit vector pointing from the feature to `p`
    /// (zero when `p` lies on the feature); `None` when the squared distance
    /// exceeds `beyond2`, before the square root and divisions that most
    /// listed features would not need.
    fn away(&self, p: Point, beyond2: f64) -> Option<(f64, Vector)> {
        let closest = match *self {
            Feature::Edge(a, b) => {
                let ab = b - a;
                let len2 = ab.norm_squared();
                let t = if len2 == 0.0 { 0.0 } else { ((p - a).dot(&ab) / len2).clamp(0.0, 1.0) };
                a + ab * t
            }
            Feature::Circle(c, r) => {
                let v = p - c;
                let n = v.norm();
                if n == 0.0 {
                    return Some((0.0, Vector::zeros()));
                }
                c + v * (r / n)
            }
        };
        let v = p - closest;
        // `norm` is the square root of `norm_squared`: the same `d` as before.
        let d2 = v.norm_squared();
        if d2 > beyond2 {
            return None;
        }
        let d = d2.sqrt();
        if d == 0.0 {
            Some((0.0, Vector::zeros()))
        } else {
            Some((d, v / d))
        }
    }
}

/// The features of a world bucketed by coarse cells (compressed rows).
#[derive(Clone, Debug)]
pub(super) struct Sensing {
    features: Vec<Feature>,
    origin: Point,
    cell: f64,
    nx: usize,
    ny: usize,
    /// Features of cell `k` are `items[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
    r_safe: f64,
}

impl Sensing {
    pub(super) fn new(world: &World) -> Self {
        let p = &world.params;
        let mut features: Vec<Feature> = world.area.edges().map(|(a, b)| Feature::Edge(a, b)).collect();
        for o in &world.obstacles {
            match o {
                Shape::Polygon(poly) => features.extend(poly.edges().map(|(a, b)| Feature::Edge(a, b))),
                Shape::Circle(c) => features.push(Feature::Circle(c.center, c.radius)),
            }
        }
        // Half a grid side keeps the lists short (a few features near a
        // wall) while the index stays about a thousand cells on a 20 x 16 m map.
        let cell = if p.a > 0.0 { p.a / 2.0 } else { 0.5 };
        let (lo, hi) = world.area.bounding_box();
        let nx = (((hi.x - lo.x) / cell).ceil().max(1.0) as usize) + 1;
        let ny = (((hi.y - lo.y) / cell).ceil().max(1.0) as usize) + 1;
        let half_diag = cell * std::f64::consts::FRAC_1_SQRT_2;
        let reach = p.r_so.max(p.a + p.r_safe).max(0.0) + half_diag;
        // (cell, feature) pairs, then a counting sort into compressed rows:
        // one allocation each instead of one per cell.
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        for (k, f) in features.iter().enumerate() {
            let (flo, fhi) = match *f {
                Feature::Edge(a, b) => (Point::new(a.x.min(b.x), a.y.min(b.y)), Point::new(a.x.max(b.x), a.y.max(b.y))),
                Feature::Circle(c, r) => (Point::new(c.x - r, c.y - r), Point::new(c.x + r, c.y + r)),
            };
            let range = |lo_v: f64, hi_v: f64, o: f64, n: usize| {
                let a = ((lo_v - reach - o) / cell).floor().max(0.0) as usize;
                let b = (((hi_v + reach - o) / cell).floor().max(0.0) as usize).min(n - 1);
                (a, b)
            };
            let (x0, x1) = range(flo.x, fhi.x, lo.x, nx);
            let (y0, y1) = range(flo.y, fhi.y, lo.y, ny);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let centre = Point::new(lo.x + (x as f64 + 0.5) * cell, lo.y + (y as f64 + 0.5) * cell);
                    if f.point_distance(centre) - half_diag <= reach {
                        pairs.push(((y * nx + x) as u32, k as u32));
                    }
                }
            }
        }
        let mut start = vec![0u32; nx * ny + 1];
        for &(c, _) in &pairs {
            start[c as usize + 1] += 1;
        }
        for k in 0..nx * ny {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; pairs.len()];
        for &(c, k) in &pairs {
            items[fill[c as usize] as usize] = k;
            fill[c as usize] += 1;
        }
        Sensing { features, origin: lo, cell, nx, ny, start, items, r_safe: p.r_safe }
    }

    fn cell_items(&self, p: Point) -> &[u32] {
        // The cast truncates, which is floor on the clamped non-negative value
        // and avoids a libm call on the hot path.
        let x = (((p.x - self.origin.x) / self.cell).max(0.0) as usize).min(self.nx - 1);
        let y = (((p.y - self.origin.y) / self.cell).max(0.0) as usize).min(self.ny - 1);
        let k = y * self.nx + x;
        &self.items[self.start[k] as usize..self.start[k + 1] as usize]
    }

    /// The sum of the obstacle and boundary repulsions sensed at `p`, and
    /// the distance to the nearest feature listed for `p`'s cell (infinite
    /// when none is) if it is within `care`: a caller comparing it with a
    /// threshold up to `care` gets the same answer. Each feature within
    /// `r_so` pushes with Khatib's magnitude `gain * (1/d - 1/r_so) / d^2`,
    /// away from its nearest point.
    pub(super) fn sense(&self, p: Point, r_so: f64, gain: f64, care: f64) -> (Vector, f64) {
        let mut f = Vector::zeros();
        let mut nearest = f64::INFINITY;
        let inv_r = 1.0 / r_so;
        // A feature further than both neither pushes nor decides a
        // comparison; the margin keeps rounding of the square on the safe side.
        let beyond = r_so.max(care).max(0.0) * (1.0 + 1e-9);
        let beyond2 = beyond * beyond;
        for &k in self.cell_items(p) {
            let Some((d, dir)) = self.features[k as usize].away(p, beyond2) else { continue };
            nearest = nearest.min(d);
            if d > 1e-9 && d < r_so && gain != 0.0 {
                f += dir * (gain * (1.0 / d - inv_r) / (d * d));
            }
        }
        (f, nearest)
    }

    /// The largest fraction `t` of the move `p -> p + v` (with `|v| <= a`)
    /// along which the robot keeps `r_safe` from every feature, to within
    /// 2^-10 of the move; `1.0` when the whole move is clear.
    pub(super) fn clear_fraction(&self, p: Point, v: Vector) -> f64 {
        let items = self.cell_items(p);
        if items.is_empty() {
            return 1.0;
        }
        let clear = |t: f64| {
            let q = p + v * t;
            items.iter().all(|&k| self.features[k as usize].segment_distance(p, q) >= self.r_safe)
        };
        if clear(1.0) {
            return 1.0;
        }
        // The clear prefixes of a segment are an interval starting at 0.
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..10 {
            let mid = 0.5 * (lo + hi);
            if clear(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }
}
