//! The world's side of the round protocol, with no I/O of its own: it reads
//! robots' bytes through a [`Link`] and answers through it. It mirrors
//! `gridswarm::engine` step by step (same referee calls, same order, same
//! time model), so that without failures the trajectories are the engine's.
//!
//! One round:
//! 1. `Tick` to every alive robot: its sonar, laser and radio readings.
//! 2. Each robot answers with its map (and, in situation 1, the targets it
//!    just found). Targets are relayed to every alive robot, a map to the
//!    sender's radio neighbours of this round, as they arrive. Once every
//!    alive robot's map is in, `ExchangeDone` to all.
//! 3. Robots choose in priority order; each `Choice` is relayed at once to
//!    the chooser's neighbours (the chain of step 5). A `Stop` ends the
//!    search with no moves that round. Once every alive robot has chosen,
//!    all moves are executed at once by the referee.
//!
//! Failures (Sec. 4.2): the world is the one authority, so every robot sees
//! the same story. A robot the world waits for is declared failed when its
//! process is gone (checked after `check` of silence) or when it stays silent
//! for `suspect` while nothing it waits for is missing. It leaves the alive
//! set at the vertex it stands on, its radio neighbours get `Failed`, it is
//! never waited for again and never moves again; a robot declared by deadline
//! also gets `Deposed`. Whatever a failed robot sends afterwards is dropped
//! and counted as stale.

use std::time::{Duration, Instant};

use gridswarm::bitset::Bitset;
use gridswarm::engine::RASTER_CELL;
use gridswarm::geometry::Point;
use gridswarm::grid::VertexId;
use gridswarm::ipc::{Detection, Dropped, Pause, RunReport};
use gridswarm::map::RobotId;
use gridswarm::outcome::RunResult;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::protocol::{
    decode_to_world_exact, encode_from_world, FromWorld, Limits, Message, ToWorld,
};
use gridswarm::referee::{longest_wait_chain, priority_order, round_time, Referee};
use gridswarm::world::World;

/// The world's transport: robots' outboxes and inboxes, and waiting.
pub trait Link {
    /// Queues `bytes` (a `FromWorld`) in robot `robot`'s inbox, without
    /// waking it: the robot reads it with whatever wakes it next.
    fn post(&mut self, robot: usize, bytes: &[u8]);
    /// Marks robot `robot` to be woken at the next flush.
    fn wake(&mut self, robot: usize);
    /// Wakes every robot marked since the last flush.
    fn flush(&mut self);
    /// Blocks until some robot signals or `timeout` passes; pushes the
    /// robots that signalled (a hint: their outboxes may hold messages).
    fn wait(&mut self, timeout: Duration, woke: &mut Vec<usize>);
    /// The next message in robot `robot`'s outbox, into `buf`.
    fn recv(&mut self, robot: usize, buf: &mut Vec<u8>) -> bool;
    /// Robots whose node the middleware reports dead.
    fn dead_robots(&mut self) -> Vec<usize>;
}

/// A run's settings.
#[derive(Clone, Debug)]
pub struct Settings {
    pub policy: Policy,
    pub situation: Situation,
    pub seed: u64,
    pub max_rounds: u32,
    /// Silence after which a waited-for robot's process is checked.
    pub check: Duration,
    /// Silence after which a waited-for robot is declared failed.
    pub suspect: Duration,
    /// How long to wait for every robot's hello.
    pub hello_timeout: Duration,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    Hello,
    Exchange,
    Choice,
}

#[derive(Debug)]
pub enum ServerError {
    /// Not every robot said hello in time.
    Hello(String),
}

impl std::fmt::Display for ServerError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ServerError::Hello(s) => f.write_str(s),
        }
    }
}

pub struct Server<'w> {
    world: &'w World,
    set: Settings,
    n: usize,
    limits: Limits,
    starts: Vec<VertexId>,
    referee: Referee<'w>,
    t0: Instant,
    pids: Vec<Option<u32>>,
    alive: Vec<bool>,
    /// For each failed robot, which robots the world has told of it.
    told: Vec<Option<Vec<bool>>>,
    nbrs: Vec<Vec<RobotId>>,
    map_in: Vec<bool>,
    choice: Vec<Option<VertexId>>,
    /// Since when the world has been waiting for this robot with nothing
    /// the robot itself waits for.
    ready_since: Vec<Instant>,
    round: u32,
    phase: Phase,
    stopped: bool,
    /// Targets broadcast so far (situation 1): what every robot knows.
    known_targets: Bitset,
    last_progress: Instant,
    last_check: Instant,
    /// Last time the middleware's node list was read (it costs a directory
    /// scan and a lock probe per node, so at most every ten checks).
    last_node_list: Instant,
    // Accounting.
    dropped: Dropped,
    failures: Vec<Detection>,
    refused: u32,
    collisions: u32,
    time: f64,
    robot_rounds: u64,
    vertices: Vec<Vec<u32>>,
    round_wall_ms: Vec<f64>,
    exchange_wall_ms: Vec<f64>,
    choice_wall_ms: Vec<f64>,
    chain_len: Vec<u32>,
    round_end_times_s: Vec<f64>,
    agent_rss: Vec<u64>,
    agent_cpu: Vec<f64>,
    cpu_at_hello: f64,
    cpu_at_end: f64,
    pauses: Vec<Pause>,
    startup_ms: f64,
    // Scratch.
    order: Vec<usize>,
    chain: Vec<u32>,
    next: Vec<VertexId>,
    buf: Vec<u8>,
    out: Vec<u8>,
    woke: Vec<usize>,
}

impl<'w> Server<'w> {
    pub fn new(world: &'w World, starts: &[VertexId], set: Settings) -> Self {
        let n = starts.len();
        let now = Instant::now();
        Server {
            world,
            n,
            limits: Limits {
                vertices: world.grid.len(),
                targets: world.targets.len(),
                robots: n,
            },
            starts: starts.to_vec(),
            referee: Referee::new(world, starts),
            t0: now,
            pids: vec![None; n],
            alive: vec![true; n],
            told: vec![None; n],
            nbrs: vec![Vec::with_capacity(8); n],
            map_in: vec![false; n],
            choice: vec![None; n],
            ready_since: vec![now; n],
            round: 0,
            phase: Phase::Hello,
            stopped: false,
            known_targets: Bitset::new(world.targets.len()),
            last_progress: now,
            last_check: now,
            last_node_list: now,
            dropped: Dropped::default(),
            failures: Vec::new(),
            refused: 0,
            collisions: 0,
            time: 0.0,
            robot_rounds: 0,
            vertices: starts.iter().map(|&v| vec![v]).collect(),
            round_wall_ms: Vec::new(),
            exchange_wall_ms: Vec::new(),
            choice_wall_ms: Vec::new(),
            chain_len: Vec::new(),
            round_end_times_s: Vec::new(),
            agent_rss: vec![0; n],
            agent_cpu: vec![0.0; n],
            cpu_at_hello: 0.0,
            cpu_at_end: 0.0,
            pauses: Vec::new(),
            startup_ms: 0.0,
            order: (0..n).collect(),
            chain: vec![0; n],
            next: vec![0; n],
            buf: Vec::with_capacity(1024),
            out: Vec::with_capacity(1024),
            woke: Vec::with_capacity(n),
            set,
        }
    }

    fn ms(&self, t: Instant) -> f64 {
        t.duration_since(self.t0).as_secs_f64() * 1e3
    }

    pub fn round(&self) -> u32 {
        self.round
    }

    pub fn alive_count(&self) -> usize {
        self.alive.iter().filter(|&&a| a).count()
    }

    #[cfg(test)]
    pub fn dropped(&self) -> &Dropped {
        &self.dropped
    }

    /// Sends `m` to `robot` and wakes it.
    fn send(&mut self, link: &mut impl Link, robot: usize, m: &FromWorld) {
        self.post(link, robot, m);
        link.wake(robot);
    }

    /// Sends `m` to `robot` without waking it.
    fn post(&mut self, link: &mut impl Link, robot: usize, m: &FromWorld) {
        self.out.clear();
        self.out.extend_from_slice(&encode_from_world(m));
        link.post(robot, &self.out);
    }

    /// Waits for every robot's hello (its pid, for the liveness checks).
    pub fn hello(&mut self, link: &mut impl Link) -> Result<(), ServerError> {
        let deadline = Instant::now() + self.set.hello_timeout;
        while self.pids.iter().any(Option::is_none) {
            let now = Instant::now();
            if now >= deadline {
                let missing: Vec<String> = (0..self.n)
                    .filter(|&k| self.pids[k].is_none())
                    .map(|k| k.to_string())
                    .collect();
                return Err(ServerError::Hello(format!(
                    "no hello from robot(s) {} after {:?}",
                    missing.join(", "),
                    self.set.hello_timeout
                )));
            }
            self.pump(link, (deadline - now).min(Duration::from_millis(200)));
        }
        self.startup_ms = self.ms(Instant::now());
        self.cpu_at_hello = gridswarm::ipc::cpu_ms_of(std::process::id());
        Ok(())
    }

    /// Records a pause at the start of the coming round (failure injection).
    pub fn paused(&mut self) {
        let go = self.ms(Instant::now());
        self.pauses.push(Pause {
            round: self.round,
            go_ms: go,
        });
    }

    /// Plays one round. Returns false once the search is over (a stop rule
    /// fired, the round limit, or no robot left); `End` has then been sent.
    pub fn play_round(&mut self, link: &mut impl Link) -> bool {
        let started = Instant::now();
        if self.alive_count() == 0 {
            return false;
        }
        // Steps 1-2: every alive robot's readings.
        self.phase = Phase::Exchange;
        let alive = self.alive.clone();
        for k in 0..self.n {
            self.map_in[k] = false;
            self.choice[k] = None;
            if !alive[k] {
                self.nbrs[k].clear();
                continue;
            }
            let mut nb = std::mem::take(&mut self.nbrs[k]);
            self.referee.radio(k, |j| alive[j], &mut nb);
            self.nbrs[k] = nb;
            let (open, occupied) = self.referee.sonar(k);
            let targets = self.referee.laser(k).to_vec();
            let tick = FromWorld::Tick {
                round: self.round,
                at: self.referee.position(k),
                open,
                occupied,
                targets,
                neighbours: self.nbrs[k].clone(),
            };
            self.send(link, k, &tick);
        }
        self.tell_newcomers(link);
        link.flush();
        let now = Instant::now();
        self.ready_since.iter_mut().for_each(|t| *t = now);
        self.last_progress = now;
        self.last_check = now;
        // Step 3: maps (relayed as they come).
        while self.waiting_any() {
            self.pump(link, self.next_timeout());
        }
        // Step 7 is each robot's own, after the exchange; step 5 follows it.
        self.phase = Phase::Choice;
        let now = Instant::now();
        self.exchange_wall_ms
            .push(now.duration_since(started).as_secs_f64() * 1e3);
        self.ready_since.iter_mut().for_each(|t| *t = now);
        self.last_progress = now;
        self.last_check = now;
        for k in 0..self.n {
            if self.alive[k] {
                // A robot still waiting for a higher-priority neighbour can
                // do nothing yet: it is woken with the last choice it waits
                // for (its stop test then runs; the world ends the round only
                // once every robot has chosen or one has stopped, so a stop
                // found later ends the search all the same).
                self.post(link, k, &FromWorld::ExchangeDone { round: self.round });
                if !self.blocked(k) {
                    link.wake(k);
                }
            }
        }
        link.flush();
        while !self.stopped && self.waiting_any() {
            self.pump(link, self.next_timeout());
        }
        self.choice_wall_ms.push(now.elapsed().as_secs_f64() * 1e3);
        if self.stopped || self.round >= self.set.max_rounds || self.alive_count() == 0 {
            self.end(link);
            self.round_wall_ms
                .push(started.elapsed().as_secs_f64() * 1e3);
            return false;
        }
        // Step 6: all moves at once. Failed robots stay where they are.
        for k in 0..self.n {
            self.next[k] = match (self.alive[k], self.choice[k]) {
                (true, Some(v)) => v,
                _ => self.referee.position(k),
            };
        }
        let longest = match self.set.policy {
            Policy::Ru => 1,
            _ => {
                for k in 0..self.n {
                    self.order[k] = k;
                }
                priority_order(&self.world.grid, self.referee.positions(), &mut self.order);
                longest_wait_chain(
                    &self.world.grid,
                    self.referee.positions(),
                    &self.nbrs,
                    &self.order,
                    &mut self.chain,
                )
            }
        };
        self.chain_len.push(longest);
        let report = self.referee.execute(&self.next);
        self.collisions += report.collisions;
        self.refused += report.refused;
        self.time += round_time(&self.world.params, longest, &report);
        self.round_end_times_s.push(self.time);
        self.robot_rounds += self.alive_count() as u64;
        self.round += 1;
        for k in 0..self.n {
            self.vertices[k].push(self.referee.position(k));
        }
        self.round_wall_ms
            .push(started.elapsed().as_secs_f64() * 1e3);
        true
    }

    fn end(&mut self, link: &mut impl Link) {
        // The agents' peak memory, while they still run.
        for k in 0..self.n {
            if let Some(pid) = self.pids[k] {
                self.agent_rss[k] = gridswarm::ipc::peak_rss_kib_of(pid);
                self.agent_cpu[k] = gridswarm::ipc::cpu_ms_of(pid);
            }
        }
        self.cpu_at_end = gridswarm::ipc::cpu_ms_of(std::process::id());
        for k in 0..self.n {
            if self.alive[k] {
                self.send(link, k, &FromWorld::End { round: self.round });
            }
        }
        link.flush();
    }

    /// Robots the world waits for in this phase.
    fn waiting(&self, k: usize) -> bool {
        self.alive[k]
            && match self.phase {
                Phase::Hello => self.pids[k].is_none(),
                Phase::Exchange => !self.map_in[k],
                Phase::Choice => self.choice[k].is_none(),
            }
    }

    fn waiting_any(&self) -> bool {
        (0..self.n).any(|k| self.waiting(k))
    }

    /// Whether robot `k` itself still waits for a higher-priority neighbour
    /// (then its silence is no sign of failure).
    fn blocked(&self, k: usize) -> bool {
        if self.phase != Phase::Choice || self.set.policy == Policy::Ru {
            return false;
        }
        let grid = &self.world.grid;
        let key = grid.priority_key(self.referee.position(k));
        self.nbrs[k].iter().any(|&j| {
            let j = j as usize;
            self.alive[j]
                && self.choice[j].is_none()
                && grid.priority_key(self.referee.position(j)) > key
        })
    }

    fn next_timeout(&self) -> Duration {
        let now = Instant::now();
        let check = (self.last_check.max(self.last_progress) + self.set.check)
            .saturating_duration_since(now);
        let mut t = check.max(Duration::from_millis(1));
        if self.phase != Phase::Hello {
            for k in 0..self.n {
                if self.waiting(k) && !self.blocked(k) {
                    t = t.min(
                        (self.ready_since[k] + self.set.suspect).saturating_duration_since(now),
                    );
                }
            }
        }
        t.max(Duration::from_micros(200))
    }

    /// Waits once, handles whatever arrived, checks for failures.
    fn pump(&mut self, link: &mut impl Link, timeout: Duration) {
        let mut woke = std::mem::take(&mut self.woke);
        woke.clear();
        link.wait(timeout, &mut woke);
        woke.sort_unstable();
        woke.dedup();
        for &k in &woke {
            if k < self.n {
                self.drain(link, k);
            }
        }
        self.woke = woke;
        let now = Instant::now();
        if now.duration_since(self.last_progress.max(self.last_check)) >= self.set.check {
            self.last_check = now;
            // A wake-up is only a hint: look at every outbox we wait on.
            for k in 0..self.n {
                if self.waiting(k) {
                    self.drain(link, k);
                }
            }
            if self.phase != Phase::Hello {
                self.check_deaths(link);
                self.check_deadlines(link);
            }
        }
        link.flush();
    }

    fn drain(&mut self, link: &mut impl Link, k: usize) {
        let mut buf = std::mem::take(&mut self.buf);
        while link.recv(k, &mut buf) {
            self.handle(link, k, &buf);
        }
        self.buf = buf;
    }

    /// Robots waited for whose process is gone: its pid is not running (a
    /// zombie counts as gone), or iceoryx2 lists its node as dead.
    fn check_deaths(&mut self, link: &mut impl Link) {
        let mut dead: Vec<usize> = (0..self.n)
            .filter(|&k| {
                self.waiting(k) && self.pids[k].is_some_and(|p| !gridswarm::ipc::pid_alive(p))
            })
            .collect();
        let now = Instant::now();
        if now.duration_since(self.last_node_list) >= 10 * self.set.check {
            self.last_node_list = now;
            for k in link.dead_robots() {
                if k < self.n && self.waiting(k) && !dead.contains(&k) {
                    dead.push(k);
                }
            }
        }
        dead.sort_unstable();
        for k in dead {
            self.declare(link, k, "death");
        }
    }

    fn check_deadlines(&mut self, link: &mut impl Link) {
        let now = Instant::now();
        let late: Vec<usize> = (0..self.n)
            .filter(|&k| {
                self.waiting(k)
                    && !self.blocked(k)
                    && now.duration_since(self.ready_since[k]) >= self.set.suspect
            })
            .collect();
        for k in late {
            // Blocked-ness changes as robots are declared; re-check.
            if self.waiting(k) && !self.blocked(k) {
                self.declare(link, k, "deadline");
                self.send(link, k, &FromWorld::Deposed { round: self.round });
            }
        }
    }

    /// A robot that comes within radio range of a failed robot finds it
    /// silent: the world tells it (once) that the robot failed, as it told
    /// the failed robot's neighbours when it was declared. Without this, a
    /// robot that died with nobody in range would stay unknown, and its
    /// vertex would look unvisited but never be reachable (rule 4 would
    /// never fire).
    fn tell_newcomers(&mut self, link: &mut impl Link) {
        let mut near = Vec::new();
        for f in 0..self.n {
            if self.told[f].is_none() {
                continue;
            }
            let alive = &self.alive;
            self.referee.radio(f, |j| alive[j], &mut near);
            let at = self.referee.position(f);
            let msg = FromWorld::Failed {
                round: self.round,
                robot: f as RobotId,
                at,
            };
            for &k in &near {
                let k = k as usize;
                if !self.told[f].as_ref().expect("checked")[k] {
                    self.told[f].as_mut().expect("checked")[k] = true;
                    // Read with the tick, before the robot can act.
                    self.post(link, k, &msg);
                    if let Some(d) = self.failures.iter_mut().find(|d| d.robot as usize == f) {
                        d.detected_by.push(k as RobotId);
                    }
                }
            }
        }
    }

    /// Sec. 4.2: robot `k` is failed for good, at the vertex it stands on.
    fn declare(&mut self, link: &mut impl Link, k: usize, cause: &str) {
        if !self.alive[k] {
            return;
        }
        self.alive[k] = false;
        let at = self.referee.position(k);
        let told: Vec<RobotId> = self.nbrs[k]
            .iter()
            .copied()
            .filter(|&j| self.alive[j as usize])
            .collect();
        let mut mark = vec![false; self.n];
        for &j in &told {
            mark[j as usize] = true;
        }
        self.told[k] = Some(mark);
        let msg = FromWorld::Failed {
            round: self.round,
            robot: k as RobotId,
            at,
        };
        for &j in &told {
            // During the exchange a robot cannot act on it before
            // `ExchangeDone` wakes it anyway.
            if self.phase == Phase::Choice {
                self.send(link, j as usize, &msg);
            } else {
                self.post(link, j as usize, &msg);
            }
        }
        let c = self.world.grid.coord(at);
        self.failures.push(Detection {
            robot: k as RobotId,
            round: self.round,
            at: [c.i, c.j],
            cause: cause.to_string(),
            detected_by: told.clone(),
            at_ms: self.ms(Instant::now()),
        });
        // Its neighbours no longer wait for it.
        let now = Instant::now();
        for &j in &told {
            self.ready_since[j as usize] = now;
        }
        self.last_progress = now;
    }

    /// One message from robot `i`'s outbox. Anything malformed, spoofed,
    /// stale or out of place is dropped and counted, never trusted.
    pub fn handle(&mut self, link: &mut impl Link, i: usize, bytes: &[u8]) {
        let m = match decode_to_world_exact(bytes, &self.limits) {
            Ok(m) => m,
            Err(_) => {
                self.dropped.malformed += 1;
                return;
            }
        };
        let m = match m {
            ToWorld::Hello { robot, pid } => {
                if robot as usize != i {
                    self.dropped.spoofed += 1;
                } else if self.phase != Phase::Hello || self.pids[i].is_some() {
                    self.dropped.unexpected += 1;
                } else {
                    self.pids[i] = Some(pid);
                    self.last_progress = Instant::now();
                }
                return;
            }
            ToWorld::Radio(m) => m,
        };
        if m.from() as usize != i {
            self.dropped.spoofed += 1;
            return;
        }
        if !self.alive[i] || m.round() < self.round {
            self.dropped.stale += 1;
            return;
        }
        if m.round() > self.round {
            self.dropped.unexpected += 1;
            return;
        }
        let now = Instant::now();
        match (&m, self.phase) {
            (Message::Targets { targets, .. }, Phase::Exchange)
                if self.set.situation == Situation::One && !self.map_in[i] =>
            {
                // Step 1: a broadcast, to every robot (as engine.rs does).
                for &t in targets {
                    self.known_targets.set(t as usize);
                }
                // Robots act on it only after `ExchangeDone`, which wakes them.
                for k in 0..self.n {
                    if k != i && self.alive[k] {
                        link.post(k, bytes);
                    }
                }
            }
            (Message::Map { at, .. }, Phase::Exchange) if !self.map_in[i] => {
                if *at != self.referee.position(i) {
                    // It claims to stand elsewhere than it does.
                    self.dropped.malformed += 1;
                    return;
                }
                for &j in &self.nbrs[i] {
                    if self.alive[j as usize] {
                        link.post(j as usize, bytes);
                    }
                }
                self.map_in[i] = true;
            }
            (Message::Choice { next, .. }, Phase::Choice) if self.choice[i].is_none() => {
                self.choice[i] = Some(*next);
                if self.set.policy != Policy::Ru {
                    for k in 0..self.nbrs[i].len() {
                        let j = self.nbrs[i][k] as usize;
                        if self.alive[j] {
                            link.post(j, bytes);
                            // The chain of step 5: wake a neighbour only
                            // once it has every choice it waits for.
                            if self.choice[j].is_none() && !self.blocked(j) {
                                link.wake(j);
                                self.ready_since[j] = now;
                            }
                        }
                    }
                }
            }
            (Message::Stop { .. }, Phase::Choice) => self.stopped = true,
            _ => {
                self.dropped.unexpected += 1;
                return;
            }
        }
        self.last_progress = now;
    }

    /// The run's report, once [`Server::play_round`] returned false.
    pub fn report(&self, ended_by: &str, world_fds: usize, world_peak_rss_kib: u64) -> RunReport {
        let world = self.world;
        let complete = match (self.set.situation, self.stopped) {
            // Rule (3): every robot knows every target (in situation 1 every
            // robot knows exactly the targets broadcast, so all robots' stop
            // rules agree; see engine.rs, which takes the first robot's).
            (Situation::One, true) => self.known_targets.count() >= world.targets.len(),
            (Situation::Two, true) => {
                // Every vertex of Va the alive robots can still reach, failed
                // robots' vertices blocked, was visited. With no failure this
                // is all of Va, as in engine.rs.
                let failed: Vec<VertexId> = (0..self.n)
                    .filter(|&k| !self.alive[k])
                    .map(|k| self.referee.position(k))
                    .collect();
                let from: Vec<VertexId> = (0..self.n)
                    .filter(|&k| self.alive[k])
                    .map(|k| self.referee.position(k))
                    .collect();
                let va = if failed.is_empty() {
                    world.reachable_from(&self.starts)
                } else {
                    reachable_avoiding(world, &from, &failed)
                };
                (0..world.grid.len()).all(|v| !va[v] || self.referee.visited().get(v))
            }
            _ => false,
        };
        let centres: Vec<Point> = self
            .referee
            .visited()
            .iter()
            .map(|v| world.grid.position(v as VertexId))
            .collect();
        let coverage = world
            .raster(RASTER_CELL * world.params.a)
            .detected_fraction(centres, world.params.r_st);
        RunReport {
            result: RunResult {
                algorithm: self.set.policy,
                robots: self.n,
                seed: self.set.seed,
                situation: self.set.situation.number(),
                rounds: self.round,
                search_time_s: self.time,
                targets_found: self.referee.found().count(),
                targets_total: world.targets.len(),
                collisions: self.collisions,
                coverage: Some(coverage),
                complete,
                robot_rounds: self.robot_rounds,
                trajectories: Vec::new(),
            },
            vertices: self.vertices.clone(),
            failures: self.failures.clone(),
            refused_moves: self.refused,
            dropped: self.dropped.clone(),
            round_wall_ms: self.round_wall_ms.clone(),
            exchange_wall_ms: self.exchange_wall_ms.clone(),
            choice_wall_ms: self.choice_wall_ms.clone(),
            chain: self.chain_len.clone(),
            round_end_times_s: self.round_end_times_s.clone(),
            agent_peak_rss_kib: self.agent_rss.clone(),
            world_cpu_ms: self.cpu_at_end - self.cpu_at_hello,
            agent_cpu_ms: self.agent_cpu.clone(),
            pauses: self.pauses.clone(),
            startup_ms: self.startup_ms,
            world_peak_rss_kib,
            world_fds,
            ended_by: ended_by.to_string(),
        }
    }

    pub fn stopped(&self) -> bool {
        self.stopped
    }
}

/// Accessible vertices reachable from `from` over traversable edges without
/// entering any of `blocked`.
fn reachable_avoiding(world: &World, from: &[VertexId], blocked: &[VertexId]) -> Vec<bool> {
    let grid = &world.grid;
    let mut seen = vec![false; grid.len()];
    let mut stop = vec![false; grid.len()];
    for &b in blocked {
        stop[b as usize] = true;
    }
    let mut queue: Vec<VertexId> = Vec::new();
    for &s in from {
        if !seen[s as usize] {
            seen[s as usize] = true;
            queue.push(s);
        }
    }
    while let Some(v) = queue.pop() {
        for &w in &grid.neighbors(v)[..grid.degree()] {
            if w != gridswarm::grid::NONE
                && !seen[w as usize]
                && !stop[w as usize]
                && world.can_move(v, w)
            {
                seen[w as usize] = true;
                queue.push(w);
            }
        }
    }
    seen
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridswarm::map::Map;
    use gridswarm::protocol::encode_to_world;
    use gridswarm::scenario::Scenario;

    /// A link that records what the world sends and delivers nothing.
    #[derive(Default)]
    struct Recorder {
        sent: Vec<(usize, Vec<u8>)>,
    }

    impl Link for Recorder {
        fn post(&mut self, robot: usize, bytes: &[u8]) {
            self.sent.push((robot, bytes.to_vec()));
        }
        fn wake(&mut self, _: usize) {}
        fn flush(&mut self) {}
        fn wait(&mut self, _: Duration, _: &mut Vec<usize>) {}
        fn recv(&mut self, _: usize, _: &mut Vec<u8>) -> bool {
            false
        }
        fn dead_robots(&mut self) -> Vec<usize> {
            Vec::new()
        }
    }

    fn settings() -> Settings {
        Settings {
            policy: Policy::Repulsive,
            situation: Situation::One,
            seed: 1,
            max_rounds: 100,
            check: Duration::from_millis(20),
            suspect: Duration::from_secs(2),
            hello_timeout: Duration::from_secs(1),
        }
    }

    fn hello_all(s: &mut Server, link: &mut Recorder, n: usize) {
        for k in 0..n {
            s.handle(
                link,
                k,
                &encode_to_world(&ToWorld::Hello {
                    robot: k as RobotId,
                    pid: 1,
                }),
            );
        }
    }

    #[test]
    fn malformed_spoofed_stale_and_misplaced_bytes_are_dropped_and_counted() {
        let sc = Scenario::builtin("paper").unwrap();
        let world = sc.world();
        let starts = sc.start_vertices(&world, 3).unwrap();
        let mut s = Server::new(&world, &starts, settings());
        let mut link = Recorder::default();
        // Garbage, truncated and trailing bytes.
        s.handle(&mut link, 0, &[]);
        s.handle(&mut link, 0, &[0xff; 40]);
        let mut hello = encode_to_world(&ToWorld::Hello { robot: 0, pid: 7 });
        hello.push(1);
        s.handle(&mut link, 0, &hello);
        assert_eq!(s.dropped().malformed, 3);
        // Robot 1 speaking as robot 0.
        s.handle(
            &mut link,
            1,
            &encode_to_world(&ToWorld::Hello { robot: 0, pid: 7 }),
        );
        assert_eq!(s.dropped().spoofed, 1);
        hello_all(&mut s, &mut link, 3);
        // A second hello.
        s.handle(
            &mut link,
            2,
            &encode_to_world(&ToWorld::Hello { robot: 2, pid: 1 }),
        );
        assert_eq!(s.dropped().unexpected, 1);
        // Out of range ids never reach the round logic.
        let bad = ToWorld::Radio(Message::Choice {
            round: 0,
            from: 0,
            next: world.grid.len() as u32,
        });
        s.handle(&mut link, 0, &encode_to_world(&bad));
        assert_eq!(s.dropped().malformed, 4);
        // Round 0, exchange phase: a choice is out of place, a map from the
        // wrong vertex is refused, a map from a future round is unexpected.
        s.phase = Phase::Exchange;
        let choice = ToWorld::Radio(Message::Choice {
            round: 0,
            from: 0,
            next: starts[0],
        });
        s.handle(&mut link, 0, &encode_to_world(&choice));
        assert_eq!(s.dropped().unexpected, 2);
        let map = Map::new(world.grid.len(), world.targets.len());
        let wrong = ToWorld::Radio(Message::Map {
            round: 0,
            from: 0,
            at: starts[1],
            map: map.clone(),
        });
        s.handle(&mut link, 0, &encode_to_world(&wrong));
        assert_eq!(s.dropped().malformed, 5);
        let future = ToWorld::Radio(Message::Map {
            round: 3,
            from: 0,
            at: starts[0],
            map: map.clone(),
        });
        s.handle(&mut link, 0, &encode_to_world(&future));
        assert_eq!(s.dropped().unexpected, 3);
        assert!(link.sent.is_empty(), "nothing was relayed");
        // A good map is relayed verbatim to the radio neighbours only.
        s.nbrs[0] = vec![1];
        let good = encode_to_world(&ToWorld::Radio(Message::Map {
            round: 0,
            from: 0,
            at: starts[0],
            map,
        }));
        s.handle(&mut link, 0, &good);
        assert_eq!(link.sent, vec![(1, good.clone())]);
        assert!(s.map_in[0]);
        // The same map again is out of place; from a failed robot, stale.
        s.handle(&mut link, 0, &good);
        assert_eq!(s.dropped().unexpected, 4);
        s.alive[0] = false;
        s.handle(&mut link, 0, &good);
        assert_eq!(s.dropped().stale, 1);
        assert_eq!(link.sent.len(), 1);
    }

    #[test]
    fn a_silent_robot_is_declared_and_its_neighbours_told() {
        let sc = Scenario::builtin("paper").unwrap();
        let world = sc.world();
        let starts = sc.start_vertices(&world, 3).unwrap();
        let mut set = settings();
        set.suspect = Duration::from_millis(30);
        set.check = Duration::from_millis(5);
        let mut s = Server::new(&world, &starts, set);
        let mut link = Recorder::default();
        hello_all(&mut s, &mut link, 3);
        s.phase = Phase::Exchange;
        s.nbrs[1] = vec![0, 2];
        s.nbrs[0] = vec![1];
        s.nbrs[2] = vec![1];
        s.map_in[0] = true;
        s.map_in[2] = true;
        let past = Instant::now() - Duration::from_millis(50);
        s.ready_since[1] = past;
        s.last_progress = past;
        s.last_check = past;
        s.pump(&mut link, Duration::ZERO);
        assert!(!s.alive[1]);
        assert_eq!(s.failures.len(), 1);
        assert_eq!(s.failures[0].cause, "deadline");
        assert_eq!(s.failures[0].detected_by, vec![0, 2]);
        let told: Vec<(usize, FromWorld)> = link
            .sent
            .iter()
            .map(|(k, b)| {
                (
                    *k,
                    gridswarm::protocol::decode_from_world(b, &s.limits).unwrap(),
                )
            })
            .collect();
        let failed = FromWorld::Failed {
            round: 0,
            robot: 1,
            at: starts[1],
        };
        assert_eq!(
            told,
            vec![
                (0, failed.clone()),
                (2, failed),
                (1, FromWorld::Deposed { round: 0 })
            ]
        );
        assert!(!s.waiting_any());
    }
}
