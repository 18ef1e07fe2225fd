//! The handshake of a distributed run. Before the first slot every robot
//! says hello with the run's agreement as it holds it
//! ([`gridswarm::agreement`]). The world answers each with a verdict: it
//! accepts, once every robot has said hello, a hello that agrees with its
//! own, and refuses at once, naming what differs on both sides, one that
//! does not, one claiming a robot number outside the team, or a second
//! claim to a number taken. A refusal before the first slot ends the run
//! ([`Failure::Refused`]): the agents whose hellos it held are refused
//! too, and the world lingers a moment so that every agent reads its
//! verdict. A claim that comes once the run is under way is refused and
//! changes nothing.

use std::time::{Duration, Instant};

use gridswarm::agreement;
use gridswarm::ipc;
use gridswarm::wire::{self, Assembler, Hello, ToAgent, ToWorld, Verdict, HANDSHAKE};

use super::Remote;

/// How long a world that refused an agent before the first slot goes on
/// refusing hellos, so that the agents read their verdicts before it goes.
const LINGER: Duration = Duration::from_secs(1);

/// Why the world does not run.
#[derive(Debug)]
pub enum Failure {
    /// An agent does not agree with the world (exit status 2, as a usage error).
    Refused(String),
    Other(String),
}

impl From<String> for Failure {
    fn from(e: String) -> Self {
        Failure::Other(e)
    }
}

/// The agent that holds a robot number.
pub(super) struct Claim {
    nonce: u64,
    pid: u32,
    host: String,
}

/// `robot-agent 3 (pid 42 on lab2)`, its host's name escaped.
fn who(h: &Hello, r: usize) -> String {
    format!("robot-agent {r} (pid {} on {})", h.pid, agreement::shown(&h.host))
}

impl Remote<'_> {
    /// Waits until every robot has said hello (within `timeout`), and
    /// answers each; a refusal ends the wait, and the run.
    pub fn hello(&mut self, timeout: Duration) -> Result<(), Failure> {
        let start = Instant::now();
        let mut missing = self.pids.len();
        while missing > 0 {
            if start.elapsed() > timeout {
                let who: Vec<usize> = (0..self.pids.len()).filter(|&r| self.pids[r] == 0).take(10).collect();
                let why = self.recv_error.take().map(|(r, e)| format!("; robot {r}'s outbox: {e}")).unwrap_or_default();
                return Err(
                    format!("{missing} robot(s) did not say hello within {timeout:?}, e.g. {who:?}{why}").into()
                );
            }
            let refused = self.hellos(&mut missing)?;
            if let Some(why) = refused.or_else(|| self.refuse_strangers()) {
                return Err(self.call_off(why));
            }
        }
        Ok(self.accept_all()?)
    }

    /// Reads the hellos that came within a short wait and answers them;
    /// counts the robots accepted off `missing`. Returns the first refusal.
    fn hellos(&mut self, missing: &mut usize) -> Result<Option<String>, String> {
        self.woke.clear();
        let mut woke = std::mem::take(&mut self.woke);
        self.ports.wait(Duration::from_millis(50), &mut woke);
        self.heartbeat()?;
        let n = self.pids.len();
        let mut refused = None;
        for &r in woke.iter().filter(|&&r| r < n) {
            while let Some(m) = self.take(r) {
                if let ToWorld::Hello(h) = m {
                    match self.claim(r, &h)? {
                        Ok(true) => *missing -= 1,
                        Ok(false) => {}
                        Err(why) => {
                            refused.get_or_insert(why);
                        }
                    }
                }
            }
        }
        self.woke = woke;
        Ok(refused)
    }

    /// Answers robot `r`'s hello: `Ok(true)` accepted (told once every
    /// robot is: [`Remote::accept_all`]), `Ok(false)` a repeat or not a
    /// hello to count, `Err` refused (told at once).
    fn claim(&mut self, r: usize, h: &Hello) -> Result<Result<bool, String>, String> {
        if h.robot as usize != r || h.pid == 0 {
            self.dropped += 1;
            return Ok(Ok(false));
        }
        let refusal = match &self.claims[r] {
            Some(c) if c.nonce == h.nonce => None,
            Some(c) => Some(format!(
                "{} claims robot {r}, which is already taken by pid {} on {}",
                who(h, r),
                c.pid,
                agreement::shown(&c.host)
            )),
            None => {
                let d = self.agreement.differences(&h.agreement);
                (!d.is_empty()).then(|| format!("{} does not agree with the world: {}", who(h, r), d.join("; ")))
            }
        };
        if let Some(why) = refusal {
            self.verdict(r, h.nonce, Some(why.clone()))?;
            return Ok(Err(why));
        }
        let fresh = self.claims[r].is_none();
        self.claims[r] = Some(Claim { nonce: h.nonce, pid: h.pid, host: h.host.clone() });
        self.pids[r] = h.pid;
        Ok(Ok(fresh))
    }

    /// Accepts every robot, once all have said hello. Not before: over
    /// iceoryx2 a robot's first message and first wake-up each cost the
    /// world a connection, better spent reading every hello first (a
    /// world short of descriptors then says so at its first wake-up,
    /// `cannot wake robot`, instead of missing hellos).
    fn accept_all(&self) -> Result<(), String> {
        for (r, c) in self.claims.iter().enumerate() {
            if let Some(c) = c {
                self.verdict(r, c.nonce, None)?;
            }
        }
        Ok(())
    }

    /// Posts a verdict into robot `r`'s inbox. The robot is not woken: an
    /// agent waiting for its verdict looks at its inbox every
    /// `--world-timeout-ms` anyway, and its first wake-up follows.
    fn verdict(&self, r: usize, nonce: u64, refusal: Option<String>) -> Result<(), String> {
        let bytes = wire::encode_to_agent(&ToAgent::Verdict(Verdict { nonce, refusal }));
        self.ports.post(r, HANDSHAKE, &bytes)
    }

    /// Refuses every hello sent under a robot number outside the team;
    /// returns the first refusal.
    pub(super) fn refuse_strangers(&mut self) -> Option<String> {
        let mut first = None;
        while let Some(r) = self.ports.stranger(&mut self.buf) {
            let mut asm = Assembler::new(ipc::OUTBOX_CHUNKS * ipc::CHUNK_BYTES);
            let hello = match asm.push(&self.buf) {
                Ok(Some((_, bytes))) => wire::decode_to_world(bytes, &self.limits),
                _ => continue,
            };
            let Ok(ToWorld::Hello(h)) = hello else {
                self.dropped += 1;
                continue;
            };
            let why = format!(
                "{} claims robot {r}, which is not in this run: its {} robot(s) are numbered {}",
                who(&h, r),
                self.pids.len(),
                agreement::robot_range(self.pids.len())
            );
            let verdict = ToAgent::Verdict(Verdict { nonce: h.nonce, refusal: Some(why.clone()) });
            let _ = self.ports.post_stranger(r, &wire::encode_to_agent(&verdict));
            first.get_or_insert(why);
        }
        first
    }

    /// Ends the run before its first slot for `why`: refuses the agents
    /// accepted so far, then every hello for [`LINGER`], so that each agent
    /// hears why.
    fn call_off(&mut self, why: String) -> Failure {
        let off = format!("the run is off: {why}");
        for r in 0..self.claims.len() {
            if let Some(nonce) = self.claims[r].take().map(|c| c.nonce) {
                let _ = self.verdict(r, nonce, Some(off.clone()));
            }
        }
        let until = Instant::now() + LINGER;
        while Instant::now() < until {
            let mut woke = std::mem::take(&mut self.woke);
            woke.clear();
            self.ports.wait(Duration::from_millis(20), &mut woke);
            let n = self.claims.len();
            for &r in woke.iter().filter(|&&r| r < n) {
                while let Some(m) = self.take(r) {
                    if let ToWorld::Hello(h) = m {
                        let _ = self.verdict(r, h.nonce, Some(off.clone()));
                    }
                }
            }
            self.woke = woke;
            self.refuse_strangers();
        }
        Failure::Refused(why)
    }

    /// A hello once the run is under way: a repeat of an accepted one is
    /// accepted again (its verdict may have been lost), any other claim
    /// refused (the run goes on without it).
    pub(super) fn late_hello(&mut self, r: usize, h: &Hello) {
        match &self.claims[r] {
            Some(c) if c.nonce == h.nonce => {
                let _ = self.verdict(r, h.nonce, None);
            }
            _ => {
                let taken = self.claims[r].as_ref().map(|c| (c.pid, agreement::shown(&c.host).into_owned()));
                let why = match taken {
                    Some((pid, host)) => format!(
                        "{} claims robot {r}, which is already taken by pid {pid} on {host}, and the run is under way",
                        who(h, r)
                    ),
                    None => format!("{} came after the run started without robot {r}", who(h, r)),
                };
                let _ = self.verdict(r, h.nonce, Some(why));
            }
        }
    }
}
