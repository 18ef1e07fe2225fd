//! Robots in other processes, as the simulated world ([`gridswarm::sim`])
//! sees them: [`Remote`] implements [`Robots`] over a [`WorldTransport`]
//! (iceoryx2 or zenoh).
//! Frames are opaque bytes (`Rc<[u8]>`): the world carries them and never
//! decodes one.
//!
//! A wake-up publishes every call, then waits for every called robot's
//! answer (matched by sequence number; stale answers are dropped). A robot
//! that stays silent is checked after a short while: if the transport says
//! it is gone (iceoryx2: its node dead, or no process under its pid;
//! zenoh: its liveliness token vanished) its answer is
//! `None` and the kernel counts it dead. A live robot silent for longer
//! than the run's patience is an error that ends the run, naming it, and
//! so is a wake-up that reaches no listener of a live robot.
//!
//! At a fault the world pauses: it prints `fault K` and waits for `go` on
//! stdin while the orchestrator signals the robot's process.
//!
//! Before the first slot every robot says hello and is answered ([`hello`]).

use std::io::{BufRead, Write};
use std::rc::Rc;
use std::time::{Duration, Instant};

use gridswarm::agreement::Agreement;
use gridswarm::ipc;
use gridswarm::sim::{Delivery, Fault, Output, Robots, Time, Transmit, WakeCall};
use gridswarm::transport::WorldTransport;
use gridswarm::wire::{self, AgentOutput, Assembler, ByteSlice, ToAgent, ToWorld, WakeRef, WireFrameRef, WireLimits};

use hello::Claim;
pub use hello::Failure;

mod hello;

/// A robot's answer to a wake-up, once collected: `Some(None)` when it
/// turned out dead.
type Slot = Option<Option<Output<Rc<[u8]>>>>;

/// How often a waiting world says `alive` (with `--progress`): the
/// orchestrator ends a run whose world says nothing for 10 s, stopped
/// (SIGSTOP) or stuck.
const HEARTBEAT: Duration = Duration::from_secs(1);

/// How long the world waits, and whom it tells about progress.
pub struct Patience {
    /// Silence after which it checks whether silent robots still exist.
    pub check: Duration,
    /// Silence of a live robot that ends the run.
    pub limit: Duration,
    /// Print `tick K` at the start of every slot, and `alive` every
    /// [`HEARTBEAT`] while waiting.
    pub progress: bool,
}

/// The robots of a run, each in its own process.
pub struct Remote<'a> {
    ports: &'a dyn WorldTransport,
    /// The world's: every hello must present the same.
    agreement: Agreement,
    claims: Vec<Option<Claim>>,
    limits: WireLimits,
    patience: Patience,
    faults: Vec<Fault>,
    pids: Vec<u32>,
    gone: Vec<bool>,
    asm: Vec<Assembler>,
    seq: u64,
    buf: Vec<u8>,
    /// The last wake-up encoded (its allocation reused).
    encoded: Vec<u8>,
    woke: Vec<usize>,
    /// Why the run cannot go on; every later wake-up answers `None`.
    pub failed: Option<String>,
    /// Wall time per round, pauses left out.
    pub round_wall_ms: Vec<f64>,
    slot_start: Option<Instant>,
    paused: Duration,
    pub paused_total: Duration,
    pub dropped: u64,
    /// Times the world checked whether silent robots still exist.
    pub liveness_checks: u64,
    /// Wake-ups of several robots at one simulated instant (round trips).
    pub batches: u64,
    /// Bytes of the largest wake-up message.
    pub largest_wake: usize,
    /// The last failure to read a robot's outbox: (robot, error).
    recv_error: Option<(usize, String)>,
    /// When the world last printed a line to the orchestrator.
    said: Instant,
}

impl<'a> Remote<'a> {
    pub fn new(
        ports: &'a dyn WorldTransport,
        agreement: Agreement,
        limits: WireLimits,
        patience: Patience,
        faults: Vec<Fault>,
    ) -> Self {
        let n = limits.robots;
        Remote {
            ports,
            agreement,
            claims: (0..n).map(|_| None).collect(),
            limits,
            patience,
            faults,
            pids: vec![0; n],
            gone: vec![false; n],
            asm: (0..n).map(|_| Assembler::new(ipc::OUTBOX_CHUNKS * ipc::CHUNK_BYTES)).collect(),
            seq: 0,
            buf: Vec::with_capacity(ipc::CHUNK_BYTES),
            encoded: Vec::new(),
            woke: Vec::new(),
            failed: None,
            round_wall_ms: Vec::new(),
            slot_start: None,
            paused: Duration::ZERO,
            paused_total: Duration::ZERO,
            dropped: 0,
            liveness_checks: 0,
            batches: 0,
            largest_wake: 0,
            recv_error: None,
            said: Instant::now(),
        }
    }

    /// `alive` to the orchestrator, if the world said nothing for a [`HEARTBEAT`].
    fn heartbeat(&mut self) -> Result<(), String> {
        if self.patience.progress && self.said.elapsed() >= HEARTBEAT {
            self.said = Instant::now();
            say("alive")?;
        }
        Ok(())
    }

    pub fn pids(&self) -> &[u32] {
        &self.pids
    }

    /// Robots whose process vanished while the world waited on them.
    pub fn died(&self) -> Vec<usize> {
        (0..self.gone.len()).filter(|&r| self.gone[r]).collect()
    }

    /// The next complete, valid message in robot `r`'s outbox (a failure
    /// to read it is kept in `recv_error`).
    fn take(&mut self, r: usize) -> Option<ToWorld> {
        loop {
            match self.ports.recv(r, &mut self.buf) {
                Ok(true) => {}
                Ok(false) => return None,
                Err(e) => {
                    self.recv_error = Some((r, e));
                    return None;
                }
            }
            match self.asm[r].push(&self.buf) {
                Ok(Some((_, bytes))) => match wire::decode_to_world(bytes, &self.limits) {
                    Ok(m) => return Some(m),
                    Err(_) => self.dropped += 1,
                },
                Ok(None) => {}
                Err(_) => self.dropped += 1,
            }
        }
    }

    /// Tells every robot still there that the run is over.
    pub fn end(&mut self) {
        let bytes = wire::encode_to_agent(&ToAgent::End);
        self.seq += 1;
        for r in 0..self.pids.len() {
            // A robot that cannot hear `End` is killed by the orchestrator.
            if !self.gone[r] && self.ports.post(r, self.seq, &bytes).is_ok() {
                let _ = self.ports.notify(r);
            }
        }
    }

    /// Closes the wall-time record of the last round.
    pub fn finish_rounds(&mut self) {
        if let Some(t) = self.slot_start.take() {
            let wall = t.elapsed().saturating_sub(self.paused);
            self.round_wall_ms.push(wall.as_secs_f64() * 1e3);
        }
    }

    fn publish(&mut self, calls: &[WakeCall<Rc<[u8]>>]) -> Result<(), String> {
        let mut bytes = std::mem::take(&mut self.encoded);
        for c in calls {
            let wake = WakeRef {
                seq: self.seq,
                now: c.now,
                tick: c.tick.as_ref(),
                frames: c.frames.iter().map(frame).collect(),
            };
            wire::encode_wake_into(&wake, &mut bytes);
            self.ports.post(c.robot, self.seq, &bytes)?;
            self.largest_wake = self.largest_wake.max(bytes.len());
        }
        self.encoded = bytes;
        // Every inbox filled before the first robot runs: a woken robot
        // may take the world's core at once.
        for c in calls {
            if !self.ports.notify(c.robot) {
                self.unreachable(c.robot)?;
            }
        }
        Ok(())
    }

    /// A wake-up that reached no one: fine if the robot's process is gone
    /// (its silence will bury it), an error otherwise, for the robot
    /// would never hear the world and the run would crawl on time-outs.
    fn unreachable(&self, r: usize) -> Result<(), String> {
        let pid = self.pids[r];
        if self.ports.liveness(r, pid) == Some(false) {
            return Ok(());
        }
        // Counting open files would itself need a descriptor: say the limit.
        let limit = gridswarm::nofile::limits().map_or_else(|_| "unknown".into(), |(soft, _)| soft.to_string());
        Err(format!(
            "cannot wake robot {r} (pid {pid}): its listener cannot be reached (out of open files? the limit is {limit})"
        ))
    }

    /// Collects the answers to `calls` into `slots`.
    fn collect(&mut self, calls: &[WakeCall<Rc<[u8]>>], slots: &mut [Slot]) -> Result<(), String> {
        let mut missing = calls.len();
        let mut heard = Instant::now();
        let mut last_check: Option<Instant> = None;
        while missing > 0 {
            let mut woke = std::mem::take(&mut self.woke);
            woke.clear();
            self.ports.wait(self.patience.check, &mut woke);
            self.heartbeat()?;
            for &r in &woke {
                let Ok(k) = calls.binary_search_by_key(&r, |c| c.robot) else { continue };
                while let Some(m) = self.take(r) {
                    match m {
                        ToWorld::Output(o) if o.seq == self.seq && slots[k].is_none() => {
                            slots[k] = Some(Some(output(o)));
                            missing -= 1;
                            heard = Instant::now();
                            last_check = None;
                        }
                        ToWorld::Hello(h) => self.late_hello(r, &h),
                        _ => self.dropped += 1,
                    }
                }
            }
            self.woke = woke;
            self.refuse_strangers();
            // An outbox the world cannot read would look like silence.
            if let Some((r, e)) = self.recv_error.take() {
                if self.ports.liveness(r, self.pids[r]) != Some(false) {
                    return Err(format!("cannot read robot {r}'s answers (pid {}): {e}", self.pids[r]));
                }
            }
            if missing == 0 {
                break;
            }
            if missing > 1 {
                // Let the robots still computing have the core rather than
                // wake the world once per answer.
                std::thread::yield_now();
            }
            // After a short silence, and now and then after that: is a
            // silent robot's process gone?
            let due = last_check.is_none_or(|t| t.elapsed() >= self.patience.check * 10);
            if heard.elapsed() >= self.patience.check && due {
                missing -= self.bury_the_dead(calls, slots);
                last_check = Some(Instant::now());
            }
            if missing > 0 && heard.elapsed() >= self.patience.limit {
                let r = calls.iter().zip(slots.iter()).find(|(_, s)| s.is_none()).map_or(0, |(c, _)| c.robot);
                return Err(format!(
                    "robot {r} (pid {}) is alive but has not answered for {} s",
                    self.pids[r],
                    self.patience.limit.as_secs_f64()
                ));
            }
        }
        Ok(())
    }

    /// Answers `None` for every silent robot the transport finds gone;
    /// returns how many. Its quick check (iceoryx2: `/proc`, microseconds
    /// per robot) goes first; the thorough one (iceoryx2's node list reads
    /// every node's files, milliseconds at 200 robots) only when the quick
    /// one cannot tell (see [`ipc::pid_alive`]).
    fn bury_the_dead(&mut self, calls: &[WakeCall<Rc<[u8]>>], slots: &mut [Slot]) -> usize {
        self.liveness_checks += 1;
        let mut dead_nodes: Option<Vec<usize>> = None;
        let mut n = 0;
        for (k, c) in calls.iter().enumerate() {
            let r = c.robot;
            if slots[k].is_some() {
                continue;
            }
            let gone = match self.ports.liveness(r, self.pids[r]) {
                Some(alive) => !alive,
                None => dead_nodes.get_or_insert_with(|| self.ports.gone()).contains(&r),
            };
            if gone {
                slots[k] = Some(None);
                self.gone[r] = true;
                n += 1;
            }
        }
        n
    }
}

fn frame(d: &Delivery<Rc<[u8]>>) -> WireFrameRef<'_> {
    WireFrameRef { from: d.from, at: d.at, bytes: ByteSlice(&d.payload) }
}

fn output(o: AgentOutput) -> Output<Rc<[u8]>> {
    Output {
        send: o
            .send
            .into_iter()
            .map(|s| Transmit { payload: Rc::from(s.bytes.0), ready: s.ready, copies: s.copies })
            .collect(),
        motor: o.motor,
        alarm: o.alarm,
        listen: o.listen,
        notes: o.notes,
    }
}

/// One line to the orchestrator.
pub fn say(line: &str) -> Result<(), String> {
    let mut out = std::io::stdout().lock();
    writeln!(out, "{line}").and_then(|_| out.flush()).map_err(|e| format!("cannot write to stdout: {e}"))
}

/// Waits for the line `go` on stdin.
fn wait_go() -> Result<(), String> {
    let mut line = String::new();
    let n = std::io::stdin().lock().read_line(&mut line).map_err(|e| format!("cannot read stdin: {e}"))?;
    match (n, line.trim()) {
        (0, _) => Err("stdin closed while paused at a fault".into()),
        (_, "go") => Ok(()),
        (_, other) => Err(format!("expected `go` on stdin, got `{other}`")),
    }
}

impl Robots for Remote<'_> {
    type Payload = Rc<[u8]>;

    fn wake(&mut self, calls: &mut [WakeCall<Rc<[u8]>>], outputs: &mut Vec<Option<Output<Rc<[u8]>>>>) {
        let calls: &[WakeCall<Rc<[u8]>>] = calls;
        outputs.clear();
        if self.failed.is_none() {
            self.seq += 1;
            self.batches += 1;
            let mut slots: Vec<Slot> = vec![None; calls.len()];
            let res = self.publish(calls).and_then(|()| self.collect(calls, &mut slots));
            match res {
                Ok(()) => {
                    outputs.extend(slots.into_iter().map(Option::flatten));
                    return;
                }
                Err(e) => self.failed = Some(e),
            }
        }
        outputs.extend(calls.iter().map(|_| None));
    }

    fn slot_started(&mut self, round: u32, _now: Time) {
        self.finish_rounds();
        self.slot_start = Some(Instant::now());
        self.paused = Duration::ZERO;
        if self.patience.progress && self.failed.is_none() {
            self.said = Instant::now();
            if let Err(e) = say(&format!("tick {round}")) {
                self.failed = Some(e);
            }
        }
    }

    fn inject(&mut self, fault: &Fault, _now: Time) {
        if self.failed.is_some() {
            return;
        }
        let Some(k) = self.faults.iter().position(|f| f == fault) else { return };
        let t = Instant::now();
        if let Err(e) = say(&format!("fault {k}")).and_then(|()| wait_go()) {
            self.failed = Some(e);
        }
        self.paused += t.elapsed();
        self.paused_total += t.elapsed();
    }
}
