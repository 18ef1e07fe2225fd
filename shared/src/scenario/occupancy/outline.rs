//! From pixels to polygons: the image is read in square cells of `k x k`
//! pixels, the largest 4-connected free region becomes the area and every
//! blocked region inside it one obstacle, each traced as one rectilinear
//! outline (its cells merged). The scenario format wants simple polygons,
//! obstacles inside the area and clear of its boundary and of one another;
//! the rules below give exactly that, and count what they changed:
//!
//! - a cell is occupied if any of its pixels is, else free if at least half
//!   are free (pixels past the image's edge are unknown), else unknown;
//!   unknown cells are blocked unless the sidecar reads them as free;
//! - free cells that no square of free cells `sliver` wide covers (slots,
//!   spikes and specks narrower than a robot, mostly pixel noise along
//!   walls, which would read as passages and pockets no robot can enter)
//!   are blocked;
//! - free cells apart from the largest free region (pockets no robot could
//!   reach from it) are blocked;
//! - where two free cells touch only at a corner, between two blocked ones,
//!   an outline would touch itself: the first of them is blocked;
//! - blocked cells 8-connected to the outside are the outside; every other
//!   8-connected blocked region is an obstacle, at least one free cell away
//!   from the outside and from every other obstacle.

use super::image::{Class, Raster};

/// Where the cells are: the image's lower-left corner and its pixel side.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    pub origin: (f64, f64),
    pub resolution: f64,
}

/// The map read at one cell size: polygons as corner lists, and counts.
#[derive(Clone, Debug, Default)]
pub struct Outline {
    pub area: Vec<(f64, f64)>,
    pub obstacles: Vec<Vec<(f64, f64)>>,
    /// Free cells in slivers narrower than the sliver width.
    pub sliver_cells: usize,
    /// Free cells in pockets apart from the largest free region, and pockets.
    pub pocket_cells: usize,
    pub pockets: usize,
    /// Free cells blocked where free cells touched only at a corner.
    pub pinch_cells: usize,
    /// Blocked cells merged into the obstacles.
    pub obstacle_cells: usize,
    pub free_cells: usize,
}

/// Cells with a ring of blocked cells around the image, row 0 at the bottom.
struct Cells {
    w: usize,
    h: usize,
    free: Vec<bool>,
}

impl Cells {
    fn at(&self, i: usize, j: usize) -> usize {
        j * self.w + i
    }

    /// The 4 or 8 neighbours of cell `c` (the ring keeps every real cell
    /// off the edge; the ring's own cells get the ones that exist).
    fn neighbours(&self, c: usize, eight: bool) -> impl Iterator<Item = usize> + '_ {
        let (i, j) = ((c % self.w) as isize, (c / self.w) as isize);
        const FOUR: [(isize, isize); 4] = [(1, 0), (-1, 0), (0, 1), (0, -1)];
        const DIAG: [(isize, isize); 4] = [(1, 1), (-1, 1), (1, -1), (-1, -1)];
        let diag = if eight { &DIAG[..] } else { &[] };
        FOUR.iter().chain(diag).filter_map(move |&(di, dj)| {
            let (x, y) = (i + di, j + dj);
            (x >= 0 && y >= 0 && (x as usize) < self.w && (y as usize) < self.h)
                .then(|| self.at(x as usize, y as usize))
        })
    }

    /// Connected components of the cells where `member` holds, as labels
    /// (`u32::MAX` for the others) and their sizes, in scan order.
    fn components(&self, member: impl Fn(usize) -> bool, eight: bool) -> (Vec<u32>, Vec<usize>) {
        let mut label = vec![u32::MAX; self.free.len()];
        let mut sizes = Vec::new();
        let mut stack = Vec::new();
        for start in 0..self.free.len() {
            if label[start] != u32::MAX || !member(start) {
                continue;
            }
            let id = sizes.len() as u32;
            label[start] = id;
            stack.push(start);
            let mut size = 0;
            while let Some(c) = stack.pop() {
                size += 1;
                for n in self.neighbours(c, eight) {
                    if label[n] == u32::MAX && member(n) {
                        label[n] = id;
                        stack.push(n);
                    }
                }
            }
            sizes.push(size);
        }
        (label, sizes)
    }
}

/// The cells of `raster` at `k x k` pixels each.
fn coarsen(raster: &Raster, k: usize, unknown_free: bool) -> Cells {
    let (w, h) = (raster.width.div_ceil(k) + 2, raster.height.div_ceil(k) + 2);
    let mut occupied = vec![0u32; w * h];
    let mut free = vec![0u32; w * h];
    for (row, line) in raster.cells.chunks(raster.width).enumerate() {
        let j = (raster.height - 1 - row) / k + 1;
        for (x, class) in line.iter().enumerate() {
            let c = j * w + x / k + 1;
            match class {
                Class::Occupied => occupied[c] += 1,
                Class::Free => free[c] += 1,
                Class::Unknown if unknown_free => free[c] += 1,
                Class::Unknown => {}
            }
        }
    }
    let whole = (k * k) as u32;
    let mut cells = Cells { w, h, free: vec![false; w * h] };
    for j in 1..h - 1 {
        for i in 1..w - 1 {
            let c = j * w + i;
            // Past the image's edge: unknown, or free when unknown is.
            let beyond = if unknown_free { whole - occupied[c] - free[c] } else { 0 };
            cells.free[c] = occupied[c] == 0 && 2 * (free[c] + beyond) >= whole;
        }
    }
    cells
}

/// Blocks the free cells that no `s x s` square of free cells covers (a
/// morphological opening, separable: runs along rows, then columns);
/// returns how many.
fn drop_slivers(cells: &mut Cells, s: usize) -> usize {
    if s <= 1 {
        return 0;
    }
    let (w, h) = (cells.w, cells.h);
    // Free cells from each cell rightwards, up to s.
    let mut run = vec![0u16; w * h];
    for j in 0..h {
        let mut r = 0;
        for i in (0..w).rev() {
            r = if cells.free[j * w + i] { (r + 1).min(s) } else { 0 };
            run[j * w + i] = r as u16;
        }
    }
    // The lower-left cells of the s x s squares of free cells.
    let mut origin = vec![false; w * h];
    for i in 0..w {
        let mut r = 0;
        for j in (0..h).rev() {
            r = if run[j * w + i] as usize == s { (r + 1).min(s) } else { 0 };
            origin[j * w + i] = r == s;
        }
    }
    // Covered: a square's origin within s - 1 cells left, then below.
    let mut near = vec![false; w * h];
    for j in 0..h {
        let mut last = None;
        for i in 0..w {
            if origin[j * w + i] {
                last = Some(i);
            }
            near[j * w + i] = last.is_some_and(|l| i - l < s);
        }
    }
    let mut dropped = 0;
    for i in 0..w {
        let mut last = None;
        for j in 0..h {
            let c = j * w + i;
            if near[c] {
                last = Some(j);
            }
            if cells.free[c] && !last.is_some_and(|l| j - l < s) {
                cells.free[c] = false;
                dropped += 1;
            }
        }
    }
    dropped
}

/// Blocks every free cell outside the largest 4-connected free region;
/// returns the pockets and cells blocked.
fn keep_largest(cells: &mut Cells) -> (usize, usize) {
    let (label, sizes) = cells.components(|c| cells.free[c], false);
    let Some(main) = (0..sizes.len()).max_by_key(|&k| (sizes[k], std::cmp::Reverse(k))) else {
        return (0, 0);
    };
    let mut blocked = 0;
    for (c, &l) in label.iter().enumerate() {
        if l != u32::MAX && l as usize != main {
            cells.free[c] = false;
            blocked += 1;
        }
    }
    (sizes.len() - 1, blocked)
}

/// Blocks one free cell of every 2 x 2 block whose free cells touch only
/// at its centre, rechecking the blocks around each cell blocked; returns
/// the cells blocked.
fn close_pinches(cells: &mut Cells) -> usize {
    let w = cells.w;
    let pinched = |free: &[bool], c: usize| {
        let (a, b, d, e) = (free[c], free[c + 1], free[c + w], free[c + w + 1]);
        a == e && b == d && a != b
    };
    let mut blocked = 0;
    let mut todo: Vec<usize> = (0..cells.h - 1).flat_map(|j| (0..w - 1).map(move |i| j * w + i)).collect();
    todo.reverse();
    while let Some(c) = todo.pop() {
        if !pinched(&cells.free, c) {
            continue;
        }
        let first = [c, c + 1, c + w, c + w + 1].into_iter().find(|&x| cells.free[x]).expect("a pinch has free cells");
        cells.free[first] = false;
        blocked += 1;
        let (i, j) = (first % w, first / w);
        for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            if i >= di && j >= dj && i - di < w - 1 && j - dj < cells.h - 1 {
                todo.push((j - dj) * w + i - di);
            }
        }
    }
    blocked
}

/// The outline of the cells where `inside` holds, which must form one
/// region whose boundary is one simple closed curve, starting at cell
/// `first` (its lowest-then-leftmost cell): the corners as lattice points.
fn trace(cells: &Cells, members: &[usize], inside: impl Fn(usize) -> bool) -> Result<Vec<(usize, usize)>, String> {
    let w = cells.w;
    // Each boundary edge, region on its left, by its start point.
    let mut next = std::collections::HashMap::new();
    for &c in members {
        let (i, j) = (c % w, c / w);
        for (n, from, to) in [
            (c - w, (i, j), (i + 1, j)),
            (c + 1, (i + 1, j), (i + 1, j + 1)),
            (c + w, (i + 1, j + 1), (i, j + 1)),
            (c - 1, (i, j + 1), (i, j)),
        ] {
            if !inside(n) && next.insert(from, to).is_some() {
                return Err(format!("two outline edges leave the point ({}, {})", from.0, from.1));
            }
        }
    }
    let start = (members[0] % w, members[0] / w);
    let mut corners = Vec::new();
    let (mut prev, mut at) = (start, start);
    let mut steps = 0;
    loop {
        let to = *next.get(&at).ok_or("the outline does not close")?;
        let turn = (at.0 as isize - prev.0 as isize, at.1 as isize - prev.1 as isize)
            != (to.0 as isize - at.0 as isize, to.1 as isize - at.1 as isize);
        if turn || steps == 0 {
            corners.push(at);
        }
        steps += 1;
        (prev, at) = (at, to);
        if at == start {
            break;
        }
    }
    if steps != next.len() {
        return Err(format!("the outline has {} edges, but the region's boundary {}", steps, next.len()));
    }
    Ok(corners)
}

/// Reads `raster` in cells of `k x k` pixels into an outline, dropping
/// free slivers narrower than `sliver` cells.
pub fn outline(raster: &Raster, frame: Frame, k: usize, sliver: usize, unknown_free: bool) -> Result<Outline, String> {
    let mut cells = coarsen(raster, k, unknown_free);
    let mut out = Outline::default();
    // Each step keeps what the ones before it made (an opening stays open
    // when whole regions go), so once no corner touch is left, none of
    // them would change anything: reading the written map back is a fixed point.
    loop {
        out.sliver_cells += drop_slivers(&mut cells, sliver);
        let (pockets, cut) = keep_largest(&mut cells);
        out.pockets += pockets;
        out.pocket_cells += cut;
        let pinched = close_pinches(&mut cells);
        out.pinch_cells += pinched;
        if pinched == 0 {
            break;
        }
    }
    out.free_cells = cells.free.iter().filter(|&&f| f).count();
    if out.free_cells == 0 {
        return Err("has no free cells: nothing to search".into());
    }
    let (blocked, _) = cells.components(|c| !cells.free[c], true);
    // Label 0 holds cell 0, in the ring: the outside.
    let outside = 0;
    let point = |(p, q): (usize, usize)| {
        let x = ((p - 1) * k).min(raster.width) as f64;
        let y = ((q - 1) * k).min(raster.height) as f64;
        (frame.origin.0 + x * frame.resolution, frame.origin.1 + y * frame.resolution)
    };
    let region: Vec<usize> = (0..cells.free.len()).filter(|&c| blocked[c] != outside).collect();
    out.area = trace(&cells, &region, |c| blocked[c] != outside)?.into_iter().map(point).collect();
    let mut holes: Vec<Vec<usize>> = Vec::new();
    for &c in &region {
        let l = blocked[c];
        if l != u32::MAX {
            // Labels were given in scan order: obstacle `l - 1`.
            let hole = l as usize - 1;
            if holes.len() <= hole {
                holes.resize(hole + 1, Vec::new());
            }
            holes[hole].push(c);
        }
    }
    for hole in holes.iter().filter(|h| !h.is_empty()) {
        out.obstacle_cells += hole.len();
        let corners = trace(&cells, hole, |c| blocked[c] == blocked[hole[0]])?;
        out.obstacles.push(corners.into_iter().map(point).collect());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A raster from rows of `.` free, `#` occupied, `?` unknown, top row first.
    pub(crate) fn raster(rows: &[&str]) -> Raster {
        let cells = rows
            .iter()
            .flat_map(|r| {
                r.chars().map(|c| match c {
                    '.' => Class::Free,
                    '#' => Class::Occupied,
                    _ => Class::Unknown,
                })
            })
            .collect();
        Raster { width: rows[0].len(), height: rows.len(), cells }
    }

    const UNIT: Frame = Frame { origin: (0.0, 0.0), resolution: 1.0 };

    #[test]
    fn a_room_with_a_pillar_is_an_area_and_one_obstacle() {
        let r = raster(&["??????", "?....?", "?.#..?", "?....?", "??????"]);
        let o = outline(&r, UNIT, 1, 1, false).unwrap();
        assert_eq!(o.area, [(1.0, 1.0), (5.0, 1.0), (5.0, 4.0), (1.0, 4.0)]);
        assert_eq!(o.obstacles, [vec![(2.0, 2.0), (3.0, 2.0), (3.0, 3.0), (2.0, 3.0)]]);
        assert_eq!((o.pockets, o.pinch_cells, o.obstacle_cells, o.free_cells), (0, 0, 1, 11));
    }

    #[test]
    fn pockets_and_corner_touches_are_blocked_and_counted() {
        // A pocket (right) and two free cells touching at a corner (top left).
        let r = raster(&[".#####", "#...#.", "#...##", "######"]);
        let o = outline(&r, UNIT, 1, 1, false).unwrap();
        assert_eq!((o.pockets, o.pocket_cells), (2, 2), "{o:?}");
        assert_eq!(o.area.len(), 4, "{o:?}");
        // An obstacle touching another at a corner is merged with it.
        let r = raster(&["......", ".#....", "..#...", "......"]);
        let o = outline(&r, UNIT, 1, 1, false).unwrap();
        assert_eq!(o.obstacles.len(), 1);
        assert_eq!((o.pinch_cells, o.obstacles[0].len()), (1, 6), "{o:?}");
    }

    #[test]
    fn cells_merge_pixels_and_a_wall_wins() {
        let r = raster(&["....", "...#", "....", "...."]);
        let o = outline(&r, UNIT, 2, 1, false).unwrap();
        // The top-right cell holds an occupied pixel: blocked, and outside.
        assert_eq!(o.area, [(0.0, 0.0), (4.0, 0.0), (4.0, 2.0), (2.0, 2.0), (2.0, 4.0), (0.0, 4.0)]);
        assert!(outline(&raster(&["##", "#?"]), UNIT, 1, 1, false).unwrap_err().contains("no free cells"));
        // Unknown read as free.
        let o = outline(&raster(&["??", "??"]), Frame { origin: (-1.0, 2.0), resolution: 0.5 }, 1, 1, true).unwrap();
        assert_eq!(o.area, [(-1.0, 2.0), (0.0, 2.0), (0.0, 3.0), (-1.0, 3.0)]);
    }

    #[test]
    fn slivers_narrower_than_a_robot_are_dropped_and_counted() {
        // A room with a dead-end slot one cell wide: no robot fits in it.
        let r =
            raster(&["##########", "#.....#.##", "#.....#.##", "#........#", "#........#", "#........#", "##########"]);
        let o = outline(&r, UNIT, 1, 3, false).unwrap();
        assert_eq!(o.sliver_cells, 2, "{o:?}");
        assert_eq!(o.area.len(), 6, "{o:?}");
        let opened = outline(&r, UNIT, 1, 1, false).unwrap();
        assert!(opened.area.len() > o.area.len(), "{opened:?} / {o:?}");
    }
}
