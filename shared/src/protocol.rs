//! The messages robots exchange (steps 1, 3, 5, 8), as serde types encoded
//! with postcard. Decoding checks every id and size against the run, so a
//! malformed or hostile message is an error to count, never a panic or an
//! out-of-bounds index in the decision core.

use serde::{Deserialize, Serialize};

use crate::grid::VertexId;
use crate::map::{Map, RobotId};

/// Robot-to-robot messages. Every one carries its round so stale ones can
/// be told apart and dropped.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Message {
    /// Step 1 broadcast to all robots: targets the sender just found.
    Targets { round: u32, from: RobotId, targets: Vec<u16> },
    /// Step 3 to communication neighbours: the sender's map as it was after
    /// sensing, and the vertex it stands on.
    Map { round: u32, from: RobotId, at: VertexId, map: Map },
    /// Step 5 to communication neighbours: the sender's next vertex.
    Choice { round: u32, from: RobotId, next: VertexId },
    /// Step 8 broadcast: the sender's stop rule fired.
    Stop { round: u32, from: RobotId },
}

impl Message {
    pub fn round(&self) -> u32 {
        match self {
            Message::Targets { round, .. }
            | Message::Map { round, .. }
            | Message::Choice { round, .. }
            | Message::Stop { round, .. } => *round,
        }
    }

    pub fn from(&self) -> RobotId {
        match self {
            Message::Targets { from, .. }
            | Message::Map { from, .. }
            | Message::Choice { from, .. }
            | Message::Stop { from, .. } => *from,
        }
    }
}

/// World-server to robot: what the robot's sensors and radio deliver.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum FromWorld {
    /// Start of a round: the robot's readings (steps 1-2) and who is in
    /// radio range. `at` is where the robot stands (its odometry).
    Tick { round: u32, at: VertexId, open: u8, occupied: u8, targets: Vec<u16>, neighbours: Vec<RobotId> },
    /// A message from another robot, carried by the radio.
    Relay(Message),
    /// Every step 1 and step 3 message of this round has been delivered.
    ExchangeDone { round: u32 },
    /// The radio lost `robot`, standing on `at`, for good (Sec. 4.2).
    Failed { round: u32, robot: RobotId, at: VertexId },
    /// The receiver itself was declared failed: it must stop for good.
    Deposed { round: u32 },
    /// The search is over.
    End { round: u32 },
}

/// Robot to world-server: messages for the radio to carry. A `Choice` is
/// also the robot's move for the round; a `Stop` ends the search.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ToWorld {
    Hello { robot: RobotId, pid: u32 },
    Radio(Message),
}

/// The sizes of the run a message must fit.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    pub vertices: usize,
    pub targets: usize,
    pub robots: usize,
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum DecodeError {
    #[error("undecodable message: {0}")]
    Format(String),
    #[error("message out of range: {0}")]
    Range(String),
}

pub fn encode(m: &Message) -> Vec<u8> {
    postcard::to_allocvec(m).expect("a message always serializes")
}

/// Decodes and validates a message against the run's `limits`.
pub fn decode(bytes: &[u8], limits: &Limits) -> Result<Message, DecodeError> {
    let m: Message = postcard::from_bytes(bytes).map_err(|e| DecodeError::Format(e.to_string()))?;
    check(&m, limits)?;
    Ok(m)
}

fn in_range(what: &str, v: usize, n: usize) -> Result<(), DecodeError> {
    if v < n {
        Ok(())
    } else {
        Err(DecodeError::Range(format!("{what} {v} not below {n}")))
    }
}

/// Checks every id and size in `m` against `limits`.
fn check(m: &Message, limits: &Limits) -> Result<(), DecodeError> {
    in_range("sender", m.from() as usize, limits.robots)?;
    match m {
        Message::Targets { targets, .. } => {
            for &t in targets {
                in_range("target", t as usize, limits.targets)?;
            }
        }
        Message::Map { at, map, .. } => {
            in_range("vertex", *at as usize, limits.vertices)?;
            map.validate(limits.vertices, limits.targets, limits.robots).map_err(DecodeError::Range)?;
        }
        Message::Choice { next, .. } => in_range("vertex", *next as usize, limits.vertices)?,
        Message::Stop { .. } => {}
    }
    Ok(())
}

pub fn encode_to_world(m: &ToWorld) -> Vec<u8> {
    postcard::to_allocvec(m).expect("a message always serializes")
}

pub fn encode_from_world(m: &FromWorld) -> Vec<u8> {
    postcard::to_allocvec(m).expect("a message always serializes")
}

/// Decodes and validates what a robot sent to the world.
pub fn decode_to_world(bytes: &[u8], limits: &Limits) -> Result<ToWorld, DecodeError> {
    let m: ToWorld = postcard::from_bytes(bytes).map_err(|e| DecodeError::Format(e.to_string()))?;
    check_to_world(m, limits)
}

/// [`decode_to_world`] that also refuses bytes after the message. The
/// world-server relays the bytes of a robot's `ToWorld::Radio(m)` unchanged
/// as `FromWorld::Relay(m)` (both are variant 1 of their enum, so postcard
/// encodes them alike; tested below): with this check what it relays is
/// exactly one valid message.
pub fn decode_to_world_exact(bytes: &[u8], limits: &Limits) -> Result<ToWorld, DecodeError> {
    let (m, rest) = postcard::take_from_bytes::<ToWorld>(bytes).map_err(|e| DecodeError::Format(e.to_string()))?;
    if !rest.is_empty() {
        return Err(DecodeError::Format(format!("{} bytes after the message", rest.len())));
    }
    check_to_world(m, limits)
}

fn check_to_world(m: ToWorld, limits: &Limits) -> Result<ToWorld, DecodeError> {
    match &m {
        ToWorld::Hello { robot, .. } if (*robot as usize) >= limits.robots => {
            Err(DecodeError::Range(format!("robot {robot} not below {}", limits.robots)))
        }
        ToWorld::Radio(inner) => check(inner, limits).map(|_| m),
        _ => Ok(m),
    }
}

/// Decodes and validates what the world sent to a robot.
pub fn decode_from_world(bytes: &[u8], limits: &Limits) -> Result<FromWorld, DecodeError> {
    let m: FromWorld = postcard::from_bytes(bytes).map_err(|e| DecodeError::Format(e.to_string()))?;
    match &m {
        FromWorld::Tick { at, targets, neighbours, .. } => {
            in_range("vertex", *at as usize, limits.vertices)?;
            for &t in targets {
                in_range("target", t as usize, limits.targets)?;
            }
            for &n in neighbours {
                in_range("robot", n as usize, limits.robots)?;
            }
        }
        FromWorld::Relay(inner) => check(inner, limits)?,
        FromWorld::Failed { robot, at, .. } => {
            in_range("robot", *robot as usize, limits.robots)?;
            in_range("vertex", *at as usize, limits.vertices)?;
        }
        _ => {}
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const LIMITS: Limits = Limits { vertices: 100, targets: 9, robots: 13 };

    fn a_map() -> Map {
        let mut m = Map::new(100, 9);
        m.visited.set(3);
        m.known.set(4);
        m.open[3] = 0x81;
        m.targets.set(8);
        m.add_failed(2, 50);
        m
    }

    #[test]
    fn round_trip() {
        for m in [
            Message::Targets { round: 3, from: 1, targets: vec![0, 8] },
            Message::Map { round: 4, from: 12, at: 99, map: a_map() },
            Message::Choice { round: 5, from: 0, next: 7 },
            Message::Stop { round: 6, from: 2 },
        ] {
            assert_eq!(decode(&encode(&m), &LIMITS), Ok(m));
        }
    }

    #[test]
    fn out_of_range_is_refused() {
        let bad = [
            Message::Targets { round: 0, from: 13, targets: vec![] },
            Message::Targets { round: 0, from: 1, targets: vec![9] },
            Message::Choice { round: 0, from: 1, next: 100 },
            Message::Map { round: 0, from: 1, at: 0, map: Map::new(101, 9) },
            Message::Map { round: 0, from: 1, at: 0, map: Map::new(100, 70) },
        ];
        for m in bad {
            assert!(matches!(decode(&encode(&m), &LIMITS), Err(DecodeError::Range(_))), "{m:?}");
        }
    }

    #[test]
    fn world_messages_round_trip_and_are_checked() {
        let tick = FromWorld::Tick { round: 1, at: 5, open: 0x3f, occupied: 1, targets: vec![2], neighbours: vec![3, 4] };
        assert_eq!(decode_from_world(&encode_from_world(&tick), &LIMITS), Ok(tick));
        let bad = FromWorld::Tick { round: 1, at: 5, open: 0, occupied: 0, targets: vec![], neighbours: vec![13] };
        assert!(decode_from_world(&encode_from_world(&bad), &LIMITS).is_err());
        let radio = ToWorld::Radio(Message::Choice { round: 2, from: 3, next: 99 });
        assert_eq!(decode_to_world(&encode_to_world(&radio), &LIMITS), Ok(radio));
        let bad = ToWorld::Radio(Message::Choice { round: 2, from: 3, next: 100 });
        assert!(decode_to_world(&encode_to_world(&bad), &LIMITS).is_err());
    }

    #[test]
    fn relayed_bytes_are_the_radio_bytes() {
        for m in [
            Message::Targets { round: 3, from: 1, targets: vec![0, 8] },
            Message::Map { round: 4, from: 12, at: 99, map: a_map() },
            Message::Choice { round: 5, from: 0, next: 7 },
            Message::Stop { round: 6, from: 2 },
        ] {
            let radio = encode_to_world(&ToWorld::Radio(m.clone()));
            assert_eq!(radio, encode_from_world(&FromWorld::Relay(m.clone())));
            assert_eq!(decode_to_world_exact(&radio, &LIMITS), Ok(ToWorld::Radio(m)));
            let mut long = radio.clone();
            long.push(0);
            assert!(matches!(decode_to_world_exact(&long, &LIMITS), Err(DecodeError::Format(_))));
        }
    }

    proptest! {
        #[test]
        fn arbitrary_exact_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
            if let Ok(m) = decode_to_world_exact(&bytes, &LIMITS) {
                // Exactly one message: it re-encodes to the same bytes.
                prop_assert_eq!(encode_to_world(&m), bytes);
            }
        }

        #[test]
        fn arbitrary_world_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
            let _ = decode_to_world(&bytes, &LIMITS);
            let _ = decode_from_world(&bytes, &LIMITS);
        }

        #[test]
        fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..600)) {
            let _ = decode(&bytes, &LIMITS);
        }

        #[test]
        fn corrupted_messages_never_panic(flips in prop::collection::vec((0usize..2000, any::<u8>()), 1..8)) {
            let mut bytes = encode(&Message::Map { round: 4, from: 12, at: 99, map: a_map() });
            for (k, b) in flips {
                let n = bytes.len();
                bytes[k % n] ^= b;
            }
            if let Ok(m) = decode(&bytes, &LIMITS) {
                // Whatever survives decoding is inside the run's limits.
                prop_assert!((m.from() as usize) < LIMITS.robots);
            }
        }
    }
}
