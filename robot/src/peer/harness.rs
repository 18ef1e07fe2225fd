//! A scripted neighbourhood for one [`Peer`], with no world: a test says
//! when each slot starts, which frames reach the robot from which
//! neighbour and when, and wakes it at its own alarms; then reads what it
//! sent, its motor command and its notes. Test-only.

use super::*;
use crate::geometry::Point;
use crate::grid::NONE;
use crate::lattice::{Coord, Lattice, LatticeKind};

/// A millisecond, in [`Time`].
pub const MS: Time = 1000;

/// One robot and what it did since its slot began.
pub struct Script {
    pub peer: Peer<'static>,
    pub t: Timing,
    pub grid: &'static Grid,
    /// Where it stands: where its last `Go` took it.
    pub at: VertexId,
    pub now: Time,
    pub round: u32,
    /// The last wake-up's answer.
    pub out: Output<Frame>,
    /// Since the slot's tick: its motor command, notes and frames sent.
    pub motor: Option<(Motor, Time)>,
    pub notes: Vec<Note>,
    pub sent: Vec<Frame>,
}

impl Script {
    /// Robot `id` of the paper's rules (1),(2)&(3), situation 2, default
    /// parameters, at (0, 0) of a square lattice of side `a` = 1.
    pub fn new(id: RobotId) -> Self {
        Self::with(id, Policy::Repulsive, Situation::Two, &Params::default())
    }

    pub fn with(id: RobotId, policy: Policy, situation: Situation, params: &Params) -> Self {
        let lattice = Lattice::new(LatticeKind::Square, params.a);
        let grid: &'static Grid = Box::leak(Box::new(Grid::new(lattice, Point::new(-5.0, -5.0), Point::new(5.0, 5.0))));
        let robot = RobotConfig::new(id, policy, situation, 0, params.r_safe, 1);
        let cfg = PeerConfig::new(robot, params);
        let at = grid.id_of(Coord::new(0, 0)).expect("in the box");
        let (peer, out) = (Peer::new(grid, cfg), Output::default());
        Script { peer, t: cfg.timing, grid, at, now: 0, round: 0, out, motor: None, notes: vec![], sent: vec![] }
    }

    /// The vertex at lattice coordinates `(i, j)`: east is `i`, and in
    /// step 4's order a robot further east chooses first.
    pub fn v(&self, i: i32, j: i32) -> VertexId {
        self.grid.id_of(Coord::new(i, j)).expect("in the box")
    }

    /// Slot `round`, begun at `start`, sensed at `now` with robots on
    /// `occupied` next to it, and the frames waiting in its radio.
    pub fn tick_at(
        &mut self,
        now: Time,
        round: u32,
        start: Time,
        occupied: &[VertexId],
        frames: &[(RobotId, Time, Frame)],
    ) {
        let adj = &self.grid.neighbors(self.at)[..self.grid.degree()];
        let bits = |keep: &dyn Fn(VertexId) -> bool| {
            adj.iter().enumerate().filter(|(_, &v)| v != NONE && keep(v)).fold(0u8, |b, (d, _)| b | 1 << d)
        };
        let (open, occupied) = (bits(&|_| true), bits(&|v| occupied.contains(&v)));
        let tick = Tick { round, start, at: self.at, open, occupied, targets: vec![] };
        (self.round, self.motor, self.notes, self.sent) = (round, None, vec![], vec![]);
        self.wake(now, Some(&tick), frames);
    }

    /// Slot `round` begins at `start`, and the robot senses on time.
    pub fn slot(&mut self, round: u32, start: Time, occupied: &[VertexId]) {
        self.tick_at(start, round, start, occupied, &[]);
    }

    /// Frames `(from, arrived, frame)` wake it at `now`.
    pub fn hear(&mut self, now: Time, frames: &[(RobotId, Time, Frame)]) {
        self.wake(now, None, frames);
    }

    /// One frame from `from`, arriving (and waking it) at `now`.
    pub fn deliver(&mut self, now: Time, from: RobotId, f: Frame) {
        self.hear(now, &[(from, now, f)]);
    }

    /// Wakes it at its own alarm; returns when that was.
    pub fn alarm(&mut self) -> Time {
        let at = self.out.alarm.expect("an alarm is set");
        self.wake(at, None, &[]);
        at
    }

    fn wake(&mut self, now: Time, tick: Option<&Tick>, frames: &[(RobotId, Time, Frame)]) {
        assert!(now >= self.now, "time runs forward: {now} after {}", self.now);
        self.now = now;
        self.peer.wake(now, tick, frames.iter().map(|(id, at, f)| (*id, *at, f)), &mut self.out);
        if let Some(m) = self.out.motor {
            self.motor = Some(m);
            if let Motor::Go(v) = m.0 {
                self.at = v;
            }
        }
        self.notes.extend(self.out.notes.iter().copied());
        self.sent.extend(self.out.send.iter().map(|t| t.payload.clone()));
    }

    /// Neighbour `from`'s map of this slot, from `at`, as it sensed at `sent`.
    pub fn map(&self, from: RobotId, at: VertexId, sent: Time) -> Frame {
        let mut map = Map::new(self.grid.len());
        map.set_visited(at, true);
        map.set_known(at, true);
        Frame::Map { round: self.round, from, at, sent, halted: false, stop: false, map }
    }

    pub fn choice(&self, from: RobotId, at: VertexId, next: VertexId, accounted: &[RobotId]) -> Frame {
        Frame::Choice { round: self.round, from, at, next, accounted: accounted.to_vec() }
    }

    pub fn ack(&self, from: RobotId, acked: &[RobotId], refused: &[RobotId]) -> Frame {
        Frame::Ack { round: self.round, from, acked: acked.to_vec(), refused: refused.to_vec() }
    }

    pub fn commit(&self, from: RobotId, moving: bool) -> Frame {
        Frame::Commit { round: self.round, from, moving }
    }

    pub fn wait(&self, from: RobotId) -> Frame {
        Frame::Wait { round: self.round, from }
    }

    pub fn stop(&self, from: RobotId) -> Frame {
        Frame::Flood { round: self.round, from, targets: vec![], stop: true }
    }

    /// The frames of one kind it sent this slot.
    pub fn sent(&self, kind: &str) -> Vec<&Frame> {
        self.sent.iter().filter(|f| kind_of(f) == kind).collect()
    }

    /// The vertex its `Choice` of this slot announced.
    pub fn chose(&self) -> Option<VertexId> {
        self.sent.iter().find_map(|f| match f {
            Frame::Choice { next, .. } => Some(*next),
            _ => None,
        })
    }

    /// Where its motor command of this slot sends it, and when.
    pub fn go(&self) -> Option<(VertexId, Time)> {
        match self.motor {
            Some((Motor::Go(v), t)) => Some((v, t)),
            _ => None,
        }
    }
}

pub fn kind_of(f: &Frame) -> &'static str {
    match f {
        Frame::Map { .. } => "map",
        Frame::Choice { .. } => "choice",
        Frame::Ack { .. } => "ack",
        Frame::Commit { .. } => "commit",
        Frame::Flood { .. } => "flood",
        Frame::Wait { .. } => "wait",
    }
}

/// Each rule of the protocol (the module docs of [`crate::peer`]), one
/// robot at (0, 0) at a time, its neighbours scripted.
#[cfg(test)]
mod rules {
    use super::*;

    /// Step 1: a map inside the exchange window makes its sender a
    /// neighbour for the slot (the robot waits for its acknowledgement);
    /// a map after the window does not hold the robot's decision, and
    /// widens its window from the next slot on, to take such a map in.
    #[test]
    fn a_map_in_the_window_makes_a_neighbour_and_a_later_one_widens_the_next() {
        let mut h = Script::new(0);
        let t = h.t;
        let west = h.v(-1, 0);
        // Slot 0: neighbour 3's map arrives 30 ms into the 50 ms window.
        h.slot(0, 0, &[west]);
        assert_eq!(h.sent("map").len(), 1, "it broadcasts its map on sensing");
        assert_eq!(h.out.alarm, Some(t.exchange), "and sleeps to its window's end");
        let m = h.map(3, west, 0);
        h.deliver(30 * MS, 3, m);
        assert_eq!(h.alarm(), t.exchange);
        let c = h.chose().expect("nobody ahead of it: it chooses at its window's end");
        assert_ne!(c, h.v(0, 0));
        assert_eq!(h.motor, None, "3 is a neighbour: it waits for 3's answer");
        let ack = h.ack(3, &[0], &[]);
        h.deliver(t.exchange + t.choice + 10 * MS, 3, ack);
        assert_eq!(h.go(), Some((c, t.exchange + t.choice + 10 * MS)), "3 acked: it moves");

        // Slot 1: 3's map does not come by the window's end: it decides
        // without it. (3 is then also missed: it stays, unsure.)
        let start = 10_000 * MS;
        h.slot(1, start, &[]);
        assert_eq!(h.alarm(), start + t.exchange, "the window is not widened yet");
        assert!(h.chose().is_some(), "it chose at its window's end, 3 missing: {:?}", h.notes);
        // Having missed a map it expected, it listens a hop per copy past
        // its choice before it commits.
        assert_eq!(h.alarm(), start + t.exchange + t.choice + t.hop * t.copies as Time);
        assert!(h.motor.is_some());
        let late = 200 * MS;
        let m = h.map(3, west, start + late);
        h.deliver(start + late, 3, m);
        assert!(h.out.send.is_empty() && h.out.motor.is_none(), "the late map changes nothing this slot");

        // Slot 2: its window is widened to take in a map that late (and a hop).
        let start = 20_000 * MS;
        h.slot(2, start, &[]);
        assert_eq!(h.out.alarm, Some(start + late + t.hop), "widened by the late map");
    }
}
