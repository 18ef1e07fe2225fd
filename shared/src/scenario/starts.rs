//! Placing robots on start vertices (Assumption 2.2: "allocated at different
//! vertices along the border of the area").

use std::collections::VecDeque;

use super::ScenarioError;
use crate::geometry::Point;
use crate::grid::{VertexId, NONE};
use crate::world::World;

/// Whether `v` is on the border: accessible, missing a usable neighbour in
/// some slot, and near the area's own boundary. The distance test keeps the
/// ring around an obstacle out, so robots start along the edge of the area
/// as the paper's Fig. 5 shows, not around an obstacle in the middle.
fn on_border(w: &World, v: VertexId) -> bool {
    if !w.is_accessible(v) {
        return false;
    }
    let g = &w.grid;
    let blocked = g.neighbors(v)[..g.degree()].iter().any(|&n| n == NONE || !w.is_accessible(n));
    blocked && w.area.boundary_distance(g.position(v)) <= w.params.a + w.params.r_safe + 1e-9
}

/// `robots` distinct vertices that form a chain along the border, beginning
/// at the border vertex nearest to `from`: breadth-first over traversable
/// edges between border vertices, so every vertex taken is adjacent to one
/// taken before it. If the border is too short the search goes on over all of
/// `Va`. Ties go to the lower vertex id and neighbours are visited in slot
/// order, so the result depends on nothing but the world.
pub(crate) fn border(w: &World, from: Point, robots: usize, file: &str) -> Result<Vec<VertexId>, ScenarioError> {
    let g = &w.grid;
    let err = |msg: String| ScenarioError::new(file, None, "starts.border", msg);
    let border: Vec<bool> = (0..g.len() as VertexId).map(|v| on_border(w, v)).collect();
    let first = (0..g.len() as VertexId)
        .filter(|&v| border[v as usize])
        .min_by(|&u, &v| (g.position(u) - from).norm().total_cmp(&(g.position(v) - from).norm()))
        .ok_or_else(|| err("the area has no accessible vertex along its border".into()))?;
    let va = w.reachable_from(&[first]);
    let va_len = va.iter().filter(|&&b| b).count();
    if va_len < robots {
        let p = g.position(first);
        return Err(err(format!(
            "robots = {robots} but only {va_len} vertices are reachable from the border vertex ({:.2}, {:.2}) nearest to ({}, {})",
            p.x, p.y, from.x, from.y
        )));
    }

    let mut taken = Vec::with_capacity(robots);
    let mut seen = vec![false; g.len()];
    let bfs = |queue: &mut VecDeque<VertexId>, seen: &mut Vec<bool>, taken: &mut Vec<VertexId>, only_border: bool| {
        while let Some(v) = queue.pop_front() {
            if taken.len() == robots {
                return;
            }
            taken.push(v);
            for (d, &n) in g.neighbors(v)[..g.degree()].iter().enumerate() {
                if w.open_mask(v) >> d & 1 == 1 && !seen[n as usize] && (!only_border || border[n as usize]) {
                    seen[n as usize] = true;
                    queue.push_back(n);
                }
            }
        }
    };
    seen[first as usize] = true;
    bfs(&mut VecDeque::from([first]), &mut seen, &mut taken, true);
    if taken.len() < robots {
        // The border chain ran out: grow from every vertex taken so far, in
        // the order taken, over all of Va. Vertices queued but not taken in
        // the first pass cannot exist (it ended with an empty queue).
        let mut queue = VecDeque::new();
        let already = taken.clone();
        taken.clear();
        seen.iter_mut().for_each(|s| *s = false);
        for &v in &already {
            seen[v as usize] = true;
            queue.push_back(v);
        }
        bfs(&mut queue, &mut seen, &mut taken, false);
    }
    debug_assert_eq!(taken.len(), robots);
    Ok(taken)
}

/// The first `robots` given points, each snapped to its nearest vertex.
pub(crate) fn points(w: &World, pts: &[Point], robots: usize, file: &str) -> Result<Vec<VertexId>, ScenarioError> {
    if pts.len() < robots {
        return Err(ScenarioError::new(
            file,
            None,
            "starts.points",
            format!("{} start points for {robots} robots: give at least one point per robot", pts.len()),
        ));
    }
    let mut out: Vec<VertexId> = Vec::with_capacity(robots);
    for (k, &p) in pts[..robots].iter().enumerate() {
        let field = format!("starts.points[{k}]");
        let v = w.grid.nearest(p).filter(|&v| w.is_accessible(v)).ok_or_else(|| {
            ScenarioError::new(
                file,
                None,
                field.clone(),
                format!("the vertex nearest to ({}, {}) is not accessible", p.x, p.y),
            )
        })?;
        if let Some(j) = out.iter().position(|&u| u == v) {
            return Err(ScenarioError::new(file, None, field, format!("is on the same vertex as starts.points[{j}]")));
        }
        out.push(v);
    }
    Ok(out)
}
