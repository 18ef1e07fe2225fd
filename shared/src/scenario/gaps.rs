//! Gaps between the pieces of a map: obstacle to obstacle, obstacle to the
//! area's boundary, and across a polygon's own concavities. Validation uses
//! them to reject overlapping or escaping obstacles; Assumption 3.1.3 uses
//! them to find the narrowest passage.

use crate::geometry::{segments_intersect, Point, Polygon, Shape};

/// The closest pair of points of two pieces and their distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Gap {
    pub width: f64,
    pub a: Point,
    pub b: Point,
}

impl Gap {
    fn new(a: Point, b: Point) -> Self {
        Gap { width: (b - a).norm(), a, b }
    }

    /// A zero-width gap: the pieces meet.
    fn touching(at: Point) -> Self {
        Gap { width: 0.0, a: at, b: at }
    }

    pub fn midpoint(&self) -> Point {
        Point::from((self.a.coords + self.b.coords) / 2.0)
    }

    fn min(self, other: Gap) -> Gap {
        if other.width < self.width {
            other
        } else {
            self
        }
    }
}

const FAR: Gap = Gap { width: f64::INFINITY, a: Point::new(0.0, 0.0), b: Point::new(0.0, 0.0) };

/// The point of the segment `[a, b]` nearest to `p`.
pub(crate) fn closest_on_segment(p: Point, a: Point, b: Point) -> Point {
    let ab = b - a;
    let len2 = ab.norm_squared();
    if len2 == 0.0 {
        return a;
    }
    a + ab * ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
}

/// Closest points of two segments (a zero gap when they meet).
pub(crate) fn segment_gap(a: Point, b: Point, c: Point, d: Point) -> Gap {
    if segments_intersect(a, b, c, d) {
        return Gap::touching(a);
    }
    // Disjoint segments are closest at an endpoint of one of them.
    Gap::new(a, closest_on_segment(a, c, d))
        .min(Gap::new(b, closest_on_segment(b, c, d)))
        .min(Gap::new(closest_on_segment(c, a, b), c))
        .min(Gap::new(closest_on_segment(d, a, b), d))
}

/// Gap from the segment `[a, b]` to the circle of `center`, `radius`
/// (zero when the segment reaches into the disc).
fn segment_circle_gap(a: Point, b: Point, center: Point, radius: f64) -> Gap {
    let q = closest_on_segment(center, a, b);
    let d = (q - center).norm();
    if d <= radius {
        return Gap::touching(q);
    }
    Gap::new(q, center + (q - center) * (radius / d))
}

/// A lower bound on the gap between two shapes: the distance between their
/// bounding boxes (zero when the boxes meet). Pairs of pieces are quadratic
/// in number; this skips the exact gap of every pair too far apart to matter.
pub(crate) fn box_distance(s: &(Point, Point), t: &(Point, Point)) -> f64 {
    let dx = (t.0.x - s.1.x).max(s.0.x - t.1.x).max(0.0);
    let dy = (t.0.y - s.1.y).max(s.0.y - t.1.y).max(0.0);
    dx.hypot(dy)
}

/// Gap between two shapes; zero when they overlap, touch or nest.
pub(crate) fn shape_gap(s: &Shape, t: &Shape) -> Gap {
    match (s, t) {
        (Shape::Circle(c), Shape::Circle(e)) => {
            let d = (e.center - c.center).norm();
            if d <= c.radius + e.radius || d == 0.0 {
                return Gap::touching(c.center);
            }
            let u = (e.center - c.center) / d;
            Gap::new(c.center + u * c.radius, e.center - u * e.radius)
        }
        (Shape::Polygon(p), Shape::Circle(c)) => polygon_circle_gap(p, c.center, c.radius),
        (Shape::Circle(c), Shape::Polygon(p)) => {
            let g = polygon_circle_gap(p, c.center, c.radius);
            Gap { width: g.width, a: g.b, b: g.a }
        }
        (Shape::Polygon(p), Shape::Polygon(q)) => {
            if p.contains(q.points[0]) {
                return Gap::touching(q.points[0]);
            }
            if q.contains(p.points[0]) {
                return Gap::touching(p.points[0]);
            }
            let mut best = FAR;
            for (a, b) in p.edges() {
                for (c, d) in q.edges() {
                    best = best.min(segment_gap(a, b, c, d));
                }
            }
            best
        }
    }
}

fn polygon_circle_gap(p: &Polygon, center: Point, radius: f64) -> Gap {
    if p.contains(center) {
        return Gap::touching(center);
    }
    p.edges().map(|(a, b)| segment_circle_gap(a, b, center, radius)).fold(FAR, Gap::min)
}

/// Gap from a shape to the boundary of `area` (zero when it meets or
/// crosses it). Says nothing about which side the shape is on.
pub(crate) fn boundary_gap(area: &Polygon, s: &Shape) -> Gap {
    boundary_gap_of(area.edges(), s)
}

/// [`boundary_gap`] over some of the area's edges only, in order: those
/// whose boxes come near the shape's (see [`super::pairs`]); infinite when
/// there are none.
pub(crate) fn boundary_gap_of(edges: impl Iterator<Item = (Point, Point)>, s: &Shape) -> Gap {
    let mut best = FAR;
    for (a, b) in edges {
        let g = match s {
            Shape::Circle(c) => segment_circle_gap(a, b, c.center, c.radius),
            Shape::Polygon(p) => p.edges().map(|(c, d)| segment_gap(c, d, a, b)).fold(FAR, Gap::min),
        };
        // Keep the boundary point second, as `a` is always the shape's side.
        best = best.min(Gap { width: g.width, a: g.b, b: g.a });
    }
    best
}

/// Whether `s` lies strictly inside `area`, clear of its boundary.
pub(crate) fn strictly_inside(area: &Polygon, s: &Shape) -> bool {
    strictly_inside_near(area, area.edges(), s)
}

/// [`strictly_inside`], measuring the gap to `edges` of the area only:
/// they must include every edge whose box meets the shape's.
pub(crate) fn strictly_inside_near(area: &Polygon, edges: impl Iterator<Item = (Point, Point)>, s: &Shape) -> bool {
    let probe = match s {
        Shape::Circle(c) => c.center,
        Shape::Polygon(p) => p.points[0],
    };
    area.contains(probe) && boundary_gap_of(edges, s).width > 0.0
}

/// Narrowest gap across a polygon's own concavity: between two non-adjacent
/// edges that face each other through the free side (the inside of the area,
/// the outside of an obstacle). Facing means the free-side normals point
/// against each other (walls more than 90 degrees apart) and toward the other
/// edge's closest point; that keeps a corridor or a slot, and drops a step or
/// a chamfered corner whose edges are near only through a short edge between
/// them. `free_inside` is true for the area, false for an obstacle.
pub(crate) fn self_passages(p: &Polygon, free_inside: bool) -> Vec<(usize, usize, Gap)> {
    let n = p.points.len();
    let orient = if p.signed_area() > 0.0 { 1.0 } else { -1.0 };
    let side = if free_inside { orient } else { -orient };
    let edges: Vec<(Point, Point)> = p.edges().collect();
    // The left normal of a counter-clockwise edge points inside.
    let normal = |k: usize| {
        let d = edges[k].1 - edges[k].0;
        crate::geometry::Vector::new(-d.y, d.x).normalize() * side
    };
    let mut out = Vec::new();
    for x in 0..n {
        for y in x + 2..n {
            if x == 0 && y == n - 1 {
                continue;
            }
            let (nx, ny) = (normal(x), normal(y));
            if nx.dot(&ny) >= 0.0 {
                continue;
            }
            let g = segment_gap(edges[x].0, edges[x].1, edges[y].0, edges[y].1);
            if g.width == 0.0 {
                continue;
            }
            let across = (g.b - g.a) / g.width;
            if nx.dot(&across) > 1e-9 && ny.dot(&-across) > 1e-9 {
                out.push((x, y, g));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Circle;

    fn poly(pts: &[(f64, f64)]) -> Polygon {
        Polygon::new(pts.iter().map(|&(x, y)| Point::new(x, y)).collect())
    }

    #[test]
    fn shape_gaps() {
        let sq = Shape::Polygon(poly(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]));
        let c = Shape::Circle(Circle { center: Point::new(3.0, 0.5), radius: 0.5 });
        assert!((shape_gap(&sq, &c).width - 1.5).abs() < 1e-12);
        assert!((shape_gap(&c, &sq).a - Point::new(2.5, 0.5)).norm() < 1e-12);
        let inner = Shape::Polygon(poly(&[(0.2, 0.2), (0.4, 0.2), (0.3, 0.4)]));
        assert_eq!(shape_gap(&sq, &inner).width, 0.0);
    }

    #[test]
    fn corridor_is_a_passage_step_and_chamfer_are_not() {
        // A U: two prongs 1.6 apart, joined at the bottom.
        let u = poly(&[(0.0, 0.0), (5.0, 0.0), (5.0, 5.0), (4.0, 5.0), (4.0, 1.0), (1.0, 1.0), (1.0, 5.0), (0.0, 5.0)]);
        // The slot between the prongs is outside the U: a passage for an
        // obstacle of this shape, not for an area.
        let slot = self_passages(&u, false);
        assert_eq!(slot.len(), 1);
        assert!((slot[0].2.width - 3.0).abs() < 1e-12);
        // Inside, the bottom bar (1 m thick) is not a passage of the area
        // between prong walls facing each other, only the prongs are.
        let inside = self_passages(&u, true);
        let narrow: Vec<_> = inside.iter().filter(|(_, _, g)| g.width < 3.0).collect();
        assert_eq!(narrow.len(), 3, "{inside:?}");
        assert!(narrow.iter().all(|(_, _, g)| (g.width - 1.0).abs() < 1e-12), "{inside:?}");
        // A chamfered square corner is no passage: its two walls are near
        // only through the short chamfer (the room's width is measured, but
        // it is far above 3a).
        let chamfer = poly(&[(0.0, 0.0), (4.7, 0.0), (5.0, 0.3), (5.0, 5.0), (0.0, 5.0)]);
        assert!(self_passages(&chamfer, true).iter().all(|(_, _, g)| g.width >= 4.5));
        // Nor is a step.
        let step = poly(&[(0.0, 0.0), (5.0, 0.0), (5.0, 0.5), (10.0, 0.5), (10.0, 5.0), (0.0, 5.0)]);
        assert!(self_passages(&step, true).iter().all(|(_, _, g)| g.width >= 4.5 - 1e-12));
    }
}
