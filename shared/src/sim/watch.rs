//! What an observer outside the run may see of the world while it runs:
//! frames on the air, faults, slots closing, sensor readings. For logs and
//! live views (the command's `--mcap` and `--live`); the world only calls
//! these, never reads anything back, so a watched run is the same run.
//! The world-server records what it sees on a [`Tape`] that the
//! orchestrator reads as the run goes.

use std::io::Write;

use serde::{Deserialize, Serialize};

use super::{Fault, Tick, Time};
use crate::grid::VertexId;

/// A frame transmitted: by whom, who heard it and on whose links every copy was lost.
pub struct Sent<'a, P> {
    pub at: Time,
    pub from: usize,
    pub payload: &'a P,
    /// Robots within range that receive it (or will, after its latency).
    pub heard: &'a [u32],
    /// Robots within range that lost every copy.
    pub lost: &'a [u32],
}

/// An observer of one run. Every method is called in simulated-time order.
pub trait Watch<P> {
    /// A robot read its sensors at the start of a slot.
    fn ticked(&mut self, _robot: usize, _tick: &Tick) {}
    fn sent(&mut self, _frame: Sent<'_, P>) {}
    fn fault(&mut self, _at: Time, _fault: &Fault) {}
    /// Slot `round` closed at `end`: every robot's vertex after the moves,
    /// and the collisions the referee counted.
    fn closed(&mut self, _round: u32, _end: Time, _positions: &[VertexId], _collisions: u32) {}
}

/// What a [`Watch`] sees, owned, as the world-server records it for the
/// orchestrator ([`Tape`]): a frame travels as the bytes its sender wrote.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Event {
    Ticked { robot: u32, tick: Tick },
    Sent { at: Time, from: u32, frame: Vec<u8>, heard: Vec<u32>, lost: Vec<u32> },
    Fault { at: Time, fault: Fault },
    Closed { round: u32, end: Time, positions: Vec<VertexId>, collisions: u32 },
}

/// A [`Watch`] that writes every event to `out` as it happens: a 4-byte
/// little-endian length, then the postcard encoding of an [`Event`];
/// flushed as every slot closes, so a reader can follow the run.
pub struct Tape<W: Write> {
    out: W,
    buf: Vec<u8>,
    /// The first write that failed; nothing is written after it.
    pub failed: Option<std::io::Error>,
}

impl<W: Write> Tape<W> {
    pub fn new(out: W) -> Self {
        Tape { out, buf: Vec::new(), failed: None }
    }

    fn put(&mut self, ev: &Event) {
        if self.failed.is_some() {
            return;
        }
        self.buf.clear();
        self.buf.extend_from_slice(&[0; 4]);
        let res = postcard::to_extend(ev, std::mem::take(&mut self.buf)).map_err(std::io::Error::other).and_then(|b| {
            self.buf = b;
            let n = (self.buf.len() - 4) as u32;
            self.buf[..4].copy_from_slice(&n.to_le_bytes());
            self.out.write_all(&self.buf)
        });
        self.failed = res.err();
    }

    /// Flushes what is buffered; the first error of the whole tape.
    pub fn finish(mut self) -> std::io::Result<()> {
        match self.failed.take() {
            Some(e) => Err(e),
            None => self.out.flush(),
        }
    }
}

/// The next event of a tape in `bytes`: the event and its length, or
/// `None` if the tape does not hold a whole record yet.
pub fn read_event(bytes: &[u8]) -> Option<Result<(Event, usize), postcard::Error>> {
    let n = u32::from_le_bytes(bytes.get(..4)?.try_into().ok()?) as usize;
    let body = bytes.get(4..4 + n)?;
    Some(postcard::from_bytes(body).map(|e| (e, 4 + n)))
}

impl<W: Write, P: AsRef<[u8]>> Watch<P> for Tape<W> {
    fn ticked(&mut self, robot: usize, tick: &Tick) {
        self.put(&Event::Ticked { robot: robot as u32, tick: tick.clone() });
    }

    fn sent(&mut self, s: Sent<'_, P>) {
        let frame = s.payload.as_ref().to_vec();
        self.put(&Event::Sent { at: s.at, from: s.from as u32, frame, heard: s.heard.to_vec(), lost: s.lost.to_vec() });
    }

    fn fault(&mut self, at: Time, fault: &Fault) {
        self.put(&Event::Fault { at, fault: *fault });
    }

    fn closed(&mut self, round: u32, end: Time, positions: &[VertexId], collisions: u32) {
        self.put(&Event::Closed { round, end, positions: positions.to_vec(), collisions });
        if self.failed.is_none() {
            self.failed = self.out.flush().err();
        }
    }
}
