//! A robot's interface to its body and its radio, the only things it
//! touches: the readings it gets at the start of a slot ([`Tick`]), the
//! frames it sends ([`Transmit`]) and what it tells its motors ([`Motor`])
//! and the experimenter ([`Note`]) in one [`Output`] per wake-up, and its
//! receive filter ([`Listen`]). The world (`gridswarm::sim`) and the
//! robot-agent's transport deliver and execute these; a robot never learns
//! more than they carry.

use serde::{Deserialize, Serialize};

use crate::grid::VertexId;
use crate::map::RobotId;
use crate::spot::Spot;

/// Simulated time in microseconds.
pub type Time = u64;

/// Seconds to [`Time`], rounded to the microsecond.
#[inline]
pub fn micros(seconds: f64) -> Time {
    (seconds * 1e6).round().max(0.0) as Time
}

/// [`Time`] to seconds.
#[inline]
pub fn seconds(t: Time) -> f64 {
    t as f64 / 1e6
}

/// A robot's sensor readings at the start of a slot, and the slot it is.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Tick {
    /// The slot, and when it started: the world's count under the
    /// adaptive slot rule; under the fixed rule a robot reads both off its
    /// own clock (`peer::Timing::slot_at`) and these only agree with it.
    pub round: u32,
    pub start: Time,
    /// Where the robot stands (odometry).
    pub at: VertexId,
    /// Adjacency slots whose edge is free of obstacles and boundary (sonar).
    pub open: u8,
    /// Adjacency slots whose vertex holds another robot (sonar).
    pub occupied: u8,
    /// Targets within `r_st`, each where it is (laser).
    pub targets: Vec<crate::spot::Spot>,
}

/// A frame to broadcast.
#[derive(Clone, Debug, PartialEq)]
pub struct Transmit<P> {
    pub payload: P,
    /// When the radio starts sending (after the robot's own computing).
    pub ready: Time,
    /// Transmissions of the same frame (1 + retries), `t_hop` apart.
    pub copies: u8,
}

/// A motor command for the current slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Motor {
    /// Go to this vertex at the end of the slot (its own vertex to stay).
    Go(VertexId),
    /// Stop searching: stay, and give no more motor commands until `Resume`.
    Halt,
    /// Search again after a halt (a robot cut off behind robots it held
    /// failed, one of which was heard again): it owes motor commands again.
    Resume,
}

/// What a robot records for the experimenter. The world keeps these for
/// the report and never acts on them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Note {
    /// It declared `robot` failed.
    Declared { robot: RobotId },
    /// It heard `robot`, once declared failed, alive again.
    Rejoined { robot: RobotId },
    /// It gave up waiting for `robot`'s choice this round.
    TimedOut { robot: RobotId },
    /// It stayed for want of acknowledgements.
    Unsure,
    /// It stopped searching; `ends_search` when its stop ends the search
    /// for everyone, `relayed` when it stopped on another robot's stop,
    /// `exhausted` when it ends the search knowing targets are unfound
    /// (situation 1, nothing left to visit: rule (4) where rule (3) failed).
    Stopped { ends_search: bool, relayed: bool, exhausted: bool },
    /// It dropped a frame of another round.
    Stale,
    /// It dropped a frame it could not decode or that lied about its sender.
    Malformed,
}

/// A robot's answer to one wake-up.
#[derive(Clone, Debug, PartialEq)]
pub struct Output<P> {
    pub send: Vec<Transmit<P>>,
    /// The motor command of the current slot, and when it was given.
    pub motor: Option<(Motor, Time)>,
    /// When to wake it next (replaces any earlier alarm; `None` cancels).
    pub alarm: Option<Time>,
    /// Which frames reaching it should wake it (the others wait for its
    /// next wake-up).
    pub listen: Listen,
    pub notes: Vec<Note>,
}

impl<P> Default for Output<P> {
    fn default() -> Self {
        Output { send: Vec::new(), motor: None, alarm: None, listen: Listen::OFF, notes: Vec::new() }
    }
}

impl<P> Output<P> {
    #[inline]
    pub fn clear(&mut self) {
        self.send.clear();
        self.motor = None;
        self.alarm = None;
        self.listen = Listen::OFF;
        self.notes.clear();
    }
}

/// What a radio can read of a frame without its payload: the header the
/// robot wrote at the frame's start when it transmitted (its kind and
/// round, and a tag of 64 bits the protocol fills, e.g. with its
/// addressees), or `None` when there is none to read. The world uses it
/// for nothing but a receiver's [`Listen`] filter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Header {
    pub kind: u8,
    pub round: u32,
    pub tag: u64,
}

/// A frame as the radio carries it: opaque, but with a header.
pub trait Framed {
    fn header(&self) -> Option<Header>;

    /// Whether the frame carries the stop that ends the search (step 8),
    /// as the human controller's receiver reads it: the world never
    /// looks (the controller's receiver does, `gridswarm::sim::CONTROLLER`).
    fn carries_stop(&self) -> bool;

    /// A flood's targets and stop (step 8), as the human controller's
    /// base station reads them to relay what is new to it
    /// (`crate::params::Broadcast::Controller`); `None` for any other frame.
    fn flood(&self) -> Option<(Vec<Spot>, bool)>;

    /// Whether it is a flood, from its kind alone (checked on every
    /// transmission, so cheaper than [`Framed::flood`]).
    fn is_flood(&self) -> bool;

    /// Its length on the wire in bytes, header included: what a robot
    /// process sends for it. Counted for the experimenter only.
    fn wire_len(&self) -> usize;
}

/// A robot's receive filter, its own setting (as a radio's address filter,
/// or a sleeping processor whose radio buffers frames): whether a frame
/// reaching it wakes it, or waits in its receive buffer for its next
/// wake-up. Frames of round `round` whose kind `k` is in `hold` wait,
/// unless their transmitter is among `except[k]` or their header's tag
/// shares a bit with `tags[k]`; every other frame wakes it. A robot sets it
/// so that a frame held back is one whose earlier reading would not have
/// changed anything it did (the protocol argues it, `crate::peer`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Listen {
    /// Whether frames may wake it at all (off: every frame waits).
    pub on: bool,
    pub round: u32,
    /// Frame kinds held, one bit a kind ([`Header::kind`], below 8).
    pub hold: u8,
    /// For each kind, the transmitters whose frames wake it all the same:
    /// bit `id % 64` per robot ([`Listen::bit`]), so two robots may share a
    /// bit and a frame may wake it needlessly, never the other way.
    pub except: [u64; 8],
    /// For each kind, the header tag bits that wake it all the same.
    pub tags: [u64; 8],
}

impl Listen {
    /// Nothing wakes it.
    pub const OFF: Listen = Listen { on: false, round: 0, hold: 0, except: [0; 8], tags: [0; 8] };
    /// Every frame wakes it.
    pub const ALL: Listen = Listen { on: true, round: 0, hold: 0, except: [0; 8], tags: [0; 8] };

    /// The bit of robot `id` in [`Listen::except`] (and in a tag of robots).
    #[inline]
    pub fn bit(id: RobotId) -> u64 {
        1 << (id % 64)
    }

    /// Whether a frame from `from` with header `h` wakes the robot.
    #[inline]
    pub fn wakes(&self, from: RobotId, h: Option<Header>) -> bool {
        if !self.on {
            return false;
        }
        let Some(h) = h else { return true };
        let k = h.kind as usize;
        let held = h.round == self.round && k < 8 && self.hold >> k & 1 == 1;
        !held || self.except[k] & Self::bit(from) != 0 || self.tags[k] & h.tag != 0
    }
}
