//! The ground truth: area, obstacles and targets laid over the grid frame.
//! Decides which vertices are accessible and which edges traversable by the
//! `r_safe` clearance (docs/paper.md "The world"), and measures the detected
//! fraction of `Ad` on a raster. Only engines and the world-server hold a
//! `World`; a robot learns of it through sensing alone.

use std::collections::VecDeque;
use std::sync::{Arc, OnceLock};

pub(crate) mod buckets;
pub mod coverage;
mod rows;

use crate::bitset::Bitset;
use crate::geometry::{crosses_ray, point_segment_distance, segment_segment_distance, Point, Polygon, Shape};
use crate::grid::{Grid, VertexId, NONE};
use crate::lattice::{Lattice, LatticeKind};
use crate::params::Params;
use crate::spot::Spot;

#[derive(Clone, Debug)]
pub struct World {
    pub grid: Grid,
    pub area: Polygon,
    pub obstacles: Vec<Shape>,
    pub targets: Vec<Point>,
    pub params: Params,
    accessible: Vec<bool>,
    /// `open[v]` bit `d`: the edge in slot `d` of `v` is traversable.
    open: Vec<u8>,
    /// Targets within `r_st` of each vertex.
    targets_near: Vec<Vec<u32>>,
    /// The engines' raster for coverage as it goes, made on first use and
    /// shared by every run on this world (and its clones).
    footprints: OnceLock<Arc<coverage::Footprints>>,
}

/// What can be near a point of the grid, for building a world: obstacles
/// and area edges within `r_safe` of a vertex or of an edge from it, the
/// area edges a ray from it may cross, the targets within `r_st`. Each
/// answer is a superset (the exact tests follow), so a world is the same as
/// testing every item, only faster on large maps.
struct Near {
    edges: Vec<(Point, Point)>,
    /// Obstacle boxes grown by `r_safe`: a point or edge outside one is
    /// clear of that obstacle.
    boxes: Vec<(Point, Point)>,
    by_cell: buckets::Buckets,
    edges_by_cell: buckets::Buckets,
    /// Edges by horizontal band, for the even-odd test.
    edges_by_row: buckets::Buckets,
    targets_by_cell: buckets::Buckets,
}

impl Near {
    fn new(area: &Polygon, obstacles: &[Shape], targets: &[Point], params: &Params, lo: Point, hi: Point) -> Self {
        let a = if params.a > 0.0 { params.a } else { (hi.x - lo.x).max(hi.y - lo.y).max(1.0) };
        let cell = (2.0 * a, 2.0 * a);
        // An edge from a vertex is `a` long: what is within r_safe of it is
        // within r_safe + a of the vertex.
        let reach = params.r_safe.max(0.0) + a;
        let m = params.r_safe;
        let boxes: Vec<(Point, Point)> = obstacles
            .iter()
            .map(|o| {
                let (lo, hi) = o.bounding_box();
                (Point::new(lo.x - m, lo.y - m), Point::new(hi.x + m, hi.y + m))
            })
            .collect();
        let edges: Vec<(Point, Point)> = area.edges().collect();
        let edge_boxes: Vec<(Point, Point)> = edges
            .iter()
            .map(|&(p, q)| (Point::new(p.x.min(q.x), p.y.min(q.y)), Point::new(p.x.max(q.x), p.y.max(q.y))))
            .collect();
        let points: Vec<(Point, Point)> = targets.iter().map(|&t| (t, t)).collect();
        let one_column = (2.0 * (hi.x - lo.x).abs() + 1.0, a);
        Near {
            by_cell: buckets::Buckets::new(lo, hi, cell, &boxes, reach),
            edges_by_cell: buckets::Buckets::new(lo, hi, cell, &edge_boxes, reach),
            edges_by_row: buckets::Buckets::new(lo, hi, one_column, &edge_boxes, 0.0),
            targets_by_cell: buckets::Buckets::new(lo, hi, cell, &points, params.r_st.max(0.0)),
            edges,
            boxes,
        }
    }

    /// The even-odd test of the area ([`Polygon::contains`]) on the edges
    /// whose band holds `p`: the others cannot cross its ray.
    fn inside(&self, p: Point) -> bool {
        self.edges_by_row
            .near(p)
            .iter()
            .filter(|&&k| crosses_ray(p, self.edges[k as usize].0, self.edges[k as usize].1))
            .count()
            % 2
            == 1
    }

    /// Area edges that may come within `r_safe` of `p` or of an edge from it.
    fn edges(&self, p: Point) -> impl Iterator<Item = (Point, Point)> + '_ {
        self.edges_by_cell.near(p).iter().map(|&k| self.edges[k as usize])
    }

    /// Obstacles whose grown box meets the box of the segment `[p, q]`
    /// (`q` at most `a` from `p`).
    fn obstacles(&self, p: Point, q: Point) -> impl Iterator<Item = usize> + '_ {
        let (lo, hi) = (Point::new(p.x.min(q.x), p.y.min(q.y)), Point::new(p.x.max(q.x), p.y.max(q.y)));
        self.by_cell.near(p).iter().map(|&k| k as usize).filter(move |&k| {
            let (a, b) = self.boxes[k];
            lo.x <= b.x && hi.x >= a.x && lo.y <= b.y && hi.y >= a.y
        })
    }

    /// Targets that may be within `r_st` of `p`, ascending.
    fn targets(&self, p: Point) -> impl Iterator<Item = u32> + '_ {
        self.targets_by_cell.near(p).iter().copied()
    }
}

impl World {
    pub fn new(area: Polygon, obstacles: Vec<Shape>, targets: Vec<Point>, params: Params, kind: LatticeKind) -> Self {
        let (lo, hi) = area.bounding_box();
        let grid = Grid::new(Lattice::new(kind, params.a), lo, hi);
        let near = Near::new(&area, &obstacles, &targets, &params, lo, hi);
        let r_safe = params.r_safe;
        let clear = |p: Point| {
            near.inside(p)
                && near.edges(p).all(|(a, b)| point_segment_distance(p, a, b) >= r_safe)
                && near.obstacles(p, p).all(|k| obstacles[k].distance(p) >= r_safe)
        };
        let accessible: Vec<bool> = (0..grid.len() as VertexId).map(|v| clear(grid.position(v))).collect();
        let open = (0..grid.len() as VertexId)
            .map(|v| {
                let mut mask = 0u8;
                if !accessible[v as usize] {
                    return mask;
                }
                let p = grid.position(v);
                for (d, &n) in grid.neighbors(v)[..grid.degree()].iter().enumerate() {
                    if n == NONE || !accessible[n as usize] {
                        continue;
                    }
                    let q = grid.position(n);
                    let ok = near.edges(p).all(|(a, b)| segment_segment_distance(p, q, a, b) >= r_safe)
                        && near.obstacles(p, q).all(|k| obstacles[k].segment_distance(p, q) >= r_safe);
                    if ok {
                        mask |= 1 << d;
                    }
                }
                mask
            })
            .collect();
        let targets_near = (0..grid.len() as VertexId)
            .map(|v| {
                let p = grid.position(v);
                near.targets(p).filter(|&t| (targets[t as usize] - p).norm() <= params.r_st).collect()
            })
            .collect();
        World { grid, area, obstacles, targets, params, accessible, open, targets_near, footprints: OnceLock::new() }
    }

    pub fn is_accessible(&self, v: VertexId) -> bool {
        self.accessible[v as usize]
    }

    /// Traversable-edge mask of `v` by adjacency slot.
    pub fn open_mask(&self, v: VertexId) -> u8 {
        self.open[v as usize]
    }

    /// Whether the move `from → to` is along a traversable edge.
    pub fn can_move(&self, from: VertexId, to: VertexId) -> bool {
        self.grid.slot_of(from, to).is_some_and(|d| self.open[from as usize] >> d & 1 == 1)
    }

    /// Targets within `r_st` of vertex `v`.
    pub fn targets_near(&self, v: VertexId) -> &[u32] {
        &self.targets_near[v as usize]
    }

    /// Where target `t` is, as a robot's laser reads it: robots never see
    /// the world's target ids.
    pub fn spot(&self, t: u32) -> Spot {
        Spot::at(self.targets[t as usize], self.params.a)
    }

    /// Accessible vertices, in id order.
    pub fn accessible_vertices(&self) -> impl Iterator<Item = VertexId> + '_ {
        (0..self.grid.len() as VertexId).filter(|&v| self.accessible[v as usize])
    }

    /// `Va`: the accessible vertices reachable from `starts` over traversable edges.
    pub fn reachable_from(&self, starts: &[VertexId]) -> Vec<bool> {
        self.reachable_avoiding(starts, &[])
    }

    /// Accessible vertices reachable from `starts` over traversable edges
    /// without entering any of `blocked` (the bodies of failed robots).
    pub fn reachable_avoiding(&self, starts: &[VertexId], blocked: &[VertexId]) -> Vec<bool> {
        let mut seen = vec![false; self.grid.len()];
        let mut stop = vec![false; self.grid.len()];
        for &b in blocked {
            stop[b as usize] = true;
        }
        let mut queue: VecDeque<VertexId> = VecDeque::new();
        for &s in starts {
            if self.accessible[s as usize] && !seen[s as usize] {
                seen[s as usize] = true;
                queue.push_back(s);
            }
        }
        while let Some(v) = queue.pop_front() {
            for (d, &n) in self.grid.neighbors(v)[..self.grid.degree()].iter().enumerate() {
                if self.open[v as usize] >> d & 1 == 1 && !seen[n as usize] && !stop[n as usize] {
                    seen[n as usize] = true;
                    queue.push_back(n);
                }
            }
        }
        seen
    }

    /// Whether `p` lies in `Ad` (in the area, outside every obstacle).
    pub fn in_ad(&self, p: Point) -> bool {
        self.area.contains(p) && !self.obstacles.iter().any(|o| o.contains(p))
    }

    /// The detected fraction of `Ad` once robots have stood on the
    /// `visited` vertices: a run's `coverage`, on the engines' raster.
    pub fn detected_fraction_of(&self, visited: &Bitset) -> f64 {
        let centres = visited.iter().map(|v| self.grid.position(v as VertexId));
        self.raster(crate::engine::RASTER_CELL * self.params.a).detected_fraction(centres, self.params.r_st)
    }

    /// The engines' raster and the vertices' footprints on it, for
    /// [`coverage::Coverage`]: made by the first run that asks, from the
    /// parameters then (a world's parameters are not changed once runs
    /// have started on it).
    pub fn footprints(&self) -> &coverage::Footprints {
        self.footprints.get_or_init(|| {
            let raster = self.raster(crate::engine::RASTER_CELL * self.params.a);
            Arc::new(coverage::Footprints::new(raster, self.params.r_st))
        })
    }

    /// A raster of `Ad` with cells of side `h`, for the detected fraction:
    /// the same cells as [`World::in_ad`], found a row at a time
    /// ([`rows`]; a 180 m map with a thousand obstacles took 24 s testing
    /// every cell against every obstacle).
    pub fn raster(&self, h: f64) -> Raster {
        let (lo, hi) = self.area.bounding_box();
        let nx = ((hi.x - lo.x) / h).ceil().max(1.0) as usize;
        let ny = ((hi.y - lo.y) / h).ceil().max(1.0) as usize;
        let inside = rows::in_ad(&self.area, &self.obstacles, lo, h, nx, ny);
        let count = inside.iter().filter(|&&b| b).count();
        Raster { origin: lo, h, nx, ny, inside, count }
    }
}

/// Sample points (cell centres) of `Ad`; a sample is detected once it lies
/// within the sensing range of some visited point.
#[derive(Clone, Debug)]
pub struct Raster {
    origin: Point,
    h: f64,
    nx: usize,
    ny: usize,
    inside: Vec<bool>,
    count: usize,
}

impl Raster {
    /// Whether cell `k` (row-major, `nx` cells a row from the area's
    /// bounding box) lies in `Ad`.
    pub fn cell_in_ad(&self, k: usize) -> bool {
        self.inside[k]
    }

    /// Number of samples in `Ad`.
    pub fn samples(&self) -> usize {
        self.count
    }

    /// Fraction of the samples of `Ad` within `r` of at least one of `centres`.
    pub fn detected_fraction(&self, centres: impl IntoIterator<Item = Point>, r: f64) -> f64 {
        if self.count == 0 {
            return 1.0;
        }
        let mut hit = self.unmarked();
        let detected: usize = centres.into_iter().map(|c| self.mark(&mut hit, c, r)).sum();
        detected as f64 / self.count as f64
    }

    /// The samples of `Ad` not marked in `hit` (from [`Raster::mark`]):
    /// where the area stays undetected.
    pub fn unmarked_samples<'a>(&'a self, hit: &'a [bool]) -> impl Iterator<Item = Point> + 'a {
        (0..self.inside.len()).filter(move |&k| self.inside[k] && !hit[k]).map(move |k| {
            let (x, y) = (k % self.nx, k / self.nx);
            Point::new(self.origin.x + (x as f64 + 0.5) * self.h, self.origin.y + (y as f64 + 0.5) * self.h)
        })
    }

    /// A blank record for [`Raster::mark`]: no sample detected yet.
    pub fn unmarked(&self) -> Vec<bool> {
        vec![false; self.inside.len()]
    }

    /// Marks in `hit` (from [`Raster::unmarked`]) the samples of `Ad` within
    /// `r` of `c`, returning how many were not marked before. The
    /// incremental form of [`Raster::detected_fraction`], for the detected
    /// fraction round by round.
    pub fn mark(&self, hit: &mut [bool], c: Point, r: f64) -> usize {
        let mut detected = 0;
        let x0 = (((c.x - r - self.origin.x) / self.h).floor().max(0.0)) as usize;
        let y0 = (((c.y - r - self.origin.y) / self.h).floor().max(0.0)) as usize;
        let x1 = (((c.x + r - self.origin.x) / self.h).ceil().max(0.0) as usize).min(self.nx);
        let y1 = (((c.y + r - self.origin.y) / self.h).ceil().max(0.0) as usize).min(self.ny);
        for y in y0..y1 {
            for x in x0..x1 {
                let k = y * self.nx + x;
                if !self.inside[k] || hit[k] {
                    continue;
                }
                let p =
                    Point::new(self.origin.x + (x as f64 + 0.5) * self.h, self.origin.y + (y as f64 + 0.5) * self.h);
                if (p - c).norm() <= r {
                    hit[k] = true;
                    detected += 1;
                }
            }
        }
        detected
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Circle;

    /// The world as testing every vertex and edge against every area edge,
    /// obstacle and target: what [`Near`]'s cells must not change.
    fn tested_against_everything(w: &World) -> (Vec<bool>, Vec<u8>, Vec<Vec<u32>>) {
        let (g, r) = (&w.grid, w.params.r_safe);
        let clear = |p: Point| {
            w.area.contains(p) && w.area.boundary_distance(p) >= r && w.obstacles.iter().all(|o| o.distance(p) >= r)
        };
        let accessible: Vec<bool> = (0..g.len() as VertexId).map(|v| clear(g.position(v))).collect();
        let open = (0..g.len() as VertexId)
            .map(|v| {
                let (p, mut mask) = (g.position(v), 0u8);
                for (d, &n) in g.neighbors(v)[..g.degree()].iter().enumerate() {
                    if accessible[v as usize] && n != NONE && accessible[n as usize] {
                        let q = g.position(n);
                        let ok = w.area.boundary_segment_distance(p, q) >= r
                            && w.obstacles.iter().all(|o| o.segment_distance(p, q) >= r);
                        mask |= (ok as u8) << d;
                    }
                }
                mask
            })
            .collect();
        let near = (0..g.len() as VertexId)
            .map(|v| {
                (0..w.targets.len() as u32)
                    .filter(|&t| (w.targets[t as usize] - g.position(v)).norm() <= w.params.r_st)
                    .collect()
            })
            .collect();
        (accessible, open, near)
    }

    #[test]
    fn cells_change_nothing() {
        let mut worlds: Vec<World> = ["paper", "cave", "large", "open", "small", "comb"]
            .iter()
            .map(|n| crate::scenario::Scenario::builtin(n).unwrap().world())
            .collect();
        for seed in 1..=4 {
            let spec = format!("random:{seed},size=60x40,density=0.3,targets=40");
            worlds.push(crate::scenario::Scenario::load(&spec).unwrap().world());
        }
        // A many-cornered area: its edges are found by band and by cell.
        let star: Vec<Point> = (0..300)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 300.0;
                let r = 12.0 + 2.0 * (7.0 * t).sin();
                Point::new(15.0 + r * t.cos(), 15.0 + r * t.sin())
            })
            .collect();
        let targets = vec![Point::new(15.0, 15.0), Point::new(10.0, 18.0)];
        worlds.push(World::new(Polygon::new(star), vec![], targets, Params::default(), LatticeKind::Triangular));
        for w in &worlds {
            let (accessible, open, near) = tested_against_everything(w);
            assert!(accessible.iter().any(|&a| a) && open.iter().any(|&m| m != 0));
            assert_eq!(w.accessible, accessible);
            assert_eq!(w.open, open);
            assert_eq!(w.targets_near, near);
            // The raster's cells too, at a side that puts cell centres
            // on and near obstacle and area edges.
            let r = w.raster(w.params.a / 3.0);
            let (lo, _) = w.area.bounding_box();
            let h = w.params.a / 3.0;
            let tested = (0..r.ny)
                .flat_map(|y| (0..r.nx).map(move |x| (x, y)))
                .filter(|&(x, y)| w.in_ad(Point::new(lo.x + (x as f64 + 0.5) * h, lo.y + (y as f64 + 0.5) * h)));
            assert!(tested.clone().all(|(x, y)| r.inside[y * r.nx + x]));
            assert_eq!(tested.count(), r.count);
        }
    }

    fn rect(w: f64, h: f64) -> Polygon {
        Polygon::new(vec![Point::new(0.0, 0.0), Point::new(w, 0.0), Point::new(w, h), Point::new(0.0, h)])
    }

    #[test]
    fn clearance_rules_vertices_and_edges() {
        let params = Params::default();
        let obstacle = Shape::Circle(Circle { center: Point::new(5.0, 5.0), radius: 1.0 });
        let w = World::new(rect(10.0, 10.0), vec![obstacle.clone()], vec![], params, LatticeKind::Triangular);
        for v in 0..w.grid.len() as VertexId {
            let p = w.grid.position(v);
            let clear =
                p.x >= 0.3 && p.x <= 9.7 && p.y >= 0.3 && p.y <= 9.7 && (p - Point::new(5.0, 5.0)).norm() >= 1.3;
            assert_eq!(w.is_accessible(v), clear, "{p:?}");
        }
        // Every open edge keeps the clearance along its whole length.
        for v in w.accessible_vertices() {
            for d in 0..6 {
                if w.open_mask(v) >> d & 1 == 1 {
                    let n = w.grid.neighbors(v)[d];
                    assert!(obstacle.segment_distance(w.grid.position(v), w.grid.position(n)) >= 0.3);
                    // Symmetric.
                    assert!(w.can_move(n, v));
                }
            }
        }
    }

    #[test]
    fn wall_splits_va() {
        let params = Params::default();
        let wall = Shape::Polygon(rect(0.2, 10.0));
        let wall = match wall {
            Shape::Polygon(mut p) => {
                p.points.iter_mut().for_each(|q| q.x += 4.9);
                Shape::Polygon(p)
            }
            s => s,
        };
        let w = World::new(rect(10.0, 6.0), vec![wall], vec![], params, LatticeKind::Square);
        let left = w.grid.nearest(Point::new(1.0, 1.0)).unwrap();
        let va = w.reachable_from(&[left]);
        for v in w.accessible_vertices() {
            assert_eq!(va[v as usize], w.grid.position(v).x < 5.0);
        }
    }

    #[test]
    fn raster_fraction_of_full_cover_is_one() {
        let w = World::new(rect(4.0, 4.0), vec![], vec![], Params::default(), LatticeKind::Triangular);
        let r = w.raster(0.1);
        assert_eq!(r.samples(), 1600);
        assert_eq!(r.detected_fraction([Point::new(2.0, 2.0)], 10.0), 1.0);
        let half = r.detected_fraction([Point::new(0.0, 2.0)], 2.0);
        assert!(half > 0.35 && half < 0.45, "{half}");
        let mut hit = r.unmarked();
        let marked = r.mark(&mut hit, Point::new(0.0, 2.0), 2.0);
        let rest: Vec<Point> = r.unmarked_samples(&hit).collect();
        assert_eq!(marked + rest.len(), 1600);
        assert!(rest.iter().all(|p| (p - Point::new(0.0, 2.0)).norm() > 2.0));
    }
}
