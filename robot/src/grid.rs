//! The grid frame every robot shares (Assumption 2.2): the lattice vertices
//! inside the area's bounding box, numbered densely, with their lattice
//! adjacency. It says nothing about obstacles: robots learn those only by
//! sensing, so this is the part of the world a robot may hold.

use rustc_hash::FxHashMap as HashMap;

use crate::geometry::Point;
use crate::lattice::{Coord, Lattice, LatticeKind, MAX_DEGREE};

/// Dense index of a vertex in a [`Grid`].
pub type VertexId = u32;
/// Marks an empty adjacency slot.
pub const NONE: VertexId = VertexId::MAX;

/// Lattice vertices in a box, with fixed-width adjacency tables so that the
/// hot path never allocates or hashes.
#[derive(Clone, Debug)]
pub struct Grid {
    pub lattice: Lattice,
    coords: Vec<Coord>,
    positions: Vec<Point>,
    keys: Vec<(i64, i64)>,
    /// `adj[v][d]`: the neighbour of `v` in lattice direction slot `d`, or [`NONE`].
    adj: Vec<[VertexId; MAX_DEGREE]>,
    index: HashMap<Coord, VertexId>,
}

impl Grid {
    /// The frame of lattice vertices whose positions lie in `[lo, hi]`.
    pub fn new(lattice: Lattice, lo: Point, hi: Point) -> Self {
        let coords = lattice.coords_in_box(lo, hi);
        // Every agent builds its grid at start: SipHash was a third of an
        // agent's start-up on `large`. Lookups only, so order cannot leak.
        let index: HashMap<Coord, VertexId> = coords.iter().enumerate().map(|(k, &c)| (c, k as VertexId)).collect();
        let positions = coords.iter().map(|&c| lattice.position(c)).collect();
        let keys = coords.iter().map(|&c| lattice.priority_key(c)).collect();
        let adj = coords
            .iter()
            .map(|&c| {
                let mut row = [NONE; MAX_DEGREE];
                for (d, &(di, dj)) in lattice.offsets(c).iter().enumerate() {
                    row[d] = index.get(&Coord::new(c.i + di, c.j + dj)).copied().unwrap_or(NONE);
                }
                row
            })
            .collect();
        Grid { lattice, coords, positions, keys, adj, index }
    }

    #[inline]
    pub fn len(&self) -> usize {
        self.coords.len()
    }

    #[inline]
    pub fn is_empty(&self) -> bool {
        self.coords.is_empty()
    }

    /// How many adjacency slots this lattice uses (6, 4 or 3).
    #[inline]
    pub fn degree(&self) -> usize {
        match self.lattice.kind {
            LatticeKind::Triangular => 6,
            LatticeKind::Square => 4,
            LatticeKind::Hexagonal => 3,
        }
    }

    /// The slot of the edge `v → adj[v][d]` seen from the other end.
    #[inline]
    pub fn opposite(&self, d: usize) -> usize {
        match self.lattice.kind {
            LatticeKind::Triangular => (d + 3) % 6,
            LatticeKind::Square => (d + 2) % 4,
            // The two honeycomb sublattices list opposite offsets in the same slot.
            LatticeKind::Hexagonal => d,
        }
    }

    #[inline]
    pub fn coord(&self, v: VertexId) -> Coord {
        self.coords[v as usize]
    }

    #[inline]
    pub fn position(&self, v: VertexId) -> Point {
        self.positions[v as usize]
    }

    /// Exact priority key (step 4): higher key chooses first.
    #[inline]
    pub fn priority_key(&self, v: VertexId) -> (i64, i64) {
        self.keys[v as usize]
    }

    /// `v`'s class in the colouring of [`Lattice::class`].
    pub fn class(&self, v: VertexId) -> u8 {
        self.lattice.class(self.coords[v as usize])
    }

    /// Neighbour slots of `v`; only the first [`Grid::degree`] can be set.
    #[inline]
    pub fn neighbors(&self, v: VertexId) -> &[VertexId; MAX_DEGREE] {
        &self.adj[v as usize]
    }

    /// The slot `d` with `adj[from][d] == to`, if `to` is adjacent.
    #[inline]
    pub fn slot_of(&self, from: VertexId, to: VertexId) -> Option<usize> {
        self.adj[from as usize][..self.degree()].iter().position(|&n| n == to)
    }

    #[inline]
    pub fn id_of(&self, c: Coord) -> Option<VertexId> {
        self.index.get(&c).copied()
    }

    /// The frame vertex nearest to `p`, if the nearest lattice vertex is in the frame.
    #[inline]
    pub fn nearest(&self, p: Point) -> Option<VertexId> {
        self.id_of(self.lattice.nearest(p))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every edge read from its other end sits in the opposite slot: what
    /// `Map::edge_open` relies on to read an edge sensed from one end. On
    /// the honeycomb the two sublattices list opposite offsets in the same
    /// slot, so there the opposite of a slot is itself.
    #[test]
    fn an_edge_read_from_its_other_end_is_in_the_opposite_slot() {
        for kind in [LatticeKind::Triangular, LatticeKind::Square, LatticeKind::Hexagonal] {
            let g = Grid::new(Lattice::new(kind, 1.0), Point::new(0.0, 0.0), Point::new(9.0, 7.0));
            let mut edges = 0;
            for v in 0..g.len() as VertexId {
                for d in 0..g.degree() {
                    let n = g.neighbors(v)[d];
                    if n != NONE {
                        assert_eq!(g.neighbors(n)[g.opposite(d)], v, "{kind:?}: {v} slot {d} to {n}");
                        edges += 1;
                    }
                }
            }
            assert!(edges > 2 * g.len(), "{kind:?}: a grid with edges ({edges})");
        }
    }
}
