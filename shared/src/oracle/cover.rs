//! The oracle's waypoints in situation 1: vertices of `Va` whose sensing
//! discs (radius `r_st`) cover the area around `Va`, so the plan need not
//! visit every vertex (with `r_st = 1.3 a` about every other row covers
//! it). The area is sampled: every triangle of the lattice with a corner
//! in `Va`, at [`SUB`] points a side (of one with a corner outside, the
//! points nearest to a vertex of `Va`). The waypoints start as every other
//! row of `Va` (rows a tour sweeps along, one move a waypoint), then a
//! greedy set cover (the vertex covering the most uncovered samples first,
//! the lowest id among equals) covers what the rows leave, by walls and
//! gaps; of the two row parities, the one needing fewer waypoints (a
//! greedy cover from scratch scatters its waypoints, and a tour through
//! them costs nearly as much as visiting every vertex). Deterministic. A
//! target in a sliver between samples (or beyond them, by a wall) may be
//! missed: the execution then plans again for the rest of `Va`, so
//! every run completes.

use std::collections::{BinaryHeap, HashMap};

use crate::geometry::Point;
use crate::grid::{VertexId, NONE};
use crate::world::World;

use super::plan::Dist;

/// Samples a triangle side: points every `a / SUB`.
const SUB: usize = 4;

/// Which compact vertices of `d` are waypoints.
pub(super) fn waypoints(world: &World, d: &Dist) -> Vec<bool> {
    let samples = samples(world, d);
    let covers = coverers(world, d, &samples);
    let row = |c: usize| world.grid.coord(d.verts[c]).j.rem_euclid(2);
    let [even, odd] = [0, 1].map(|p| {
        let rows: Vec<bool> = (0..d.len()).map(|c| row(c) == p).collect();
        greedy(rows, &covers, samples.len())
    });
    let count = |x: &[bool]| x.iter().filter(|&&b| b).count();
    if count(&odd) < count(&even) {
        odd
    } else {
        even
    }
}

/// Points of every lattice triangle with a corner in `Va` (nearest to a
/// vertex of `Va` when not all are), each once.
fn samples(world: &World, d: &Dist) -> Vec<Point> {
    let g = &world.grid;
    let deg = g.degree();
    let key = |p: Point| ((p.x * 1e6).round() as i64, (p.y * 1e6).round() as i64);
    let mut seen: HashMap<(i64, i64), ()> = HashMap::new();
    let mut out = Vec::new();
    for &v in &d.verts {
        let n = &g.neighbors(v)[..deg];
        let o = g.position(v);
        for s in 0..deg {
            let (a, b) = (n[s], n[(s + 1) % deg]);
            if a == NONE || b == NONE {
                continue;
            }
            let outside = |v: VertexId| d.index[v as usize] == u32::MAX;
            let all_in = !(outside(a) || outside(b));
            let (ea, eb) = (g.position(a) - o, g.position(b) - o);
            for i in 0..=SUB {
                for j in 0..=SUB - i {
                    let p = o + ea * (i as f64 / SUB as f64) + eb * (j as f64 / SUB as f64);
                    // Of a triangle reaching past a wall, only the part
                    // nearer to Va than to the wall's side: all of it would
                    // ask for waypoints along every wall for area beyond it,
                    // none of it would miss targets by the walls.
                    if !all_in && g.nearest(p).is_none_or(outside) {
                        continue;
                    }
                    if seen.insert(key(p), ()).is_none() {
                        out.push(p);
                    }
                }
            }
        }
    }
    out
}

/// For each compact vertex, the samples within `r_st` of it. A sample's
/// coverers are found among the grid vertices near the first vertex of
/// `Va` within reach, by a walk over the lattice (obstacles do not block
/// the laser's range here, as in the world's sensing).
fn coverers(world: &World, d: &Dist, samples: &[Point]) -> Vec<Vec<u32>> {
    let g = &world.grid;
    let r = world.params.r_st + 1e-9;
    let mut covers = vec![Vec::new(); d.len()];
    let mut near: Vec<VertexId> = Vec::new();
    let mut mark: HashMap<VertexId, ()> = HashMap::new();
    for (k, &p) in samples.iter().enumerate() {
        let Some(start) = g.nearest(p) else { continue };
        near.clear();
        mark.clear();
        near.push(start);
        mark.insert(start, ());
        let mut head = 0;
        // Every vertex within `r_st + a` of the sample: those within `r_st`
        // are reached through them.
        while head < near.len() {
            let v = near[head];
            head += 1;
            for &w in &g.neighbors(v)[..g.degree()] {
                if w != NONE && (g.position(w) - p).norm() <= r + world.params.a && mark.insert(w, ()).is_none() {
                    near.push(w);
                }
            }
        }
        for &v in &near {
            let c = d.index[v as usize];
            if c != u32::MAX && (g.position(v) - p).norm() <= r {
                covers[c as usize].push(k as u32);
            }
        }
    }
    covers
}

/// The greedy set cover completing `pick`: lazily re-evaluated gains in
/// a heap, the most first, the lowest vertex among equals.
fn greedy(mut pick: Vec<bool>, covers: &[Vec<u32>], samples: usize) -> Vec<bool> {
    let n = pick.len();
    let mut done = vec![false; samples];
    for u in (0..n).filter(|&u| pick[u]) {
        for &s in &covers[u] {
            done[s as usize] = true;
        }
    }
    let mut heap: BinaryHeap<(usize, std::cmp::Reverse<u32>)> =
        (0..n).map(|u| (covers[u].len(), std::cmp::Reverse(u as u32))).collect();
    while let Some((gain, std::cmp::Reverse(u))) = heap.pop() {
        if gain == 0 {
            break;
        }
        let now = covers[u as usize].iter().filter(|&&s| !done[s as usize]).count();
        if now < gain {
            heap.push((now, std::cmp::Reverse(u)));
            continue;
        }
        pick[u as usize] = true;
        for &s in &covers[u as usize] {
            done[s as usize] = true;
        }
    }
    pick
}
