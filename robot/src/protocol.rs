//! The radio frames robots exchange (steps 1, 3, 5 and 8, and the
//! acknowledgements that keep moves collision-free without an oracle), as
//! serde types encoded with postcard. Decoding checks every id and size
//! against the run, so a malformed or hostile frame is an error to count,
//! never a panic or an out-of-bounds index in the decision core.
//!
//! What each frame means is the robot's radio protocol ([`crate::peer`]);
//! the medium that carries frames never looks inside one.

use std::rc::Rc;

use serde::{Deserialize, Serialize};

use crate::grid::VertexId;
use crate::io::{Framed, Header, Listen};
use crate::map::{Map, RobotId};
use crate::spot::Spot;

/// Robot-to-robot frames, all broadcast to whoever is in radio range. Every
/// one carries its round, so frames of another round can be told apart and dropped.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Frame {
    /// Step 3, sent at the start of every slot: the sender's map as it was
    /// after sensing, where it stands, whether it has stopped searching, and
    /// whether it carries the step-8 stop that ends the search. `sent` is
    /// when the sender sensed (by its clock, in simulated microseconds):
    /// robots that sensed late order themselves by it (`crate::peer`).
    Map { round: u32, from: RobotId, at: VertexId, sent: u64, halted: bool, stop: bool, map: Map },
    /// Step 5: the sender's next vertex (its own to stay), and the
    /// neighbours whose announced choices it avoided: for each of them this
    /// is the acknowledgement that lets it move.
    Choice { round: u32, from: RobotId, at: VertexId, next: VertexId, accounted: Vec<RobotId> },
    /// The sender has the choices of `acked` and has not committed to a move
    /// that conflicts with them (it will avoid them); it has committed to
    /// one that conflicts with `refused`'s.
    Ack { round: u32, from: RobotId, acked: Vec<RobotId>, refused: Vec<RobotId> },
    /// After its motor command: whether the sender really leaves its vertex
    /// this round (a robot following into that vertex waits for this).
    Commit { round: u32, from: RobotId, moving: bool },
    /// Steps 1 and 8, flooded over several hops: targets found, and the stop.
    Flood { round: u32, from: RobotId, targets: Vec<Spot>, stop: bool },
    /// The sender has not chosen yet, and still waits for the choices of
    /// robots ahead of it (step 4): sent every half `t_wait` while it
    /// waits, so that robots waiting for its choice in turn know it alive
    /// and wait on (`crate::peer`, "long chains").
    Wait { round: u32, from: RobotId },
}

impl Frame {
    #[inline]
    pub fn round(&self) -> u32 {
        match self {
            Frame::Map { round, .. }
            | Frame::Choice { round, .. }
            | Frame::Ack { round, .. }
            | Frame::Commit { round, .. }
            | Frame::Flood { round, .. }
            | Frame::Wait { round, .. } => *round,
        }
    }

    pub fn from(&self) -> RobotId {
        match self {
            Frame::Map { from, .. }
            | Frame::Choice { from, .. }
            | Frame::Ack { from, .. }
            | Frame::Commit { from, .. }
            | Frame::Flood { from, .. }
            | Frame::Wait { from, .. } => *from,
        }
    }

    /// Its header ([`encode`] writes it first): the kind ([`KIND_MAP`]..)
    /// and round, and a tag for receive filters: an ack's addressees (bit
    /// `id % 64` each, [`Listen::bit`]), a flood's stop ([`FLOOD_STOP`]),
    /// 0 otherwise. A flood's targets have no tag: a target is a position,
    /// and no fixed set of bits could say which ones a robot knows.
    #[inline]
    pub fn header(&self) -> Header {
        let (kind, tag) = match self {
            Frame::Map { stop, .. } => (KIND_MAP, if *stop { MAP_STOP } else { 0 }),
            Frame::Choice { .. } => (KIND_CHOICE, 0),
            Frame::Ack { acked, refused, .. } => {
                (KIND_ACK, acked.iter().chain(refused).fold(0, |t, &r| t | Listen::bit(r)))
            }
            Frame::Commit { .. } => (KIND_COMMIT, 0),
            Frame::Flood { stop, .. } => (KIND_FLOOD, if *stop { FLOOD_STOP } else { 0 }),
            Frame::Wait { .. } => (KIND_WAIT, 0),
        };
        Header { kind, round: self.round(), tag }
    }

    /// A short name for counts and logs.
    pub fn kind(&self) -> &'static str {
        match self {
            Frame::Map { .. } => "map",
            Frame::Choice { .. } => "choice",
            Frame::Ack { .. } => "ack",
            Frame::Commit { .. } => "commit",
            Frame::Flood { .. } => "flood",
            Frame::Wait { .. } => "wait",
        }
    }
}

/// Frame kinds in a [`Header`]: the variants' indices, in order.
pub const KIND_MAP: u8 = 0;
pub const KIND_CHOICE: u8 = 1;
pub const KIND_ACK: u8 = 2;
pub const KIND_COMMIT: u8 = 3;
pub const KIND_FLOOD: u8 = 4;
pub const KIND_WAIT: u8 = 5;

/// A flood's tag bit for the stop it carries.
pub const FLOOD_STOP: u64 = 1 << 63;
/// A map's tag bit for the stop it carries (maps are never held by a
/// receive filter: the bit is for the controller's receiver).
pub const MAP_STOP: u64 = 1;

/// The header at the start of an encoded frame, read without decoding the
/// frame after it; `None` if it is not there.
pub fn header_of(bytes: &[u8]) -> Option<Header> {
    postcard::take_from_bytes::<Header>(bytes).ok().map(|(h, _)| h)
}

impl Frame {
    /// Whether it carries the step-8 stop that ends the search.
    #[inline]
    pub fn carries_stop(&self) -> bool {
        matches!(self, Frame::Map { stop: true, .. } | Frame::Flood { stop: true, .. })
    }
}

impl Framed for Rc<Frame> {
    #[inline]
    fn header(&self) -> Option<Header> {
        Some(Frame::header(self))
    }

    #[inline]
    fn carries_stop(&self) -> bool {
        Frame::carries_stop(self)
    }

    #[inline]
    fn is_flood(&self) -> bool {
        matches!(**self, Frame::Flood { .. })
    }

    fn flood(&self) -> Option<(Vec<Spot>, bool)> {
        match &**self {
            Frame::Flood { targets, stop, .. } => Some((targets.clone(), *stop)),
            _ => None,
        }
    }

    fn wire_len(&self) -> usize {
        Frame::wire_len(self)
    }
}

impl Framed for Rc<[u8]> {
    fn header(&self) -> Option<Header> {
        header_of(self)
    }

    /// A map or a flood says so in its header, checked by decoding the
    /// flood (floods are small). Bytes that do not decode carry none.
    fn carries_stop(&self) -> bool {
        match header_of(self) {
            Some(h) if h.kind == KIND_MAP => h.tag & MAP_STOP != 0,
            Some(h) if h.kind == KIND_FLOOD && h.tag & FLOOD_STOP != 0 => postcard::take_from_bytes::<Header>(self)
                .and_then(|(_, rest)| postcard::from_bytes::<Frame>(rest))
                .is_ok_and(|f| f.carries_stop()),
            _ => false,
        }
    }

    fn is_flood(&self) -> bool {
        header_of(self).is_some_and(|h| h.kind == KIND_FLOOD)
    }

    /// Decoded only when its header says it is a flood; bytes that do not
    /// decode tell nothing.
    fn flood(&self) -> Option<(Vec<Spot>, bool)> {
        if header_of(self)?.kind != KIND_FLOOD {
            return None;
        }
        match postcard::take_from_bytes::<Header>(self).and_then(|(_, rest)| postcard::from_bytes::<Frame>(rest)) {
            Ok(Frame::Flood { targets, stop, .. }) => Some((targets, stop)),
            _ => None,
        }
    }

    fn wire_len(&self) -> usize {
        self.len()
    }
}

/// Robot ids are below this (a robot does not know the team size).
pub const MAX_ROBOTS: usize = u16::MAX as usize;
/// The transmitter a robot sees on a frame the human controller's base
/// station relayed (step 8): the one number [`MAX_ROBOTS`] leaves free.
/// The frame itself still names the robot that sent it.
pub const CONTROLLER: RobotId = RobotId::MAX;
/// A frame holds at most this many targets in situation 2 (a robot does not know how many).
pub const MAX_TARGETS: usize = 1 << 20;

/// The sizes a frame must fit. A robot does not know the team size or (in
/// situation 2) the number of targets, so those two are upper bounds.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    pub vertices: usize,
    /// A frame holds at most this many targets.
    pub targets: usize,
    /// Robot ids are below this.
    pub robots: usize,
}

impl Limits {
    /// What a robot can check a frame against: the grid it holds, the
    /// number of targets if it knows it (situation 1, else 0).
    pub fn for_robot(vertices: usize, targets_total: usize) -> Self {
        Limits { vertices, targets: if targets_total > 0 { targets_total } else { MAX_TARGETS }, robots: MAX_ROBOTS }
    }
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum DecodeError {
    #[error("undecodable frame: {0}")]
    Format(String),
    #[error("frame out of range: {0}")]
    Range(String),
}

/// The bytes postcard takes for the unsigned integer `x` (7 bits a byte).
#[inline]
pub(crate) fn varint_len(x: u64) -> usize {
    /// By leading zeros.
    const LEN: [u8; 65] = {
        let mut t = [1u8; 65];
        let mut z = 0;
        while z < 57 {
            t[z] = (64 - z).div_ceil(7) as u8;
            z += 1;
        }
        t
    };
    LEN[x.leading_zeros() as usize] as usize
}

impl Frame {
    /// `encode(self).len()`, without encoding: summed by hand from the
    /// fields as postcard writes them (a `u8` and a `bool` a byte, other
    /// integers and lengths a varint), as every frame a robot sends is
    /// counted and encoding its map would cost more than the slot's work.
    pub fn wire_len(&self) -> usize {
        let v = |x: u64| varint_len(x);
        let ids = |l: &[RobotId]| v(l.len() as u64) + l.iter().map(|&r| v(r.into())).sum::<usize>();
        // The header (kind, round, tag), then the variant's index (below
        // 128: a byte), the round and the sender, then the variant's
        // fields: one match, the tag's with them (only acks and floods tag
        // their header with more than a bit).
        let (round, from, rest) = match self {
            Frame::Map { round, from, at, sent, map, .. } => {
                (round, from, 1 + v((*at).into()) + v(*sent) + 2 + map.wire_len())
            }
            Frame::Choice { round, from, at, next, accounted } => {
                (round, from, 1 + v((*at).into()) + v((*next).into()) + ids(accounted))
            }
            Frame::Ack { round, from, acked, refused } => {
                (round, from, v(self.header().tag) + ids(acked) + ids(refused))
            }
            Frame::Commit { round, from, .. } => (round, from, 1 + 1),
            Frame::Flood { round, from, targets, stop } => {
                (round, from, v(if *stop { FLOOD_STOP } else { 0 }) + crate::spot::wire_len(targets) + 1)
            }
            Frame::Wait { round, from } => (round, from, 1),
        };
        let round = v((*round).into());
        1 + round + 1 + round + v((*from).into()) + rest
    }
}

/// The frame's header ([`Frame::header`]), then the frame.
pub fn encode(f: &Frame) -> Vec<u8> {
    let bytes = postcard::to_allocvec(&f.header()).expect("a header always serializes");
    postcard::to_extend(f, bytes).expect("a frame always serializes")
}

/// Decodes and validates exactly one frame (no bytes after it) behind a
/// header that matches it: a radio may have filtered on that header.
pub fn decode(bytes: &[u8], limits: &Limits) -> Result<Frame, DecodeError> {
    let format = |e: postcard::Error| DecodeError::Format(e.to_string());
    let (h, rest) = postcard::take_from_bytes::<Header>(bytes).map_err(format)?;
    let (f, rest) = postcard::take_from_bytes::<Frame>(rest).map_err(format)?;
    if !rest.is_empty() {
        return Err(DecodeError::Format(format!("{} bytes after the frame", rest.len())));
    }
    if h != f.header() {
        return Err(DecodeError::Format(format!("header {h:?} does not match the frame's {:?}", f.header())));
    }
    check(&f, limits)?;
    Ok(f)
}

pub fn in_range(what: &str, v: usize, n: usize) -> Result<(), DecodeError> {
    if v < n {
        Ok(())
    } else {
        Err(DecodeError::Range(format!("{what} {v} not below {n}")))
    }
}

/// Checks every id and size in `f` against `limits`.
pub fn check(f: &Frame, limits: &Limits) -> Result<(), DecodeError> {
    in_range("sender", f.from() as usize, limits.robots)?;
    match f {
        Frame::Map { at, map, .. } => {
            in_range("vertex", *at as usize, limits.vertices)?;
            map.validate(limits.vertices, limits.targets, limits.robots).map_err(DecodeError::Range)?;
        }
        Frame::Choice { at, next, accounted, .. } => {
            in_range("vertex", *at as usize, limits.vertices)?;
            in_range("vertex", *next as usize, limits.vertices)?;
            for &r in accounted {
                in_range("robot", r as usize, limits.robots)?;
            }
        }
        Frame::Ack { acked, refused, .. } => {
            for &r in acked.iter().chain(refused) {
                in_range("robot", r as usize, limits.robots)?;
            }
        }
        Frame::Commit { .. } | Frame::Wait { .. } => {}
        Frame::Flood { targets, .. } => {
            if targets.len() > limits.targets {
                return Err(DecodeError::Range(format!("{} targets, more than {}", targets.len(), limits.targets)));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const LIMITS: Limits = Limits { vertices: 100, targets: 9, robots: 13 };

    fn spot(x: i32) -> Spot {
        Spot { x, y: -x }
    }

    fn a_map() -> Map {
        let mut m = Map::new(100);
        m.set_visited(3, true);
        m.set_known(4, true);
        m.or_open(3, 0x81);
        m.targets.insert(spot(8));
        m.add_failed(2, 50, 1);
        m
    }

    fn frames() -> Vec<Frame> {
        vec![
            Frame::Map { round: 4, from: 12, at: 99, sent: 7_000_000, halted: false, stop: true, map: a_map() },
            Frame::Choice { round: 5, from: 0, at: 6, next: 7, accounted: vec![1, 12] },
            Frame::Ack { round: 5, from: 3, acked: vec![0, 4], refused: vec![9] },
            Frame::Commit { round: 6, from: 2, moving: true },
            Frame::Flood { round: 3, from: 1, targets: vec![spot(0), spot(8)], stop: false },
            Frame::Wait { round: 5, from: 7 },
        ]
    }

    #[test]
    fn round_trip() {
        for f in frames() {
            assert_eq!(decode(&encode(&f), &LIMITS), Ok(f));
        }
    }

    /// A robot's frames move by value (`Transmit`, 16 bytes more): past
    /// 256 bytes a move is a longer copy, and the map's wire lengths kept
    /// beside its tiles had pushed it there.
    #[cfg(target_pointer_width = "64")]
    #[test]
    fn a_frame_is_at_most_240_bytes() {
        assert!(std::mem::size_of::<Frame>() <= 240, "{}", std::mem::size_of::<Frame>());
    }

    #[test]
    fn a_frames_length_is_its_encodings() {
        for f in frames() {
            assert_eq!(f.wire_len(), encode(&f).len(), "{f:?}");
            let bytes: Rc<[u8]> = encode(&f).into();
            assert_eq!(Framed::wire_len(&bytes), Framed::wire_len(&Rc::new(f)));
        }
    }

    #[test]
    fn a_header_reads_the_same_from_the_frame_and_from_its_bytes() {
        let kinds: Vec<u8> = frames().iter().map(|f| f.header().kind).collect();
        assert_eq!(kinds, [KIND_MAP, KIND_CHOICE, KIND_ACK, KIND_COMMIT, KIND_FLOOD, KIND_WAIT]);
        for f in frames() {
            assert_eq!(header_of(&encode(&f)), Some(f.header()), "{f:?}");
        }
        assert_eq!(frames()[2].header().tag, Listen::bit(0) | Listen::bit(4) | Listen::bit(9), "an ack's addressees");
        assert_eq!(frames()[4].header().tag, 0, "a flood's targets have no tag");
        let f = Frame::Flood { round: 70_000, from: 1, targets: vec![spot(2)], stop: true };
        assert_eq!(f.header(), Header { kind: KIND_FLOOD, round: 70_000, tag: FLOOD_STOP });
        assert_eq!(header_of(&[]), None);
        assert_eq!(header_of(&[2, 1]), None, "no tag");
    }

    #[test]
    fn the_controller_reads_the_stop_from_frames_and_from_their_bytes() {
        let stop_map = Frame::Map { round: 4, from: 2, at: 9, sent: 0, halted: true, stop: true, map: a_map() };
        let map = Frame::Map { round: 4, from: 2, at: 9, sent: 0, halted: true, stop: false, map: a_map() };
        let stop_flood = Frame::Flood { round: 3, from: 1, targets: vec![], stop: true };
        let far_target = Frame::Flood { round: 3, from: 1, targets: vec![spot(70)], stop: false };
        let choice = Frame::Choice { round: 1, from: 1, at: 2, next: 3, accounted: vec![] };
        for (f, stop) in [(stop_map, true), (map, false), (stop_flood, true), (far_target, false), (choice, false)] {
            let bytes: Rc<[u8]> = encode(&f).into();
            assert_eq!(Framed::carries_stop(&Rc::new(f.clone())), stop, "{f:?}");
            assert_eq!(bytes.carries_stop(), stop, "{f:?} as bytes");
        }
        let garbage: Rc<[u8]> = vec![4, 3, 0x80, 0x80, 0x80].into();
        assert!(!garbage.carries_stop());
    }

    #[test]
    fn the_controller_reads_a_floods_news_from_frames_and_from_their_bytes() {
        let flood = Frame::Flood { round: 3, from: 1, targets: vec![spot(70), spot(2)], stop: true };
        let map = Frame::Map { round: 4, from: 2, at: 9, sent: 0, halted: true, stop: true, map: a_map() };
        for (f, news) in [(flood, Some((vec![spot(70), spot(2)], true))), (map, None)] {
            let bytes: Rc<[u8]> = encode(&f).into();
            assert_eq!(Framed::flood(&Rc::new(f.clone())), news, "{f:?}");
            assert_eq!(bytes.flood(), news, "{f:?} as bytes");
            assert_eq!(Framed::is_flood(&Rc::new(f.clone())), news.is_some(), "{f:?}");
            assert_eq!(bytes.is_flood(), news.is_some(), "{f:?} as bytes");
        }
        let garbage: Rc<[u8]> = vec![4, 3, 0x80, 0x80, 0x80].into();
        assert_eq!(garbage.flood(), None, "a flood header over bytes that do not decode tells nothing");
    }

    #[test]
    fn a_header_that_lies_about_its_frame_is_refused() {
        let f = &frames()[2];
        let mut bytes = postcard::to_allocvec(&Header { tag: 0, ..f.header() }).unwrap();
        bytes.extend(postcard::to_allocvec(f).unwrap());
        assert!(matches!(decode(&bytes, &LIMITS), Err(DecodeError::Format(e)) if e.contains("does not match")));
    }

    /// A map holding the spots `xs` as given, in order and with repeats,
    /// as a malformed frame may.
    fn with_targets(xs: impl IntoIterator<Item = i32>) -> Map {
        let spots: Vec<Spot> = xs.into_iter().map(spot).collect();
        let mut m = Map::new(100);
        m.targets = postcard::from_bytes(&postcard::to_allocvec(&spots).unwrap()).unwrap();
        m
    }

    #[test]
    fn out_of_range_and_trailing_bytes_are_refused() {
        let bad = [
            Frame::Flood { round: 0, from: 13, targets: vec![], stop: false },
            Frame::Flood { round: 0, from: 1, targets: (0..10).map(spot).collect(), stop: false },
            Frame::Choice { round: 0, from: 1, at: 0, next: 100, accounted: vec![] },
            Frame::Choice { round: 0, from: 1, at: 0, next: 1, accounted: vec![13] },
            Frame::Ack { round: 0, from: 1, acked: vec![], refused: vec![13] },
            Frame::Wait { round: 0, from: 13 },
            Frame::Map { round: 0, from: 1, at: 0, sent: 0, halted: false, stop: false, map: Map::new(101) },
            Frame::Map { round: 0, from: 1, at: 0, sent: 0, halted: false, stop: false, map: with_targets(0..10) },
            Frame::Map { round: 0, from: 1, at: 0, sent: 0, halted: false, stop: false, map: with_targets([2, 1]) },
            Frame::Map { round: 0, from: 1, at: 0, sent: 0, halted: false, stop: false, map: with_targets([1, 1]) },
        ];
        for f in bad {
            assert!(matches!(decode(&encode(&f), &LIMITS), Err(DecodeError::Range(_))), "{f:?}");
        }
        let mut long = encode(&frames()[3]);
        long.push(0);
        assert!(matches!(decode(&long, &LIMITS), Err(DecodeError::Format(_))));
    }

    /// A map's length is kept tile by tile: asked for between
    /// changes of every kind (marks, merges, copies sent, copies into
    /// earlier copies), it is still its encoding's.
    #[test]
    fn a_maps_remembered_length_follows_its_changes() {
        // Asked of the map itself, so its own memo is filled from now on.
        let check = |m: &Map, what: &str| {
            assert_eq!(m.wire_len(), postcard::to_allocvec(m).unwrap().len(), "{what}");
        };
        let (mut a, mut b) = (Map::new(1100), Map::new(1100));
        check(&a, "empty");
        for v in (0..1100).step_by(37) {
            a.set_visited(v, true);
            check(&a, "a marked");
        }
        for v in (5..1100).step_by(3) {
            b.set_known(v, true);
            b.set_visited(v + 1, true);
        }
        check(&b, "b");
        a.merge(&b);
        check(&a, "a merged with b");
        let mut sent = a.send_copy(1, None);
        check(&sent, "first copy");
        a.set_visited(1099, true);
        a.set_known(0, true);
        check(&a, "a after its copy");
        sent = a.send_copy(2, Some((sent, 1)));
        check(&sent, "copy into the last copy");
        assert_eq!(postcard::to_allocvec(&sent).unwrap(), postcard::to_allocvec(&a).unwrap());
        // A change in another tile only: the copy's tiles changed before
        // are not marked any more, and their lengths must be right.
        a.set_visited(600, true);
        sent = a.send_copy(3, Some((sent, 2)));
        check(&sent, "a third copy, into the second, after a change elsewhere");
        a.set_known(1000, true);
        sent = a.send_copy(4, Some((sent, 3)));
        check(&sent, "a fourth copy");
        check(&a, "a after its copies");
        let mut c = Map::new(1100);
        c.set_visited(700, true);
        check(&c, "c");
        c.merge_changes(&a);
        check(&c, "c merged with a's changes");
        b.merge(&c);
        check(&b, "b merged with c");
        let mut d = b.clone();
        d.set_visited(3, true);
        check(&d, "a clone marked");
        check(&b, "its original");
        d.sightings.add(crate::map::sightings::Sighting { robot: 300, at: 1099, round: 70_000 });
        check(&d, "a sighting");
        b.merge(&d);
        check(&b, "a sighting merged");
    }

    proptest! {
        /// Maps of every size and content: long varints, empty tiles, lists.
        #[test]
        fn a_maps_length_is_its_encodings(
            vertices in 1usize..1500,
            marks in prop::collection::vec((any::<u32>(), any::<u8>(), 0u8..4), 0..300),
            round in any::<u32>(),
            sent in any::<u64>(),
        ) {
            let mut m = Map::new(vertices);
            for (v, bits, what) in marks {
                let v = v % vertices as u32;
                match what {
                    0 => m.set_visited(v, true),
                    1 => m.set_known(v, true),
                    2 => m.or_open(v, bits | 1),
                    _ => {
                        m.targets.insert(Spot { x: i32::from(bits) * 977 - 100_000, y: (v as i32).wrapping_mul(-31) });
                        m.add_failed(bits as RobotId, v, round);
                        m.add_body(v, round / 2);
                        m.free_body(v / 2, round);
                        m.alive.push((bits as RobotId * 300, round >> (bits % 32)));
                        let robot = (bits as RobotId) << (bits % 9);
                        m.sightings.add(crate::map::sightings::Sighting { robot, at: v, round: round >> (bits % 32) });
                    }
                }
            }
            let f = Frame::Map { round, from: 3, at: vertices as u32 - 1, sent, halted: true, stop: false, map: m };
            prop_assert_eq!(f.wire_len(), encode(&f).len());
        }

        /// Every other kind, with values of every varint length.
        #[test]
        fn a_frames_length_is_its_encodings_whatever_its_values(
            round in any::<u32>(),
            from in any::<u16>(),
            at in any::<u32>(),
            ids in prop::collection::vec(any::<u16>(), 0..200),
            targets in prop::collection::vec((any::<i32>(), any::<i32>()), 0..200),
            flag in any::<bool>(),
        ) {
            let split = ids.len() / 3;
            for f in [
                Frame::Choice { round, from, at, next: at / 3, accounted: ids.clone() },
                Frame::Ack { round, from, acked: ids[..split].to_vec(), refused: ids[split..].to_vec() },
                Frame::Commit { round, from, moving: flag },
                Frame::Flood { round, from, targets: targets.iter().map(|&(x, y)| Spot { x, y }).collect(), stop: flag },
                Frame::Wait { round, from },
            ] {
                prop_assert_eq!(f.wire_len(), encode(&f).len(), "{:?}", f);
            }
        }

        #[test]
        fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
            if let Ok(f) = decode(&bytes, &LIMITS) {
                // Exactly one frame: it re-encodes to the same bytes.
                prop_assert_eq!(encode(&f), bytes);
            }
        }

        #[test]
        fn corrupted_frames_never_panic(k in 0usize..6, flips in prop::collection::vec((0usize..2000, any::<u8>()), 1..8)) {
            let mut bytes = encode(&frames()[k]);
            for (i, b) in flips {
                let n = bytes.len();
                bytes[i % n] ^= b;
            }
            if let Ok(f) = decode(&bytes, &LIMITS) {
                // Whatever survives decoding is inside the run's limits.
                prop_assert!((f.from() as usize) < LIMITS.robots);
            }
        }
    }
}
