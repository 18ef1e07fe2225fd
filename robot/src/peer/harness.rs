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
    /// Frames its receive filter ([`Output::listen`]) held back, for its
    /// next wake-up.
    held: Vec<(RobotId, Time, Frame)>,
    /// Neighbouring vertices its sonar finds walled off.
    pub walls: Vec<VertexId>,
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
        Script {
            peer,
            t: cfg.timing,
            grid,
            at,
            now: 0,
            round: 0,
            out,
            motor: None,
            notes: vec![],
            sent: vec![],
            held: vec![],
            walls: vec![],
        }
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
        let (open, occupied) = (bits(&|v| !self.walls.contains(&v)), bits(&|v| occupied.contains(&v)));
        let tick = Tick { round, start, at: self.at, open, occupied, targets: vec![] };
        (self.round, self.motor, self.notes, self.sent) = (round, None, vec![], vec![]);
        self.wake(now, Some(&tick), frames);
    }

    /// Slot `round` begins at `start`, and the robot senses on time.
    pub fn slot(&mut self, round: u32, start: Time, occupied: &[VertexId]) {
        self.tick_at(start, round, start, occupied, &[]);
    }

    /// Frames `(from, arrived, frame)` reach it at `now`: they wake it if
    /// its receive filter lets one through, else they wait in its radio for
    /// its next wake-up, as on a real radio. Returns whether it woke.
    /// Alarms due before `now` ring first.
    pub fn hear(&mut self, now: Time, frames: &[(RobotId, Time, Frame)]) -> bool {
        self.until(now);
        let listen = self.out.listen;
        let woken = frames.iter().any(|(id, _, f)| listen.wakes(*id, Some(f.header())));
        self.held.extend(frames.iter().cloned());
        if woken {
            self.wake(now, None, &[]);
        }
        woken
    }

    /// One frame from `from`, arriving at `now`.
    pub fn deliver(&mut self, now: Time, from: RobotId, f: Frame) -> bool {
        self.hear(now, &[(from, now, f)])
    }

    /// Time passes to `now`, the robot woken at each of its alarms before.
    pub fn until(&mut self, now: Time) {
        while self.out.alarm.is_some_and(|a| a < now) {
            self.alarm();
        }
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
        let mut frames = frames.to_vec();
        frames.splice(0..0, std::mem::take(&mut self.held));
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

    /// Neighbour `from`'s map of this slot, from `at`, as it sensed at
    /// `sent`: its own vertex visited, and what it sensed around it.
    pub fn map(&self, from: RobotId, at: VertexId, sent: Time) -> Frame {
        // What it sensed there: every edge of the lattice open.
        let open = self.grid.neighbors(at)[..self.grid.degree()]
            .iter()
            .enumerate()
            .filter(|(_, &v)| v != NONE)
            .fold(0u8, |b, (d, _)| b | 1 << d);
        let mut map = Map::new(self.grid.len());
        map.record_sensing(self.grid, at, open);
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
        self.sent.iter().filter(|f| f.kind() == kind).collect()
    }

    pub fn halted(&self) -> bool {
        self.peer.halted()
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

/// Each rule of the protocol (the module docs of [`crate::peer`]), one
/// robot at (0, 0) at a time, its neighbours scripted.
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
        assert!(!h.deliver(start + late, 3, m), "committed, it does not listen: the late map waits");

        // Slot 2: read on waking, the late map widens its window to take in
        // a map that late (and a hop).
        let start = 20_000 * MS;
        h.slot(2, start, &[]);
        assert_eq!(h.out.alarm, Some(start + late + t.hop), "widened by the late map");
    }

    /// Slot 0 with neighbour 2 east of it (ahead in step 4's order), whose
    /// map arrives 30 ms in; the robot wakes at its window's end.
    fn behind_two() -> Script {
        let mut h = Script::new(0);
        let east = h.v(1, 0);
        h.slot(0, 0, &[east]);
        let m = h.map(2, east, 0);
        h.deliver(30 * MS, 2, m);
        assert_eq!(h.alarm(), h.t.exchange);
        assert_eq!(h.chose(), None, "it waits for 2's choice");
        h
    }

    /// Step 4: it chooses as soon as its higher-priority neighbour's choice
    /// arrives, avoiding it, and acknowledges that choice.
    #[test]
    fn it_chooses_once_the_higher_priority_choice_arrives() {
        let mut h = behind_two();
        let t = h.t;
        let (east, far_east) = (h.v(1, 0), h.v(2, 0));
        assert_eq!(h.out.alarm, Some(t.exchange + t.wait / 2), "its first `Wait`, before its deadline");
        let at = 200 * MS;
        let c = h.choice(2, east, far_east, &[]);
        assert!(h.deliver(at, 2, c), "a choice wakes it");
        let acks = h.sent("ack");
        assert!(matches!(acks[..], [Frame::Ack { ref acked, .. }] if acked == &[2]), "{acks:?}");
        let mine = h.chose().expect("chosen on 2's choice");
        assert_ne!(mine, far_east);
        assert_eq!(h.go(), Some((mine, at + t.choice)), "2's choice is compatible: it moves");
        assert!(h.notes.is_empty(), "{:?}", h.notes);
    }

    /// Step 4's timeout: the choice never comes, so `t_wait` past its
    /// window it suspects 2 for the slot and chooses as if 2 stood still;
    /// 2 then never answers, and it stays ("stay when unsure").
    #[test]
    fn a_silent_higher_priority_neighbour_is_given_up_after_t_wait() {
        let mut h = behind_two();
        let t = h.t;
        assert_eq!(h.alarm(), t.exchange + t.wait / 2);
        assert_eq!(h.sent("wait").len(), 1, "it tells those behind it that it still waits");
        assert_eq!(h.chose(), None);
        assert_eq!(h.alarm(), t.exchange + t.wait, "its deadline");
        assert_eq!(h.notes, vec![Note::TimedOut { robot: 2 }]);
        let mine = h.chose().expect("chosen without 2");
        assert_ne!(mine, h.v(1, 0), "2 is taken to stand still");
        assert_eq!(h.motor, None, "2 has not acknowledged");
        let deadline = t.exchange + t.wait + t.choice + t.wait;
        assert_eq!(h.alarm(), deadline, "it waits `t_wait` past its choice for 2's answer");
        assert_eq!(h.go(), Some((h.v(0, 0), deadline)), "no answer: it stays");
        assert_eq!(h.notes, vec![Note::TimedOut { robot: 2 }, Note::Unsure]);
    }

    /// `Wait` frames keep it waiting: after each, for as long again as the
    /// slot had lasted, `BEACON_GROWTH` times (at least `t_wait`).
    #[test]
    fn wait_frames_keep_it_waiting_longer_each_time() {
        let mut h = behind_two();
        let t = h.t;
        let patience = |said: Time| said + t.wait.max(BEACON_GROWTH * said);
        let said = t.exchange + t.wait / 2 + 10 * MS;
        let w = h.wait(2);
        assert!(!h.deliver(said, 2, w), "a `Wait` waits for its next wake-up");
        assert_eq!(h.sent("wait").len(), 1, "its own first `Wait` went out before");
        assert_eq!(h.alarm(), t.exchange + t.wait, "its first deadline");
        assert!(h.notes.is_empty() && h.chose().is_none(), "2 said it waits: it waits on");
        let mut at = h.alarm();
        while at < patience(said) {
            assert_eq!(h.chose(), None, "still waiting at {at}");
            at = h.alarm();
        }
        assert_eq!(at, patience(said));
        assert_eq!(h.notes, vec![Note::TimedOut { robot: 2 }], "given up {at} µs in");
        assert!(h.chose().is_some());

        // A second `Wait` before that patience ends extends it again.
        let mut h = behind_two();
        for said in [said, patience(said) - MS] {
            let w = h.wait(2);
            h.deliver(said, 2, w);
        }
        let last = patience(said) - MS;
        while h.chose().is_none() {
            assert!(h.now < patience(last), "given up too early, at {}", h.now);
            h.alarm();
        }
        assert_eq!(h.now, patience(last), "given up when its patience ran out");
        assert_eq!(h.notes, vec![Note::TimedOut { robot: 2 }]);
    }

    /// Slot 0 with neighbour 3 west of it (behind in step 4's order),
    /// whose map arrives 30 ms in: the robot chooses at its window's end
    /// and waits for 3's answer. Returns its choice.
    fn ahead_of_three() -> (Script, VertexId) {
        let mut h = Script::new(0);
        let west = h.v(-1, 0);
        h.slot(0, 0, &[west]);
        let m = h.map(3, west, 0);
        h.deliver(30 * MS, 3, m);
        assert_eq!(h.alarm(), h.t.exchange);
        let c = h.chose().expect("nobody ahead: it chooses");
        assert!(c != h.v(0, 0) && c != west, "{c}");
        assert_eq!(h.motor, None, "it waits for 3's answer");
        (h, c)
    }

    /// Step 6: it moves once every neighbour acknowledged its choice, or
    /// announced a choice that avoided it.
    #[test]
    fn it_moves_on_an_ack_or_on_a_choice_that_avoided_it() {
        let t = Timing::from_params(&Params::default());
        let (mut h, c) = ahead_of_three();
        let at = t.exchange + t.choice + 5 * MS;
        let a = h.ack(3, &[0], &[]);
        assert!(h.deliver(at, 3, a), "an ack to it wakes it");
        assert_eq!(h.go(), Some((c, at)));
        assert!(matches!(h.sent("commit")[..], [Frame::Commit { moving: true, .. }]), "it tells followers it leaves");

        // An ack to someone else is not one to it.
        let (mut h, _) = ahead_of_three();
        let a = h.ack(3, &[5], &[]);
        h.deliver(at, 3, a);
        assert_eq!(h.motor, None, "{:?}", h.sent);

        // 3's own choice, avoiding this robot's (3 lists it accounted).
        let (mut h, c) = ahead_of_three();
        let (west, far_west) = (h.v(-1, 0), h.v(-2, 0));
        let ch = h.choice(3, west, far_west, &[0]);
        assert!(h.deliver(at, 3, ch));
        assert_eq!(h.go(), Some((c, at)), "3 avoided it");
        let acks = h.sent("ack");
        assert!(
            matches!(acks[..], [Frame::Ack { ref acked, .. }] if acked == &[3]),
            "3's move is compatible: {acks:?}"
        );
    }

    /// Step 6's "stay when unsure": no answer within `t_wait` of its
    /// choice, or a refusal, and it stays.
    #[test]
    fn without_every_answer_it_stays() {
        let t = Timing::from_params(&Params::default());
        let (mut h, _) = ahead_of_three();
        let deadline = t.exchange + t.choice + t.wait;
        assert_eq!(h.alarm(), deadline);
        assert_eq!(h.go(), Some((h.v(0, 0), deadline)), "no answer: it stays");
        assert_eq!(h.notes, vec![Note::Unsure]);
        assert!(h.sent("commit").iter().all(|f| matches!(f, Frame::Commit { moving: false, .. })));

        // 3 refuses (it committed to a conflicting move) and leaves: both
        // cannot go, and it stays.
        let (mut h, _) = ahead_of_three();
        let at = t.exchange + t.choice + 5 * MS;
        let (no, leaves) = (h.ack(3, &[], &[0]), h.commit(3, true));
        h.deliver(at, 3, no);
        h.deliver(at + MS, 3, leaves);
        assert_eq!(h.go(), Some((h.v(0, 0), at + MS)), "refused: it stays");
        assert_eq!(h.notes, vec![Note::Unsure]);

        // A robot ahead of it refuses (it gave this one up and chose first):
        // it stays at once.
        let mut h = behind_two();
        let (east, far_east) = (h.v(1, 0), h.v(2, 0));
        h.until(t.exchange + t.wait + MS);
        let mine = h.chose().expect("2 given up");
        let (theirs, no) = (h.choice(2, east, far_east, &[]), h.ack(2, &[], &[0]));
        let late = t.exchange + t.wait + t.choice + 5 * MS;
        h.hear(late, &[(2, late, theirs), (2, late, no)]);
        assert_eq!(h.go(), Some((h.v(0, 0), late)), "refused by {mine}'s leader: it stays");
        assert!(h.notes.ends_with(&[Note::Unsure]), "{:?}", h.notes);
    }

    /// A refusal from a robot behind it that should have waited for its
    /// choice (it gave this one up): that robot stays, and this one moves
    /// once it knows so, its move safe beside the other standing still.
    #[test]
    fn a_refusal_from_behind_yields_to_its_staying() {
        let t = Timing::from_params(&Params::default());
        let (mut h, c) = ahead_of_three();
        let at = t.exchange + t.choice + 5 * MS;
        let (no, stays) = (h.ack(3, &[], &[0]), h.commit(3, false));
        h.deliver(at, 3, no);
        assert_eq!(h.motor, None, "refused: it waits for 3's commit");
        h.deliver(at + MS, 3, stays);
        assert_eq!(h.go(), Some((c, at + MS)), "3 stays: it moves");
    }

    /// Failure detection: a neighbour heard last slot and expected in range
    /// again, whose map does not come for `suspect_rounds` slots, is
    /// declared failed where it was last heard; heard again, it rejoins.
    #[test]
    fn a_neighbour_missing_for_suspect_rounds_slots_is_declared_and_rejoins_when_heard() {
        let params = Params { suspect_rounds: 2, ..Params::default() };
        let mut h = Script::with(0, Policy::Repulsive, Situation::Two, &params);
        let t = h.t;
        let (home, west) = (h.v(0, 0), h.v(-1, 0));
        let slot = 10_000 * MS;
        // Slot 0: 3 is heard (and answers).
        h.slot(0, 0, &[west]);
        let m = h.map(3, west, 0);
        h.deliver(30 * MS, 3, m);
        h.until(t.exchange + MS);
        let a = h.ack(3, &[0], &[]);
        h.deliver(t.exchange + t.choice, 3, a);
        assert!(h.go().is_some());
        let failed = |h: &Script| h.peer.robot().unwrap().map().is_failed(3);
        // Slots 1 and 2 (the robot put back home by the script, 3 in
        // range): no map from 3.
        for round in 1..=2 {
            h.at = home;
            h.slot(round, round as Time * slot, &[west]);
            h.until(round as Time * slot + t.exchange + MS);
            let declared = h.notes.contains(&Note::Declared { robot: 3 });
            assert_eq!(declared, round == 2, "slot {round}: {:?}", h.notes);
            assert_eq!(failed(&h), round == 2);
            h.until(round as Time * slot + t.decision_time());
        }
        // Slot 3: 3's map comes: it is alive.
        h.at = home;
        h.slot(3, 3 * slot, &[west]);
        let m = h.map(3, west, 3 * slot);
        h.deliver(3 * slot + 30 * MS, 3, m);
        h.until(3 * slot + t.exchange + MS);
        assert_eq!(h.notes, vec![Note::Rejoined { robot: 3 }]);
        assert!(!failed(&h), "revived");
    }

    /// The stop (rule 3, step 8): a robot that hears a stop flood halts,
    /// floods the stop once, and carries it in its maps from then on.
    #[test]
    fn a_heard_stop_halts_it_and_is_flooded_once() {
        let mut h = behind_two();
        let s = h.stop(3);
        assert!(h.deliver(500 * MS, 3, s), "a flood wakes it");
        assert!(h.halted());
        assert_eq!(h.motor, Some((Motor::Halt, 500 * MS)));
        assert_eq!(h.notes, vec![Note::Stopped { ends_search: true, relayed: true, exhausted: false }]);
        let floods = h.sent("flood");
        assert!(matches!(floods[..], [Frame::Flood { stop: true, .. }]), "flooded once: {floods:?}");
        assert_eq!(h.out.alarm, None, "halted, it sets no alarm");
        let s = h.stop(2);
        h.deliver(600 * MS, 2, s);
        assert_eq!(h.sent("flood").len(), 1, "not again");
        h.slot(1, 10_000 * MS, &[]);
        let maps = h.sent("map");
        assert!(matches!(maps[..], [Frame::Map { halted: true, stop: true, .. }]), "{maps:?}");
        assert_eq!(h.motor, None, "halted for good");
    }

    /// A robot that senses late, behind a neighbour that sensed on time:
    /// more than half a `t_wait` into the slot it stays at once; within
    /// half a `t_wait` it listens a window from its sensing and chooses.
    #[test]
    fn a_late_robot_stays_unless_within_half_a_t_wait() {
        let t = Timing::from_params(&Params::default());
        let late = |now: Time| {
            let mut h = Script::new(0);
            let west = h.v(-1, 0);
            // 3 sensed at the slot's start; its map waits in the radio.
            let m = h.map(3, west, 0);
            h.tick_at(now, 0, 0, &[west], &[(3, 30 * MS, m)]);
            h
        };
        let too_late = t.wait / 2 + MS;
        let h = late(too_late);
        assert_eq!(h.chose(), Some(h.v(0, 0)), "it announces it stays");
        assert_eq!(h.go(), Some((h.v(0, 0), too_late + t.choice)), "and stays, at once");

        let in_time = t.wait / 2 - MS;
        let mut h = late(in_time);
        assert_eq!(h.chose(), None);
        assert_eq!(h.alarm(), in_time + t.exchange, "it listens a window from its sensing");
        let c = h.chose().expect("then chooses");
        assert_ne!(c, h.v(0, 0));
        let a = h.ack(3, &[0], &[]);
        h.deliver(in_time + t.exchange + t.choice, 3, a);
        assert_eq!(h.go(), Some((c, in_time + t.exchange + t.choice)), "and moves on 3's ack");
    }

    /// Step 5: after it chose, it acknowledges a choice compatible with its
    /// own and refuses one that is not.
    #[test]
    fn after_choosing_it_refuses_a_conflicting_choice() {
        let t = Timing::from_params(&Params::default());
        let (mut h, c) = ahead_of_three();
        let (west, far_west) = (h.v(-1, 0), h.v(-2, 0));
        let at = t.exchange + t.choice;
        let clash = h.choice(3, west, c, &[]);
        h.deliver(at, 3, clash);
        let acks = h.sent("ack");
        assert!(matches!(acks[..], [Frame::Ack { ref acked, ref refused, .. }] if acked.is_empty() && refused == &[3]));
        let (mut h, _) = ahead_of_three();
        let away = h.choice(3, west, far_west, &[]);
        h.deliver(at, 3, away);
        let acks = h.sent("ack");
        assert!(matches!(acks[..], [Frame::Ack { ref acked, ref refused, .. }] if acked == &[3] && refused.is_empty()));
    }

    /// Step 6: following into a leader's vertex, it moves only once the
    /// leader committed to leaving; a leader that stays keeps it home.
    #[test]
    fn it_follows_into_a_vertex_only_once_its_robot_commits_to_leaving() {
        let t = Timing::from_params(&Params::default());
        for leaves in [true, false] {
            let mut h = Script::new(0);
            let (east, far_east) = (h.v(1, 0), h.v(2, 0));
            // Walls all round but to the east, where 2 stands.
            h.walls = [h.v(0, 1), h.v(0, -1), h.v(-1, 0)].to_vec();
            h.slot(0, 0, &[east]);
            let m = h.map(2, east, 0);
            h.deliver(30 * MS, 2, m);
            let ch = h.choice(2, east, far_east, &[]);
            h.deliver(t.exchange + 10 * MS, 2, ch);
            assert_eq!(h.chose(), Some(east), "it follows 2");
            assert_eq!(h.motor, None, "not before 2 commits");
            let at = t.exchange + t.choice + 20 * MS;
            let cm = h.commit(2, leaves);
            assert!(h.deliver(at, 2, cm), "its leader's commit wakes it");
            let go = if leaves { east } else { h.v(0, 0) };
            assert_eq!(h.go(), Some((go, at)), "2 leaves: {leaves}");
        }
    }

    /// Under a fixed slot, `Wait` frames keep it waiting only until it must
    /// choose for its choice to be acknowledged within the slot: two
    /// reactions and two trips (the latency it measured, a hop a copy)
    /// before the decisions end; and its command comes by then.
    #[test]
    fn under_a_fixed_slot_it_chooses_in_time_for_the_acks() {
        let params = Params { slot: SlotRule::Fixed, ..Params::default() };
        let mut h = Script::with(0, Policy::Repulsive, Situation::Two, &params);
        let t = h.t;
        let end = t.decision.expect("a fixed slot");
        let east = h.v(1, 0);
        h.slot(0, 0, &[east]);
        let latency = 30 * MS;
        let m = h.map(2, east, 0);
        h.deliver(latency, 2, m);
        // 2 keeps saying it waits: its patience would run past the slot.
        let said = t.exchange + t.wait / 2 + 10 * MS;
        let w = h.wait(2);
        h.deliver(said, 2, w);
        assert!(said + BEACON_GROWTH * said > end, "the script needs a patience past the slot");
        let cap = end - 2 * t.choice - 2 * (latency + t.hop * t.copies as Time);
        h.until(cap);
        assert_eq!(h.chose(), None, "waiting until {cap}");
        assert_eq!(h.alarm(), cap);
        assert_eq!(h.notes, vec![Note::TimedOut { robot: 2 }]);
        assert!(h.chose().is_some());
        h.until(end + 1);
        let (at, when) = h.go().expect("a command");
        assert_eq!((at, when), (h.v(0, 0), end), "2 never answered: it stays, by the slot's end");
    }
}
