//! The world's event loop: slots, wake-ups, the radio, motor commands,
//! faults. Generic over how robots are reached ([`Robots`]), so the
//! in-process engine and the world-server run this same loop.

use std::rc::Rc;

use super::controller::Controller;
use super::medium::Medium;
use super::stats::ProtocolStats;
use super::watch::{Sent, Watch};
use super::{micros, seconds, Delivery, Framed, Listen, Motor, Output, Robots, Tick, Time, WakeCall};
use crate::geometry::Point;
use crate::grid::VertexId;
use crate::map::RobotId;
use crate::outcome::{Pose, RunConfig, RunResult};
use crate::referee::Referee;
use crate::world::coverage::Coverage;
use crate::world::World;
use queue::Queue;

mod faults;
mod finish;
mod notes;
mod queue;

/// A run's settings for the world.
pub type Settings = RunConfig;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Body {
    Running,
    Frozen,
    Dead,
}

#[derive(Debug)]
enum Ev<P> {
    SlotStart,
    Deliver {
        to: u32,
        d: Delivery<P>,
    },
    /// A frame reaching several robots at once (a perfect radio).
    Broadcast {
        to: Rc<[u32]>,
        d: Delivery<P>,
    },
    Alarm {
        robot: u32,
        gen: u64,
    },
    Fault(usize),
    /// A slow robot's delayed wake-up.
    React {
        robot: u32,
    },
    /// Every motor command is in; the slot ends when the last one is due.
    Close {
        round: u32,
    },
    /// The slot's hard limit.
    Limit {
        round: u32,
    },
    /// A frame carrying the stop, sent in slot `round`, reaches the human controller.
    Heard {
        round: u32,
    },
    /// A flood reaches the human controller, which relays it if it is news.
    Relay {
        d: Delivery<P>,
    },
}

struct Bot<P> {
    body: Body,
    halted: bool,
    listen: Listen,
    alarm_gen: u64,
    tick_due: bool,
    marked: bool,
    react_pending: bool,
    react_now: bool,
    slow: Time,
    pending: Vec<Delivery<P>>,
    motor: Option<VertexId>,
    tx_seq: u64,
    /// Rounds at whose end this robot was not running and searching, as
    /// inclusive ranges.
    idle: Vec<(u32, u32)>,
    /// Frames it handed to the radio, and their bytes on the wire.
    frames: u64,
    bytes: u64,
    /// It has sent the stop (step 8). A stop is for good, and a halted
    /// robot sends its map, the stop in it, every slot: unless it fails,
    /// the controller hears it in the end, however lossy its link.
    sent_stop: bool,
    /// It noted an unsure stay this round (counted at the round's end,
    /// once, if it is still searching then: a stay is a robot-round).
    unsure: bool,
}

/// The world of one run.
pub struct Kernel<'w, P> {
    world: &'w World,
    cfg: &'w RunConfig,
    referee: Referee<'w>,
    medium: Medium,
    /// Each robot's links of this slot, shared by its broadcasts (made on
    /// its first broadcast of the slot).
    links: Vec<Option<Rc<[u32]>>>,
    queue: Queue<P>,
    bots: Vec<Bot<P>>,
    marked: Vec<u32>,
    starts: Vec<VertexId>,
    round: u32,
    now: Time,
    slot_start: Time,
    slot_open: bool,
    close_scheduled: bool,
    last_motor: Time,
    ended: Option<&'static str>,
    /// The stop that ended the search came from a robot that knew targets
    /// were left unfound ([`Note::Stopped`]'s `exhausted`).
    stop_exhausted: bool,
    /// The human controller heard a stop (step 8): the search is over.
    stop_heard: bool,
    /// Frames carrying a stop on their way to the controller.
    stops_in_flight: u32,
    /// The human controller's base station, which relays news to every robot.
    controller: Controller,
    /// Every robot: who hears the controller's relays on a perfect radio.
    everyone: Rc<[u32]>,
    /// Slots in a row closed with no robot searching ([`Kernel::quiet_enough`]).
    quiet: u32,
    /// The stated bounds of the world's parameters, and slots in a row
    /// past one in which robots searched and none moved ([`Kernel::stalled`]).
    bounds: crate::bounds::Bounds,
    stall: u32,
    /// Slots in a row past a bound in which no vertex was visited first,
    /// and the referee's count of first visits at the last slot's end.
    aimless: u32,
    visits: usize,
    exchange: Time,
    hop: Time,
    slot_limit: Time,
    /// Under the fixed slot rule, when after its start a slot's decisions
    /// end (the robots' clocks, [`crate::peer::Timing::decision_time`]):
    /// the world closes it then, whoever has commanded.
    fixed: Option<Time>,
    /// Something that can close the slot happened since the last check.
    may_close: bool,
    stats: ProtocolStats,
    collisions: u32,
    robot_rounds: u64,
    round_end_times: Vec<f64>,
    round_collisions: Vec<u32>,
    trajectories: Vec<Vec<Pose>>,
    /// The detected fraction as the run goes, when measured.
    coverage: Option<Coverage<'w>>,
    /// When each target was first found, in order.
    targets_s: Vec<f64>,
    /// `(failure record, robot, round)`: robots that timed out waiting on a failed robot.
    waiters: Vec<(usize, RobotId, u32)>,
    /// Frames of the last wake-ups that reach nobody, handed back to the
    /// engine as read ones are ([`Robots::reclaim`]).
    unheard: Vec<Delivery<P>>,
    /// `GRIDSWARM_TRACE` set: every wake-up, motor command, fault and slot on stderr.
    trace: bool,
    /// Buffers of every slot's start and close, kept so that a slot does not allocate them.
    points: Vec<Point>,
    before_next: (Vec<VertexId>, Vec<VertexId>),
    /// An observer of the run ([`Kernel::watched`]), and the receivers of a frame for it.
    watch: Option<&'w mut dyn Watch<P>>,
    fates: (Vec<u32>, Vec<u32>),
}

impl<'w, P: Clone + Framed> Kernel<'w, P> {
    pub fn new(world: &'w World, starts: &[VertexId], cfg: &'w RunConfig) -> Self {
        let n = starts.len();
        let p = &world.params;
        let timing = crate::peer::Timing::from_params(p);
        // The protocol's own bound (the widest exchange a robot may choose, a
        // wait for choices, the choice, a wait for acknowledgements, a few
        // hops), with room for a robot slow by up to 4 t_wait: a late robot
        // reacts twice, to sense and to decide after listening a window
        // (`Peer::start_slot`). Robots waiting for a longer chain of choices
        // than `t_wait` covers wait on while its robots say they wait
        // (`Frame::Wait`): a chain through the whole team, one choice and
        // one latency a link, stays inside the limit too.
        let link = timing.choice + timing.hop + cfg.radio.delay + cfg.radio.jitter;
        let slot_limit = timing.widest() + 8 * timing.wait + timing.choice + 20 * timing.hop + n as Time * link;
        let (exchange, fixed) = (timing.exchange, timing.decision);
        let bots = (0..n)
            .map(|_| Bot {
                body: Body::Running,
                halted: false,
                listen: Listen::OFF,
                alarm_gen: 0,
                tick_due: false,
                marked: false,
                react_pending: false,
                react_now: false,
                slow: 0,
                pending: Vec::new(),
                motor: None,
                tx_seq: 0,
                idle: Vec::new(),
                frames: 0,
                bytes: 0,
                sent_stop: false,
                unsure: false,
            })
            .collect();
        let mut k = Kernel {
            world,
            cfg,
            referee: Referee::new(world, starts).seeded(cfg.seed),
            medium: Medium::new(cfg.seed, cfg.radio, micros(p.t_hop), p.r_c, n),
            links: vec![None; n],
            queue: Queue::new(),
            bots,
            marked: Vec::with_capacity(n),
            starts: starts.to_vec(),
            round: 0,
            now: 0,
            slot_start: 0,
            slot_open: false,
            close_scheduled: false,
            last_motor: 0,
            ended: None,
            stop_exhausted: false,
            stop_heard: false,
            stops_in_flight: 0,
            controller: Controller::new(p.broadcast),
            everyone: (0..n as u32).collect(),
            quiet: 0,
            bounds: crate::bounds::Bounds::of(p),
            stall: 0,
            aimless: 0,
            visits: 0,
            exchange,
            hop: micros(p.t_hop),
            slot_limit,
            fixed,
            may_close: false,
            stats: ProtocolStats::default(),
            collisions: 0,
            robot_rounds: 0,
            round_end_times: Vec::new(),
            round_collisions: Vec::new(),
            trajectories: if cfg.record_trajectories { vec![Vec::new(); n] } else { Vec::new() },
            coverage: cfg.measure_coverage.then(|| Coverage::new(world)),
            targets_s: Vec::new(),
            waiters: Vec::new(),
            unheard: Vec::new(),
            trace: std::env::var_os("GRIDSWARM_TRACE").is_some(),
            points: Vec::with_capacity(n),
            before_next: (Vec::with_capacity(n), Vec::with_capacity(n)),
            watch: None,
            fates: (Vec::new(), Vec::new()),
        };
        k.record_poses();
        k.cover(0);
        k.push(0, Ev::SlotStart);
        k
    }

    /// The run shown to `watch` as it goes; the same run.
    pub fn watched(mut self, watch: &'w mut dyn Watch<P>) -> Self {
        self.watch = Some(watch);
        self
    }

    fn push(&mut self, time: Time, ev: Ev<P>) {
        self.queue.push(time, ev);
    }

    fn mark(&mut self, r: usize) {
        if !self.bots[r].marked {
            self.bots[r].marked = true;
            self.marked.push(r as u32);
        }
    }

    /// Marks where the robots stand as detected by time `at`.
    fn cover(&mut self, at: Time) {
        if let Some(c) = self.coverage.as_mut() {
            for &v in self.referee.positions() {
                c.stand(v);
            }
            c.at(seconds(at));
        }
    }

    fn record_poses(&mut self) {
        let grid = &self.world.grid;
        for (k, t) in self.trajectories.iter_mut().enumerate() {
            let v = self.referee.position(k);
            t.push(Pose { vertex: Some(grid.coord(v)), position: grid.position(v) });
        }
    }

    /// Runs the search to its end.
    pub fn run<R: Robots<Payload = P>>(mut self, robots: &mut R) -> RunResult {
        let mut calls = Vec::new();
        let mut ids = Vec::new();
        let mut outs = Vec::new();
        while self.ended.is_none() {
            let Some(t) = self.queue.peek_time() else {
                // Nothing can happen any more: a robot waits with no alarm.
                self.close_slot(true);
                continue;
            };
            self.now = t;
            while self.queue.peek_time() == Some(t) && self.ended.is_none() {
                let (_, ev) = self.queue.pop().expect("peeked");
                self.handle(ev, robots);
            }
            if self.ended.is_some() {
                break;
            }
            self.collect(&mut calls, &mut ids);
            if !calls.is_empty() {
                self.stats.wakes += calls.len() as u64;
                robots.wake(&mut calls, &mut outs);
                self.recycle(&mut calls, robots);
                for (k, &id) in ids.iter().enumerate() {
                    self.apply(id, outs.get_mut(k).and_then(Option::as_mut));
                }
                if !self.unheard.is_empty() {
                    robots.reclaim(&mut self.unheard);
                    self.unheard.clear();
                }
            }
            self.check_close();
        }
        self.finish()
    }

    fn handle<R: Robots<Payload = P>>(&mut self, ev: Ev<P>, robots: &mut R) {
        match ev {
            Ev::SlotStart => {
                robots.slot_started(self.round, self.now);
                self.begin_slot();
            }
            Ev::Deliver { to, d } => {
                let h = d.payload.header();
                self.deliver(to, d, h);
            }
            Ev::Broadcast { to, d } => {
                let h = d.payload.header();
                for &t in to.iter() {
                    self.deliver(t, d.clone(), h);
                }
            }
            Ev::Alarm { robot, gen } => {
                let b = &self.bots[robot as usize];
                // A frozen robot's alarm is lost: its thaw wakes it anyway.
                if b.alarm_gen == gen && b.body == Body::Running {
                    self.mark(robot as usize);
                }
            }
            Ev::Fault(i) => {
                let f = self.cfg.faults[i];
                if let Some(w) = self.watch.as_deref_mut() {
                    w.fault(self.now, &f);
                }
                robots.inject(&f, self.now);
                self.apply_fault(&f);
            }
            Ev::React { robot } => {
                let b = &mut self.bots[robot as usize];
                b.react_pending = false;
                b.react_now = true;
                self.mark(robot as usize);
            }
            Ev::Close { round } => {
                if round == self.round {
                    self.close_scheduled = false;
                    self.may_close = true;
                }
            }
            Ev::Heard { round } => {
                self.stops_in_flight -= 1;
                self.stop_heard = true;
                if !self.slot_open || round < self.round {
                    // A stop of a slot that has closed (heard during the
                    // moves, or in a slot that began at once because
                    // nobody moved): the record ends with the closed slots.
                    self.ended = Some("stop");
                }
            }
            Ev::Relay { d } => self.relay(d),
            Ev::Limit { round } => {
                if round == self.round && self.slot_open {
                    // A fixed slot ends here by rule; an adaptive one is forced.
                    self.close_slot(self.fixed.is_none());
                }
            }
        }
    }

    /// Puts a frame in robot `to`'s receive buffer, and wakes it if its
    /// filter lets the frame's header through.
    fn deliver(&mut self, to: u32, d: Delivery<P>, h: Option<super::Header>) {
        let b = &mut self.bots[to as usize];
        if b.body == Body::Dead {
            return;
        }
        // A slow robot reacts `slow` after whatever wakes it, so the frame
        // that wakes it decides when it reads all the others: a filter
        // exact for a robot on time is not for it, and the model keeps
        // waking it for every frame (faults are the world's, not a setting
        // the robot could know).
        let wakes = if b.slow > 0 { b.listen.on } else { b.listen.wakes(d.from, h) };
        b.pending.push(d);
        if b.body == Body::Running && wakes {
            self.mark(to as usize);
        }
    }

    fn begin_slot(&mut self) {
        self.slot_start = self.now;
        self.slot_open = true;
        // A slot nobody owes a command in closes after the exchange.
        self.may_close = true;
        self.close_scheduled = false;
        self.last_motor = self.now;
        let grid = &self.world.grid;
        let mut positions = std::mem::take(&mut self.points);
        positions.clear();
        positions.extend(self.referee.positions().iter().map(|&v| grid.position(v)));
        self.medium.relink(&positions);
        self.points = positions;
        self.links.iter_mut().for_each(|l| *l = None);
        for r in 0..self.bots.len() {
            let b = &mut self.bots[r];
            b.motor = None;
            if b.body != Body::Dead {
                b.tick_due = true;
                if b.body == Body::Running {
                    self.mark(r);
                }
            }
        }
        for (i, f) in self.cfg.faults.iter().enumerate() {
            if f.round == self.round {
                self.push(self.now + f.offset, Ev::Fault(i));
            }
        }
        let round = self.round;
        self.push(self.now + self.fixed.unwrap_or(self.slot_limit), Ev::Limit { round });
    }

    fn tick(&mut self, r: usize) -> Tick {
        let (open, occupied) = self.referee.sonar(r);
        let found = self.referee.found_count();
        let world = self.world;
        let targets = self.referee.laser(r).iter().map(|&t| world.spot(t)).collect();
        for _ in found..self.referee.found_count() {
            self.targets_s.push(seconds(self.now));
        }
        let tick =
            Tick { round: self.round, start: self.slot_start, at: self.referee.position(r), open, occupied, targets };
        if let Some(w) = self.watch.as_deref_mut() {
            w.ticked(r, &tick);
        }
        tick
    }

    /// The wake-ups due now, robot by robot in ascending order.
    fn collect(&mut self, calls: &mut Vec<WakeCall<P>>, ids: &mut Vec<usize>) {
        calls.clear();
        ids.clear();
        let mut marked = std::mem::take(&mut self.marked);
        marked.sort_unstable();
        for &r in &marked {
            let r = r as usize;
            self.bots[r].marked = false;
            if self.bots[r].body != Body::Running {
                continue;
            }
            let b = &mut self.bots[r];
            if b.tick_due && !self.slot_open {
                // It owes a look at a slot that has not begun: the slot's
                // start wakes it, with everything that reached it meanwhile.
                continue;
            }
            if b.slow > 0 && !b.react_now {
                if !b.react_pending {
                    b.react_pending = true;
                    let at = self.now + b.slow;
                    self.push(at, Ev::React { robot: r as u32 });
                }
                continue;
            }
            b.react_now = false;
            let tick = if std::mem::take(&mut self.bots[r].tick_due) { Some(self.tick(r)) } else { None };
            let b = &mut self.bots[r];
            calls.push(WakeCall { robot: r, now: self.now, tick, frames: std::mem::take(&mut b.pending) });
            ids.push(r);
        }
        marked.clear();
        self.marked = marked;
    }

    /// Gives each robot back its emptied frame buffer, so that delivering
    /// does not allocate afresh every wake-up.
    fn recycle<R: Robots<Payload = P>>(&mut self, calls: &mut Vec<WakeCall<P>>, robots: &mut R) {
        for c in calls.drain(..) {
            let mut frames = c.frames;
            robots.reclaim(&mut frames);
            frames.clear();
            let pending = &mut self.bots[c.robot].pending;
            if pending.is_empty() && frames.capacity() > pending.capacity() {
                *pending = frames;
            }
        }
    }

    /// Applies robot `r`'s output, emptying its `send` and `notes` (the
    /// buffers stay with the robots' side for the next wake-up).
    fn apply(&mut self, r: usize, out: Option<&mut Output<P>>) {
        let Some(out) = out else {
            self.may_close = true;
            // Its process is gone: physics, not a scheduled fault.
            if self.bots[r].body != Body::Dead {
                self.bots[r].body = Body::Dead;
                self.bots[r].pending.clear();
                self.open_record(r, "died");
            }
            return;
        };
        let now = self.now;
        if self.trace {
            eprintln!(
                "{:>10} r{} robot {r}: send {} motor {:?} alarm {:?} listen {:?} notes {:?}",
                now,
                self.round,
                out.send.len(),
                out.motor,
                out.alarm,
                out.listen,
                out.notes
            );
        }
        for tx in out.send.drain(..) {
            self.transmit(r, tx.payload, tx.ready.max(now), tx.copies);
        }
        if let Some((m, t)) = out.motor {
            self.may_close = true;
            let b = &mut self.bots[r];
            if m != Motor::Halt {
                // A command, or a resume (which a command in the same
                // wake-up replaces): it searches again.
                b.halted = false;
            }
            // Under a fixed slot a move must start at the slot's end: a
            // command timed later is no command (the robot stays).
            let in_time = self.fixed.is_none_or(|d| t <= self.slot_start + d);
            if !in_time && matches!(m, Motor::Go(v) if v != self.referee.position(r)) {
                self.stats.late_motors += 1;
            }
            let given = match m {
                Motor::Go(v) if self.slot_open && b.motor.is_none() && in_time => {
                    b.motor = Some(v);
                    true
                }
                Motor::Halt if self.slot_open && b.motor.is_none() && !b.halted => {
                    b.halted = true;
                    true
                }
                _ => false,
            };
            if given {
                self.last_motor = self.last_motor.max(t.max(now));
            }
        }
        let b = &mut self.bots[r];
        b.alarm_gen += 1;
        b.listen = out.listen;
        if let Some(t) = out.alarm {
            let gen = b.alarm_gen;
            self.push(t.max(now), Ev::Alarm { robot: r as u32, gen });
        }
        for note in out.notes.drain(..) {
            self.note(r, note);
        }
    }

    fn transmit(&mut self, r: usize, payload: P, ready: Time, copies: u8) {
        let copies = copies.max(1);
        let st = &mut self.stats;
        st.frames += 1;
        st.transmissions += copies as u64;
        st.retransmissions += copies as u64 - 1;
        let b = &mut self.bots[r];
        let seq = b.tx_seq;
        b.tx_seq += 1;
        b.frames += 1;
        b.bytes += payload.wire_len() as u64;
        let from = r as RobotId;
        let stop = !self.stop_heard && payload.carries_stop();
        let flood = self.controller.relays() && payload.is_flood();
        if stop || flood {
            let at = self.to_controller(r, seq, ready, copies);
            if stop {
                self.bots[r].sent_stop = true;
                if let Some(at) = at {
                    self.stops_in_flight += 1;
                    let round = payload.header().map_or(self.round, |h| h.round);
                    self.push(at, Ev::Heard { round });
                }
            }
            if let (true, Some(at)) = (flood, at) {
                self.push(at, Ev::Relay { d: Delivery { from, at, payload: payload.clone() } });
            }
        }
        if self.medium.radio().is_perfect() {
            // Every receiver hears it one hop later: one event for all.
            let medium = &self.medium;
            let to = self.links[r].get_or_insert_with(|| Rc::from(medium.links(r))).clone();
            let at = ready + self.hop;
            if let Some(w) = self.watch.as_deref_mut() {
                w.sent(Sent { at: ready, from: r, payload: &payload, heard: &to, lost: &[] });
            }
            let d = Delivery { from, at, payload };
            if to.is_empty() {
                // A lone robot's map every slot: its buffers go back too.
                self.unheard.push(d);
            } else {
                self.stats.deliveries += to.len() as u64;
                self.push(at, Ev::Broadcast { to, d });
            }
            return;
        }
        self.fates.0.clear();
        self.fates.1.clear();
        for k in 0..self.medium.links(r).len() {
            let to = self.medium.links(r)[k];
            let fate = self.medium.fate(r, seq, to as usize, ready, copies);
            if self.watch.is_some() {
                let fates = if fate.arrival.is_some() { &mut self.fates.0 } else { &mut self.fates.1 };
                fates.push(to);
            }
            self.stats.lost += fate.lost as u64;
            if let Some(at) = fate.arrival {
                self.stats.deliveries += 1;
                self.push(at, Ev::Deliver { to, d: Delivery { from, at, payload: payload.clone() } });
            }
            if let Some(at) = fate.duplicate {
                self.stats.duplicated += 1;
                self.push(at, Ev::Deliver { to, d: Delivery { from, at, payload: payload.clone() } });
            }
        }
        if let Some(w) = self.watch.as_deref_mut() {
            w.sent(Sent { at: ready, from: r, payload: &payload, heard: &self.fates.0, lost: &self.fates.1 });
        }
    }

    /// When the controller's receiver hears transmission `seq` of robot
    /// `r`, if its link lets it through.
    fn to_controller(&self, r: usize, seq: u64, ready: Time, copies: u8) -> Option<Time> {
        if self.medium.radio().is_perfect() {
            Some(ready + self.hop)
        } else {
            self.medium.fate(r, seq, super::CONTROLLER, ready, copies).arrival
        }
    }

    /// The controller heard flood `d`: if it tells it something new, it
    /// sends it on, as it was, to every robot over its own link, as its
    /// own transmission ([`crate::protocol::CONTROLLER`]).
    fn relay(&mut self, d: Delivery<P>) {
        let d = Delivery { from: crate::protocol::CONTROLLER, ..d };
        let Some((targets, stop)) = d.payload.flood() else { return };
        if !self.controller.news(&targets, stop) {
            return;
        }
        let seq = self.controller.next_seq();
        self.stats.relays += 1;
        let copies = (1 + self.world.params.retries).min(u8::MAX as u32) as u8;
        if self.medium.radio().is_perfect() {
            let to = self.everyone.clone();
            self.stats.deliveries += to.len() as u64;
            self.push(self.now + self.hop, Ev::Broadcast { to, d: Delivery { at: self.now + self.hop, ..d } });
            return;
        }
        for to in 0..self.bots.len() {
            let fate = self.medium.fate(super::CONTROLLER, seq, to, self.now, copies);
            self.stats.lost += fate.lost as u64;
            for at in fate.arrival.into_iter().chain(fate.duplicate) {
                self.stats.deliveries += 1;
                let payload = d.payload.clone();
                self.push(at, Ev::Deliver { to: to as u32, d: Delivery { from: d.from, at, payload } });
            }
            self.stats.duplicated += fate.duplicate.is_some() as u64;
        }
    }

    /// Whether a robot still owes a motor command this slot.
    fn owes_motor(b: &Bot<P>) -> bool {
        b.body == Body::Running && !b.halted && b.motor.is_none()
    }

    fn check_close(&mut self) {
        // A fixed slot never looks at who has commanded: its limit closes it.
        if !std::mem::take(&mut self.may_close) || self.fixed.is_some() {
            return;
        }
        if !self.slot_open || self.close_scheduled || self.bots.iter().any(Self::owes_motor) {
            return;
        }
        // With nobody running the clock still turns: a slot lasts at least the exchange.
        let searching = self.bots.iter().any(|b| b.body == Body::Running && !b.halted);
        let at = if searching { self.last_motor } else { self.last_motor.max(self.slot_start + self.exchange) };
        if at > self.now {
            self.close_scheduled = true;
            let round = self.round;
            self.push(at, Ev::Close { round });
        } else {
            self.close_slot(false);
        }
    }

    fn close_slot(&mut self, forced: bool) {
        if !self.slot_open {
            // Nothing scheduled and no slot to close: the run cannot go on.
            self.ended = Some("no_robots");
            return;
        }
        self.slot_open = false;
        if forced {
            self.stats.forced_slots += 1;
        }
        // The slot lasts until it closes, whoever gave the last command.
        self.last_motor = self.last_motor.max(self.now);
        let (mut before, mut next) = std::mem::take(&mut self.before_next);
        before.clear();
        before.extend_from_slice(self.referee.positions());
        next.clear();
        next.extend(self.bots.iter().zip(&before).map(|(b, &p)| b.motor.unwrap_or(p)));
        let report = self.referee.execute(&next);
        let moved = next.iter().zip(&before).filter(|(a, b)| a != b).count() as u64;
        self.stats.moves += moved - report.refused as u64;
        self.stats.refused += report.refused as u64;
        self.collisions += report.collisions;
        let p = &self.world.params;
        let dur = match self.fixed {
            // The robots' clocks cannot know whether anybody moved, or
            // collided: every slot leaves room for one move.
            Some(d) => d + micros(p.t_rot) + micros(p.t_trans),
            None => {
                let mut dur = self.last_motor - self.slot_start;
                if report.rotated {
                    dur += micros(p.t_rot);
                }
                if report.translated {
                    dur += micros(p.t_trans);
                }
                dur + micros(p.collision_penalty(report.collisions))
            }
        };
        let end = self.slot_start + dur;
        if self.trace && report.collisions > 0 {
            let g = &self.world.grid;
            let moves: Vec<String> = before
                .iter()
                .zip(&next)
                .enumerate()
                .map(|(k, (&a, &b))| {
                    format!("{k}:{:?}->{:?}", (g.coord(a).i, g.coord(a).j), (g.coord(b).i, g.coord(b).j))
                })
                .collect();
            eprintln!("COLLISION round {}: {}", self.round, moves.join(" "));
        }
        if self.trace {
            eprintln!(
                "{:>10} r{} close{}: motors {:?} collisions {} -> next slot at {end}",
                self.now,
                self.round,
                if forced { " FORCED" } else { "" },
                self.bots.iter().map(|b| (b.body, b.halted, b.motor)).collect::<Vec<_>>(),
                report.collisions
            );
        }
        self.before_next = (before, next);
        self.round_end_times.push(seconds(end));
        if let Some(w) = self.watch.as_deref_mut() {
            w.closed(self.round, end, self.referee.positions(), report.collisions);
        }
        self.round_collisions.push(report.collisions);
        let mut searching = 0;
        let round = self.round;
        if searching_left(&self.bots) {
            self.quiet = 0;
        }
        for b in self.bots.iter_mut() {
            let unsure = std::mem::take(&mut b.unsure);
            if b.body == Body::Running && !b.halted {
                searching += 1;
                self.stats.unsure += unsure as u64;
            } else {
                match b.idle.last_mut() {
                    Some(last) if last.1 + 1 == round => last.1 = round,
                    _ => b.idle.push((round, round)),
                }
            }
        }
        self.robot_rounds += searching;
        self.round += 1;
        self.record_poses();
        self.cover(end);
        if self.stop_heard {
            // Step 8: the stop reached the human controller, and the record
            // of the search ends with this slot. No robot is told anything:
            // those the flood reached this slot have stopped, the others
            // would learn it from the robots they meet.
            self.ended = Some("stop");
        } else if self.stalled(moved - report.refused as u64) {
            self.ended = Some("past_bound");
        } else if self.round >= self.cfg.max_rounds && searching_left(&self.bots) {
            self.ended = Some("max_rounds");
            self.stats.past_bound = self.past_bound();
        } else if !searching_left(&self.bots)
            && !self.thaw_ahead()
            && self.stops_in_flight == 0
            && !self.stop_on_air()
            && self.quiet_enough()
        {
            self.ended =
                Some(if self.bots.iter().any(|b| b.halted && b.body != Body::Dead) { "cut_off" } else { "no_robots" });
        } else if self.round >= self.cfg.max_rounds {
            self.ended = Some("max_rounds");
            self.stats.past_bound = self.past_bound();
        } else {
            self.now = end;
            self.push(end, Ev::SlotStart);
        }
    }
}

impl<'w, P: Clone + Framed> Kernel<'w, P> {
    /// Whether nobody searching is final: robots halted cut off still
    /// exchange maps, and one resumes once what cut it off is gone (a
    /// robot it held failed heard again, a body found gone), news that
    /// takes one slot a hop. Slots in a row with no robot searching but
    /// some halted and running are counted; once they exceed the most hops
    /// between two such robots by one, every map holds what the others
    /// hold, and nothing can change any more. The one: the last robot to
    /// halt decided on what it sensed before that slot's moves, so the
    /// first reading of the world as it stays is the next slot's (a body
    /// sensed where a robot stood, silent, before it moved on).
    fn quiet_enough(&mut self) -> bool {
        self.quiet += 1;
        let parked = self.bots.iter().any(|b| b.halted && b.body == Body::Running);
        !parked || self.quiet > self.hops_across() + 1
    }

    /// Whether a running robot sends a stop the controller has not heard
    /// yet (its frames to the controller lost): the search has ended, but
    /// its record does not end before the controller hears it.
    fn stop_on_air(&self) -> bool {
        self.bots.iter().any(|b| b.sent_stop && b.body == Body::Running)
    }

    /// The most radio hops between two running robots that can reach each
    /// other (the diameter of their radio graph, the largest over its parts).
    fn hops_across(&self) -> u32 {
        let running = |k: usize| self.bots[k].body == Body::Running;
        let mut hops = vec![u32::MAX; self.bots.len()];
        let mut queue = std::collections::VecDeque::new();
        let mut most = 0;
        for from in (0..self.bots.len()).filter(|&k| running(k)) {
            hops.fill(u32::MAX);
            hops[from] = 0;
            queue.push_back(from);
            while let Some(k) = queue.pop_front() {
                most = most.max(hops[k]);
                for &j in self.medium.links(k) {
                    let j = j as usize;
                    if running(j) && hops[j] == u32::MAX {
                        hops[j] = hops[k] + 1;
                        queue.push_back(j);
                    }
                }
            }
        }
        most
    }
}

fn searching_left<P>(bots: &[Bot<P>]) -> bool {
    bots.iter().any(|b| b.body == Body::Running && !b.halted)
}
