//! A robot's explored map (step 3): what it has visited, which vertices it
//! knows to be accessible, which edges it has sensed open, which targets it
//! knows, and which robots it knows to have failed. Every part merges by
//! union, so merging is commutative and idempotent: the order in which maps
//! arrive can never change a decision.

use std::borrow::Cow;

use serde::{Deserialize, Serialize};

use crate::bitset::Bitset;
use crate::grid::{Grid, VertexId};
use crate::spot::Spots;

pub mod sightings;
pub mod thin;
pub mod tiles;

use sightings::Sightings;
use thin::Thin;
use tiles::Tiles;

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
    /// Some robot's sonar found `at` occupied since the declaration. A
    /// declaration says only that a robot went unheard (under loss, of a
    /// live robot that moved on); until someone has seen the body, the
    /// robots it cuts off go and look ([`crate::robot::Robot`]).
    pub seen: bool,
}

/// A robot's map. The per-vertex parts live in shared [`tiles`]; on the
/// wire a map is, as it always was, the flat fields of [`Flat`].
#[derive(Debug, Default)]
pub struct Map {
    /// Per vertex: visited (some robot stood on it), known (accessible:
    /// visited, or the open end of a sensed edge), and the edge mask (bit
    /// `d` set when the edge in slot `d` was sensed traversable; [`SENSED`]
    /// set once anyone sensed there), the masks in a table shared with
    /// other maps (see [`tiles`]).
    cells: Tiles,
    /// Targets known found, by where they are.
    pub targets: Spots,
    /// The latest failure declared of each robot, sorted by robot.
    pub failed: Vec<Failure>,
    /// For robots once declared failed: the latest round in which one was
    /// heard alive again (a rejoin), sorted by robot. A failure counts only
    /// while its round is later than this.
    pub alive: Vec<(RobotId, u32)>,
    /// Silent bodies: vertices where a sonar found a robot nobody heard,
    /// with the latest round one was found there, sorted by vertex. Spread
    /// like failures, so that robots who never pass by learn that the
    /// vertex will never be visited (and that what lies behind it may be
    /// cut off).
    pub bodies: Vec<(VertexId, u32)>,
    /// For vertices once holding a body: the latest round a sonar found
    /// the vertex free. A body counts only while found later than this.
    pub freed: Thin<(VertexId, u32)>,
    /// Where robots were last heard, written once failures are known.
    pub sightings: Sightings,
    /// The round of a map this map's robot sent, from which this map
    /// differs only in the tiles marked changed: for a robot's own map its
    /// last copy sent, for that copy the copy before ([`Map::send_copy`],
    /// [`Map::merge_changes`]). Not content, and not on the wire: a map
    /// decoded has none, and is merged whole.
    pub base: Option<u32>,
}

/// Content only: where a map came from is not part of it.
impl PartialEq for Map {
    fn eq(&self, other: &Self) -> bool {
        self.cells == other.cells
            && self.targets == other.targets
            && self.failed == other.failed
            && self.alive == other.alive
            && self.bodies == other.bodies
            && self.freed == other.freed
            && self.sightings == other.sightings
    }
}

impl Eq for Map {}

/// A map as it travels: visited and known as bitsets, the edge masks as
/// one byte string (in postcard the same bytes as a sequence of `u8`,
/// without one call per vertex).
#[derive(Serialize, Deserialize)]
#[serde(rename = "Map")]
struct Flat<'a, T, F, A, B, S> {
    visited: Bitset,
    known: Bitset,
    /// Borrowed from the frame when the format allows (postcard does): a
    /// robot process decodes a dozen maps a slot, and need not copy them.
    #[serde(borrow, with = "byte_string")]
    open: Cow<'a, [u8]>,
    targets: T,
    failed: F,
    alive: A,
    bodies: B,
    freed: B,
    sightings: S,
}

impl Clone for Map {
    fn clone(&self) -> Self {
        Map {
            cells: self.cells.clone(),
            targets: self.targets.clone(),
            failed: self.failed.clone(),
            alive: self.alive.clone(),
            bodies: self.bodies.clone(),
            freed: self.freed.clone(),
            sightings: self.sightings.clone(),
            base: self.base,
        }
    }

    /// Field by field, keeping this map's allocations: a robot copies its
    /// map into a spare every slot.
    fn clone_from(&mut self, source: &Self) {
        self.cells.clone_from(&source.cells);
        self.clone_rest_from(source);
    }
}

impl Serialize for Map {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        Flat {
            visited: Bitset::from_words(self.cells.words(false).collect()),
            known: Bitset::from_words(self.cells.words(true).collect()),
            open: {
                let mut open = Vec::new();
                self.cells.open_bytes_into(&mut open);
                Cow::Owned(open)
            },
            targets: &self.targets,
            failed: &self.failed,
            alive: &self.alive,
            bodies: &self.bodies[..],
            freed: &self.freed[..],
            sightings: &self.sightings,
        }
        .serialize(s)
    }
}

impl<'de> Deserialize<'de> for Map {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let f = Flat::<Spots, Vec<Failure>, Vec<(RobotId, u32)>, Vec<(VertexId, u32)>, Sightings>::deserialize(d)?;
        let cells = Tiles::from_flat(f.visited.words(), f.known.words(), &f.open).ok_or_else(|| {
            serde::de::Error::custom("map bitsets sized for another grid than its edge masks, or set past the end")
        })?;
        Ok(Map {
            cells,
            targets: f.targets,
            failed: f.failed,
            alive: f.alive,
            bodies: f.bodies,
            freed: Thin::from(f.freed),
            sightings: f.sightings,
            base: None,
        })
    }
}

impl Map {
    /// The bytes postcard writes for this map (the fields of [`Flat`]),
    /// without writing them: the bitsets' words one varint each, the edge
    /// masks a byte a vertex, the lists as they are. Summed by hand rather
    /// than through serde: every map a robot sends is counted.
    pub fn wire_len(&self) -> usize {
        use crate::protocol::varint_len as v;
        let vertices = self.cells.vertices();
        let n = vertices.div_ceil(64);
        // Without failures or bodies (most maps sent), five empty lists.
        let lists = if self.failed.is_empty()
            && self.alive.is_empty()
            && self.bodies.is_empty()
            && self.freed.is_empty()
            && self.sightings.is_empty()
        {
            5
        } else {
            self.lists_wire_len()
        };
        2 * v(n as u64) + self.cells.words_wire_len() + v(vertices as u64) + vertices + self.targets.wire_len() + lists
    }

    /// The bytes of the failures', rejoins', bodies', freed vertices' and
    /// sightings' lists, out of [`Map::wire_len`]'s way.
    #[inline(never)]
    fn lists_wire_len(&self) -> usize {
        use crate::protocol::varint_len as v;
        let pairs =
            |l: &[(u32, u32)]| v(l.len() as u64) + l.iter().map(|&(a, b)| v(a.into()) + v(b.into())).sum::<usize>();
        let alive =
            v(self.alive.len() as u64) + self.alive.iter().map(|&(a, b)| v(a.into()) + v(b.into())).sum::<usize>();
        let failed = v(self.failed.len() as u64)
            + self.failed.iter().map(|f| v(f.robot.into()) + v(f.at.into()) + v(f.round.into()) + 1).sum::<usize>();
        let sightings = v(self.sightings.len() as u64)
            + self.sightings.iter().map(|s| v(s.robot.into()) + v(s.at.into()) + v(s.round.into())).sum::<usize>();
        failed + alive + pairs(&self.bodies) + pairs(&self.freed) + sightings
    }

    pub fn new(vertices: usize) -> Self {
        Map {
            cells: Tiles::new(vertices),
            targets: Spots::default(),
            failed: Vec::new(),
            alive: Vec::new(),
            bodies: Vec::new(),
            freed: Thin::default(),
            sightings: Sightings::default(),
            base: None,
        }
    }

    /// Vertices of the grid it describes.
    pub fn vertices(&self) -> usize {
        self.cells.vertices()
    }

    /// Some robot has stood on `v`.
    pub fn visited(&self, v: VertexId) -> bool {
        self.cells.visited(v as usize)
    }

    /// `v` is known accessible.
    pub fn known(&self, v: VertexId) -> bool {
        self.cells.known(v as usize)
    }

    /// The edge mask sensed at `v` ([`SENSED`] once anyone sensed there).
    pub fn open(&self, v: VertexId) -> u8 {
        self.cells.open(v as usize)
    }

    pub fn set_visited(&mut self, v: VertexId, on: bool) {
        self.cells.set_visited(v as usize, on);
    }

    pub fn set_known(&mut self, v: VertexId, on: bool) {
        self.cells.set_known(v as usize, on);
    }

    /// Adds `bits` to the edge mask of `v`.
    pub fn or_open(&mut self, v: VertexId, bits: u8) {
        self.cells.or_open(v as usize, bits);
    }

    /// The per-vertex parts, for tests of how copies share them.
    pub fn cells(&self) -> &Tiles {
        &self.cells
    }

    /// A copy of this map to send in round `round`: it carries the round
    /// of the copy sent before and the tiles changed since. `into` is an
    /// earlier copy to copy into, if the caller has one, with the round it
    /// was sent in: if that was the last, it need only take the tiles
    /// changed since.
    pub fn send_copy(&mut self, round: u32, into: Option<(Map, u32)>) -> Map {
        let m = match into {
            Some((mut m, sent)) if Some(sent) == self.base => {
                m.cells.copy_changes_from(&self.cells);
                m.clone_rest_from(self);
                m
            }
            Some((mut m, _)) => {
                m.clone_from(self);
                m
            }
            None => self.clone(),
        };
        self.base = Some(round);
        self.cells.forget_changes();
        m
    }

    /// Everything but the tiles, copied from `source` into this map's allocations.
    fn clone_rest_from(&mut self, source: &Map) {
        self.targets.clone_from_spots(&source.targets);
        self.failed.clone_from(&source.failed);
        self.alive.clone_from(&source.alive);
        self.bodies.clone_from(&source.bodies);
        self.freed.clone_from(&source.freed);
        self.sightings.clone_from_sightings(&source.sightings);
        self.base = source.base;
    }

    /// Records what a robot standing on `v` senses: the open edge slots.
    pub fn record_sensing(&mut self, grid: &Grid, v: VertexId, open: u8) {
        self.set_visited(v, true);
        self.set_known(v, true);
        self.or_open(v, open | SENSED);
        for (d, &n) in grid.neighbors(v)[..grid.degree()].iter().enumerate() {
            if open >> d & 1 == 1 {
                self.set_known(n, true);
            }
        }
    }

    /// `self ∪= other`: sets by union, failures and rejoins by their latest round.
    pub fn merge(&mut self, other: &Map) {
        self.cells.merge(&other.cells);
        self.merge_lists(other);
    }

    /// [`Map::merge`] for a map whose sender's map of round
    /// `other.base` this one has merged already (and has lost nothing of
    /// since): only the tiles changed since then are looked at.
    pub fn merge_changes(&mut self, other: &Map) {
        self.cells.merge_changes(&other.cells);
        self.merge_lists(other);
    }

    /// Targets, failures and rejoins of a merge: short lists, merged whole.
    fn merge_lists(&mut self, other: &Map) {
        self.targets.union(&other.targets);
        for f in &other.failed {
            self.merge_failure(*f);
        }
        for &(id, round) in &other.alive {
            self.revive(id, round);
        }
        for &(v, round) in &other.bodies {
            latest(&mut self.bodies, v, round);
        }
        for &(v, round) in other.freed.iter() {
            latest(self.freed.vec_mut(), v, round);
        }
        self.sightings.merge(&other.sightings);
    }

    /// A sonar found a silent robot on `v` in `round`.
    pub fn add_body(&mut self, v: VertexId, round: u32) {
        latest(&mut self.bodies, v, round);
    }

    /// A sonar found `v` free in `round`: a body found there up to that
    /// round no longer counts. Recorded only where a body was known.
    pub fn free_body(&mut self, v: VertexId, round: u32) {
        if self.bodies.binary_search_by_key(&v, |b| b.0).is_ok() {
            latest(self.freed.vec_mut(), v, round);
        }
    }

    /// The silent bodies that count now, with the round each was found in.
    pub fn bodies_found_now(&self) -> impl Iterator<Item = (VertexId, u32)> + '_ {
        self.bodies.iter().filter(|b| round_of(&self.freed, b.0).is_none_or(|r| r < b.1)).copied()
    }

    /// Vertices holding a silent body now.
    pub fn bodies_now(&self) -> impl Iterator<Item = VertexId> + '_ {
        self.bodies_found_now().map(|b| b.0)
    }

    /// Declares `id` failed on `at` in `round`. Of two declarations the
    /// later round wins (the lower vertex on a tie, so merging stays
    /// independent of order).
    pub fn add_failed(&mut self, id: RobotId, at: VertexId, round: u32) {
        self.merge_failure(Failure { robot: id, at, round, seen: false });
    }

    /// Of two declarations the later round wins (the lower vertex on a
    /// tie); the same declaration is seen if either says so.
    fn merge_failure(&mut self, f: Failure) {
        match self.failed.binary_search_by_key(&f.robot, |g| g.robot) {
            Ok(k) => {
                let old = &mut self.failed[k];
                let order = |g: &Failure| (g.round, std::cmp::Reverse(g.at));
                if order(&f) > order(old) {
                    *old = f;
                } else if order(&f) == order(old) {
                    old.seen |= f.seen;
                }
            }
            Err(k) => self.failed.insert(k, f),
        }
    }

    /// The sonar found `id`'s vertex occupied: its failure is seen.
    pub fn see_failed(&mut self, id: RobotId) {
        if let Ok(k) = self.failed.binary_search_by_key(&id, |f| f.robot) {
            self.failed[k].seen = true;
        }
    }

    /// `id` was heard alive in `round`: any failure declared of it up to
    /// that round no longer counts.
    pub fn revive(&mut self, id: RobotId, round: u32) {
        latest(&mut self.alive, id, round);
    }

    fn alive_round(&self, id: RobotId) -> Option<u32> {
        round_of(&self.alive, id)
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
        self.failures_now().map(|f| (f.robot, f.at))
    }

    /// [`Map::failed_now`] with whether each one's body was seen.
    pub fn failures_now(&self) -> impl Iterator<Item = Failure> + '_ {
        self.failed.iter().filter(|f| self.alive_round(f.robot).is_none_or(|r| r < f.round)).copied()
    }

    /// Whether some robot counts as failed now.
    pub fn any_failed(&self) -> bool {
        self.failed_now().next().is_some()
    }

    /// Whether some known accessible vertex is not yet visited.
    pub fn has_unvisited(&self) -> bool {
        self.cells.any_known_unvisited()
    }

    /// Whether the edge `v` → slot `d` is known traversable, sensed from either end.
    pub fn edge_open(&self, grid: &Grid, v: VertexId, d: usize) -> bool {
        if self.open(v) >> d & 1 == 1 {
            return true;
        }
        let n = grid.neighbors(v)[d];
        self.open(n) >> grid.opposite(d) & 1 == 1
    }

    /// Whether some robot sensed an open edge into `v` (so `v` is known
    /// accessible, whether or not anyone stood on it).
    pub fn reached(&self, grid: &Grid, v: VertexId) -> bool {
        (0..grid.degree()).any(|d| grid.neighbors(v)[d] != crate::grid::NONE && self.edge_open(grid, v, d))
    }

    /// Checks a map that came from elsewhere against the grid it claims to
    /// describe, so a malformed message cannot index out of bounds.
    /// `targets` is the largest number of targets a map may hold.
    pub fn validate(&self, vertices: usize, targets: usize, robots: usize) -> Result<(), String> {
        if self.vertices() != vertices {
            return Err(format!("map sized for another grid (expected {vertices} vertices)"));
        }
        if self.targets.count() > targets {
            return Err(format!("map target set larger than {targets} targets"));
        }
        if !self.targets.is_canonical() {
            return Err("map target set not sorted, or repeating a spot".into());
        }
        if self.cells.past_end() {
            return Err("map sets a bit past the end".into());
        }
        if self.failed.windows(2).any(|w| w[0].robot >= w[1].robot) || self.alive.windows(2).any(|w| w[0].0 >= w[1].0) {
            return Err("map failure list not sorted by robot".into());
        }
        if self.bodies.windows(2).any(|w| w[0].0 >= w[1].0) || self.freed.windows(2).any(|w| w[0].0 >= w[1].0) {
            return Err("map body list not sorted by vertex".into());
        }
        if self.bodies.iter().chain(self.freed.iter()).any(|b| b.0 as usize >= vertices) {
            return Err("map names a vertex that does not exist".into());
        }
        if self.failed.iter().any(|f| f.robot as usize >= robots || f.at as usize >= vertices)
            || self.alive.iter().any(|a| a.0 as usize >= robots)
        {
            return Err("map names a robot or vertex that does not exist".into());
        }
        self.sightings.validate(vertices, robots)
    }
}

/// `list[key] := max(list[key], round)`, `list` sorted by key: rejoins by
/// robot, bodies found and freed by vertex.
fn latest<K: Ord + Copy>(list: &mut Vec<(K, u32)>, key: K, round: u32) {
    match list.binary_search_by_key(&key, |e| e.0) {
        Ok(k) => list[k].1 = list[k].1.max(round),
        Err(k) => list.insert(k, (key, round)),
    }
}

fn round_of<K: Ord + Copy>(list: &[(K, u32)], key: K) -> Option<u32> {
    list.binary_search_by_key(&key, |e| e.0).ok().map(|k| list[k].1)
}

/// Serde for bytes as one byte string (`serialize_bytes`), borrowed from
/// the input where the format can lend them.
mod byte_string {
    use std::borrow::Cow;

    use serde::de::{Deserializer, SeqAccess, Visitor};
    use serde::Serializer;

    pub fn serialize<S: Serializer>(v: &[u8], s: S) -> Result<S::Ok, S::Error> {
        s.serialize_bytes(v)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Cow<'de, [u8]>, D::Error> {
        d.deserialize_bytes(Bytes)
    }

    struct Bytes;

    impl<'de> Visitor<'de> for Bytes {
        type Value = Cow<'de, [u8]>;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a byte string")
        }

        fn visit_borrowed_bytes<E>(self, v: &'de [u8]) -> Result<Self::Value, E> {
            Ok(Cow::Borrowed(v))
        }

        fn visit_bytes<E>(self, v: &[u8]) -> Result<Self::Value, E> {
            Ok(Cow::Owned(v.to_vec()))
        }

        fn visit_byte_buf<E>(self, v: Vec<u8>) -> Result<Self::Value, E> {
            Ok(Cow::Owned(v))
        }

        // Formats without byte strings (JSON) give a sequence.
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
            let mut v = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1 << 20));
            while let Some(b) = seq.next_element()? {
                v.push(b);
            }
            Ok(Cow::Owned(v))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same fields, flat, with `open` as a plain sequence: the encoding before tiles.
    #[derive(Serialize)]
    struct Plain<'a> {
        visited: Bitset,
        known: Bitset,
        open: Vec<u8>,
        targets: &'a Spots,
        failed: &'a Vec<Failure>,
        alive: &'a Vec<(RobotId, u32)>,
        bodies: &'a Vec<(VertexId, u32)>,
        freed: &'a [(VertexId, u32)],
        sightings: &'a Sightings,
    }

    #[test]
    fn maps_encode_as_flat_fields_and_round_trip() {
        let mut m = Map::new(300);
        m.set_visited(3, true);
        m.set_known(299, true);
        m.or_open(7, 0x81);
        m.or_open(299, 0xff);
        m.targets.insert(crate::spot::Spot { x: 8, y: -3 });
        m.add_failed(2, 50, 1);
        m.revive(1, 3);
        let (mut visited, mut known, mut open) = (Bitset::new(300), Bitset::new(300), vec![0u8; 300]);
        visited.set(3);
        known.set(299);
        open[7] = 0x81;
        open[299] = 0xff;
        let plain = Plain {
            visited,
            known,
            open,
            targets: &m.targets,
            failed: &m.failed,
            alive: &m.alive,
            bodies: &m.bodies,
            freed: &m.freed[..],
            sightings: &m.sightings,
        };
        let bytes = postcard::to_allocvec(&m).unwrap();
        assert_eq!(bytes, postcard::to_allocvec(&plain).unwrap());
        assert_eq!(postcard::from_bytes::<Map>(&bytes).unwrap(), m);
        assert_eq!(m.validate(300, 9, 3), Ok(()));
        // A bit past the end of the grid, in the last word or beyond.
        let mut bad = m.clone();
        bad.set_visited(300, true);
        assert!(bad.validate(300, 9, 3).is_err());
        let mut bad = m.clone();
        bad.set_known(319, true);
        assert!(bad.validate(300, 9, 3).is_err());
        assert!(m.validate(320, 9, 3).is_err(), "sized for another grid");
        // On the wire: bitsets sized for another grid, or set past the end.
        let mut plain = plain;
        plain.visited = Bitset::new(400);
        assert!(postcard::from_bytes::<Map>(&postcard::to_allocvec(&plain).unwrap()).is_err());
        plain.visited = Bitset::new(300);
        plain.visited.set(301);
        assert!(postcard::from_bytes::<Map>(&postcard::to_allocvec(&plain).unwrap()).is_err());
    }

    /// Sets on three vertices of a map: a visited and known flag and an edge mask each.
    fn marked(n: usize, marks: &[(usize, u8)]) -> Map {
        let mut m = Map::new(n);
        mark(&mut m, marks);
        m
    }

    /// [`marked`]'s marks on a map that may hold some already (a flag may go off).
    fn mark(m: &mut Map, marks: &[(usize, u8)]) {
        let n = m.vertices();
        for &(v, bits) in marks {
            let v = (v % n) as VertexId;
            m.set_visited(v, bits & 1 == 1);
            m.set_known(v, bits & 2 == 2);
            m.or_open(v, bits);
        }
    }

    /// Merges `b` into a copy of `a`: the result is the flat union, shares
    /// what it can, and neither `a` nor `b` changes.
    fn check_merge(a: &Map, b: &Map) -> Result<Map, proptest::test_runner::TestCaseError> {
        let n = a.vertices() as VertexId;
        let (before_a, before_b) = (postcard::to_allocvec(a).unwrap(), postcard::to_allocvec(b).unwrap());
        let mut ab = a.clone();
        proptest::prop_assert_eq!(ab.cells().unshared(), 0);
        ab.merge(b);
        // Per tile: whether `b`'s holds all of `a`'s.
        let mut only_b = vec![true; (n as usize).div_ceil(tiles::TILE)];
        for v in 0..n {
            only_b[v as usize / tiles::TILE] &=
                (!a.visited(v) || b.visited(v)) && (!a.known(v) || b.known(v)) && a.open(v) & !b.open(v) == 0;
        }
        for v in 0..n {
            proptest::prop_assert_eq!(ab.visited(v), a.visited(v) || b.visited(v));
            proptest::prop_assert_eq!(ab.known(v), a.known(v) || b.known(v));
            proptest::prop_assert_eq!(ab.open(v), a.open(v) | b.open(v));
            // A tile of `b` that holds all of `a`'s is taken whole.
            if only_b[v as usize / tiles::TILE] && ab.cells().shares_masks(b.cells()) {
                proptest::prop_assert!(ab.cells().shares(b.cells(), v as usize));
            }
        }
        proptest::prop_assert_eq!(
            postcard::to_allocvec(a).unwrap(),
            before_a,
            "merging into a copy changed the original"
        );
        proptest::prop_assert_eq!(postcard::to_allocvec(b).unwrap(), before_b);
        proptest::prop_assert_eq!(ab.has_unvisited(), (0..n).any(|v| ab.known(v) && !ab.visited(v)));
        Ok(ab)
    }

    proptest::proptest! {
        /// Merging tiles gives what merging the flat fields gives, in
        /// either order, whether the two maps read one table of masks (made
        /// up masks that disagree included), two, or one came off the wire.
        #[test]
        fn tiles_merge_as_flat_unions(
            n in 1usize..6000,
            a in proptest::collection::vec((0usize..6000, proptest::prelude::any::<u8>()), 0..80),
            b in proptest::collection::vec((0usize..6000, proptest::prelude::any::<u8>()), 0..80),
        ) {
            let apart = (marked(n, &a), marked(n, &b));
            let decode = |m: &Map| postcard::from_bytes::<Map>(&postcard::to_allocvec(m).unwrap()).unwrap();
            let wire = decode(&apart.1);
            let (shared, shared_wire) = {
                let _one = tiles::SharedMasks::new(n);
                ((marked(n, &a), marked(n, &b)), decode(&apart.1))
            };
            let ab = check_merge(&apart.0, &apart.1)?;
            proptest::prop_assert_eq!(&ab, &check_merge(&apart.1, &apart.0)?);
            proptest::prop_assert_eq!(&ab, &check_merge(&shared.0, &shared.1)?);
            proptest::prop_assert_eq!(&ab, &check_merge(&shared.1, &shared.0)?);
            proptest::prop_assert_eq!(&ab, &check_merge(&shared.0, &wire)?);
            proptest::prop_assert_eq!(&ab, &check_merge(&wire, &shared.0)?);
            proptest::prop_assert_eq!(&ab, &check_merge(&shared.0, &shared_wire)?);
            // Copying into a map of the same grid or of another.
            for mut into in [marked(n, &b), Map::new(n + 300), Map::default()] {
                into.clone_from(&ab);
                proptest::prop_assert_eq!(&into, &ab);
                proptest::prop_assert_eq!(into.cells().unshared(), 0);
            }
        }
    }

    proptest::proptest! {
        /// A receiver that merged a robot's last copy and merges only the
        /// tiles changed since in its next holds what merging all of it
        /// gives, whatever the robot did between: sensing, merging, flags
        /// going off (dropped claims), with one table of masks or not.
        #[test]
        fn merging_the_changes_is_merging_the_whole_copy(
            n in 1usize..3000,
            shared in proptest::prelude::any::<bool>(),
            first in proptest::collection::vec((0usize..3000, proptest::prelude::any::<u8>()), 0..60),
            later in proptest::collection::vec((0usize..3000, proptest::prelude::any::<u8>()), 0..60),
            heard in proptest::collection::vec((0usize..3000, proptest::prelude::any::<u8>()), 0..60),
            own in proptest::collection::vec((0usize..3000, proptest::prelude::any::<u8>()), 0..60),
            reuse in proptest::prelude::any::<bool>(),
            again in proptest::collection::vec((0usize..60, proptest::prelude::any::<u8>()), 0..20),
        ) {
            let _one = shared.then(|| tiles::SharedMasks::new(n));
            let mut robot = marked(n, &first);
            let old = robot.send_copy(3, None);
            proptest::prop_assert_eq!((old.base, robot.base, robot.cells().changes()), (None, Some(3), 0));
            let mut receiver = marked(n, &own);
            receiver.merge(&old);
            receiver.merge(&marked(n, &heard));
            mark(&mut robot, &later);
            // More edges sensed open where it held a mask already: only the byte changes.
            for &(k, bits) in &again {
                if let Some(&(v, _)) = first.get(k) {
                    robot.or_open((v % n) as VertexId, bits);
                }
            }
            robot.merge(&marked(n, &heard[..heard.len() / 2]));
            // The copy goes into the last copy, or into an older one (another map).
            let spare = if reuse { (old.clone(), 3) } else { (marked(n, &own), 2) };
            let new = robot.send_copy(4, Some(spare));
            proptest::prop_assert_eq!(&new, &robot);
            proptest::prop_assert_eq!(new.base, Some(3));
            let (mut whole, mut changes) = (receiver.clone(), receiver.clone());
            whole.merge(&new);
            changes.merge_changes(&new);
            proptest::prop_assert_eq!(&changes, &whole);
            // The tiles not marked are the old copy's, content for content.
            for v in 0..n as VertexId {
                let tile = v as usize / tiles::TILE;
                if !new.cells().changed(tile) {
                    proptest::prop_assert_eq!(
                        (new.visited(v), new.known(v), new.open(v)),
                        (old.visited(v), old.known(v), old.open(v))
                    );
                }
            }
        }
    }

    /// Robots that sense the same physics never copy the table they share,
    /// however their maps merge; only a map that needs another byte where
    /// one is held gets a table of its own.
    #[test]
    fn honest_maps_keep_one_table_of_masks() {
        use crate::geometry::Point;
        use crate::lattice::{Lattice, LatticeKind};
        let grid = Grid::new(Lattice::new(LatticeKind::Triangular, 1.0), Point::new(0.0, 0.0), Point::new(20.0, 20.0));
        let last = grid.len() as VertexId - 1;
        // Open towards every neighbour in the grid whose slot is odd or whose id is even.
        let physics = |v: VertexId| {
            let near = grid.neighbors(v)[..grid.degree()].iter().enumerate();
            near.filter(|&(d, &n)| n != crate::grid::NONE && (d % 2 == 1 || n % 2 == 0)).fold(0, |m, (d, _)| m | 1 << d)
        };
        let one = tiles::SharedMasks::new(grid.len());
        let maps: Vec<Map> = {
            (0..4u32)
                .map(|r| {
                    let mut m = Map::new(grid.len());
                    for v in (r * 50..r * 50 + 120).chain([last]) {
                        m.record_sensing(&grid, v, physics(v));
                    }
                    m
                })
                .collect()
        };
        let mut all = maps[0].clone();
        for m in &maps[1..] {
            all.merge(m);
            all.merge(&all.clone());
        }
        assert!(maps.iter().all(|m| m.cells().shares_masks(all.cells())));
        assert_eq!(all.open(last), physics(last) | SENSED);
        assert_eq!(all.open(last - 1), 0, "nobody sensed there");
        // A map that disagrees takes a copy; the others still read the old byte.
        let mut odd = maps[0].clone();
        odd.or_open(0, 0x40);
        assert!(!odd.cells().shares_masks(all.cells()));
        assert_eq!((odd.open(0), all.open(0)), (physics(0) | SENSED | 0x40, physics(0) | SENSED));
        // Decoded, an honest map reads the same table, and one that
        // contradicts it (hostile) a copy of its own.
        let decode = |m: &Map| postcard::from_bytes::<Map>(&postcard::to_allocvec(m).unwrap()).unwrap();
        let (back, odd_back) = (decode(&all), decode(&odd));
        assert!(back.cells().shares_masks(all.cells()));
        assert!(!odd_back.cells().shares_masks(all.cells()));
        assert_eq!((&back, &odd_back), (&all, &odd));
        assert_eq!(all.open(0), physics(0) | SENSED);
        drop(one);
        // Outside the scope every new map has a table of its own.
        assert!(!Map::new(grid.len()).cells().shares_masks(Map::new(grid.len()).cells()));
    }

    #[test]
    fn failures_merge_by_latest_round_and_rejoins_overrule_them() {
        let mut a = Map::new(10);
        let mut b = Map::new(10);
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
        assert_eq!(ab.failure(3), Some(Failure { robot: 3, at: 6, round: 4, seen: false }));
        // Seen by one robot, seen in every map that merges its own.
        let mut seen = ab.clone();
        seen.see_failed(3);
        ab.merge(&seen);
        assert!(ab.failure(3).is_some_and(|f| f.seen));
        ab.merge(&a);
        assert!(ab.failure(3).is_some_and(|f| f.seen), "an unseen copy of the same declaration");
        assert_eq!(ab.failed_now().collect::<Vec<_>>(), vec![(3, 6)]);
        // Targets grow to the union.
        let (mut t, mut u) = (Map::new(10), Map::new(10));
        let s = |x| crate::spot::Spot { x, y: 70 };
        t.targets.insert(s(1));
        u.targets.insert(s(2));
        t.merge(&u);
        assert_eq!(t.targets.iter().collect::<Vec<_>>(), [s(1), s(2)]);
    }
}
