//! What the world-server and a robot-agent say to each other (the
//! distributed engine's transport, no iceoryx2 here): the world wakes a
//! robot with what its sensors, radio and clock deliver ([`Wake`]), the
//! robot answers with what its radio and motors should do ([`AgentOutput`]).
//! Radio frames cross as opaque bytes: the world never decodes one.
//!
//! Messages are postcard bytes. One message may be bigger than a transport
//! sample, so it travels as [`chunks`] of at most a given size, each with a
//! small header (sequence number, part, parts), put back together by an
//! [`Assembler`]. Decoding checks every size and id against [`WireLimits`]
//! and returns a [`WireError`]; it never panics on any input.
//!
//! A robot's first message is its [`Hello`]: its number, its process and
//! the run's [`Agreement`] as it holds it. The world answers it with a
//! [`Verdict`], its acceptance or its refusal naming what differs. Hello
//! and verdict are message number 0 (the handshake); wake-ups count from 1.

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::{Deserialize, Serialize, Serializer};

use crate::agreement::Agreement;
use crate::io::{Listen, Motor, Note, Tick, Time};
use crate::map::RobotId;

/// Bytes, serialized as one postcard byte string (length and bytes, copied
/// in one go) rather than element by element.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Bytes(pub Vec<u8>);

impl Serialize for Bytes {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_bytes(&self.0)
    }
}

impl<'de> Deserialize<'de> for Bytes {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Bytes;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("bytes")
            }
            fn visit_bytes<E: de::Error>(self, v: &[u8]) -> Result<Bytes, E> {
                Ok(Bytes(v.to_vec()))
            }
            fn visit_byte_buf<E: de::Error>(self, v: Vec<u8>) -> Result<Bytes, E> {
                Ok(Bytes(v))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Bytes, A::Error> {
                let mut out = Vec::new();
                while let Some(b) = seq.next_element::<u8>()? {
                    out.push(b);
                }
                Ok(Bytes(out))
            }
        }
        d.deserialize_byte_buf(V)
    }
}

/// A frame that reached the robot: its transmitter, when, and its bytes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WireFrame {
    pub from: RobotId,
    pub at: Time,
    pub bytes: Bytes,
}

/// One wake-up of one robot (`gridswarm::sim::WakeCall` with bytes for frames).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Wake {
    /// Answered by the [`AgentOutput`] with the same number.
    pub seq: u64,
    pub now: Time,
    pub tick: Option<Tick>,
    pub frames: Vec<WireFrame>,
}

/// World to agent.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ToAgent {
    Wake(Wake),
    /// The run is over: exit.
    End,
    /// The world's answer to a hello.
    Verdict(Verdict),
}

/// The world's answer to the hello of the agent whose nonce it names:
/// over zenoh every agent claiming a robot number reads that number's
/// inbox, so an agent acts only on its own.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Verdict {
    pub nonce: u64,
    /// `None`: accepted. Otherwise why not, in the world's words.
    pub refusal: Option<String>,
}

/// Message number of the handshake (a hello and its verdict): never put
/// again by the world, never taken for an answer to a wake-up.
pub const HANDSHAKE: u64 = 0;

/// A frame to broadcast ([`crate::io::Transmit`] with bytes).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WireSend {
    pub bytes: Bytes,
    pub ready: Time,
    pub copies: u8,
}

/// A robot's answer to the [`Wake`] numbered `seq` ([`crate::io::Output`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AgentOutput {
    pub seq: u64,
    pub send: Vec<WireSend>,
    pub motor: Option<(Motor, Time)>,
    pub alarm: Option<Time>,
    pub listen: Listen,
    pub notes: Vec<Note>,
}

/// A [`ToAgent::Wake`] to encode, borrowing the frames' bytes: the world
/// encodes every wake-up from frames it shares, without copying them first.
/// Encodes to exactly the bytes of the owned message.
#[derive(Serialize)]
enum ToAgentRef<'a> {
    Wake(&'a WakeRef<'a>),
}

#[derive(Serialize)]
pub struct WakeRef<'a> {
    pub seq: u64,
    pub now: Time,
    pub tick: Option<&'a Tick>,
    pub frames: Vec<WireFrameRef<'a>>,
}

#[derive(Serialize)]
pub struct WireFrameRef<'a> {
    pub from: RobotId,
    pub at: Time,
    pub bytes: ByteSlice<'a>,
}

/// Borrowed bytes, serialized as [`Bytes`] is.
pub struct ByteSlice<'a>(pub &'a [u8]);

impl Serialize for ByteSlice<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_bytes(self.0)
    }
}

/// Encodes a wake-up into `out` (cleared first), reusing its allocation.
pub fn encode_wake_into(w: &WakeRef, out: &mut Vec<u8>) {
    let mut buf = std::mem::take(out);
    buf.clear();
    *out = postcard::to_extend(&ToAgentRef::Wake(w), buf).expect("a message always serializes");
}

/// A robot-agent's first message.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Hello {
    /// First: its protocol version leads the message.
    pub agreement: Agreement,
    pub robot: u32,
    /// Its process id (on its own host).
    pub pid: u32,
    /// Its host's name, for messages.
    pub host: String,
    /// Drawn once per process: tells two claims to one robot number apart.
    pub nonce: u64,
}

/// Agent to world.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ToWorld {
    /// The agent is up (boxed: the rare message is the big one).
    Hello(Box<Hello>),
    Output(AgentOutput),
}

/// Bytes of a text field of a hello or a verdict (names, keys, hosts,
/// a refusal), at most.
pub const MAX_TEXT: usize = 4096;

/// What a message must fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WireLimits {
    /// Robot ids are below this.
    pub robots: usize,
    /// Vertex ids are below this.
    pub vertices: usize,
    /// A tick holds at most this many targets.
    pub targets: usize,
    /// Bytes of one radio frame, at most.
    pub frame_bytes: usize,
    /// Frames in one wake or one output, and notes in one output, at most.
    pub items: usize,
}

/// Radio frames are at most this big (a map of a million vertices fits).
pub const MAX_FRAME_BYTES: usize = 4 << 20;
/// Frames, sends or notes in one message, at most.
pub const MAX_ITEMS: usize = 1 << 16;

impl WireLimits {
    /// What the world checks an agent's message against.
    pub fn for_world(robots: usize, vertices: usize, targets: usize) -> Self {
        WireLimits { robots, vertices, targets, frame_bytes: MAX_FRAME_BYTES, items: MAX_ITEMS }
    }

    /// What a robot checks the world's messages against: the grid it holds
    /// and the number of targets if it knows it; it does not know the team size.
    pub fn for_robot(vertices: usize, targets_total: usize) -> Self {
        let p = crate::protocol::Limits::for_robot(vertices, targets_total);
        WireLimits { robots: p.robots, vertices, targets: p.targets, frame_bytes: MAX_FRAME_BYTES, items: MAX_ITEMS }
    }
}

#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum WireError {
    #[error("undecodable message: {0}")]
    Format(String),
    #[error("message out of range: {0}")]
    Range(String),
    #[error("bad chunk: {0}")]
    Chunk(String),
}

fn range(what: &str, v: usize, n: usize) -> Result<(), WireError> {
    if v < n {
        Ok(())
    } else {
        Err(WireError::Range(format!("{what} {v} not below {n}")))
    }
}

fn at_most(what: &str, v: usize, n: usize) -> Result<(), WireError> {
    if v <= n {
        Ok(())
    } else {
        Err(WireError::Range(format!("{what} {v} above {n}")))
    }
}

fn decode_exact<'a, T: Deserialize<'a>>(bytes: &'a [u8]) -> Result<T, WireError> {
    let (v, rest) = postcard::take_from_bytes::<T>(bytes).map_err(|e| WireError::Format(e.to_string()))?;
    if !rest.is_empty() {
        return Err(WireError::Format(format!("{} bytes after the message", rest.len())));
    }
    Ok(v)
}

pub fn encode_to_agent(m: &ToAgent) -> Vec<u8> {
    postcard::to_allocvec(m).expect("a message always serializes")
}

pub fn encode_to_world(m: &ToWorld) -> Vec<u8> {
    postcard::to_allocvec(m).expect("a message always serializes")
}

/// Decodes and checks a message of the world.
pub fn decode_to_agent(bytes: &[u8], l: &WireLimits) -> Result<ToAgent, WireError> {
    let m: ToAgent = decode_exact(bytes)?;
    match &m {
        ToAgent::Wake(w) => check_wake(w, l)?,
        ToAgent::Verdict(v) => at_most("refusal bytes", v.refusal.as_ref().map_or(0, String::len), MAX_TEXT)?,
        ToAgent::End => {}
    }
    Ok(m)
}

fn check_wake(w: &Wake, l: &WireLimits) -> Result<(), WireError> {
    at_most("frames", w.frames.len(), l.items)?;
    for f in &w.frames {
        // A robot, or the controller's base station relaying a flood.
        if f.from != crate::protocol::CONTROLLER {
            range("transmitter", f.from as usize, l.robots)?;
        }
        at_most("frame bytes", f.bytes.0.len(), l.frame_bytes)?;
    }
    if let Some(t) = &w.tick {
        range("vertex", t.at as usize, l.vertices)?;
        at_most("targets", t.targets.len(), l.targets.min(l.items))?;
    }
    Ok(())
}

/// Decodes and checks a message of an agent.
pub fn decode_to_world(bytes: &[u8], l: &WireLimits) -> Result<ToWorld, WireError> {
    let m: ToWorld = decode_exact(bytes)?;
    match &m {
        // A robot number outside the team is the world's to refuse, in words.
        ToWorld::Hello(h) => check_hello(h)?,
        ToWorld::Output(o) => check_output(o, l)?,
    }
    Ok(m)
}

fn check_hello(h: &Hello) -> Result<(), WireError> {
    let a = &h.agreement;
    for (what, text) in [("key", &a.key), ("scenario name", &a.scenario.name), ("scenario hash", &a.scenario.sha3_256)]
    {
        at_most(what, text.len(), MAX_TEXT)?;
    }
    at_most("algorithm", a.algorithm.len(), MAX_TEXT)?;
    at_most("host", h.host.len(), MAX_TEXT)?;
    let p = &a.params;
    let reals = [
        p.a,
        p.r_rob,
        p.r_safe,
        p.r_so,
        p.r_st,
        p.r_c,
        p.t_rot,
        p.t_trans,
        p.t_choice,
        p.t_exchange,
        p.t_hop,
        p.t_wait,
        a.lo[0],
        a.lo[1],
        a.hi[0],
        a.hi[1],
    ];
    if reals.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(WireError::Range("a parameter that is not a finite number".into()))
    }
}

fn check_output(o: &AgentOutput, l: &WireLimits) -> Result<(), WireError> {
    at_most("sends", o.send.len(), l.items)?;
    at_most("notes", o.notes.len(), l.items)?;
    for s in &o.send {
        at_most("frame bytes", s.bytes.0.len(), l.frame_bytes)?;
    }
    if let Some((Motor::Go(v), _)) = o.motor {
        range("vertex", v as usize, l.vertices)?;
    }
    for n in &o.notes {
        if let Note::Declared { robot } | Note::Rejoined { robot } | Note::TimedOut { robot } = n {
            range("robot", *robot as usize, l.robots)?;
        }
    }
    Ok(())
}

/// Bytes of a chunk's header: sequence number, part, parts (little endian).
pub const CHUNK_HEADER: usize = 16;

/// Splits `message` (numbered `seq`) into chunks of at most `max` bytes,
/// header included, and hands each to `out`. `max` must exceed the header.
pub fn chunks(seq: u64, message: &[u8], max: usize, mut out: impl FnMut(&[u8])) {
    let body = max.saturating_sub(CHUNK_HEADER).max(1);
    let parts = message.len().div_ceil(body).max(1);
    let mut buf = Vec::with_capacity(max.min(message.len() + CHUNK_HEADER));
    for k in 0..parts {
        let part = &message[(k * body).min(message.len())..((k + 1) * body).min(message.len())];
        buf.clear();
        buf.extend_from_slice(&seq.to_le_bytes());
        buf.extend_from_slice(&(k as u32).to_le_bytes());
        buf.extend_from_slice(&(parts as u32).to_le_bytes());
        buf.extend_from_slice(part);
        out(&buf);
    }
}

/// How many chunks of at most `max` bytes a message of `len` bytes takes.
pub fn chunk_count(len: usize, max: usize) -> usize {
    len.div_ceil(max.saturating_sub(CHUNK_HEADER).max(1)).max(1)
}

/// Puts chunks back together, one message at a time. A chunk of a newer
/// message drops an incomplete older one; chunks of older messages than
/// the one in progress are dropped.
#[derive(Debug, Default)]
pub struct Assembler {
    seq: u64,
    next: u32,
    parts: u32,
    buf: Vec<u8>,
    /// Refuses messages bigger than this.
    max_len: usize,
    /// Chunks dropped (stale, out of order).
    pub dropped: u64,
}

impl Assembler {
    pub fn new(max_len: usize) -> Self {
        Assembler { max_len, ..Default::default() }
    }

    /// Adds a chunk; returns the sequence number and the bytes of a
    /// message it completed.
    pub fn push(&mut self, chunk: &[u8]) -> Result<Option<(u64, &[u8])>, WireError> {
        if chunk.len() < CHUNK_HEADER {
            return Err(WireError::Chunk(format!("{} bytes, shorter than its header", chunk.len())));
        }
        let seq = u64::from_le_bytes(chunk[0..8].try_into().expect("8 bytes"));
        let part = u32::from_le_bytes(chunk[8..12].try_into().expect("4 bytes"));
        let parts = u32::from_le_bytes(chunk[12..16].try_into().expect("4 bytes"));
        if parts == 0 || part >= parts {
            return Err(WireError::Chunk(format!("part {part} of {parts}")));
        }
        if part == 0 {
            self.seq = seq;
            self.next = 0;
            self.parts = parts;
            self.buf.clear();
        } else if seq != self.seq || part != self.next || parts != self.parts {
            self.dropped += 1;
            return Ok(None);
        }
        if self.buf.len() + chunk.len() - CHUNK_HEADER > self.max_len {
            self.next = u32::MAX;
            return Err(WireError::Chunk(format!("message longer than {} bytes", self.max_len)));
        }
        self.buf.extend_from_slice(&chunk[CHUNK_HEADER..]);
        self.next = part + 1;
        if self.next == parts {
            self.next = u32::MAX;
            return Ok(Some((seq, &self.buf)));
        }
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spot::Spot;
    use proptest::prelude::*;

    const L: WireLimits = WireLimits { robots: 13, vertices: 100, targets: 9, frame_bytes: 1000, items: 50 };

    fn wake() -> ToAgent {
        ToAgent::Wake(Wake {
            seq: 7,
            now: 1_500_000,
            tick: Some(Tick {
                round: 3,
                start: 1_000_000,
                at: 99,
                open: 0x3f,
                occupied: 1,
                targets: vec![Spot { x: 0, y: 1 }, Spot { x: 8, y: -2 }],
            }),
            frames: vec![WireFrame { from: 12, at: 1_400_000, bytes: Bytes(vec![1, 2, 3]) }],
        })
    }

    fn output() -> ToWorld {
        ToWorld::Output(AgentOutput {
            seq: 7,
            send: vec![WireSend { bytes: Bytes(vec![9; 300]), ready: 1_600_000, copies: 2 }],
            motor: Some((Motor::Go(42), 1_700_000)),
            alarm: Some(2_000_000),
            listen: Listen::ALL,
            notes: vec![Note::Declared { robot: 4 }, Note::Unsure],
        })
    }

    fn hello(robot: u32) -> ToWorld {
        let id = crate::agreement::ScenarioId { name: "small".into(), sha3_256: "ab".repeat(32) };
        let policy = crate::policy::Policy::Repulsive;
        let params = crate::params::Params::default();
        let setup = crate::setup::RobotSetup {
            id: robot as crate::map::RobotId,
            lattice: crate::lattice::LatticeKind::Triangular,
            lo: [0.0, 0.0],
            hi: [20.0, 16.0],
            params,
            policy,
            situation: crate::params::Situation::Two,
            targets_total: 0,
            seed: 7,
            team: 13,
        };
        let agreement = Agreement::of("k", id, &setup);
        ToWorld::Hello(Box::new(Hello { agreement, robot, pid: 77, host: "h".into(), nonce: 5 }))
    }

    #[test]
    fn a_hello_starts_with_its_protocol_version() {
        // Its variant, then its agreement's first field: a later world
        // can read the version whatever follows it.
        let bytes = encode_to_world(&hello(3));
        let ((variant, version), _) = postcard::take_from_bytes::<(u32, u32)>(&bytes).unwrap();
        assert_eq!((variant, version), (0, crate::agreement::PROTOCOL_VERSION));
    }

    #[test]
    fn round_trip() {
        let w = wake();
        assert_eq!(decode_to_agent(&encode_to_agent(&w), &L), Ok(w));
        assert_eq!(decode_to_agent(&encode_to_agent(&ToAgent::End), &L), Ok(ToAgent::End));
        for m in [output(), hello(12)] {
            assert_eq!(decode_to_world(&encode_to_world(&m), &L), Ok(m));
        }
        for v in [Verdict { nonce: 9, refusal: None }, Verdict { nonce: 1, refusal: Some("seed".into()) }] {
            let m = ToAgent::Verdict(v);
            assert_eq!(decode_to_agent(&encode_to_agent(&m), &L), Ok(m));
        }
    }

    #[test]
    fn a_borrowed_wake_encodes_as_the_owned_one() {
        let ToAgent::Wake(w) = wake() else { unreachable!() };
        let r = WakeRef {
            seq: w.seq,
            now: w.now,
            tick: w.tick.as_ref(),
            frames: w
                .frames
                .iter()
                .map(|f| WireFrameRef { from: f.from, at: f.at, bytes: ByteSlice(&f.bytes.0) })
                .collect(),
        };
        let mut out = vec![1, 2, 3];
        encode_wake_into(&r, &mut out);
        assert_eq!(out, encode_to_agent(&ToAgent::Wake(w)));
    }

    #[test]
    fn bytes_are_one_byte_string() {
        let b = postcard::to_allocvec(&Bytes(vec![5; 200])).unwrap();
        assert_eq!(b.len(), 202, "varint length, then the bytes");
        assert_eq!(postcard::from_bytes::<Vec<u8>>(&b).unwrap(), vec![5; 200]);
    }

    #[test]
    fn out_of_range_is_refused() {
        let ToAgent::Wake(mut w) = wake() else { unreachable!() };
        w.frames[0].from = 13;
        assert!(matches!(decode_to_agent(&encode_to_agent(&ToAgent::Wake(w.clone())), &L), Err(WireError::Range(_))));
        w.frames[0].from = 0;
        w.tick.as_mut().unwrap().targets.extend((0..8).map(|x| Spot { x, y: 0 }));
        assert!(matches!(decode_to_agent(&encode_to_agent(&ToAgent::Wake(w)), &L), Err(WireError::Range(_))));
        let ToWorld::Output(mut o) = output() else { unreachable!() };
        o.motor = Some((Motor::Go(100), 0));
        assert!(matches!(decode_to_world(&encode_to_world(&ToWorld::Output(o.clone())), &L), Err(WireError::Range(_))));
        o.motor = None;
        o.send[0].bytes = Bytes(vec![0; 1001]);
        assert!(matches!(decode_to_world(&encode_to_world(&ToWorld::Output(o)), &L), Err(WireError::Range(_))));
        let ToWorld::Hello(mut h) = hello(13) else { unreachable!() };
        assert!(decode_to_world(&encode_to_world(&ToWorld::Hello(h.clone())), &L).is_ok(), "the world's to refuse");
        h.host = "h".repeat(MAX_TEXT + 1);
        assert!(matches!(decode_to_world(&encode_to_world(&ToWorld::Hello(h)), &L), Err(WireError::Range(_))));
        let long = ToAgent::Verdict(Verdict { nonce: 1, refusal: Some("x".repeat(MAX_TEXT + 1)) });
        assert!(decode_to_agent(&encode_to_agent(&long), &L).is_err());
        let mut long = encode_to_agent(&ToAgent::End);
        long.push(0);
        assert!(matches!(decode_to_agent(&long, &L), Err(WireError::Format(_))));
    }

    #[test]
    fn chunks_reassemble_and_stale_chunks_are_dropped() {
        let msg: Vec<u8> = (0..1000u32).map(|k| k as u8).collect();
        let mut parts = Vec::new();
        chunks(5, &msg, 100, |c| parts.push(c.to_vec()));
        assert_eq!(parts.len(), chunk_count(msg.len(), 100));
        assert!(parts.iter().all(|p| p.len() <= 100));
        let mut a = Assembler::new(10_000);
        // An older message's stray chunk first, then a fresh one cut short.
        let mut old = Vec::new();
        chunks(4, &msg, 100, |c| old.push(c.to_vec()));
        assert_eq!(a.push(&old[0]).unwrap(), None);
        assert_eq!(a.push(&parts[1]).unwrap(), None, "out of order: dropped");
        let mut done = None;
        for p in &parts {
            if let Some((s, b)) = a.push(p).unwrap() {
                done = Some((s, b.to_vec()));
            }
        }
        assert_eq!(done, Some((5, msg.clone())));
        let mut empty = Vec::new();
        chunks(9, &[], 100, |c| empty.push(c.to_vec()));
        assert_eq!(empty.len(), 1);
        assert_eq!(a.push(&empty[0]).unwrap().map(|(s, b)| (s, b.len())), Some((9, 0)));
        assert!(Assembler::new(10).push(&parts[0]).is_err(), "too long");
        assert!(a.push(&[1, 2, 3]).is_err());
    }

    proptest! {
        #[test]
        fn arbitrary_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
            let _ = decode_to_agent(&bytes, &L);
            let _ = decode_to_world(&bytes, &L);
            let mut a = Assembler::new(1000);
            let _ = a.push(&bytes);
            let _ = a.push(&bytes);
        }

        #[test]
        fn corrupted_messages_never_panic(flips in prop::collection::vec((0usize..4000, any::<u8>()), 1..8)) {
            let mut w = encode_to_agent(&wake());
            let mut o = encode_to_world(&output());
            for (i, b) in flips {
                let (nw, no) = (w.len(), o.len());
                w[i % nw] ^= b;
                o[i % no] ^= b;
            }
            if let Ok(ToAgent::Wake(w)) = decode_to_agent(&w, &L) {
                prop_assert!(w.frames.iter().all(|f| (f.from as usize) < L.robots || f.from == crate::protocol::CONTROLLER));
            }
            if let Ok(ToWorld::Output(o)) = decode_to_world(&o, &L) {
                prop_assert!(o.send.iter().all(|s| s.bytes.0.len() <= L.frame_bytes));
            }
        }
    }
}
