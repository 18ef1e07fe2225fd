//! The bodies' side of a slot, for the world ([`crate::sim`]): where every
//! robot really is, what its sonar and laser report, executing all moves at
//! once and counting collisions. It never decides for a robot.

use crate::bitset::Bitset;
use crate::geometry::swept_min_distance;
use crate::grid::{VertexId, NONE};
use crate::lattice::Coord;
use crate::world::World;

const EMPTY: u16 = u16::MAX;

/// The outcome of executing one round's moves.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RoundReport {
    /// Pairs of robots that came closer than `2 r_safe`, or shared a vertex.
    pub collisions: u32,
    /// Moves refused because they were not along a traversable edge.
    pub refused: u32,
    /// Whether any robot had to rotate, and whether any translated.
    pub rotated: bool,
    pub translated: bool,
}

/// Ground truth of robot positions on the grid.
#[derive(Clone, Debug)]
pub struct Referee<'w> {
    world: &'w World,
    pos: Vec<VertexId>,
    heading: Vec<Option<(i32, i32)>>,
    /// A robot on each vertex (any one of them if several), or `EMPTY`.
    occupant: Vec<u16>,
    visited: Bitset,
    found: Bitset,
    /// Where each robot ends this round; kept to avoid allocating per round.
    target: Vec<VertexId>,
}

impl<'w> Referee<'w> {
    pub fn new(world: &'w World, starts: &[VertexId]) -> Self {
        let mut r = Referee {
            world,
            pos: starts.to_vec(),
            heading: vec![None; starts.len()],
            occupant: vec![EMPTY; world.grid.len()],
            visited: Bitset::new(world.grid.len()),
            found: Bitset::new(world.targets.len()),
            target: Vec::with_capacity(starts.len()),
        };
        for (k, &v) in starts.iter().enumerate() {
            r.occupant[v as usize] = k as u16;
            r.visited.set(v as usize);
        }
        r
    }

    pub fn positions(&self) -> &[VertexId] {
        &self.pos
    }

    pub fn position(&self, robot: usize) -> VertexId {
        self.pos[robot]
    }

    /// Vertices robots have stood on.
    pub fn visited(&self) -> &Bitset {
        &self.visited
    }

    /// Targets found so far by anyone.
    pub fn found(&self) -> &Bitset {
        &self.found
    }

    /// Sonar: the open edge slots and the slots holding another robot.
    pub fn sonar(&self, robot: usize) -> (u8, u8) {
        let v = self.pos[robot];
        let grid = &self.world.grid;
        let mut occupied = 0u8;
        for (d, &n) in grid.neighbors(v)[..grid.degree()].iter().enumerate() {
            if n != NONE && self.occupant[n as usize] != EMPTY {
                occupied |= 1 << d;
            }
        }
        (self.world.open_mask(v), occupied)
    }

    /// Laser: targets within `r_st`; records them as found.
    pub fn laser(&mut self, robot: usize) -> &'w [u32] {
        let ts = self.world.targets_near(self.pos[robot]);
        for &t in ts {
            self.found.set(t as usize);
        }
        ts
    }

    /// Step 6 for everyone at once: every robot goes to `next[k]` (its own
    /// position to stay). A move that is not along a traversable edge is
    /// refused and the robot stays. Collisions are counted, not prevented.
    pub fn execute(&mut self, next: &[VertexId]) -> RoundReport {
        let grid = &self.world.grid;
        let mut report = RoundReport::default();
        let mut target = std::mem::take(&mut self.target);
        target.clear();
        for (k, &to) in next.iter().enumerate() {
            let from = self.pos[k];
            if to == from {
                target.push(from);
            } else if (to as usize) < grid.len() && self.world.can_move(from, to) {
                target.push(to);
            } else {
                report.refused += 1;
                target.push(from);
            }
        }
        report.collisions = self.count_collisions(&target);
        for (k, &to) in target.iter().enumerate() {
            let from = self.pos[k];
            if to == from {
                continue;
            }
            let (a, b) = (grid.coord(from), grid.coord(to));
            let dir = (b.i - a.i, b.j - a.j);
            report.translated = true;
            if self.heading[k] != Some(dir) {
                report.rotated = true;
            }
            self.heading[k] = Some(dir);
        }
        for &v in &self.pos {
            self.occupant[v as usize] = EMPTY;
        }
        for (k, &v) in target.iter().enumerate() {
            self.pos[k] = v;
            self.occupant[v as usize] = k as u16;
            self.visited.set(v as usize);
        }
        self.target = target;
        report
    }

    /// Pairs closer than `2 r_safe` at any moment of the simultaneous moves.
    fn count_collisions(&self, target: &[VertexId]) -> u32 {
        let grid = &self.world.grid;
        let params = &self.world.params;
        let limit = 2.0 * params.r_safe;
        // Two robots further apart than this at the start cannot meet.
        let reach2 = (2.0 * params.a + limit).powi(2);
        let mut count = 0;
        for i in 0..target.len() {
            let (p0, p1) = (grid.position(self.pos[i]), grid.position(target[i]));
            for j in i + 1..target.len() {
                let q0 = grid.position(self.pos[j]);
                if (q0 - p0).norm_squared() > reach2 {
                    continue;
                }
                let q1 = grid.position(target[j]);
                if target[i] == target[j] || swept_min_distance(p0, p1, q0, q1) < limit {
                    count += 1;
                }
            }
        }
        count
    }

    pub fn coord(&self, robot: usize) -> Coord {
        self.world.grid.coord(self.pos[robot])
    }
}
