//! The world's zenoh side: a router with a publisher into every robot's
//! inbox, one subscriber on every robot's answers, and one on the robots'
//! liveliness tokens.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::time::{Duration, Instant};

use zenoh::handlers::{FifoChannel, FifoChannelHandler};
use zenoh::liveliness::LivelinessToken;
use zenoh::pubsub::{Publisher, Subscriber};
use zenoh::sample::{Sample, SampleKind};
use zenoh::{Session, Wait};

use super::retry::Outstanding;
use super::{err, one_chunk, publisher, NetConfig};
use crate::credentials::Holder;
use crate::ipc;
use crate::WorldTransport;
use gridswarm_robot::wire::HANDSHAKE;

/// Answers the world's subscriber holds before zenoh's receiving thread
/// waits for the world to read them (every robot's answer to one wake-up).
const QUEUE: usize = 8192;
/// Chunks of robots outside the team kept for the world to refuse; more
/// are dropped (a flood of them must not grow the world).
const STRANGERS: usize = 64;

/// What the world knows of a robot's token.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Presence {
    Unseen,
    Alive,
    Gone,
}

pub struct ZenohWorld {
    inboxes: Vec<Publisher<'static>>,
    answers: Subscriber<FifoChannelHandler<Sample>>,
    tokens: Subscriber<FifoChannelHandler<Sample>>,
    /// Declared last: a robot that sees it can be heard.
    _token: LivelinessToken,
    /// Chunks received, by robot, not read yet.
    queues: RefCell<Vec<VecDeque<Vec<u8>>>>,
    presence: RefCell<Vec<Presence>>,
    /// Messages not answered yet, put again until they are.
    outstanding: RefCell<Outstanding>,
    /// Chunks sent under robot numbers outside the team, with the number.
    strangers: RefCell<VecDeque<(usize, Vec<u8>)>>,
    root: String,
    out_prefix: String,
    alive_prefix: String,
    /// Dropped last (fields drop in order).
    session: Session,
}

impl ZenohWorld {
    /// Opens the world's router for `robots` robots.
    pub fn open(net: &NetConfig, robots: usize) -> Result<Self, String> {
        let root = net.root()?;
        let config = net.zenoh(Holder::World, robots)?;
        let session = zenoh::open(config).wait().map_err(err("cannot open the world's session"))?;
        let inboxes = (0..robots)
            .map(|r| publisher(&session, format!("{root}/in/{r}"), "cannot declare a publisher"))
            .collect::<Result<Vec<_>, _>>()?;
        let answers = session
            .declare_subscriber(format!("{root}/out/*"))
            .with(FifoChannel::new(QUEUE))
            .wait()
            .map_err(err("cannot declare the answers' subscriber"))?;
        let tokens = session
            .liveliness()
            .declare_subscriber(format!("{root}/alive/*"))
            .history(true)
            .with(FifoChannel::new(QUEUE))
            .wait()
            .map_err(err("cannot follow the robots' tokens"))?;
        let token = session
            .liveliness()
            .declare_token(format!("{root}/world"))
            .wait()
            .map_err(err("cannot declare the world's token"))?;
        Ok(ZenohWorld {
            inboxes,
            answers,
            tokens,
            _token: token,
            queues: RefCell::new(vec![VecDeque::new(); robots]),
            presence: RefCell::new(vec![Presence::Unseen; robots]),
            outstanding: RefCell::new(Outstanding::new(robots)),
            strangers: RefCell::new(VecDeque::new()),
            root: root.clone(),
            out_prefix: format!("{root}/out/"),
            alive_prefix: format!("{root}/alive/"),
            session,
        })
    }

    /// The robot a key names under `prefix`, if it is one of the run's.
    fn robot_of(&self, key: &str, prefix: &str) -> Option<usize> {
        let r: usize = key.strip_prefix(prefix)?.parse().ok()?;
        (r < self.inboxes.len()).then_some(r)
    }

    /// Files an answer's chunk under its robot; returns the robot. A
    /// repeat of an answer already heard is dropped here; a hello (the
    /// handshake) is never a repeat, for two agents may claim one number.
    /// A chunk of a robot outside the team is kept for the world to refuse.
    fn file(&self, s: &Sample) -> Option<usize> {
        let Some(r) = self.robot_of(s.key_expr().as_str(), &self.out_prefix) else {
            self.keep_stranger(s);
            return None;
        };
        let chunk = s.payload().to_bytes();
        // A chunk too short for a header goes on: the assembler says why.
        let seq = super::retry::seq_of(&chunk);
        if seq.is_some_and(|seq| seq != HANDSHAKE && !self.outstanding.borrow_mut().heard(r, seq)) {
            return None;
        }
        self.queues.borrow_mut()[r].push_back(chunk.into_owned());
        Some(r)
    }

    fn keep_stranger(&self, s: &Sample) {
        let Some(r) = s.key_expr().as_str().strip_prefix(&self.out_prefix).and_then(|n| n.parse::<usize>().ok()) else {
            return;
        };
        let mut q = self.strangers.borrow_mut();
        if q.len() < STRANGERS {
            q.push_back((r, s.payload().to_bytes().into_owned()));
        }
    }

    /// Puts again every message whose answer is overdue, to robots whose
    /// token is there. A put that fails is left to the next repeat: the
    /// robot's silence is the world's business, not the transport's.
    fn repeat_overdue(&self) {
        let now = Instant::now();
        if !self.outstanding.borrow().due(now) {
            return;
        }
        self.follow_tokens();
        let presence = self.presence.borrow();
        self.outstanding
            .borrow_mut()
            .repeat_due(now, |r, c| presence[r] != Presence::Gone && self.inboxes[r].put(c.to_vec()).wait().is_ok());
    }

    /// How many messages were put again for want of an answer.
    pub fn repeats(&self) -> u64 {
        self.outstanding.borrow().repeats
    }

    /// Reads every token change that came.
    fn follow_tokens(&self) {
        let mut p = self.presence.borrow_mut();
        while let Ok(Some(s)) = self.tokens.try_recv() {
            if let Some(r) = self.robot_of(s.key_expr().as_str(), &self.alive_prefix) {
                p[r] = match s.kind() {
                    SampleKind::Put => Presence::Alive,
                    SampleKind::Delete => Presence::Gone,
                };
            }
        }
    }
}

impl WorldTransport for ZenohWorld {
    fn post(&self, r: usize, seq: u64, bytes: &[u8]) -> Result<(), String> {
        let chunk = one_chunk(seq, bytes, ipc::INBOX_CHUNKS).map_err(|e| format!("robot {r}'s inbox: {e}"))?;
        // A verdict is put once; the agent says hello again if it is lost.
        if seq != HANDSHAKE {
            self.outstanding.borrow_mut().posted(r, seq, &chunk, Instant::now());
        }
        self.inboxes[r].put(chunk).wait().map_err(err("cannot publish")).map_err(|e| format!("robot {r}'s inbox: {e}"))
    }

    /// The message itself wakes the robot; only a token gone says nobody
    /// will read it.
    fn notify(&self, r: usize) -> bool {
        self.follow_tokens();
        self.presence.borrow()[r] != Presence::Gone
    }

    fn wait(&self, timeout: Duration, woke: &mut Vec<usize>) {
        self.repeat_overdue();
        if let Ok(Some(s)) = self.answers.recv_timeout(timeout) {
            woke.extend(self.file(&s));
        }
        while let Ok(Some(s)) = self.answers.try_recv() {
            woke.extend(self.file(&s));
        }
    }

    fn recv(&self, r: usize, buf: &mut Vec<u8>) -> Result<bool, String> {
        match self.queues.borrow_mut()[r].pop_front() {
            Some(c) => {
                *buf = c;
                Ok(true)
            }
            None => Ok(false),
        }
    }

    /// A robot is there until its token vanishes; the pid is another
    /// host's, if the robot runs elsewhere, so it is not looked at.
    fn liveness(&self, r: usize, _pid: u32) -> Option<bool> {
        self.follow_tokens();
        Some(self.presence.borrow()[r] != Presence::Gone)
    }

    fn gone(&self) -> Vec<usize> {
        self.follow_tokens();
        self.presence.borrow().iter().enumerate().filter(|(_, p)| **p == Presence::Gone).map(|(r, _)| r).collect()
    }

    fn stranger(&self, buf: &mut Vec<u8>) -> Option<usize> {
        let (r, chunk) = self.strangers.borrow_mut().pop_front()?;
        *buf = chunk;
        Some(r)
    }

    fn post_stranger(&self, r: usize, bytes: &[u8]) -> Result<(), String> {
        let chunk = one_chunk(HANDSHAKE, bytes, ipc::INBOX_CHUNKS)?;
        self.session
            .put(format!("{}/in/{r}", self.root), chunk)
            .congestion_control(zenoh::qos::CongestionControl::Block)
            .wait()
            .map_err(err("cannot publish"))
    }
}
