//! Which pieces of a map are near enough to measure, and what measuring
//! them costs. Admission refuses obstacles that overlap, and Assumption
//! 3.1.3 measures every passage up to `3a` wide: both need the gap of every
//! two pieces that come near each other. Trying every pair of obstacles
//! was quadratic (issue 23: 8,000 thin quads took 85 s of CPU and 2.8 GB in
//! `check`); here obstacles are paired through a grid of cells over their
//! bounding boxes, so only neighbours meet, and the exact gaps of the
//! neighbours found are counted, in segment tests, against a budget: a map
//! whose obstacles crowd so that the budget would not do is refused at
//! admission ([`super::limits::MAX_PAIR_WORK`]) instead of measured for
//! minutes.

use super::gaps::box_distance;
use crate::geometry::{Point, Polygon, Shape};
use crate::world::buckets::Buckets;

/// What measuring a shape against another costs per segment of the other:
/// its edges (a circle is one test).
pub(crate) fn weight(s: &Shape) -> f64 {
    match s {
        Shape::Polygon(p) => p.points.len() as f64,
        Shape::Circle(_) => 1.0,
    }
}

/// The pairs of one map worth measuring, and their cost.
#[derive(Clone, Debug, Default)]
pub(crate) struct Near {
    /// `(i, j)`, `i < j`: obstacles whose boxes are at most the margin apart, ascending.
    pub obstacles: Vec<(u32, u32)>,
    /// `(i, edge)`: obstacle `i` and an area edge whose boxes are at most the margin apart, ascending.
    pub boundary: Vec<(u32, u32)>,
    /// Segment tests the exact gaps of all of them take, plus one per pair looked at.
    pub work: f64,
}

/// The budget ran out: the work counted so far, and where it was spent last.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Crowded {
    pub work: f64,
    pub at: Point,
}

/// The pairs of obstacles, and of an obstacle and an area edge, whose
/// boxes are at most `margin` apart, in a grid of cells of side
/// `max(margin, side)` over the area's box. Stops with [`Crowded`] once
/// their work passes `budget`, so the search costs no more than the budget
/// either.
pub(crate) fn near(area: &Polygon, obstacles: &[Shape], margin: f64, side: f64, budget: f64) -> Result<Near, Crowded> {
    let boxes: Vec<(Point, Point)> = obstacles.iter().map(Shape::bounding_box).collect();
    let (lo, hi) = area.bounding_box();
    let side = margin.max(side).max(1e-9);
    let grid = Buckets::new(lo, hi, (side, side), &boxes, margin / 2.0);
    let mut out = Near::default();
    let mut over = None;
    grid.pairs(&boxes, margin / 2.0, |i, j, first| {
        let (bi, bj) = (&boxes[i as usize], &boxes[j as usize]);
        out.work += 1.0;
        if first && box_distance(bi, bj) <= margin {
            let (wi, wj) = (weight(&obstacles[i as usize]), weight(&obstacles[j as usize]));
            // Every edge against every edge, and a corner of each inside the other.
            out.work += wi * wj + wi + wj;
            out.obstacles.push((i, j));
        }
        if out.work > budget {
            over = Some(Crowded { work: out.work, at: bi.0 });
        }
        over.is_none()
    });
    if let Some(c) = over {
        return Err(c);
    }
    out.obstacles.sort_unstable();
    // Area edges: a thousand at most, each against every obstacle's box.
    let edges: Vec<(Point, Point)> = area
        .edges()
        .map(|(p, q)| (Point::new(p.x.min(q.x), p.y.min(q.y)), Point::new(p.x.max(q.x), p.y.max(q.y))))
        .collect();
    for (i, (bx, o)) in boxes.iter().zip(obstacles).enumerate() {
        out.work += edges.len() as f64;
        for (e, eb) in edges.iter().enumerate() {
            if box_distance(bx, eb) <= margin {
                out.work += weight(o);
                out.boundary.push((i as u32, e as u32));
            }
        }
        if out.work > budget {
            return Err(Crowded { work: out.work, at: bx.0 });
        }
    }
    Ok(out)
}

/// Segment tests of a polygon against itself (simplicity, and the passages
/// across its own concavities): every two edges.
pub(crate) fn self_work(p: &Polygon) -> f64 {
    let n = p.points.len() as f64;
    n * (n - 1.0) / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Circle;

    fn square(x: f64, y: f64, s: f64) -> Shape {
        Shape::Polygon(Polygon::new(vec![
            Point::new(x, y),
            Point::new(x + s, y),
            Point::new(x + s, y + s),
            Point::new(x, y + s),
        ]))
    }

    #[test]
    fn the_grid_finds_exactly_the_pairs_every_pair_would() {
        // A scatter of squares and circles, some near, some far, some in
        // cells far apart, against the all-pairs answer.
        let area = Polygon::new(vec![
            Point::new(0.0, 0.0),
            Point::new(60.0, 0.0),
            Point::new(60.0, 40.0),
            Point::new(0.0, 40.0),
        ]);
        let mut obstacles = Vec::new();
        let mut seed = 7u64;
        let mut next = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for k in 0..300 {
            let (x, y, s) = (1.0 + 55.0 * next(), 1.0 + 35.0 * next(), 0.1 + 3.0 * next());
            obstacles.push(if k % 3 == 0 {
                Shape::Circle(Circle { center: Point::new(x, y), radius: s / 2.0 })
            } else {
                square(x, y, s)
            });
        }
        for margin in [0.0, 1.0, 3.0, 7.5] {
            let got = near(&area, &obstacles, margin, 3.0, f64::INFINITY).unwrap();
            let boxes: Vec<_> = obstacles.iter().map(Shape::bounding_box).collect();
            let mut all = Vec::new();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    if box_distance(&boxes[i], &boxes[j]) <= margin {
                        all.push((i as u32, j as u32));
                    }
                }
            }
            assert_eq!(got.obstacles, all, "margin {margin}");
            let edges = area.edges().count() as u32;
            let boundary: Vec<(u32, u32)> = (0..boxes.len() as u32)
                .flat_map(|i| (0..edges).map(move |e| (i, e)))
                .filter(|&(i, e)| {
                    let (p, q) = area.edges().nth(e as usize).unwrap();
                    let eb = (Point::new(p.x.min(q.x), p.y.min(q.y)), Point::new(p.x.max(q.x), p.y.max(q.y)));
                    box_distance(&boxes[i as usize], &eb) <= margin
                })
                .collect();
            assert_eq!(got.boundary, boundary, "margin {margin}");
        }
    }

    #[test]
    fn crowded_obstacles_stop_the_search_at_the_budget() {
        // 2,000 small squares packed 3 cm apart: 2 million pairs within 3 m.
        let area = Polygon::new(vec![
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(10.0, 10.0),
            Point::new(0.0, 10.0),
        ]);
        let obstacles: Vec<Shape> =
            (0..2000).map(|k| square(1.0 + (k % 50) as f64 * 0.03, 1.0 + (k / 50) as f64 * 0.03, 0.01)).collect();
        let e = near(&area, &obstacles, 3.0, 3.0, 1e6).unwrap_err();
        // The search stopped right past the budget: one pair's work over.
        assert!(e.work > 1e6 && e.work <= 1e6 + 25.0, "{e:?}");
        assert!(near(&area, &obstacles, 3.0, 3.0, 1e9).unwrap().obstacles.len() == 2000 * 1999 / 2);
    }
}
