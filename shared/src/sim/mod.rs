//! The physical world as a discrete-event simulation, shared by both
//! engines: the clock, the radio medium, the robots' bodies (sensors,
//! motors, collisions) and the faults injected into them.
//!
//! The world never reads a radio frame (its payload type is opaque here)
//! beyond the header its sender wrote ([`Framed`]), never tells a robot
//! anything it did not sense or hear, and never decides for one. What it
//! does:
//!
//! - keeps the clock: slot `k` starts with every robot's sensor readings
//!   ([`Tick`]); a robot asks to be woken at a time ([`Output::alarm`]) and,
//!   if it [`Output::listen`]s, when a frame reaches it that its receive
//!   filter lets through ([`Listen`]); the radio holds the others in the
//!   robot's receive buffer and hands them over, in arrival order, at its
//!   next wake-up;
//! - carries frames ([`medium`]): to every robot within `r_c` of the sender,
//!   after the frame's latency, lost, delayed or duplicated as the run's
//!   radio settings say, every draw a pure function of the seed;
//! - executes motor commands at the end of the slot, all at once, and
//!   referees collisions; under the adaptive slot rule it closes a slot
//!   early once every robot that is physically running and still searching
//!   has given its motor command, under the fixed rule at the slot's
//!   fixed end, whoever has commanded ([`crate::params::SlotRule`]);
//! - injects faults at given simulated times ([`Fault`]).
//!
//! Time is simulated, in microseconds. Robots that are woken at the same
//! instant are woken together, and their outputs applied in robot order, so
//! a run is the same whether the robots are function calls
//! ([`crate::engine`]) or processes (`world-server`).

pub mod controller;
pub mod kernel;
pub mod medium;
#[cfg(test)]
mod same_search_tests;
pub mod schedule;
pub mod stats;
pub mod watch;

use serde::{Deserialize, Serialize};

use crate::map::RobotId;

pub use gridswarm_robot::io::{micros, seconds, Framed, Header, Listen, Motor, Note, Output, Tick, Time, Transmit};
pub use kernel::{Kernel, Settings};
pub use medium::Radio;
pub use stats::{FailureRecord, ProtocolStats, ENDINGS};

/// A frame that reached a robot: who transmitted it and when it arrived.
#[derive(Clone, Debug, PartialEq)]
pub struct Delivery<P> {
    pub from: RobotId,
    pub at: Time,
    pub payload: P,
}

/// One wake-up of one robot.
#[derive(Clone, Debug)]
pub struct WakeCall<P> {
    pub robot: usize,
    pub now: Time,
    /// The readings of a slot the robot has not seen yet.
    pub tick: Option<Tick>,
    /// Frames that reached it since it last woke, in arrival order.
    pub frames: Vec<Delivery<P>>,
}

/// The human controller's receiver as a node of the radio medium (step 8):
/// it hears the whole area (a base station), each frame on its own link
/// with the run's loss, delay and jitter, and reads nothing but whether a
/// frame carries the stop and what a flood tells ([`controller`]). Its
/// number on the medium's links.
pub const CONTROLLER: usize = u32::MAX as usize;

/// The robots as the world sees them: bodies it can wake.
pub trait Robots {
    /// What a frame is to the world: bytes, or a shared value in-process.
    type Payload: Clone;

    /// Wakes every robot of `calls` (distinct, in ascending order) at once.
    /// The calls stay the world's (it reuses their buffers); the robots may
    /// take the frames out. On return `outputs[k]` answers `calls[k]`;
    /// `None` when that robot turned out to be dead (its process gone).
    /// `outputs` is the vector of the last call, its entries' `send` and
    /// `notes` emptied by the world: refill it or overwrite the entries in
    /// place to reuse their buffers.
    fn wake(&mut self, calls: &mut [WakeCall<Self::Payload>], outputs: &mut Vec<Option<Output<Self::Payload>>>);

    /// The frames of a wake-up, read and done with, before the world drops
    /// them: an engine may take back buffers it lent (leave `frames` empty
    /// or not; the world clears it).
    fn reclaim(&mut self, _frames: &mut Vec<Delivery<Self::Payload>>) {}

    /// Slot `round` starts at simulated time `now` (for wall-clock measures).
    fn slot_started(&mut self, _round: u32, _now: Time) {}

    /// A scheduled fault happens now; the distributed engine pauses here
    /// while the fault is applied to the robot's process.
    fn inject(&mut self, _fault: &Fault, _now: Time) {}
}

/// What happens to a robot's body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum FaultKind {
    /// It dies: no more computing, no radio; its body stays where it is.
    Crash,
    /// It stops computing (frames reaching it wait) until a `Thaw`.
    Freeze,
    /// It computes again.
    Thaw,
    /// From now on it reacts this many microseconds late (0: on time again).
    Slow(Time),
}

impl FaultKind {
    pub fn name(self) -> &'static str {
        match self {
            FaultKind::Crash => "crash",
            FaultKind::Freeze => "freeze",
            FaultKind::Thaw => "thaw",
            FaultKind::Slow(_) => "slow",
        }
    }
}

/// A fault at `offset` after the start of slot `round`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Fault {
    pub robot: usize,
    pub round: u32,
    pub offset: Time,
    pub kind: FaultKind,
}
