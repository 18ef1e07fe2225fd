//! A robot's explored map (step 3): what it has visited, which vertices it
//! knows to be accessible, which edges it has sensed open, which targets it
//! knows, and which robots it knows to have failed. Every part merges by
//! union, so merging is commutative and idempotent: the order in which maps
//! arrive can never change a decision.

use serde::{Deserialize, Serialize};

use crate::bitset::Bitset;
use crate::grid::{Grid, VertexId};

pub type RobotId = u16;

/// Bit of [`Map::open`] marking a vertex whose surroundings were sensed.
pub const SENSED: u8 = 0x80;

/// A robot declared failed (Sec. 4.2): where it stands for good, and the
/// round of the declaration, so that a later sign of life can overrule it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Failure {
    pub robot: RobotId,
    pub at: VertexId,
    pub round: u32,
}

#[derive(Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Map {
    /// Vertices some robot has stood on.
    pub visited: Bitset,
    /// Vertices known to be accessible: visited ones and the open ends of sensed edges.
    pub known: Bitset,
    /// Per vertex: bit `d` set when the edge in slot `d` was sensed traversable;
    /// [`SENSED`] set once anyone sensed there. (De)serialized as one byte
    /// string: in postcard the same bytes as a sequence of `u8`, without
    /// one call per vertex (maps of large scenarios are thousands of bytes
    /// and every robot sends its map every round).
    #[serde(with = "byte_string")]
    pub open: Vec<u8>,
    /// Target ids known found. It grows as targets are learnt: in situation
    /// 2 a robot does not know how many there are.
    pub targets: Bitset,
    /// The latest failure declared of each robot, sorted by robot.
    pub failed: Vec<Failure>,
    /// For robots once declared failed: the latest round in which one was
    /// heard alive again (a rejoin), sorted by robot. A failure counts only
    /// while its round is later than this.
    pub alive: Vec<(RobotId, u32)>,
}

impl Clone for Map {
    fn clone(&self) -> Self {
        let mut m = Map {
            visited: Bitset::default(),
            known: Bitset::default(),
            open: Vec::new(),
            targets: Bitset::default(),
            failed: Vec::new(),
            alive: Vec::new(),
        };
        m.clone_from(self);
        m
    }

    /// Reuses this map's buffers: a robot sends a copy of its map every
    /// slot, and the in-process engine hands it back recycled ones.
    fn clone_from(&mut self, source: &Self) {
        self.visited.clone_from(&source.visited);
        self.known.clone_from(&source.known);
        self.open.clone_from(&source.open);
        self.targets.clone_from(&source.targets);
        self.failed.clone_from(&source.failed);
        self.alive.clone_from(&source.alive);
    }
}

impl Map {
    pub fn new(vertices: usize, targets: usize) -> Self {
        Map {
            visited: Bitset::new(vertices),
            known: Bitset::new(vertices),
            open: vec![0; vertices],
            targets: Bitset::new(targets),
            failed: Vec::new(),
            alive: Vec::new(),
        }
    }

    /// Records what a robot standing on `v` senses: the open edge slots.
    pub fn record_sensing(&mut self, grid: &Grid, v: VertexId, open: u8) {
        self.visited.set(v as usize);
        self.known.set(v as usize);
        self.open[v as usize] |= open | SENSED;
        for (d, &n) in grid.neighbors(v)[..grid.degree()].iter().enumerate() {
            if open >> d & 1 == 1 {
                self.known.set(n as usize);
            }
        }
    }

    /// `self ∪= other`: sets by union, failures and rejoins by their latest round.
    pub fn merge(&mut self, other: &Map) {
        self.visited.union_with(&other.visited);
        self.known.union_with(&other.known);
        for (a, b) in self.open.iter_mut().zip(&other.open) {
            *a |= *b;
        }
        self.targets.union_growing(&other.targets);
        for f in &other.failed {
            self.add_failed(f.robot, f.at, f.round);
        }
        for &(id, round) in &other.alive {
            self.revive(id, round);
        }
    }

    /// Declares `id` failed on `at` in `round`. Of two declarations the
    /// later round wins (the lower vertex on a tie, so merging stays
    /// independent of order).
    pub fn add_failed(&mut self, id: RobotId, at: VertexId, round: u32) {
        let f = Failure { robot: id, at, round };
        match self.failed.binary_search_by_key(&id, |f| f.robot) {
            Ok(k) => {
                let old = self.failed[k];
                if (round, std::cmp::Reverse(at)) > (old.round, std::cmp::Reverse(old.at)) {
                    self.failed[k] = f;
                }
            }
            Err(k) => self.failed.insert(k, f),
        }
    }

    /// `id` was heard alive in `round`: any failure declared of it up to
    /// that round no longer counts.
    pub fn revive(&mut self, id: RobotId, round: u32) {
        match self.alive.binary_search_by_key(&id, |a| a.0) {
            Ok(k) => self.alive[k].1 = self.alive[k].1.max(round),
            Err(k) => self.alive.insert(k, (id, round)),
        }
    }

    fn alive_round(&self, id: RobotId) -> Option<u32> {
        self.alive.binary_search_by_key(&id, |a| a.0).ok().map(|k| self.alive[k].1)
    }

    /// The failure of `id` that counts now, if any.
    pub fn failure(&self, id: RobotId) -> Option<Failure> {
        let k = self.failed.binary_search_by_key(&id, |f| f.robot).ok()?;
        let f = self.failed[k];
        match self.alive_round(id) {
            Some(r) if r >= f.round => None,
            _ => Some(f),
        }
    }

    pub fn is_failed(&self, id: RobotId) -> bool {
        self.failure(id).is_some()
    }

    /// Robots failed now, with the vertex each blocks for good.
    pub fn failed_now(&self) -> impl Iterator<Item = (RobotId, VertexId)> + '_ {
        self.failed
            .iter()
            .filter(|f| self.alive_round(f.robot).is_none_or(|r| r < f.round))
            .map(|f| (f.robot, f.at))
    }

    /// Whether some robot counts as failed now.
    pub fn any_failed(&self) -> bool {
        self.failed_now().next().is_some()
    }

    /// Whether some known accessible vertex is not yet visited.
    pub fn has_unvisited(&self) -> bool {
        self.known.any_not_in(&self.visited)
    }

    /// Whether the edge `v` → slot `d` is known traversable, sensed from either end.
    pub fn edge_open(&self, grid: &Grid, v: VertexId, d: usize) -> bool {
        if self.open[v as usize] >> d & 1 == 1 {
            return true;
        }
        let n = grid.neighbors(v)[d];
        self.open[n as usize] >> grid.opposite(d) & 1 == 1
    }

    /// Copies `other` into `self`, reusing `self`'s buffers.
    pub fn copy_from(&mut self, other: &Map) {
        self.clone_from(other);
    }

    /// Checks a map that came from elsewhere against the grid it claims to
    /// describe, so a malformed message cannot index out of bounds.
    /// `targets` is the largest number of target ids a map may hold.
    pub fn validate(&self, vertices: usize, targets: usize, robots: usize) -> Result<(), String> {
        let words = |bits: usize| bits.div_ceil(64);
        if self.visited.words().len() != words(vertices) || self.known.words().len() != words(vertices) {
            return Err(format!("map bitsets sized for another grid (expected {vertices} vertices)"));
        }
        if self.open.len() != vertices {
            return Err(format!("map has {} open masks, expected {vertices}", self.open.len()));
        }
        if self.targets.words().len() > words(targets) {
            return Err(format!("map target set larger than {targets} targets"));
        }
        // Any bit at or past `n`, word by word (sizes were checked above).
        let past = |b: &Bitset, n: usize| {
            let w = b.words();
            let (full, rem) = (n / 64, n % 64);
            (rem > 0 && w.get(full).is_some_and(|&x| x >> rem != 0))
                || w.iter().skip(full + usize::from(rem > 0)).any(|&x| x != 0)
        };
        if past(&self.visited, vertices) || past(&self.known, vertices) || past(&self.targets, targets) {
            return Err("map sets a bit past the end".into());
        }
        if self.failed.windows(2).any(|w| w[0].robot >= w[1].robot) || self.alive.windows(2).any(|w| w[0].0 >= w[1].0) {
            return Err("map failure list not sorted by robot".into());
        }
        if self.failed.iter().any(|f| f.robot as usize >= robots || f.at as usize >= vertices)
            || self.alive.iter().any(|a| a.0 as usize >= robots)
        {
            return Err("map names a robot or vertex that does not exist".into());
        }
        Ok(())
    }
}

/// Serde for a `Vec<u8>` as one byte string (`serialize_bytes`).
mod byte_string {
    use serde::de::{Deserializer, SeqAccess, Visitor};
    use serde::Serializer;

    pub fn serialize<S: Serializer>(v: &[u8], s: S) -> Result<S::Ok, S::Error> {
        s.serialize_bytes(v)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<u8>, D::Error> {
        d.deserialize_byte_buf(Bytes)
    }

    struct Bytes;

    impl<'de> Visitor<'de> for Bytes {
        type Value = Vec<u8>;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a byte string")
        }

        fn visit_bytes<E>(self, v: &[u8]) -> Result<Vec<u8>, E> {
            Ok(v.to_vec())
        }

        fn visit_byte_buf<E>(self, v: Vec<u8>) -> Result<Vec<u8>, E> {
            Ok(v)
        }

        // Formats without byte strings (JSON) give a sequence.
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<u8>, A::Error> {
            let mut v = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1 << 20));
            while let Some(b) = seq.next_element()? {
                v.push(b);
            }
            Ok(v)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same fields, with `open` as a plain sequence: the encoding before.
    #[derive(Serialize)]
    struct Plain<'a> {
        visited: &'a Bitset,
        known: &'a Bitset,
        open: &'a Vec<u8>,
        targets: &'a Bitset,
        failed: &'a Vec<Failure>,
        alive: &'a Vec<(RobotId, u32)>,
    }

    #[test]
    fn open_masks_encode_as_before_and_round_trip() {
        let mut m = Map::new(300, 9);
        m.visited.set(3);
        m.known.set(299);
        m.open[7] = 0x81;
        m.open[299] = 0xff;
        m.targets.set(8);
        m.add_failed(2, 50, 1);
        m.revive(1, 3);
        let plain = Plain { visited: &m.visited, known: &m.known, open: &m.open, targets: &m.targets, failed: &m.failed, alive: &m.alive };
        let bytes = postcard::to_allocvec(&m).unwrap();
        assert_eq!(bytes, postcard::to_allocvec(&plain).unwrap());
        assert_eq!(postcard::from_bytes::<Map>(&bytes).unwrap(), m);
        assert_eq!(m.validate(300, 9, 3), Ok(()));
        // A bit past the end of the grid, in the last word or beyond.
        let mut bad = m.clone();
        bad.visited.set(300);
        assert!(bad.validate(300, 9, 3).is_err());
        let mut bad = m.clone();
        bad.known.set(319);
        assert!(bad.validate(300, 9, 3).is_err());
        assert!(m.validate(320, 9, 3).is_err(), "sized for another grid");
    }

    #[test]
    fn failures_merge_by_latest_round_and_rejoins_overrule_them() {
        let mut a = Map::new(10, 0);
        let mut b = Map::new(10, 0);
        a.add_failed(3, 4, 2);
        b.add_failed(3, 5, 1);
        b.revive(3, 2);
        let mut ab = a.clone();
        ab.merge(&b);
        let mut ba = b.clone();
        ba.merge(&a);
        assert_eq!(ab, ba, "merging is independent of order");
        // Heard alive in round 2, declared in round 2: alive wins.
        assert!(!ab.is_failed(3));
        assert_eq!(ab.failed_now().count(), 0);
        // A later declaration counts again.
        ab.add_failed(3, 6, 4);
        assert_eq!(ab.failure(3), Some(Failure { robot: 3, at: 6, round: 4 }));
        assert_eq!(ab.failed_now().collect::<Vec<_>>(), vec![(3, 6)]);
        // Targets grow to the larger set.
        let mut t = Map::new(10, 0);
        let mut u = Map::new(10, 0);
        u.targets.set_growing(70);
        t.merge(&u);
        assert!(t.targets.get(70));
    }
}
