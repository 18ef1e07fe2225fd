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

#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
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
    /// Target ids known found.
    pub targets: Bitset,
    /// Robots declared failed, with the vertex each stands on for good, sorted by id.
    pub failed: Vec<(RobotId, VertexId)>,
}

impl Map {
    pub fn new(vertices: usize, targets: usize) -> Self {
        Map {
            visited: Bitset::new(vertices),
            known: Bitset::new(vertices),
            open: vec![0; vertices],
            targets: Bitset::new(targets),
            failed: Vec::new(),
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

    /// `self ∪= other`.
    pub fn merge(&mut self, other: &Map) {
        self.visited.union_with(&other.visited);
        self.known.union_with(&other.known);
        for (a, b) in self.open.iter_mut().zip(&other.open) {
            *a |= *b;
        }
        self.targets.union_with(&other.targets);
        for &f in &other.failed {
            self.add_failed(f.0, f.1);
        }
    }

    pub fn add_failed(&mut self, id: RobotId, at: VertexId) {
        if let Err(k) = self.failed.binary_search_by_key(&id, |f| f.0) {
            self.failed.insert(k, (id, at));
        }
    }

    pub fn is_failed(&self, id: RobotId) -> bool {
        self.failed.binary_search_by_key(&id, |f| f.0).is_ok()
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

    /// Copies `other` into `self` without allocating when sizes match.
    pub fn copy_from(&mut self, other: &Map) {
        self.visited.copy_from(&other.visited);
        self.known.copy_from(&other.known);
        self.open.copy_from_slice(&other.open);
        self.targets.copy_from(&other.targets);
        self.failed.clear();
        self.failed.extend_from_slice(&other.failed);
    }

    /// Checks a map that came from elsewhere against the grid it claims to
    /// describe, so a malformed message cannot index out of bounds.
    pub fn validate(&self, vertices: usize, targets: usize, robots: usize) -> Result<(), String> {
        let words = |bits: usize| bits.div_ceil(64);
        if self.visited.words().len() != words(vertices) || self.known.words().len() != words(vertices) {
            return Err(format!("map bitsets sized for another grid (expected {vertices} vertices)"));
        }
        if self.open.len() != vertices {
            return Err(format!("map has {} open masks, expected {vertices}", self.open.len()));
        }
        if self.targets.words().len() != words(targets) {
            return Err(format!("map target set sized for another scenario (expected {targets} targets)"));
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
        if self.failed.windows(2).any(|w| w[0].0 >= w[1].0) {
            return Err("map failure list not sorted by robot".into());
        }
        if self.failed.iter().any(|&(id, at)| id as usize >= robots || at as usize >= vertices) {
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
        failed: &'a Vec<(RobotId, VertexId)>,
    }

    #[test]
    fn open_masks_encode_as_before_and_round_trip() {
        let mut m = Map::new(300, 9);
        m.visited.set(3);
        m.known.set(299);
        m.open[7] = 0x81;
        m.open[299] = 0xff;
        m.targets.set(8);
        m.add_failed(2, 50);
        let plain = Plain { visited: &m.visited, known: &m.known, open: &m.open, targets: &m.targets, failed: &m.failed };
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
}
