//! Points sorted into square cells, so that the points within a distance
//! of one are found among its 3 x 3 cells instead of among all of them:
//! the radio's links and the referee's collision pairs stay near linear in
//! the number of robots (10,000 robots make 50 million pairs a slot).

use crate::geometry::Point;

/// Point indices by cell, for one set of points at a time.
#[derive(Clone, Debug, Default)]
pub struct Cells {
    side: f64,
    /// `(cell x, cell y, point index)`, sorted.
    items: Vec<(i64, i64, u32)>,
}

impl Cells {
    /// Cells of side `side` (at least the largest distance asked about).
    pub fn new(side: f64) -> Self {
        Cells { side: side.max(1e-9), items: Vec::new() }
    }

    fn cell(&self, p: Point) -> (i64, i64) {
        ((p.x / self.side).floor() as i64, (p.y / self.side).floor() as i64)
    }

    /// Sorts `points` (indexed by position) into the cells, forgetting the last set.
    pub fn fill(&mut self, points: &[Point]) {
        self.items.clear();
        for (k, &p) in points.iter().enumerate() {
            let (x, y) = self.cell(p);
            self.items.push((x, y, k as u32));
        }
        self.items.sort_unstable();
    }

    /// Calls `f` with every point index in the 3 x 3 cells around `p`
    /// (`p`'s own index included, if it is one of the points): a superset
    /// of the points within `side` of `p`, cell row by cell row.
    pub fn around(&self, p: Point, mut f: impl FnMut(u32)) {
        let (cx, cy) = self.cell(p);
        for x in cx - 1..=cx + 1 {
            let lo = self.items.partition_point(|b| (b.0, b.1) < (x, cy - 1));
            for &(bx, by, j) in &self.items[lo..] {
                if bx != x || by > cy + 1 {
                    break;
                }
                f(j);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn around_finds_every_point_within_the_side(
            pts in prop::collection::vec((-50.0f64..50.0, -50.0f64..50.0), 1..80),
            side in 0.5f64..20.0,
        ) {
            let pts: Vec<Point> = pts.into_iter().map(|(x, y)| Point::new(x, y)).collect();
            let mut cells = Cells::new(side);
            cells.fill(&pts);
            for &p in &pts {
                let mut found = Vec::new();
                cells.around(p, |j| found.push(j));
                for (j, q) in pts.iter().enumerate() {
                    if (q - p).norm() <= side {
                        prop_assert!(found.contains(&(j as u32)), "{j} missed");
                    }
                }
            }
        }
    }
}
