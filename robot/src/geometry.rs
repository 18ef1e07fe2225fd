//! Plane geometry the world needs: polygons, circles, and the distances that
//! decide clearance (`r_safe`) of vertices and edges.

use serde::{Deserialize, Serialize};

pub type Point = nalgebra::Point2<f64>;
pub type Vector = nalgebra::Vector2<f64>;

/// Distance from `p` to the segment `[a, b]`.
#[inline]
pub fn point_segment_distance(p: Point, a: Point, b: Point) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    if len2 == 0.0 {
        return (p - a).norm();
    }
    let t = ((p - a).dot(&ab) / len2).clamp(0.0, 1.0);
    (p - (a + ab * t)).norm()
}

#[inline]
fn cross(u: Vector, v: Vector) -> f64 {
    u.x * v.y - u.y * v.x
}

/// Whether the closed segments `[a, b]` and `[c, d]` share a point.
#[inline]
pub fn segments_intersect(a: Point, b: Point, c: Point, d: Point) -> bool {
    let d1 = cross(b - a, c - a);
    let d2 = cross(b - a, d - a);
    let d3 = cross(d - c, a - c);
    let d4 = cross(d - c, b - c);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0)) {
        return true;
    }
    let on = |p: Point, q: Point, r: Point, dd: f64| {
        dd == 0.0 && r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    on(a, b, c, d1) || on(a, b, d, d2) || on(c, d, a, d3) || on(c, d, b, d4)
}

/// Distance between the segments `[a, b]` and `[c, d]` (0 when they meet).
#[inline]
pub fn segment_segment_distance(a: Point, b: Point, c: Point, d: Point) -> f64 {
    if segments_intersect(a, b, c, d) {
        return 0.0;
    }
    point_segment_distance(a, c, d)
        .min(point_segment_distance(b, c, d))
        .min(point_segment_distance(c, a, b))
        .min(point_segment_distance(d, a, b))
}

/// A simple polygon (no self-intersections), concave allowed, given by its
/// corners in either orientation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Polygon {
    pub points: Vec<Point>,
}

impl Polygon {
    pub fn new(points: Vec<Point>) -> Self {
        Polygon { points }
    }

    /// The polygon's edges as point pairs, closing back to the first corner.
    #[inline]
    pub fn edges(&self) -> impl Iterator<Item = (Point, Point)> + '_ {
        let n = self.points.len();
        (0..n).map(move |k| (self.points[k], self.points[(k + 1) % n]))
    }

    /// Even-odd point-in-polygon test; points on the boundary may go either way,
    /// which never matters because clearance tests follow.
    #[inline]
    pub fn contains(&self, p: Point) -> bool {
        self.edges().filter(|&(a, b)| crosses_ray(p, a, b)).count() % 2 == 1
    }

    #[inline]
    pub fn boundary_distance(&self, p: Point) -> f64 {
        self.edges().map(|(a, b)| point_segment_distance(p, a, b)).fold(f64::INFINITY, f64::min)
    }

    #[inline]
    pub fn boundary_segment_distance(&self, p: Point, q: Point) -> f64 {
        self.edges().map(|(a, b)| segment_segment_distance(p, q, a, b)).fold(f64::INFINITY, f64::min)
    }

    /// Signed area: positive when the corners run counter-clockwise.
    pub fn signed_area(&self) -> f64 {
        self.edges().map(|(a, b)| a.x * b.y - b.x * a.y).sum::<f64>() / 2.0
    }

    /// Whether two non-adjacent edges cross or touch.
    pub fn is_simple(&self) -> bool {
        let e: Vec<_> = self.edges().collect();
        let n = e.len();
        for x in 0..n {
            for y in x + 1..n {
                let adjacent = y == x + 1 || (x == 0 && y == n - 1);
                if !adjacent && segments_intersect(e[x].0, e[x].1, e[y].0, e[y].1) {
                    return false;
                }
            }
        }
        true
    }

    pub fn bounding_box(&self) -> (Point, Point) {
        let mut lo = Point::new(f64::INFINITY, f64::INFINITY);
        let mut hi = Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
        for p in &self.points {
            lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        (lo, hi)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Circle {
    pub center: Point,
    pub radius: f64,
}

/// An obstacle: a closed region the robots must keep `r_safe` away from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    Polygon(Polygon),
    Circle(Circle),
}

impl Shape {
    #[inline]
    pub fn contains(&self, p: Point) -> bool {
        match self {
            Shape::Polygon(poly) => poly.contains(p),
            Shape::Circle(c) => (p - c.center).norm() <= c.radius,
        }
    }

    /// Distance from `p` to the shape (0 inside).
    #[inline]
    pub fn distance(&self, p: Point) -> f64 {
        match self {
            Shape::Polygon(poly) => {
                if poly.contains(p) {
                    0.0
                } else {
                    poly.boundary_distance(p)
                }
            }
            Shape::Circle(c) => ((p - c.center).norm() - c.radius).max(0.0),
        }
    }

    /// Distance from the segment `[p, q]` to the shape (0 when they meet).
    #[inline]
    pub fn segment_distance(&self, p: Point, q: Point) -> f64 {
        match self {
            Shape::Polygon(poly) => {
                if poly.contains(p) || poly.contains(q) {
                    0.0
                } else {
                    poly.boundary_segment_distance(p, q)
                }
            }
            Shape::Circle(c) => (point_segment_distance(c.center, p, q) - c.radius).max(0.0),
        }
    }

    pub fn bounding_box(&self) -> (Point, Point) {
        match self {
            Shape::Polygon(p) => p.bounding_box(),
            Shape::Circle(c) => (
                Point::new(c.center.x - c.radius, c.center.y - c.radius),
                Point::new(c.center.x + c.radius, c.center.y + c.radius),
            ),
        }
    }
}

/// Whether the edge `a -> b` crosses the ray from `p` towards +x: the
/// even-odd test counts these. An edge whose y-span misses `p.y` never does.
#[inline]
pub fn crosses_ray(p: Point, a: Point, b: Point) -> bool {
    (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y)
}

/// Smallest distance between two moving points that start at `p0`, `q0` and
/// end at `p1`, `q1`, moving along straight lines with the same time profile
/// (step 6): their difference is linear in one parameter `s ∈ [0, 1]`.
#[inline]
pub fn swept_min_distance(p0: Point, p1: Point, q0: Point, q1: Point) -> f64 {
    let d0 = q0 - p0;
    let dv = (q1 - q0) - (p1 - p0);
    let vv = dv.norm_squared();
    let s = if vv == 0.0 { 0.0 } else { (-d0.dot(&dv) / vv).clamp(0.0, 1.0) };
    (d0 + dv * s).norm()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn square(x0: f64, y0: f64, s: f64) -> Polygon {
        Polygon::new(vec![
            Point::new(x0, y0),
            Point::new(x0 + s, y0),
            Point::new(x0 + s, y0 + s),
            Point::new(x0, y0 + s),
        ])
    }

    #[test]
    fn concave_polygon_contains() {
        // An L shape: the notch (1.5, 1.5) is outside.
        let l = Polygon::new(vec![
            Point::new(0.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(2.0, 1.0),
            Point::new(1.0, 1.0),
            Point::new(1.0, 2.0),
            Point::new(0.0, 2.0),
        ]);
        assert!(l.contains(Point::new(0.5, 1.5)));
        assert!(l.contains(Point::new(1.5, 0.5)));
        assert!(!l.contains(Point::new(1.5, 1.5)));
        assert!(l.is_simple());
        assert!((l.signed_area() - 3.0).abs() < 1e-12);
    }

    #[test]
    fn bowtie_is_not_simple() {
        let b =
            Polygon::new(vec![Point::new(0.0, 0.0), Point::new(1.0, 1.0), Point::new(1.0, 0.0), Point::new(0.0, 1.0)]);
        assert!(!b.is_simple());
    }

    #[test]
    fn head_on_swap_collides_follow_does_not() {
        let a = Point::new(0.0, 0.0);
        let b = Point::new(1.0, 0.0);
        let c = Point::new(2.0, 0.0);
        assert_eq!(swept_min_distance(a, b, b, a), 0.0);
        // Following along a line keeps the distance a.
        assert!((swept_min_distance(a, b, b, c) - 1.0).abs() < 1e-12);
        // A 120-degree follow on the triangular lattice dips to a·√3/2·... < a.
        let d = Point::new(1.5, 0.866_025_403_784_438_6);
        let m = swept_min_distance(a, b, b, d);
        assert!(m < 1.0 && m > 0.4, "{m}");
    }

    proptest! {
        #[test]
        fn point_segment_distance_is_min_over_samples(
            px in -5.0..5.0f64, py in -5.0..5.0f64,
            ax in -5.0..5.0f64, ay in -5.0..5.0f64,
            bx in -5.0..5.0f64, by in -5.0..5.0f64,
        ) {
            let (p, a, b) = (Point::new(px, py), Point::new(ax, ay), Point::new(bx, by));
            let d = point_segment_distance(p, a, b);
            let sampled = (0..=200).map(|k| (p - (a + (b - a) * (k as f64 / 200.0))).norm()).fold(f64::INFINITY, f64::min);
            prop_assert!(d <= sampled + 1e-9);
            prop_assert!(d >= sampled - (b - a).norm() / 200.0 - 1e-9);
        }

        #[test]
        fn segment_distance_is_symmetric_and_zero_iff_crossing(
            c in prop::array::uniform8(-3.0..3.0f64),
        ) {
            let (a, b, p, q) = (Point::new(c[0], c[1]), Point::new(c[2], c[3]), Point::new(c[4], c[5]), Point::new(c[6], c[7]));
            let d1 = segment_segment_distance(a, b, p, q);
            let d2 = segment_segment_distance(p, q, a, b);
            prop_assert!((d1 - d2).abs() < 1e-12);
            prop_assert_eq!(d1 == 0.0, segments_intersect(a, b, p, q));
        }

        #[test]
        fn inside_means_zero_distance(x in -1.0..3.0f64, y in -1.0..3.0f64) {
            let s = Shape::Polygon(square(0.0, 0.0, 2.0));
            let p = Point::new(x, y);
            let inside = x > 0.0 && x < 2.0 && y > 0.0 && y < 2.0;
            if inside { prop_assert_eq!(s.distance(p), 0.0); }
            let outside_by = (-x).max(x - 2.0).max(-y).max(y - 2.0);
            if outside_by > 1e-9 { prop_assert!(s.distance(p) >= outside_by - 1e-9); }
        }

        #[test]
        fn swept_distance_bounded_by_endpoints(c in prop::array::uniform8(-3.0..3.0f64)) {
            let (p0, p1, q0, q1) = (Point::new(c[0], c[1]), Point::new(c[2], c[3]), Point::new(c[4], c[5]), Point::new(c[6], c[7]));
            let m = swept_min_distance(p0, p1, q0, q1);
            prop_assert!(m <= (q0 - p0).norm() + 1e-12);
            prop_assert!(m <= (q1 - p1).norm() + 1e-12);
            for k in 0..=50 {
                let s = k as f64 / 50.0;
                let d = ((q0 + (q1 - q0) * s) - (p0 + (p1 - p0) * s)).norm();
                prop_assert!(m <= d + 1e-9);
            }
        }
    }
}
