//! The three regular lattices of Sec. 3, with exact integer vertex coordinates.
//!
//! Every lattice is addressed in the same skewed integer frame `(i, j)`; a
//! vertex's position is derived from it, never stored as the source of truth.
//! Priorities (step 4) compare the integer keys of [`Lattice::priority_key`],
//! so no float rounding can ever make two robots disagree on an order.

use serde::{Deserialize, Serialize};

use crate::geometry::Point;

/// Which regular tessellation the robots move on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LatticeKind {
    /// Equilateral triangles: 6 neighbours at distance `a` (the paper's grid).
    Triangular,
    /// Squares: 4 neighbours.
    Square,
    /// Regular hexagons (honeycomb): 3 neighbours.
    Hexagonal,
}

impl LatticeKind {
    pub const ALL: [LatticeKind; 3] = [LatticeKind::Triangular, LatticeKind::Square, LatticeKind::Hexagonal];

    pub fn name(self) -> &'static str {
        match self {
            LatticeKind::Triangular => "triangular",
            LatticeKind::Square => "square",
            LatticeKind::Hexagonal => "hexagonal",
        }
    }
}

impl std::str::FromStr for LatticeKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "triangular" => Ok(LatticeKind::Triangular),
            "square" => Ok(LatticeKind::Square),
            "hexagonal" => Ok(LatticeKind::Hexagonal),
            other => Err(format!("unknown grid `{other}` (expected triangular, square or hexagonal)")),
        }
    }
}

/// Integer lattice coordinates of a vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Coord {
    pub i: i32,
    pub j: i32,
}

impl Coord {
    pub const fn new(i: i32, j: i32) -> Self {
        Coord { i, j }
    }
}

/// The largest number of neighbours any lattice has; adjacency tables use it
/// as their fixed width.
pub const MAX_DEGREE: usize = 6;

/// Neighbour offsets of the triangular lattice in counter-clockwise order
/// starting at angle 0. Direction `d` and `(d + 3) % 6` are opposite.
const TRI_DIRS: [(i32, i32); 6] = [(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)];
const SQ_DIRS: [(i32, i32); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];

/// A lattice of side `a`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Lattice {
    pub kind: LatticeKind,
    pub a: f64,
}

const SQRT3_2: f64 = 0.866_025_403_784_438_6;

impl Lattice {
    pub fn new(kind: LatticeKind, a: f64) -> Self {
        Lattice { kind, a }
    }

    /// Whether `(i, j)` is a vertex of this lattice. The honeycomb is the
    /// triangular lattice of the same side with every third vertex (the
    /// hexagon centres, `i - j ≡ 0 mod 3`) removed.
    #[inline]
    pub fn contains(&self, c: Coord) -> bool {
        match self.kind {
            LatticeKind::Hexagonal => (c.i - c.j).rem_euclid(3) != 0,
            _ => true,
        }
    }

    #[inline]
    pub fn position(&self, c: Coord) -> Point {
        self.position_of(c.i as f64, c.j as f64)
    }

    /// The position of real-valued lattice coordinates. Positions are linear
    /// in `(i, j)`, so a mean of positions is the position of the mean.
    #[inline]
    pub fn position_of(&self, i: f64, j: f64) -> Point {
        match self.kind {
            LatticeKind::Square => Point::new(self.a * i, self.a * j),
            LatticeKind::Triangular | LatticeKind::Hexagonal => {
                Point::new(self.a * (i + 0.5 * j), self.a * SQRT3_2 * j)
            }
        }
    }

    /// Exact key with the same order as the position's `(x, y)`: robot `j`
    /// has priority over robot `i` when `key(j) > key(i)` (step 4).
    #[inline]
    pub fn priority_key(&self, c: Coord) -> (i64, i64) {
        match self.kind {
            LatticeKind::Square => (c.i as i64, c.j as i64),
            // x = a (2i + j) / 2 and y = a √3 j / 2: both monotone in these.
            LatticeKind::Triangular | LatticeKind::Hexagonal => (2 * c.i as i64 + c.j as i64, c.j as i64),
        }
    }

    /// The vertex's class in a colouring where any two vertices at most
    /// `2a` apart differ ([`Lattice::classes`] classes): two robots that
    /// can collide in a slot start at most `2a` apart (ARCHITECTURE.md,
    /// "Safety", S0), so robots of one class never can. The classes are
    /// the cosets of a sublattice whose shortest vector is longer than
    /// `2a`: `(2, 1)`, `sqrt(7) a` long, on the triangular lattice (and on
    /// the honeycomb, its subset); `(2, 1)`, `sqrt(5) a`, on the square one.
    pub fn class(&self, c: Coord) -> u8 {
        match self.kind {
            LatticeKind::Triangular | LatticeKind::Hexagonal => (c.i + 3 * c.j).rem_euclid(7) as u8,
            LatticeKind::Square => (c.i + 2 * c.j).rem_euclid(5) as u8,
        }
    }

    /// How many classes [`Lattice::class`] has.
    pub fn classes(&self) -> u8 {
        match self.kind {
            LatticeKind::Triangular | LatticeKind::Hexagonal => 7,
            LatticeKind::Square => 5,
        }
    }

    /// The neighbour offsets of the vertex `c` (for the honeycomb they depend
    /// on which of its two sublattices `c` is on).
    #[inline]
    pub fn offsets(&self, c: Coord) -> &'static [(i32, i32)] {
        match self.kind {
            LatticeKind::Triangular => &TRI_DIRS,
            LatticeKind::Square => &SQ_DIRS,
            LatticeKind::Hexagonal => {
                // B's slot d is A's slot d reversed, so that an edge read
                // from either end sits in the same slot (`Grid::opposite`).
                const A: [(i32, i32); 3] = [(1, 0), (-1, 1), (0, -1)];
                const B: [(i32, i32); 3] = [(-1, 0), (1, -1), (0, 1)];
                if (c.i - c.j).rem_euclid(3) == 1 {
                    &A
                } else {
                    &B
                }
            }
        }
    }

    /// The lattice coordinate whose position is nearest to `p`.
    #[inline]
    pub fn nearest(&self, p: Point) -> Coord {
        let (x, y) = (p.x / self.a, p.y / self.a);
        let guess = match self.kind {
            LatticeKind::Square => Coord::new(x.round() as i32, y.round() as i32),
            _ => {
                let j = (y / SQRT3_2).round() as i32;
                Coord::new((x - 0.5 * j as f64).round() as i32, j)
            }
        };
        // The rounded guess is within one step of the answer; search around it.
        let mut best = guess;
        let mut best_d = f64::INFINITY;
        for dj in -2..=2 {
            for di in -2..=2 {
                let c = Coord::new(guess.i + di, guess.j + dj);
                if !self.contains(c) {
                    continue;
                }
                let d = (self.position(c) - p).norm_squared();
                if d < best_d {
                    best_d = d;
                    best = c;
                }
            }
        }
        best
    }

    /// Every lattice coordinate whose position lies in the closed box
    /// `[lo, hi]`, row by row from the bottom, left to right.
    pub fn coords_in_box(&self, lo: Point, hi: Point) -> Vec<Coord> {
        let mut out = Vec::new();
        let (j0, j1) = match self.kind {
            LatticeKind::Square => ((lo.y / self.a).ceil() as i32, (hi.y / self.a).floor() as i32),
            _ => ((lo.y / (self.a * SQRT3_2)).ceil() as i32, (hi.y / (self.a * SQRT3_2)).floor() as i32),
        };
        for j in j0..=j1 {
            let shift = match self.kind {
                LatticeKind::Square => 0.0,
                _ => 0.5 * j as f64,
            };
            let i0 = (lo.x / self.a - shift).ceil() as i32;
            let i1 = (hi.x / self.a - shift).floor() as i32;
            for i in i0..=i1 {
                let c = Coord::new(i, j);
                if self.contains(c) {
                    out.push(c);
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours_are_at_distance_a() {
        for kind in LatticeKind::ALL {
            let l = Lattice::new(kind, 1.5);
            for c in l.coords_in_box(Point::new(-4.0, -4.0), Point::new(4.0, 4.0)) {
                for &(di, dj) in l.offsets(c) {
                    let n = Coord::new(c.i + di, c.j + dj);
                    assert!(l.contains(n), "{kind:?}: neighbour {n:?} of {c:?} not on the lattice");
                    let d = (l.position(n) - l.position(c)).norm();
                    assert!((d - 1.5).abs() < 1e-9, "{kind:?}: {c:?}->{n:?} at {d}");
                    // Adjacency is symmetric.
                    assert!(l.offsets(n).contains(&(-di, -dj)));
                }
            }
        }
    }

    #[test]
    fn vertices_within_2a_differ_in_class() {
        for kind in LatticeKind::ALL {
            let l = Lattice::new(kind, 1.3);
            let cs = l.coords_in_box(Point::new(-6.0, -6.0), Point::new(6.0, 6.0));
            let mut seen = vec![false; l.classes() as usize];
            for &p in &cs {
                seen[l.class(p) as usize] = true;
                for &q in &cs {
                    let d = (l.position(p) - l.position(q)).norm();
                    if p != q && d <= 2.0 * 1.3 + 1e-9 {
                        assert_ne!(l.class(p), l.class(q), "{kind:?} {p:?} {q:?} at {d}");
                    }
                }
            }
            assert!(seen.iter().all(|&s| s), "{kind:?}: every class is used");
        }
    }

    #[test]
    fn degrees() {
        assert_eq!(Lattice::new(LatticeKind::Triangular, 1.0).offsets(Coord::new(0, 0)).len(), 6);
        assert_eq!(Lattice::new(LatticeKind::Square, 1.0).offsets(Coord::new(0, 0)).len(), 4);
        assert_eq!(Lattice::new(LatticeKind::Hexagonal, 1.0).offsets(Coord::new(1, 0)).len(), 3);
    }

    #[test]
    fn priority_key_orders_like_positions() {
        for kind in LatticeKind::ALL {
            let l = Lattice::new(kind, 1.0);
            let cs = l.coords_in_box(Point::new(-3.0, -3.0), Point::new(3.0, 3.0));
            for &p in &cs {
                for &q in &cs {
                    let (pp, qp) = (l.position(p), l.position(q));
                    let by_pos =
                        (pp.x - qp.x).abs() > 1e-9 && pp.x > qp.x || (pp.x - qp.x).abs() <= 1e-9 && pp.y > qp.y + 1e-9;
                    assert_eq!(by_pos, l.priority_key(p) > l.priority_key(q), "{kind:?} {p:?} {q:?}");
                }
            }
        }
    }

    #[test]
    fn nearest_round_trips() {
        for kind in LatticeKind::ALL {
            let l = Lattice::new(kind, 0.7);
            for c in l.coords_in_box(Point::new(-5.0, -5.0), Point::new(5.0, 5.0)) {
                let p = l.position(c) + nalgebra::Vector2::new(0.05, -0.04);
                assert_eq!(l.nearest(p), c);
            }
        }
    }
}
