//! The cells of a raster that lie in `Ad`, a row at a time: every edge of
//! the area and of the obstacles crosses a row's line once, so a row costs
//! the edges that span it and its cells, not its cells times the
//! obstacles whose boxes cover them. A long thin diagonal obstacle has a
//! box far bigger than itself, and testing each cell of such boxes made
//! the raster of 80 of them 1.5 s (issue 23). The answer is cell for cell
//! that of [`crate::world::World::in_ad`]: the same even-odd crossing test
//! ([`crate::geometry::crosses_ray`]) of the same edges.

use crate::geometry::{Point, Polygon, Shape};

/// An edge of polygon `of` (0 the area, `k + 1` obstacle `k`), lower end first in y.
struct Edge {
    a: Point,
    b: Point,
    of: u32,
}

/// `inside[y * nx + x]` for the cells of side `h` from `lo`, `nx` by `ny`.
pub(super) fn in_ad(area: &Polygon, obstacles: &[Shape], lo: Point, h: f64, nx: usize, ny: usize) -> Vec<bool> {
    let polygons = std::iter::once(area).chain(obstacles.iter().filter_map(|o| match o {
        Shape::Polygon(p) => Some(p),
        Shape::Circle(_) => None,
    }));
    let ids = std::iter::once(0)
        .chain(obstacles.iter().enumerate().filter(|(_, o)| matches!(o, Shape::Polygon(_))).map(|(k, _)| k as u32 + 1));
    let mut edges: Vec<Edge> = polygons
        .zip(ids)
        .flat_map(|(p, of)| p.edges().map(move |(a, b)| Edge { a, b, of }))
        .filter(|e| e.a.y != e.b.y)
        .collect();
    edges.sort_by(|e, f| e.a.y.min(e.b.y).total_cmp(&f.a.y.min(f.b.y)));
    let mut circles: Vec<(Point, f64)> = obstacles
        .iter()
        .filter_map(|o| match o {
            Shape::Circle(c) => Some((c.center, c.radius)),
            Shape::Polygon(_) => None,
        })
        .collect();
    circles.sort_by(|c, d| (c.0.y - c.1).total_cmp(&(d.0.y - d.1)));

    let mut inside = vec![false; nx * ny];
    let mut odd = vec![false; obstacles.len() + 1];
    let (mut next_edge, mut next_circle) = (0, 0);
    let mut active: Vec<usize> = Vec::new();
    let mut round: Vec<usize> = Vec::new();
    let mut crossings: Vec<(f64, u32)> = Vec::new();
    for y in 0..ny {
        let py = lo.y + (y as f64 + 0.5) * h;
        // Edges whose lower end is at or below the row join; those whose
        // upper end is at or below it leave for good.
        while next_edge < edges.len() && edges[next_edge].a.y.min(edges[next_edge].b.y) <= py {
            active.push(next_edge);
            next_edge += 1;
        }
        active.retain(|&k| edges[k].a.y.max(edges[k].b.y) > py);
        crossings.clear();
        for &k in &active {
            let Edge { a, b, of } = edges[k];
            // crosses_ray's test for every p on this row: p.x < x.
            if (a.y > py) != (b.y > py) {
                crossings.push((a.x + (py - a.y) * (b.x - a.x) / (b.y - a.y), of));
            }
        }
        crossings.sort_by(|c, d| d.0.total_cmp(&c.0));
        // From the right: a cell's crossings are those right of it.
        odd.fill(false);
        let (mut area_odd, mut obstacles_odd) = (false, 0usize);
        let mut c = 0;
        let row = &mut inside[y * nx..(y + 1) * nx];
        for x in (0..nx).rev() {
            let px = lo.x + (x as f64 + 0.5) * h;
            while c < crossings.len() && px < crossings[c].0 {
                let of = crossings[c].1 as usize;
                odd[of] = !odd[of];
                if of == 0 {
                    area_odd = odd[0];
                } else if odd[of] {
                    obstacles_odd += 1;
                } else {
                    obstacles_odd -= 1;
                }
                c += 1;
            }
            row[x] = area_odd && obstacles_odd == 0;
        }
        // Circles: each cell of the row near one tested exactly.
        while next_circle < circles.len() && circles[next_circle].0.y - circles[next_circle].1 <= py + h {
            round.push(next_circle);
            next_circle += 1;
        }
        round.retain(|&k| circles[k].0.y + circles[k].1 >= py - h);
        for &k in &round {
            let (centre, r) = circles[k];
            let first = ((centre.x - r - lo.x) / h - 1.0).floor().max(0.0) as usize;
            let last = (((centre.x + r - lo.x) / h + 1.0).ceil().max(0.0) as usize).min(nx);
            for x in first.min(nx)..last {
                let p = Point::new(lo.x + (x as f64 + 0.5) * h, py);
                if (p - centre).norm() <= r {
                    row[x] = false;
                }
            }
        }
    }
    inside
}
