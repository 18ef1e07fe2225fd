//! The robot's radio protocol: one robot's side of a slot, on top of the
//! decision core ([`crate::robot`]), as a state machine with no I/O. Both
//! engines drive it through [`Peer::wake`] with what the robot's sensors,
//! radio and clock deliver, and execute what it returns ([`Output`]).
//!
//! A slot, as one robot lives it:
//!
//! 1. **Exchange.** At the start of the slot it senses, broadcasts its map
//!    (and floods newly found targets, situation 1), and sleeps until the
//!    exchange window `t_exchange` ends (widened, once it has heard maps
//!    come later than that, `Peer::widen_for`). The robots whose maps it heard are
//!    its communication neighbours for the slot.
//! 2. **Failure detection.** A robot it heard last slot and expected in
//!    range again, whose map did not come, is declared failed after
//!    `suspect_rounds` such slots, standing where it was last heard; the
//!    declaration spreads with the maps. A robot heard again after being
//!    declared rejoins: the later round wins ([`crate::map::Map::revive`]).
//! 3. **Stop.** Rules (3)/(4). A robot whose knowledge leaves nothing
//!    undetected stops and floods the stop; one cut off behind failed robots
//!    stops on its own only, and searches again once one of them is heard.
//!    A robot that hears a stop stops and relays it. What the human
//!    controller's base station relayed (from [`CONTROLLER`]) it learns and
//!    does not pass on: the controller sent it to every robot.
//! 4. **Choice.** It waits for the choices of its higher-priority
//!    neighbours (step 4) until `t_wait` after the exchange, and on for
//!    those that say they still wait themselves (`Frame::Wait`, sent half
//!    a `t_wait` into the wait, then at [`BEACON_GROWTH`] times the time
//!    waited each time:
//!    long chains in dense teams); those still missing are suspected for
//!    the slot and treated as standing still (under a fixed slot, in time
//!    for its choice to be acknowledged within the slot). Then it chooses
//!    (step 5) and broadcasts the choice.
//! 5. **Acknowledgement.** A robot that receives a choice acknowledges it
//!    if it has not committed to a conflicting move (it will avoid it), and
//!    refuses it otherwise.
//! 6. **Commit.** It moves only once every neighbour it heard this slot has
//!    acknowledged its choice, or announced a choice it avoided or that is
//!    compatible with its own; and, following into a neighbour's vertex,
//!    once that neighbour has committed to leaving. A refusal, or no answer
//!    within `t_wait`, and it stays ("stay when unsure"). Its motor command
//!    goes to the world, and a `Commit` frame tells followers whether it
//!    really leaves.
//!
//! Why no two robots collide, and what loss does to that, is argued in
//! docs/safety.md (in brief: ARCHITECTURE.md, "Safety").

use crate::geometry::swept_min_distance;
use crate::grid::{Grid, VertexId};
use crate::io::{micros, Listen, Motor, Note, Output, Tick, Time, Transmit};
use crate::map::{Map, RobotId};
use crate::params::{Params, Situation, SlotRule};
use crate::policy::Policy;
use crate::protocol::{Frame, CONTROLLER};
use crate::robot::{Robot, RobotConfig, Sensing, Stop};
use crate::spot::{Spot, Spots};

mod filter;
#[cfg(test)]
mod harness;

/// The most a robot widens its exchange window, in exchange windows (with
/// the defaults 1 s: a map later than that reads as a dead neighbour).
pub const MAX_WIDEN: Time = 20;

/// For how many slots a robot stays after it heard a map later than its
/// widest window (a radio that late some of the time may be again).
pub const TOO_SLOW_SLOTS: u32 = 10;

/// How long a robot with robots next to it and no map ever heard stays,
/// in widest windows, before it reads its neighbours' silence as death.
pub const DEAF_WINDOWS: Time = 10;

/// How much longer a waiting robot's each next `Wait` comes, in time since
/// its window, and how many times the time a slot had lasted at a robot's
/// last `Wait` those behind it wait on for its next word ([`patience`]).
/// Each `Wait` then comes with the time since the last to spare, and a
/// dead robot deep in a chain is given up after at most this many times
/// the wait so far (at least `t_wait`). Larger, fewer frames, slower
/// detection; 4 keeps 10,000 robots under the paper's order within twice
/// the local order's frames a robot-round (BENCHMARKS.md).
pub const BEACON_GROWTH: Time = 4;

/// The protocol's clock settings, in simulated microseconds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timing {
    pub exchange: Time,
    /// One frame's latency, and the spacing of its copies.
    pub hop: Time,
    pub choice: Time,
    pub wait: Time,
    /// Transmissions of every frame: 1 + retries.
    pub copies: u8,
    pub suspect_rounds: u32,
    /// Under [`SlotRule::Fixed`], how long after a slot's start its
    /// decisions end ([`Timing::decision_time`]); `None` when the world
    /// closes the slot ([`SlotRule::Adaptive`]).
    pub decision: Option<Time>,
    /// One move, rotation and translation: a fixed slot's decisions and
    /// its move make its period.
    pub moving: Time,
}

impl Timing {
    pub fn from_params(p: &Params) -> Self {
        let mut t = Timing {
            exchange: micros(p.t_exchange),
            hop: micros(p.t_hop),
            choice: micros(p.t_choice),
            wait: micros(p.t_wait),
            copies: (1 + p.retries).min(u8::MAX as u32) as u8,
            suspect_rounds: p.suspect_rounds.max(1),
            decision: None,
            moving: micros(p.t_rot) + micros(p.t_trans),
        };
        if p.slot == SlotRule::Fixed {
            t.decision = Some(t.decision_time());
        }
        t
    }

    /// The length of a fixed slot's decisions, from the protocol's own
    /// bounds: the widest exchange window a robot may choose, a wait for
    /// higher-priority choices, the choice, a wait for acknowledgements,
    /// and a hop a copy for the commit to reach followers. A robot whose
    /// timeouts all run their course still gives its command in time; one
    /// later than that (slow, thawed) stays.
    /// Under the fixed rule, which slot its clock is in at `now`, and when
    /// that slot began: slot `k` starts at `k` periods.
    pub fn slot_at(&self, now: Time) -> Option<(u32, Time)> {
        let period = self.decision? + self.moving;
        let k = now / period;
        Some((k.min(u32::MAX as Time) as u32, k * period))
    }

    /// The widest exchange window a robot may choose (its own, widened by
    /// [`MAX_WIDEN`] windows).
    pub fn widest(&self) -> Time {
        self.exchange * (1 + MAX_WIDEN)
    }

    pub fn decision_time(&self) -> Time {
        self.widest() + 2 * self.wait + self.choice + (self.copies as Time + 1) * self.hop
    }
}

/// What a robot knows about itself before it starts: the grid frame comes
/// separately; this is its identity, its algorithm and its parameters.
#[derive(Clone, Copy, Debug)]
pub struct PeerConfig {
    pub robot: RobotConfig,
    pub timing: Timing,
    /// Radio range, to tell which neighbours it should hear again.
    pub r_c: f64,
}

impl PeerConfig {
    pub fn new(robot: RobotConfig, params: &Params) -> Self {
        PeerConfig { robot, timing: Timing::from_params(params), r_c: params.r_c }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    /// Before its first slot.
    Idle,
    Exchange,
    Choosing,
    /// Its motor command for the slot is given.
    Committed,
    /// It stopped searching for good.
    Halted,
}

/// Someone heard this slot.
#[derive(Clone, Copy, Debug)]
struct Heard {
    id: RobotId,
    at: VertexId,
    map: bool,
    /// When it sensed, from its map (`Time::MAX` before its map is heard).
    sent: Time,
    halted: bool,
    choice: Option<VertexId>,
    /// Its choice avoided this robot's.
    accounted_me: bool,
    acked_me: bool,
    refused_me: bool,
    commit: Option<bool>,
    /// When its last `Wait` frame of this slot arrived (0: none).
    waiting: Time,
}

/// A robot heard last slot and expected in range again.
#[derive(Clone, Copy, Debug)]
struct Expect {
    id: RobotId,
    at: VertexId,
    missed: u32,
    /// Its last map was sent after that slot's window: it senses late, so
    /// it hears this robot's map before it senses, and stays or moves only
    /// holding this robot's answer or choice ([`Peer::sits_out`]).
    late_sender: bool,
}

enum Acks {
    Complete,
    Waiting,
    Conflict,
}

pub struct Peer<'g> {
    grid: &'g Grid,
    cfg: PeerConfig,
    robot: Option<Robot<'g>>,
    round: u32,
    phase: Phase,
    window_end: Time,
    deadline: Time,
    /// When it next tells that it still waits (`Frame::Wait`).
    beacon_at: Time,
    choice_ready: Time,
    ack_deadline: Time,
    /// A stop that ends the search is known: carried in every map from now on.
    stop_known: bool,
    stop_flooded: bool,
    /// The stop came from the controller's relay, not from a robot.
    stop_relayed: bool,
    heard: Vec<Heard>,
    expected: Vec<Expect>,
    /// Targets this robot has flooded (found or relayed).
    flooded: Spots,
    acks: Vec<RobotId>,
    refusals: Vec<RobotId>,
    /// Adjacent vertices where the sonar finds a robot nobody heard, and
    /// for how many slots in a row.
    silent: Vec<(VertexId, u32)>,
    /// A robot it expected to hear this slot stayed silent.
    missed_any: bool,
    /// When this slot began, by the robot's clock.
    slot_start: Time,
    /// When its decisions must be in: a fixed slot's end by its clock
    /// (`Time::MAX` when the world closes the slot).
    slot_end: Time,
    /// How much it widened its exchange window, for maps it heard late.
    widen: Time,
    /// The least and greatest latency it measured on maps (µs): when they
    /// differ the radio jitters, and a map may come later than any it has
    /// measured.
    latency: (Time, Time),
    /// When it sensed this slot (its first wake-up of the slot).
    sensed_at: Time,
    /// It sensed after its exchange window's nominal end.
    sensed_late: bool,
    /// It sits the slot out ([`Peer::sits_out`]), or heard no map or too
    /// late a map to know who is near: it stays this slot.
    late: bool,
    /// This slot does not follow one it took part in (its first, or back
    /// from a freeze): it expects nobody, so silence tells it nothing.
    fresh: bool,
    /// Until when it listens in a fresh slot while it has heard no map.
    fresh_end: Time,
    /// The last slot in which it heard a map later than its widest window.
    too_slow: Option<u32>,
    /// It has heard another robot's map, of any slot.
    heard_any: bool,
    /// When it sensed its first slot.
    first_sensed: Time,
    /// It halted cut off: at every slot's start it checks whether it still
    /// is, and resumes if not (a robot it held failed was heard again, a
    /// silent body moved, a parked neighbour left).
    cut_off: bool,
    /// Its map of an earlier `Map` frame, with the frame's round, to copy
    /// its map into for the next.
    spare: Option<(Map, u32)>,
}

impl<'g> Peer<'g> {
    pub fn new(grid: &'g Grid, cfg: PeerConfig) -> Self {
        Peer {
            grid,
            cfg,
            robot: None,
            round: 0,
            phase: Phase::Idle,
            window_end: 0,
            deadline: 0,
            beacon_at: 0,
            choice_ready: 0,
            ack_deadline: 0,
            stop_known: false,
            stop_flooded: false,
            stop_relayed: false,
            heard: Vec::with_capacity(16),
            expected: Vec::new(),
            flooded: Spots::default(),
            acks: Vec::new(),
            refusals: Vec::new(),
            silent: Vec::new(),
            missed_any: false,
            sensed_at: 0,
            slot_start: 0,
            slot_end: Time::MAX,
            widen: 0,
            latency: (Time::MAX, 0),
            sensed_late: false,
            late: false,
            fresh: true,
            fresh_end: 0,
            too_slow: None,
            heard_any: false,
            first_sensed: 0,
            cut_off: false,
            spare: None,
        }
    }

    /// The map of its own `Map` frame of `round`, back from every receiver
    /// (unchanged), so that sending its map every slot need not allocate
    /// (the in-process engine gives them back) and its next copy need only
    /// take what changed since the last.
    pub fn give_back_map(&mut self, map: Map, round: u32) {
        self.spare = Some((map, round));
    }

    pub fn id(&self) -> RobotId {
        self.cfg.robot.id
    }

    /// The decision core, once the first slot started.
    pub fn robot(&self) -> Option<&Robot<'g>> {
        self.robot.as_ref()
    }

    pub fn halted(&self) -> bool {
        self.phase == Phase::Halted
    }

    /// One wake-up: the readings of a new slot (if any), the frames heard
    /// since the last wake-up (with their transmitters and when each
    /// arrived), and the time.
    pub fn wake<'f>(
        &mut self,
        now: Time,
        tick: Option<&Tick>,
        frames: impl IntoIterator<Item = (RobotId, Time, &'f Frame), IntoIter: Clone>,
        out: &mut Output<Frame>,
    ) {
        out.clear();
        match tick {
            Some(t) => {
                // Under the fixed rule the robot's own clock says which
                // slot this is; the world's idealized barrier says so otherwise.
                let (round, start) = self.cfg.timing.slot_at(now).unwrap_or((t.round, t.start));
                // Frames of the slot that ended (heard after this robot
                // committed) first: they say where its neighbours went.
                let frames = frames.into_iter();
                for (from, at, f) in frames.clone().filter(|(_, _, f)| f.round() < round) {
                    self.on_frame(now, from, at, f, out);
                }
                self.start_slot(now, t, (round, start), out);
                for (from, at, f) in frames.filter(|(_, _, f)| f.round() >= round) {
                    self.on_frame(now, from, at, f, out);
                }
            }
            None => {
                for (from, at, f) in frames {
                    self.on_frame(now, from, at, f, out);
                }
            }
        }
        self.send_acks(now, out);
        // Behind another robot it stays whatever else it hears: it need
        // not listen on (a slow robot would pay another reaction for it).
        if self.phase == Phase::Exchange && (now >= self.exchange_end(now) || self.sits_out()) {
            self.end_exchange(now, out);
        }
        if self.phase == Phase::Choosing {
            self.progress(now, out);
        }
        if self.phase == Phase::Choosing && !self.has_chosen() {
            self.beacon(now, out);
        }
        let alarm = match self.phase {
            Phase::Exchange => Some(self.exchange_end(now)),
            Phase::Choosing if self.has_chosen() => match self.listen_until() {
                l if l > now => Some(self.ack_deadline.min(l)),
                _ => Some(self.ack_deadline),
            },
            Phase::Choosing => Some(self.deadline.min(self.beacon_at)),
            _ => None,
        };
        out.alarm = alarm;
        out.listen = if self.phase == Phase::Choosing { self.filter() } else { Listen::OFF };
    }

    fn send(&self, out: &mut Output<Frame>, frame: Frame, ready: Time) {
        out.send.push(Transmit { payload: frame, ready, copies: self.cfg.timing.copies });
    }

    /// When its exchange ends: its window's end, or, in a fresh slot with
    /// no map heard by then, the widest window's. (Maps wait for it while it
    /// exchanges: it learns whether any came only at its window's end.)
    fn exchange_end(&self, now: Time) -> Time {
        if now < self.window_end || self.heard.iter().any(|h| h.map) {
            self.window_end
        } else {
            self.fresh_end
        }
    }

    /// Until when it listens after its choice before it may commit.
    ///
    /// On a radio it has seen jitter, until its choice is ready (its motors
    /// could not start sooner), but no longer than a choice time past its
    /// window: a map later than its window by up to that much (jitter past
    /// the latencies it has measured), from a robot it never heard, still
    /// reaches it in time to wait for that robot's answer instead of
    /// stepping blind. A robot woken past that point (slow) has heard it
    /// already, and pays no further reaction. On a radio of steady latency
    /// its widened window takes in every map, and it commits at once (a
    /// wake-up less per slot: a third of a lone robot's).
    ///
    /// A robot that missed a map it expected this slot (a sign of loss, or
    /// of a failure) listens on for the copies' hops: with every expected
    /// map in, a robot it did not hear is one it could not have heard.
    fn listen_until(&self) -> Time {
        let t = self.cfg.timing;
        if self.missed_any {
            self.choice_ready + t.hop * t.copies as Time
        } else if self.latency.0 < self.latency.1 {
            self.choice_ready.min(self.window_end + t.choice)
        } else {
            0
        }
    }

    fn has_chosen(&self) -> bool {
        self.robot.as_ref().is_some_and(|r| r.choice().is_some())
    }

    fn heard_mut(&mut self, id: RobotId, at: VertexId) -> &mut Heard {
        let k = match self.heard.binary_search_by_key(&id, |h| h.id) {
            Ok(k) => k,
            Err(k) => {
                let h = Heard {
                    id,
                    at,
                    map: false,
                    sent: Time::MAX,
                    halted: false,
                    choice: None,
                    accounted_me: false,
                    acked_me: false,
                    refused_me: false,
                    commit: None,
                    waiting: 0,
                };
                self.heard.insert(k, h);
                k
            }
        };
        &mut self.heard[k]
    }

    /// Slot `round`, started at `start`, with the readings of `tick`.
    fn start_slot(&mut self, now: Time, tick: &Tick, (round, start): (u32, Time), out: &mut Output<Frame>) {
        if self.phase != Phase::Idle && round <= self.round {
            return;
        }
        let (grid, rcfg) = (self.grid, self.cfg.robot);
        if self.robot.is_none() {
            self.first_sensed = now;
        }
        let robot = self.robot.get_or_insert_with(|| Robot::new(grid, rcfg, tick.at));
        robot.moved(tick.at);
        let consecutive = self.phase != Phase::Idle && round == self.round + 1;
        self.expect(tick.at, consecutive);
        self.fresh = !consecutive;
        self.round = round;
        self.sensed_at = now;
        self.heard.clear();
        self.acks.clear();
        self.refusals.clear();
        let robot = self.robot.as_mut().expect("made above");
        robot.sense(round, &Sensing { open: tick.open, occupied: tick.occupied, targets: &tick.targets });
        let me = robot.id();
        let mut halted = self.phase == Phase::Halted;
        if halted && self.cut_off && !self.stop_known && robot.stop_rule() != Some(Stop::CutOff) {
            // Suspicion is never for good: what cut it off is gone. It
            // searches again (and if its map is complete, its exchange
            // ends the search like anyone's).
            halted = false;
            self.cut_off = false;
            out.motor = Some((Motor::Resume, now));
        }
        // Woken after the exchange (frozen, or slow): it still sends its map
        // (those that hear it wait for its answer like any other's), and
        // listens a whole window from now, so that it hears the map of
        // every other late robot that sensed before it: of two late robots
        // only the earlier may move (`late`, set at the end of its exchange).
        let nominal_end = start + self.cfg.timing.exchange + self.widen;
        self.sensed_late = now > nominal_end;
        let window_end = if self.sensed_late { now + self.cfg.timing.exchange + self.widen } else { nominal_end };
        self.slot_start = start;
        self.slot_end = self.cfg.timing.decision.map_or(Time::MAX, |d| start + d);
        let map = robot.map_mut().send_copy(round, self.spare.take());
        let map = Frame::Map { round, from: me, at: tick.at, sent: now, halted, stop: self.stop_known, map };
        self.send(out, map, now);
        if self.cfg.robot.situation == Situation::One {
            let new: Vec<Spot> = tick.targets.iter().copied().filter(|&t| self.flooded.insert(t)).collect();
            if !new.is_empty() {
                self.send(out, Frame::Flood { round, from: me, targets: new, stop: false }, now);
            }
        }
        if !halted {
            self.window_end = window_end;
            // Fresh, a robot that hears no map by its window's end cannot
            // tell an empty neighbourhood from a radio slower than its
            // window (it has measured none yet): it listens on to the
            // widest window before it decides alone. RU's robots too: they
            // choose on the maps they hear as well, and a lone robot is
            // then the same run, to the microsecond, under RU and rules
            // (1)&(3) and (1),(2)&(3), as the claims assume (issue 36, item 6).
            let widest = self.cfg.timing.widest();
            let listen_from = if self.sensed_late { now } else { start };
            self.fresh_end = if self.fresh { window_end.max(listen_from + widest) } else { window_end };
            self.phase = Phase::Exchange;
        }
    }

    /// Robots heard last slot that should be heard again: in range whether
    /// or not they moved as they announced. Robots still missing from
    /// earlier slots, not yet declared, stay expected.
    fn expect(&mut self, pos: VertexId, consecutive: bool) {
        // RU robots wait on nobody and announce no choice: there is no
        // failure to detect, and nowhere to expect anyone.
        if !consecutive || self.cfg.robot.policy == Policy::Ru {
            self.expected.clear();
            return;
        }
        let grid = self.grid;
        let here = grid.position(pos);
        let r_c2 = self.cfg.r_c * self.cfg.r_c;
        let in_range = |v: VertexId| (grid.position(v) - here).norm_squared() <= r_c2;
        let mut next: Vec<Expect> = Vec::new();
        for h in &self.heard {
            if !(h.map || h.choice.is_some()) {
                continue;
            }
            let at = match (h.choice, h.commit) {
                (Some(c), Some(true)) => c,
                _ => h.at,
            };
            let maybe = match (h.choice, h.commit) {
                (Some(c), None) if c != h.at => Some(c),
                _ => None,
            };
            if in_range(at) && maybe.is_none_or(in_range) {
                let late_sender = h.map && h.sent > self.slot_start + self.cfg.timing.exchange + self.widen;
                next.push(Expect { id: h.id, at, missed: 0, late_sender });
            }
        }
        for e in &self.expected {
            let declared = self.robot.as_ref().is_some_and(|r| r.map().is_failed(e.id));
            if e.missed > 0 && !declared && in_range(e.at) && !next.iter().any(|n| n.id == e.id) {
                next.push(*e);
            }
        }
        self.expected = next;
    }

    fn on_frame(&mut self, now: Time, from: RobotId, arrived: Time, f: &Frame, out: &mut Output<Frame>) {
        if from == CONTROLLER {
            self.on_relay(f, out);
            return;
        }
        if f.from() != from {
            out.notes.push(Note::Malformed);
            return;
        }
        if self.robot.is_none() || from == self.id() {
            return;
        }
        if let Frame::Flood { targets, stop, .. } = f {
            self.on_flood(now, targets, *stop, out);
            return;
        }
        if let Frame::Map { round, sent, .. } = f {
            self.widen_for(*round, arrived, *sent);
            self.heard_any = true;
        }
        if f.round() != self.round {
            out.notes.push(Note::Stale);
            return;
        }
        let me = self.id();
        match f {
            Frame::Map { at, sent, halted, stop, map, .. } => {
                let robot = self.robot.as_mut().expect("checked");
                let was_failed = robot.map().is_failed(from);
                if !robot.receive_map(from, *at, map, *halted) {
                    return;
                }
                if was_failed {
                    // Heard, so alive: the core has revived it already.
                    out.notes.push(Note::Rejoined { robot: from });
                }
                let h = self.heard_mut(from, *at);
                h.map = true;
                h.sent = *sent;
                h.at = *at;
                h.halted |= *halted;
                if *stop {
                    self.stop_known = true;
                }
            }
            Frame::Choice { at, next, accounted, .. } => {
                let robot = self.robot.as_mut().expect("checked");
                if robot.map().is_failed(from) {
                    // A choice is a sign of life: it must be avoided like any
                    // other (the core revives it on hearing it).
                    out.notes.push(Note::Rejoined { robot: from });
                }
                if !robot.receive_choice(from, *at, *next) {
                    return;
                }
                let h = self.heard_mut(from, *at);
                h.choice = Some(*next);
                h.accounted_me = accounted.contains(&me);
                self.answer_choice(from, *at, *next);
            }
            Frame::Ack { acked, refused, .. } => {
                if let Ok(k) = self.heard.binary_search_by_key(&from, |h| h.id) {
                    self.heard[k].acked_me |= acked.contains(&me);
                    self.heard[k].refused_me |= refused.contains(&me);
                }
            }
            Frame::Commit { moving, .. } => {
                if let Ok(k) = self.heard.binary_search_by_key(&from, |h| h.id) {
                    self.heard[k].commit = Some(*moving);
                }
            }
            Frame::Wait { .. } => {
                if let Ok(k) = self.heard.binary_search_by_key(&from, |h| h.id) {
                    self.heard[k].waiting = self.heard[k].waiting.max(arrived);
                }
            }
            Frame::Flood { .. } => unreachable!("handled above"),
        }
    }

    /// A map of `round` sent (its sender sensed) at `sent` that arrived at
    /// `arrived`. A map later than the window reads as a dead neighbour,
    /// whether the radio took long (`arrived - sent`, measured on maps of
    /// any slot) or its sender sensed late (a map of this slot arriving
    /// long after the slot began). The robot widens its own window to take
    /// such a map in time from the next slot on, up to [`MAX_WIDEN`]
    /// exchange windows; it never narrows it again.
    fn widen_for(&mut self, round: u32, arrived: Time, sent: Time) {
        let t = self.cfg.timing;
        let latency = arrived.saturating_sub(sent);
        self.latency = (self.latency.0.min(latency), self.latency.1.max(latency));
        let into_slot = if round == self.round { arrived.saturating_sub(self.slot_start) } else { 0 };
        let needed = (latency.max(into_slot) + t.hop).saturating_sub(t.exchange);
        if (latency + t.hop).saturating_sub(t.exchange) > MAX_WIDEN * t.exchange {
            // Past the widest window maps it needs miss every window, and a
            // robot it cannot hear in time may step where it steps.
            self.too_slow = Some(self.round);
        }
        self.widen = self.widen.max(needed.min(MAX_WIDEN * t.exchange));
    }

    /// Step 5's acknowledgement: before choosing, every choice heard is one
    /// this robot will avoid; after, only one compatible with its own.
    fn answer_choice(&mut self, from: RobotId, at: VertexId, next: VertexId) {
        if !matches!(self.phase, Phase::Exchange | Phase::Choosing) {
            return;
        }
        let robot = self.robot.as_ref().expect("checked");
        match robot.choice() {
            None => self.acks.push(from),
            Some(c) if compatible(robot, robot.position(), c, at, next) => self.acks.push(from),
            Some(_) => self.refusals.push(from),
        }
    }

    fn send_acks(&mut self, now: Time, out: &mut Output<Frame>) {
        if self.acks.is_empty() && self.refusals.is_empty() {
            return;
        }
        let acked = std::mem::take(&mut self.acks);
        let refused = std::mem::take(&mut self.refusals);
        self.send(out, Frame::Ack { round: self.round, from: self.id(), acked, refused }, now);
    }

    /// A flood the controller relayed: learnt, whatever the round, and not
    /// passed on, so the robots' own flood within `r_c` is what it is
    /// under `Broadcast::Flood` (a flood heard from a robot later is
    /// passed on as news). Only floods come that way.
    fn on_relay(&mut self, f: &Frame, out: &mut Output<Frame>) {
        let Frame::Flood { targets, stop, .. } = f else {
            out.notes.push(Note::Malformed);
            return;
        };
        let Some(robot) = self.robot.as_mut() else { return };
        robot.learn_targets(targets);
        if *stop && !self.stop_known {
            self.stop_known = true;
            self.stop_relayed = true;
        }
    }

    /// A flood: targets and the stop, relayed once, whatever the round.
    fn on_flood(&mut self, now: Time, targets: &[Spot], stop: bool, out: &mut Output<Frame>) {
        let robot = self.robot.as_mut().expect("checked");
        let new: Vec<Spot> = targets.iter().copied().filter(|&t| self.flooded.insert(t)).collect();
        robot.learn_targets(&new);
        let new_stop = stop && !self.stop_flooded;
        if new_stop {
            self.stop_known = true;
            self.stop_flooded = true;
        }
        if !new.is_empty() || new_stop {
            let f = Frame::Flood { round: self.round, from: self.id(), targets: new, stop: new_stop };
            self.send(out, f, now);
        }
    }

    fn end_exchange(&mut self, now: Time, out: &mut Output<Frame>) {
        let round = self.round;
        let robot = self.robot.as_mut().expect("started");
        let mut expected = std::mem::take(&mut self.expected);
        for e in expected.iter_mut() {
            let heard = self.heard.binary_search_by_key(&e.id, |h| h.id).is_ok_and(|k| self.heard[k].map);
            if heard {
                e.missed = 0;
                continue;
            }
            e.missed += 1;
            if e.missed >= self.cfg.timing.suspect_rounds {
                // Its map may hold the failure already, declared by another
                // robot (which wins a tie with the round this robot last
                // heard it): it is noted as its own finding all the same.
                if !robot.map().is_failed(e.id) {
                    robot.declare_failed(e.id, e.at, round);
                }
                out.notes.push(Note::Declared { robot: e.id });
            }
        }
        self.missed_any = expected.iter().any(|e| e.missed > 0);
        self.expected = expected;
        self.find_bodies();
        if self.stop_known {
            self.halt(now, None, out);
            return;
        }
        let robot = self.robot.as_mut().expect("started");
        if let Some(stop) = robot.stop_rule() {
            self.halt(now, Some(stop), out);
            return;
        }
        self.phase = Phase::Choosing;
        self.deadline = self.window_end + self.cfg.timing.wait;
        self.beacon_at = self.window_end + self.first_beacon();
        // It sensed after its exchange window, among searching neighbours
        // that sensed before it, and too late to choose with them: it sits
        // the slot out (`sits_out`). The earliest of late robots goes on,
        // and so does a late robot alone: its lateness concerns nobody, and
        // a robot slow for good must still search.
        self.late = self.sits_out();
        // Robots next to it, and not one map heard since it started: the
        // radio is slower than any window (or they all died at once). It
        // stays, until that silence has lasted `DEAF_WINDOWS` widest windows.
        let widest = self.cfg.timing.widest();
        let deaf = !self.heard_any && !self.silent.is_empty() && now < self.first_sensed + DEAF_WINDOWS * widest;
        if deaf && self.cfg.robot.policy.collision_free() {
            self.late = true;
            out.notes.push(Note::Unsure);
        }
        // The radio was slower than the widest window in one of the last
        // `TOO_SLOW_SLOTS` slots: it may not have heard who is near, and it
        // stays (degrading to stays, not to collisions).
        if self.too_slow.is_some_and(|r| r + TOO_SLOW_SLOTS > round) && self.cfg.robot.policy.collision_free() {
            self.late = true;
            out.notes.push(Note::Unsure);
        }
    }

    /// It sensed late, and heard a searching robot that sensed before it
    /// (or one heard without its map).
    fn behind(&self) -> bool {
        let me = (self.sensed_at, self.id());
        self.sensed_late && self.heard.iter().any(|h| !h.halted && (!h.map || (h.sent, h.id) < me))
    }

    /// Behind, and too late to choose: it stays this slot, deciding in the
    /// wake-up that finds it late. Their choices may be out already, and
    /// those that closed their windows before its map came have written it
    /// off for the slot. A robot that sensed within half a `t_wait` of the
    /// slot's start still chooses, after listening a whole window from its
    /// sensing (so it hears every late robot that sensed before it): it
    /// hears every map sent on time before it decides, and like any robot
    /// it moves only holding each neighbour's acknowledgement or a choice
    /// compatible with its own, so a neighbour that wrote it off is safe
    /// from it; those that waited for it still do when it answers. Sitting
    /// out every slot instead, a robot slow for good never moved while a
    /// searching robot was within its range, and robots whose way lay past
    /// it waited by it for ever (issue 37).
    fn sits_out(&self) -> bool {
        let soon = self.sensed_at < self.slot_start + self.cfg.timing.wait / 2;
        self.behind() && !(soon && self.cfg.robot.policy.collision_free())
    }

    /// The sonar's occupied neighbours that no map of this slot accounts
    /// for are silent robots; after `suspect_rounds` slots in a row they
    /// block their vertex as bodies (robots this one never heard fail).
    fn find_bodies(&mut self) {
        let robot = self.robot.as_mut().expect("started");
        let (grid, pos, occupied) = (self.grid, robot.position(), robot.occupied());
        let mut silent = Vec::new();
        for (d, &v) in grid.neighbors(pos)[..grid.degree()].iter().enumerate() {
            if v == crate::grid::NONE {
                continue;
            }
            if occupied >> d & 1 == 0 {
                robot.clear_body(v);
                continue;
            }
            let explained =
                self.heard.iter().any(|h| h.map && h.at == v) || robot.map().failed_now().any(|(_, at)| at == v);
            if explained {
                continue;
            }
            let seen = 1 + self.silent.iter().find(|s| s.0 == v).map_or(0, |s| s.1);
            if seen >= self.cfg.timing.suspect_rounds {
                robot.mark_body(v);
            }
            silent.push((v, seen));
        }
        self.silent = silent;
    }

    /// Stops searching: on its own rule `stop`, or (`None`) on a stop it
    /// heard, which it relays. For good, but for a cut-off (see `cut_off`).
    fn halt(&mut self, now: Time, stop: Option<Stop>, out: &mut Output<Frame>) {
        let ends_search = stop.is_none_or(Stop::ends_search);
        let relayed = stop.is_none();
        let exhausted = stop.is_some_and(|s| s.exhausted(self.cfg.robot.situation));
        let robot = self.robot.as_ref().expect("started");
        if let Some(c) = robot.choice() {
            if c != robot.position() {
                self.send(out, Frame::Commit { round: self.round, from: self.id(), moving: false }, now);
            }
        }
        self.phase = Phase::Halted;
        self.cut_off = !ends_search;
        out.motor = Some((Motor::Halt, now));
        out.notes.push(Note::Stopped { ends_search, relayed, exhausted });
        if ends_search {
            self.stop_known = true;
            // A stop the controller relayed reached everyone already.
            if !self.stop_flooded && !(relayed && self.stop_relayed) {
                self.stop_flooded = true;
                self.send(out, Frame::Flood { round: self.round, from: self.id(), targets: vec![], stop: true }, now);
            }
        }
    }

    fn progress(&mut self, now: Time, out: &mut Output<Frame>) {
        if self.stop_known {
            self.halt(now, None, out);
            return;
        }
        let round = self.round;
        let me = self.id();
        let timing = self.cfg.timing;
        let robot = self.robot.as_mut().expect("started");
        if robot.choice().is_none() {
            // Alone it needs nobody's answer and commits at once; a robot
            // it expected but missed may answer late, and waiting for that
            // would take another wake-up, far past the slot's limit.
            let alone = !self.missed_any && self.heard.iter().all(|h| h.halted);
            if self.late || (now >= self.deadline + timing.wait / 2 && !alone) {
                // Woken far past the time it asked for (slow, or thawed):
                // those that waited on it chose without it long ago, and a
                // choice now could not gather its acknowledgements within
                // the slot. It stays, which is safe whatever the others do
                // (nobody enters a vertex whose robot did not announce
                // leaving), and tells them so. Alone, it has nobody to
                // ask: a robot slow for good must still search.
                robot.stay();
            } else if now >= self.deadline && !robot.ready() {
                self.expire(now, out);
            }
            let robot = self.robot.as_mut().expect("started");
            let Some(mut c) = robot.choice().or_else(|| robot.choose()) else {
                return;
            };
            if c != robot.position() && near_missed(&self.expected, self.grid, c) {
                // A neighbour it expected stayed silent: dead, or its map
                // is later than the window, and then it may step next to
                // where it stood without having heard this robot either.
                robot.stay();
                out.notes.push(Note::Unsure);
                c = robot.position();
            }
            self.choice_ready = now + timing.choice;
            if robot.config().policy == Policy::Ru {
                // Particles: nobody waits for an RU robot, nobody acknowledges it.
                let to = if self.choice_ready <= self.slot_end { c } else { robot.position() };
                out.motor = Some((Motor::Go(to), self.choice_ready));
                self.phase = Phase::Committed;
                return;
            }
            let at = robot.position();
            let accounted = robot.accounted().to_vec();
            // A fixed slot's moves start at its end: acknowledgements later
            // than that are of no use.
            self.ack_deadline = (self.choice_ready + timing.wait).min(self.slot_end);
            self.send(out, Frame::Choice { round, from: me, at, next: c, accounted }, self.choice_ready);
        }
        let robot = self.robot.as_ref().expect("started");
        let (pos, c) = (robot.position(), robot.choice().expect("chosen"));
        if c == pos {
            self.commit(now, false, out);
            return;
        }
        // Choices sent at the same moment as this one by robots it did not
        // hear (their maps lost) reach it within the copies' hops: a robot
        // that missed an expected map listens that long before it commits,
        // so two robots that missed each other's maps find out they chose
        // in conflict.
        match self.acks(c) {
            Acks::Complete if now < self.listen_until() => {}
            Acks::Complete => self.commit(now, true, out),
            Acks::Conflict => {
                out.notes.push(Note::Unsure);
                self.commit(now, false, out);
            }
            Acks::Waiting if now >= self.ack_deadline => {
                out.notes.push(Note::Unsure);
                self.commit(now, false, out);
            }
            Acks::Waiting => {}
        }
    }

    /// At its deadline, step 4's wait ends for every robot it waits for
    /// that has been silent for `t_wait`: suspected for the slot, treated as
    /// standing still. One that told it waits itself (`Frame::Wait`) is
    /// alive, behind a longer chain than `t_wait` covers: it waits on, for
    /// as long after that robot's last word as the slot had lasted when the
    /// word came, and at least `t_wait` ([`Peer::patience`]). So a dead
    /// robot is given up after `t_wait` of silence, or [`BEACON_GROWTH`]
    /// times the wait so
    /// far deep in a chain, and a live one never is while its frames
    /// arrive; but under a fixed slot it chooses, at the latest, in time
    /// for its choice's acknowledgements to come back before the slot
    /// ends ([`Peer::choose_by`]): a chain longer than the slot would
    /// otherwise keep its tail standing every slot.
    fn expire(&mut self, now: Time, out: &mut Output<Frame>) {
        let cap = self.choose_by();
        let robot = self.robot.as_mut().expect("started");
        let awaited: Vec<RobotId> = robot.waiting_for().collect();
        let mut next = Time::MAX;
        for j in awaited {
            let said = self.heard.binary_search_by_key(&j, |h| h.id).map_or(0, |k| self.heard[k].waiting);
            let until = patience(self.cfg.timing.wait, self.window_end, self.slot_start, said).min(cap);
            if until > now {
                next = next.min(until);
            } else {
                robot.suspect(j);
                out.notes.push(Note::TimedOut { robot: j });
            }
        }
        if next < Time::MAX {
            self.deadline = next;
        }
    }

    /// Under a fixed slot, the latest time it may choose: its choice must
    /// reach its neighbours and their acknowledgements come back (two of
    /// the latencies it measured, each with its copies' hops, and a
    /// reaction) before the slot's decisions end. `Time::MAX` when the
    /// world closes the slot.
    fn choose_by(&self) -> Time {
        if self.slot_end == Time::MAX {
            return Time::MAX;
        }
        let t = self.cfg.timing;
        let trip = self.latency.1 + t.hop * t.copies as Time;
        self.slot_end.saturating_sub(2 * t.choice + 2 * trip)
    }

    /// When it first says it still waits: half a `t_wait` after its
    /// window, so that a `Wait` reaches every robot waiting for it within
    /// its `t_wait`, with half a `t_wait` to spare for exchange windows
    /// widened differently.
    fn first_beacon(&self) -> Time {
        (self.cfg.timing.wait / 2).max(1)
    }

    /// Still waiting for choices ahead of it: at every beacon time it tells
    /// the robots behind it that it is alive and waits (`Frame::Wait`), at
    /// [`BEACON_GROWTH`] times the time since its window each time (half a
    /// `t_wait`, then 2, 8, 32 `t_wait`, ...): those behind it wait
    /// on that many times as long after each word as the slot had lasted
    /// ([`patience`]), so each `Wait` comes with the time since the last
    /// to spare, and a robot at the end of a chain hundreds of links long
    /// says so a few times a slot, not once every half `t_wait`. A chain
    /// shorter than half a `t_wait` never sends one.
    fn beacon(&mut self, now: Time, out: &mut Output<Frame>) {
        if now < self.beacon_at {
            return;
        }
        while self.beacon_at <= now {
            self.beacon_at = next_beacon(self.window_end, self.beacon_at);
        }
        self.send(out, Frame::Wait { round: self.round, from: self.id() }, now);
    }

    /// Whether every neighbour heard this slot has acknowledged the choice
    /// `c`, or announced one that is safe beside it.
    fn acks(&self, c: VertexId) -> Acks {
        let robot = self.robot.as_ref().expect("started");
        let pos = robot.position();
        let mut waiting = false;
        for h in &self.heard {
            if h.halted || !(h.map || h.choice.is_some()) {
                continue;
            }
            let safe_choice = h.choice.is_some_and(|hc| {
                robot.accounted().contains(&h.id) || h.accounted_me || compatible(robot, pos, c, h.at, hc)
            });
            if h.refused_me || (h.choice.is_some() && !safe_choice && !h.acked_me) {
                // Known, not avoided on either side, and in conflict: both
                // stay, unless `h` should have waited for this choice (it
                // gave this robot up, a chain being longer than its
                // patience); then `h` stays, and this robot moves once it
                // knows so, if its move is safe beside `h` standing still.
                // Else, under a fixed slot, the robots that gave up on a
                // long chain all at once would refuse each other for ever.
                let yields = robot.precedes(h.id) && c != h.at && compatible(robot, pos, c, h.at, h.at);
                match h.commit {
                    _ if !yields => return Acks::Conflict,
                    Some(true) => return Acks::Conflict,
                    Some(false) => {}
                    None => waiting = true,
                }
                continue;
            }
            if !(safe_choice || h.acked_me) {
                waiting = true;
            }
            if c == h.at {
                match h.commit {
                    Some(true) => {}
                    Some(false) => return Acks::Conflict,
                    None => waiting = true,
                }
            }
        }
        if waiting {
            Acks::Waiting
        } else {
            Acks::Complete
        }
    }

    fn commit(&mut self, now: Time, moving: bool, out: &mut Output<Frame>) {
        let robot = self.robot.as_ref().expect("started");
        let (pos, c) = (robot.position(), robot.choice().expect("chosen"));
        let when = now.max(self.choice_ready);
        // Past a fixed slot's end the moves have begun without it: a
        // command now would start a move in the next slot's exchange.
        let moving = if moving && when > self.slot_end {
            out.notes.push(Note::Unsure);
            false
        } else {
            moving
        };
        out.motor = Some((Motor::Go(if moving { c } else { pos }), when));
        if c != pos {
            self.send(out, Frame::Commit { round: self.round, from: self.id(), moving }, when);
        }
        self.phase = Phase::Committed;
    }
}

/// A waiting robot's next `Wait` after the one due at `at`: the time since
/// its window ended at `window_end`, times [`BEACON_GROWTH`].
fn next_beacon(window_end: Time, at: Time) -> Time {
    window_end + BEACON_GROWTH * (at - window_end)
}

/// Until when a robot whose window ended at `window_end`, in a slot begun
/// at `start`, waits for a robot whose last `Wait` arrived at `said` (0:
/// none): `wait` after its window, and after a `Wait` at least `wait`, or
/// [`BEACON_GROWTH`] times the time the slot had lasted when it came (the sender's next
/// `Wait` comes at most that long after its window: [`Peer::beacon`]).
fn patience(wait: Time, window_end: Time, start: Time, said: Time) -> Time {
    let base = window_end + wait;
    if said == 0 {
        return base;
    }
    base.max(said + wait.max(BEACON_GROWTH * said.saturating_sub(start)))
}

/// Whether `v` is the vertex, or next to the vertex, of a robot expected
/// this slot whose map did not come (but for one that senses late: it
/// hears this robot before it decides).
fn near_missed(expected: &[Expect], grid: &Grid, v: VertexId) -> bool {
    expected.iter().any(|e| e.missed > 0 && !e.late_sender && (e.at == v || grid.neighbors(e.at).contains(&v)))
}

/// Whether the moves `a0 -> a1` and `b0 -> b1`, made at once, keep the two
/// robots `2 r_safe` apart. (Following into `b0` is compatible here; it
/// also needs `b`'s commit.)
fn compatible(robot: &Robot, a0: VertexId, a1: VertexId, b0: VertexId, b1: VertexId) -> bool {
    let g = robot.grid();
    a1 != b1
        && swept_min_distance(g.position(a0), g.position(a1), g.position(b0), g.position(b1))
            >= 2.0 * robot.config().r_safe
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use crate::lattice::{Coord, Lattice, LatticeKind};

    fn floods(out: &Output<Frame>) -> Vec<(Vec<Spot>, bool)> {
        out.send
            .iter()
            .filter_map(|t| match &t.payload {
                Frame::Flood { targets, stop, .. } => Some((targets.clone(), *stop)),
                _ => None,
            })
            .collect()
    }

    /// What the controller relayed a robot learns and keeps to itself; the
    /// same news heard from a robot it passes on, as under the flood alone.
    #[test]
    fn a_relayed_flood_is_learnt_and_not_passed_on() {
        let g = &Grid::new(Lattice::new(LatticeKind::Triangular, 1.0), Point::new(-5.0, -5.0), Point::new(5.0, 5.0));
        let v = g.id_of(Coord::new(0, 0)).unwrap();
        let robot = RobotConfig::new(0, Policy::Repulsive, Situation::One, 3, 0.3, 1);
        let mut p = Peer::new(g, PeerConfig::new(robot, &Params::default()));
        let mut out = Output::default();
        let tick = Tick { round: 0, start: 0, at: v, open: 0x3f, occupied: 0, targets: vec![] };
        p.wake(0, Some(&tick), [], &mut out);
        let t = Spot { x: 3, y: 4 };
        let relayed = Frame::Flood { round: 0, from: 7, targets: vec![t], stop: false };
        p.wake(10, None, [(CONTROLLER, 10, &relayed)], &mut out);
        assert!(p.robot.as_ref().unwrap().map().targets.contains(t), "learnt");
        assert!(floods(&out).is_empty(), "not passed on: {:?}", floods(&out));
        assert!(out.notes.is_empty(), "{:?}", out.notes);
        let heard = Frame::Flood { round: 0, from: 7, targets: vec![t], stop: false };
        p.wake(20, None, [(7, 20, &heard)], &mut out);
        assert_eq!(floods(&out), vec![(vec![t], false)], "a robot's flood is passed on once");
        p.wake(30, None, [(8, 30, &heard)], &mut out);
        assert!(floods(&out).is_empty(), "and only once");
        // Only floods come from the controller.
        let map_like = Frame::Commit { round: 0, from: 7, moving: false };
        p.wake(40, None, [(CONTROLLER, 40, &map_like)], &mut out);
        assert_eq!(out.notes, vec![Note::Malformed]);
        // A relayed stop halts it without a flood of its own.
        let stop = Frame::Flood { round: 0, from: 7, targets: vec![], stop: true };
        p.wake(50, None, [(CONTROLLER, 50, &stop)], &mut out);
        assert!(floods(&out).is_empty(), "{:?}", floods(&out));
        p.wake(p.cfg.timing.decision_time(), None, [], &mut out);
        assert!(p.halted(), "the stop is known");
        assert!(floods(&out).is_empty(), "{:?}", floods(&out));
    }

    /// Every `Wait` of a robot still waiting reaches a robot waiting for it
    /// before that robot's patience with it runs out, whichever of their
    /// windows ended first (by up to the widest window) and however the
    /// latency jitters inside the windows; and a robot that falls
    /// silent is given up at most `BEACON_GROWTH` times the slot so far
    /// after its last word.
    #[test]
    fn each_wait_comes_before_the_last_ones_patience_ends() {
        let ms = 1000;
        let (wait, widest) = (3000 * ms, 1050 * ms);
        for own in [50 * ms, 500 * ms, widest] {
            for other in [50 * ms, 500 * ms, widest] {
                // Both windows take in the radio's latency (widened to it).
                let most = own.min(other);
                for (lat, next_lat) in [(0, most), (most, 0), (2 * ms, 2 * ms)] {
                    // The follower's patience before any `Wait`.
                    let mut deadline = patience(wait, other, 0, 0);
                    let mut at = own + wait / 2;
                    let mut arrived = at + lat;
                    let mut n = 0;
                    while at < 3600 * 1000 * ms {
                        let what =
                            format!("window {own} / {other} µs, latency {lat} then {next_lat}, Wait {n} at {at}");
                        assert!(arrived <= deadline, "{what}: arrives at {arrived}, given up at {deadline}");
                        deadline = patience(wait, other, 0, arrived);
                        assert!(deadline - arrived <= wait.max(BEACON_GROWTH * arrived), "{what}");
                        at = next_beacon(own, at);
                        arrived = at + next_lat;
                        n += 1;
                    }
                    assert!(n < 20, "a few `Wait` frames an hour, not {n}");
                }
            }
        }
    }
}
