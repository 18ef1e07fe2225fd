//! The pieces of a random map: a rectilinear area with notches (and, to
//! break 3.1.2, a sharp bay), convex obstacles thrown like darts with a
//! minimum gap, and (to break 3.1.3) one obstacle closer to a wall.
//!
//! The area's walls are snapped to the triangular lattice, which is fixed in
//! the plane (rows at `y = a sqrt(3)/2 j`, columns every `a/2`): every wall
//! lies `0.4 a` from the nearest row or column of vertices on its free side,
//! clear of `r_safe = 0.3 a` with a margin, so no vertex sits on the
//! accessibility threshold and every 90 degree corner has a vertex within
//! `0.4 a sqrt(2)` of both walls. Unsnapped, a corner's apex can be 1.75 m
//! from the nearest accessible vertex (assumptions.rs, 3.1.2) and one map
//! in a few would fail the pocket check. Obstacles are convex, so they make
//! no pocket, and are not snapped.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::geometry::{Point, Polygon, Shape};
use crate::scenario::gaps;

const ROW: f64 = 0.866_025_403_784_438_6;
/// Distance from a wall to the lattice line beside it, in grid sides.
const INSET: f64 = 0.4;
/// A notch stays this far (m) from the ends of its side, so notches on two
/// sides meeting at a corner are at least as far apart as the deepest notch.
const NOTCH_MARGIN: f64 = 8.0;
const NOTCH_DEPTH: (f64, f64) = (1.5, 4.0);
const NOTCH_WIDTH: (f64, f64) = (2.0, 6.0);
/// Two notches on one side leave a tooth of the area between them at least
/// this wide (m): wider than 3a, so not a passage the check would measure.
const NOTCH_SPACING: f64 = 4.0;
/// The bay that breaks 3.1.2: 0.8 m wide, 2.5 m deep, an apex of 18 degrees.
const BAY: (f64, f64) = (0.8, 2.5);

/// Rounds to a millimetre, so a map written as TOML reads as it was made.
pub fn mm(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

fn pt(x: f64, y: f64) -> Point {
    Point::new(mm(x), mm(y))
}

/// The nearest x of a vertical wall whose free side is to the right (or left).
fn snap_x(x: f64, a: f64, free_right: bool) -> f64 {
    let off = if free_right { (0.5 - INSET) * a } else { INSET * a };
    mm(((x - off) / (0.5 * a)).round() * 0.5 * a + off)
}

/// The nearest y of a horizontal wall whose free side is above (or below).
fn snap_y(y: f64, a: f64, free_above: bool) -> f64 {
    let off = if free_above { -INSET * a } else { INSET * a };
    mm(((y - off) / (ROW * a)).round() * ROW * a + off)
}

/// A notch cut into one side: along the side from `s0` to `s1` (absolute
/// coordinates, snapped), to `depth` (absolute coordinate of its inner wall).
#[derive(Clone, Copy, Debug)]
struct Notch {
    s0: f64,
    s1: f64,
    inner: f64,
}

/// The area and its first corner (where the robots start).
pub struct Area {
    pub polygon: Polygon,
    pub corner: Point,
    /// The outer rectangle `(x0, y0, x1, y1)`.
    pub frame: (f64, f64, f64, f64),
}

/// Up to three notches of the side running from `lo` to `hi`, at most a
/// quarter of the `room` across the area deep. `snap(c, free_after)` snaps
/// a notch's side wall, `inner(depth)` gives its snapped inner wall.
fn notches(
    rng: &mut ChaCha8Rng,
    lo: f64,
    hi: f64,
    room: f64,
    snap: impl Fn(f64, bool) -> f64,
    inner: impl Fn(f64) -> f64,
) -> Vec<Notch> {
    let mut out: Vec<Notch> = Vec::new();
    let usable = hi - lo - 2.0 * NOTCH_MARGIN;
    let max_depth = (room / 4.0).min(NOTCH_DEPTH.1);
    if usable < NOTCH_WIDTH.0 || max_depth < NOTCH_DEPTH.0 {
        return out;
    }
    let wanted = rng.random_range(0..=((usable / 10.0).ceil() as usize).min(3));
    for _ in 0..wanted {
        let width = rng.random_range(NOTCH_WIDTH.0..=NOTCH_WIDTH.1.min(usable));
        let start = lo + NOTCH_MARGIN + rng.random_range(0.0..=usable - width);
        let (s0, s1) = (snap(start, false), snap(start + width, true));
        let depth = rng.random_range(NOTCH_DEPTH.0..=max_depth);
        let clear = out.iter().all(|n| s1 + NOTCH_SPACING <= n.s0 || n.s1 + NOTCH_SPACING <= s0);
        if s1 - s0 >= NOTCH_WIDTH.0 * 0.75 && clear {
            out.push(Notch { s0, s1, inner: inner(depth) });
        }
    }
    out.sort_by(|p, q| p.s0.total_cmp(&q.s0));
    out
}

/// A rectangle of about `size` with notches on its sides, walls snapped to
/// the lattice of side `a`; with `bay`, a sharp bay out of the top side.
pub fn area(rng: &mut ChaCha8Rng, size: (f64, f64), a: f64, bay: bool) -> Area {
    let (x0, y0) = (snap_x(0.0, a, true), snap_y(ROW * a, a, true));
    let (x1, y1) = (snap_x(x0 + size.0, a, false), snap_y(y0 + size.1, a, false));
    let (w, h) = (x1 - x0, y1 - y0);
    let bottom = notches(rng, x0, x1, h, |x, r| snap_x(x, a, r), |d| snap_y(y0 + d, a, true));
    let right = notches(rng, y0, y1, w, |y, above| snap_y(y, a, above), |d| snap_x(x1 - d, a, false));
    let top = notches(rng, x0, x1, h, |x, r| snap_x(x, a, r), |d| snap_y(y1 - d, a, false));
    let left = notches(rng, y0, y1, w, |y, above| snap_y(y, a, above), |d| snap_x(x0 + d, a, true));

    let mut p = vec![pt(x0, y0)];
    for n in &bottom {
        p.extend([pt(n.s0, y0), pt(n.s0, n.inner), pt(n.s1, n.inner), pt(n.s1, y0)]);
    }
    p.push(pt(x1, y0));
    for n in &right {
        p.extend([pt(x1, n.s0), pt(n.inner, n.s0), pt(n.inner, n.s1), pt(x1, n.s1)]);
    }
    p.push(pt(x1, y1));
    // The top side runs right to left; the bay is one more feature on it.
    let mut features: Vec<(f64, Vec<Point>)> =
        top.iter().map(|n| (n.s1, vec![pt(n.s1, y1), pt(n.s1, n.inner), pt(n.s0, n.inner), pt(n.s0, y1)])).collect();
    if bay {
        let mx = bay_position(rng, x0, x1, &top);
        let half = BAY.0 / 2.0;
        features.push((mx + half, vec![pt(mx + half, y1), pt(mx, y1 + BAY.1), pt(mx - half, y1)]));
    }
    features.sort_by(|p, q| q.0.total_cmp(&p.0));
    for (_, f) in features {
        p.extend(f);
    }
    p.push(pt(x0, y1));
    for n in left.iter().rev() {
        p.extend([pt(x0, n.s1), pt(n.inner, n.s1), pt(n.inner, n.s0), pt(x0, n.s0)]);
    }
    Area { polygon: Polygon::new(p), corner: pt(x0, y0), frame: (x0, y0, x1, y1) }
}

/// Where along the top side the bay opens: clear of the corners and of the
/// top notches by 2 m, so it is a pocket of its own.
fn bay_position(rng: &mut ChaCha8Rng, x0: f64, x1: f64, top: &[Notch]) -> f64 {
    for _ in 0..100 {
        let mx = rng.random_range(x0 + 3.0..=x1 - 3.0);
        if top.iter().all(|n| mx + 2.0 <= n.s0 || n.s1 + 2.0 <= mx) {
            return mx;
        }
    }
    (x0 + x1) / 2.0
}

/// Convex hull of `pts` (Andrew's monotone chain), counter-clockwise, with
/// collinear points dropped.
fn hull(mut pts: Vec<Point>) -> Vec<Point> {
    pts.sort_by(|p, q| p.x.total_cmp(&q.x).then(p.y.total_cmp(&q.y)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: Point, a: Point, b: Point| (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    let mut lower: Vec<Point> = Vec::new();
    for &p in &pts {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0.0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<Point> = Vec::new();
    for &p in pts.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0.0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// One convex obstacle around `c`: a rectangle (upright or turned), a
/// triangle, or the hull of a few points, about `r` across from its centre.
fn obstacle(rng: &mut ChaCha8Rng, c: Point, r: f64) -> Option<Polygon> {
    let turn = rng.random_range(0.0..std::f64::consts::PI);
    let kind = rng.random_range(0..4);
    let local: Vec<(f64, f64)> = match kind {
        0 | 1 => {
            let (hx, hy) = (rng.random_range(0.4 * r..=r), rng.random_range(0.4 * r..=r));
            vec![(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)]
        }
        _ => {
            let n = if kind == 2 { 3 } else { rng.random_range(5..=8) };
            (0..n)
                .map(|_| {
                    let t = rng.random_range(0.0..std::f64::consts::TAU);
                    let d = r * rng.random_range(0.6..=1.0);
                    (d * t.cos(), d * t.sin())
                })
                .collect()
        }
    };
    let (sin, cos) = if kind == 0 { (0.0, 1.0) } else { turn.sin_cos() };
    let pts = local.into_iter().map(|(x, y)| pt(c.x + x * cos - y * sin, c.y + x * sin + y * cos)).collect();
    let poly = Polygon::new(hull(pts));
    // A sliver is a wall of no width, not an obstacle the paper draws.
    (poly.points.len() >= 3 && poly.signed_area().abs() >= 0.25 * r * r).then_some(poly)
}

/// An axis-aligned box grown by `m` on every side.
fn grown((lo, hi): (Point, Point), m: f64) -> (Point, Point) {
    (Point::new(lo.x - m, lo.y - m), Point::new(hi.x + m, hi.y + m))
}

fn overlap(a: &(Point, Point), b: &(Point, Point)) -> bool {
    a.0.x <= b.1.x && b.0.x <= a.1.x && a.0.y <= b.1.y && b.0.y <= a.1.y
}

/// Where obstacles may go: the area, and its edges with their boxes so a
/// dart is measured only against the walls near it (the exact gaps cost
/// most of a map's generation otherwise).
struct Room<'a> {
    area: &'a Polygon,
    walls: Vec<(Point, Point, (Point, Point))>,
}

impl<'a> Room<'a> {
    fn new(area: &'a Polygon) -> Self {
        let walls = area
            .edges()
            .map(|(a, b)| (a, b, (Point::new(a.x.min(b.x), a.y.min(b.y)), Point::new(a.x.max(b.x), a.y.max(b.y)))))
            .collect();
        Room { area, walls }
    }

    /// Whether `poly` (with box `bx`) may join `placed`: inside the area,
    /// at least `gap` from its boundary and from every obstacle placed.
    fn fits(&self, placed: &[(Shape, (Point, Point))], poly: &Polygon, bx: (Point, Point), gap: f64) -> bool {
        let reach = grown(bx, gap);
        if !self.area.contains(poly.points[0]) {
            return false;
        }
        let near_wall = |(a, b, wb): &(Point, Point, (Point, Point))| {
            overlap(&reach, wb) && poly.edges().any(|(c, d)| gaps::segment_gap(c, d, *a, *b).width < gap)
        };
        if self.walls.iter().any(near_wall) {
            return false;
        }
        let shape = Shape::Polygon(poly.clone());
        placed.iter().all(|(o, ob)| !overlap(&reach, ob) || gaps::shape_gap(o, &shape).width >= gap)
    }
}

fn area_of(s: &Shape) -> f64 {
    match s {
        Shape::Polygon(p) => p.signed_area().abs(),
        Shape::Circle(c) => std::f64::consts::PI * c.radius * c.radius,
    }
}

/// Cut `[lo, hi]` into pieces of about `cell`, each boundary moved by up
/// to a fifth of a cell, so the layout is not a visible grid.
fn cuts(rng: &mut ChaCha8Rng, lo: f64, hi: f64, cell: f64) -> Vec<f64> {
    let n = ((hi - lo) / cell).round().max(1.0) as usize;
    let step = (hi - lo) / n as f64;
    let mut out: Vec<f64> = (0..=n).map(|k| lo + k as f64 * step).collect();
    for x in out.iter_mut().take(n).skip(1) {
        *x += rng.random_range(-0.2..=0.2) * step;
    }
    out
}

/// Obstacles covering `density` of the area, every one at least `gap` from
/// the others and from the boundary; `placed` are kept.
///
/// Dart throwing saturates near 10% at a 2 m gap on a 20 x 16 m area, so
/// the inside of the area (`gap / 2` in from the outer rectangle) is cut
/// into cells, and a cell holds at most one obstacle, inside the cell
/// shrunk by `gap / 2`: two obstacles in different cells are then `gap`
/// apart by construction. Cells are taken in random order until the
/// density is reached; the cells are larger the denser the map, since the
/// gaps cost a smaller share of a large cell. An obstacle is a convex shape
/// ([`obstacle`]) stretched to fill 60-100% of its cell in each direction,
/// as much as the density still needs, placed at random within it. `Err(covered share)` when every
/// cell is used and the density is still out of reach at that gap.
pub fn obstacles(
    rng: &mut ChaCha8Rng,
    area: &Area,
    placed: Vec<Shape>,
    density: f64,
    gap: f64,
) -> Result<Vec<Shape>, f64> {
    let total = area.polygon.signed_area().abs();
    let room = Room::new(&area.polygon);
    let mut out: Vec<(Shape, (Point, Point))> =
        placed.into_iter().map(|s| (s.bounding_box(), s)).map(|(b, s)| (s, b)).collect();
    // An empty float sum is -0.0, which would print as "-0%".
    let mut covered: f64 = 0.0 + out.iter().map(|(s, _)| area_of(s)).sum::<f64>();
    let (x0, y0, x1, y1) = area.frame;
    // Cell side where the expected fill
    // (about 0.6 of the inner box) reaches the density with a margin; at
    // most five gaps wide, so a notch spoils one cell of several, not all.
    let fill = (1.4 * density / 0.6).min(0.64).sqrt();
    let cell = (gap / (1.0 - fill)).max(gap + 2.5) * rng.random_range(1.0..=1.3);
    // A millimetre more than half the gap: corners are rounded to the
    // millimetre, and a gap exactly `gap` wide must not come out narrower.
    let h = gap / 2.0 + 1e-3;
    let xs = cuts(rng, x0 + h, x1 - h, cell);
    let ys = cuts(rng, y0 + h, y1 - h, cell);
    let mut cells: Vec<(usize, usize)> =
        (0..xs.len() - 1).flat_map(|i| (0..ys.len() - 1).map(move |j| (i, j))).collect();
    // Fisher-Yates with the map's stream, so the order is the seed's.
    for k in (1..cells.len()).rev() {
        cells.swap(k, rng.random_range(0..=k));
    }
    let cells_total = cells.len();
    for (n, (i, j)) in cells.into_iter().enumerate() {
        if covered >= density * total {
            break;
        }
        // What each cell left must hold to reach the density, with a margin
        // for the cells a notch spoils.
        let want = 2.0 * (density * total - covered) / (cells_total - n) as f64;
        let inner = (Point::new(xs[i] + h, ys[j] + h), Point::new(xs[i + 1] - h, ys[j + 1] - h));
        if inner.1.x - inner.0.x < 0.5 || inner.1.y - inner.0.y < 0.5 {
            continue;
        }
        if let Some(poly) = in_cell(rng, &room, &out, inner, want, gap) {
            let shape = Shape::Polygon(poly);
            covered += area_of(&shape);
            let bx = shape.bounding_box();
            out.push((shape, bx));
        }
    }
    if covered < density * total {
        return Err(covered / total);
    }
    Ok(out.into_iter().map(|(s, _)| s).collect())
}

/// One obstacle of about `want` square metres inside the box `inner`,
/// fitted to the walls (notches reach into some cells): tried at its size,
/// then smaller, else none.
fn in_cell(
    rng: &mut ChaCha8Rng,
    room: &Room,
    placed: &[(Shape, (Point, Point))],
    inner: (Point, Point),
    want: f64,
    gap: f64,
) -> Option<Polygon> {
    let (bw, bh) = (inner.1.x - inner.0.x, inner.1.y - inner.0.y);
    let base = (0..10).find_map(|_| obstacle(rng, Point::new(0.0, 0.0), 1.0))?;
    let (lo, hi) = base.bounding_box();
    // The share of its box the shape fills, to scale it to `want`.
    let ratio = base.signed_area().abs() / ((hi.x - lo.x) * (hi.y - lo.y));
    let s = (want / (ratio * bw * bh)).sqrt();
    let (sx, sy) =
        ((s * rng.random_range(0.8..=1.2)).clamp(0.6, 1.0), (s * rng.random_range(0.8..=1.2)).clamp(0.6, 1.0));
    let mut shrink = 1.0;
    for _ in 0..6 {
        let (w, h) = (bw * sx * shrink, bh * sy * shrink);
        let at = Point::new(inner.0.x + rng.random_range(0.0..=bw - w), inner.0.y + rng.random_range(0.0..=bh - h));
        let pts = base
            .points
            .iter()
            .map(|p| pt(at.x + (p.x - lo.x) / (hi.x - lo.x) * w, at.y + (p.y - lo.y) / (hi.y - lo.y) * h))
            .collect();
        let poly = Polygon::new(hull(pts));
        if poly.points.len() >= 3 && room.fits(placed, &poly, poly.bounding_box(), gap) {
            return Some(poly);
        }
        shrink *= 0.85;
    }
    None
}

/// The obstacle that breaks 3.1.3: a small upright rectangle exactly
/// `narrow` from one of the outer rectangle's sides, nowhere nearer to the
/// boundary. `None` if no spot was found (a notch in every try).
pub fn narrow_obstacle(rng: &mut ChaCha8Rng, area: &Area, narrow: f64) -> Option<Shape> {
    let (x0, y0, x1, y1) = area.frame;
    for _ in 0..100 {
        let (len, depth) = (mm(rng.random_range(1.2..=2.0)), mm(rng.random_range(0.8..=1.2)));
        let side = rng.random_range(0..4);
        let (lo, hi) = match side {
            0 => {
                let x = rng.random_range(x0 + 2.0..=x1 - 2.0 - len);
                ((x, y0 + narrow), (x + len, y0 + narrow + depth))
            }
            1 => {
                let y = rng.random_range(y0 + 2.0..=y1 - 2.0 - len);
                ((x1 - narrow - depth, y), (x1 - narrow, y + len))
            }
            2 => {
                let x = rng.random_range(x0 + 2.0..=x1 - 2.0 - len);
                ((x, y1 - narrow - depth), (x + len, y1 - narrow))
            }
            _ => {
                let y = rng.random_range(y0 + 2.0..=y1 - 2.0 - len);
                ((x0 + narrow, y), (x0 + narrow + depth, y + len))
            }
        };
        let shape = Shape::Polygon(Polygon::new(vec![pt(lo.0, lo.1), pt(hi.0, lo.1), pt(hi.0, hi.1), pt(lo.0, hi.1)]));
        let gap = gaps::boundary_gap(&area.polygon, &shape).width;
        if gaps::strictly_inside(&area.polygon, &shape) && (gap - narrow).abs() < 2e-3 {
            return Some(shape);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walls_snap_clear_of_the_lattice() {
        // Free to the right: 0.1 past a half-column, so one row's vertex is
        // 0.4 from the wall and the other row's 0.9.
        assert_eq!(snap_x(3.02, 1.0, true), 3.1);
        assert_eq!(snap_x(3.02, 1.0, false), 2.9);
        assert!((snap_y(1.4, 1.0, true) - (2.0 * ROW - 0.4)).abs() < 1e-3);
        assert!((snap_y(1.4, 1.0, false) - (ROW + 0.4)).abs() < 1e-3);
    }

    #[test]
    fn hull_is_convex_and_counter_clockwise() {
        let pts = [(0.0, 0.0), (2.0, 0.0), (1.0, 0.5), (2.0, 2.0), (0.0, 2.0), (1.0, 0.0)];
        let h = hull(pts.iter().map(|&(x, y)| Point::new(x, y)).collect());
        assert_eq!(h.len(), 4, "{h:?}");
        assert!(Polygon::new(h).signed_area() > 0.0);
    }
}
