//! A robot's zenoh side: a client of the world's router with a subscriber
//! on its inbox, a publisher for its answers, its liveliness token, and a
//! watch on the world's token.

use std::cell::{Cell, RefCell};
use std::collections::VecDeque;
use std::time::{Duration, Instant};

use zenoh::handlers::FifoChannelHandler;
use zenoh::liveliness::LivelinessToken;
use zenoh::pubsub::{Publisher, Subscriber};
use zenoh::sample::{Sample, SampleKind};
use zenoh::{Session, Wait};

use super::retry::{seq_of, Incoming, Replies};
use super::{err, one_chunk, publisher, NetConfig, Security};
use crate::credentials::Holder;
use crate::ipc;
use crate::AgentTransport;
use gridswarm_robot::wire::HANDSHAKE;

pub struct ZenohAgent {
    outbox: Publisher<'static>,
    inbox: Subscriber<FifoChannelHandler<Sample>>,
    world: Subscriber<FifoChannelHandler<Sample>>,
    _token: LivelinessToken,
    /// Chunks taken off the inbox by `wait`, not read yet.
    stash: RefCell<VecDeque<Vec<u8>>>,
    world_up: Cell<bool>,
    /// The newest message read and its answer, for the world's repeats.
    replies: RefCell<Replies>,
    _session: Session,
}

impl ZenohAgent {
    /// Connects robot `robot` and waits (up to the connect timeout) until
    /// the world is there, so that its hello is heard.
    pub fn open(net: &NetConfig, robot: usize) -> Result<Self, String> {
        let root = net.root()?;
        let config = net.zenoh(Holder::Robot(robot), 0)?;
        let session =
            zenoh::open(config).wait().map_err(|e| format!("zenoh: cannot reach the world: {e}{}", hint(net)))?;
        let inbox = session
            .declare_subscriber(format!("{root}/in/{robot}"))
            .wait()
            .map_err(err("cannot subscribe to the inbox"))?;
        let outbox = publisher(&session, format!("{root}/out/{robot}"), "cannot declare the outbox")?;
        let world = session
            .liveliness()
            .declare_subscriber(format!("{root}/world"))
            .history(true)
            .wait()
            .map_err(err("cannot follow the world's token"))?;
        let token = session
            .liveliness()
            .declare_token(format!("{root}/alive/{robot}"))
            .wait()
            .map_err(err("cannot declare the robot's token"))?;
        let agent = ZenohAgent {
            outbox,
            inbox,
            world,
            _token: token,
            stash: RefCell::new(VecDeque::new()),
            world_up: Cell::new(false),
            replies: RefCell::new(Replies::default()),
            _session: session,
        };
        let deadline = Instant::now() + net.connect_timeout;
        while !agent.world_alive() {
            if Instant::now() >= deadline {
                return Err(format!(
                    "no world of run `{}` appeared within {:?}{}",
                    net.key,
                    net.connect_timeout,
                    hint(net)
                ));
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        Ok(agent)
    }
}

/// Why a TLS link may fail where a plain one would not.
fn hint(net: &NetConfig) -> &'static str {
    match net.security {
        Security::Tls(_) => {
            " (over TLS the world's certificate must name the host in --connect, `gridswarm credentials --host`, \
             and the world's and the robot's certificates come from one `gridswarm credentials`)"
        }
        Security::Plain => "",
    }
}

impl AgentTransport for ZenohAgent {
    fn send(&self, seq: u64, bytes: &[u8]) -> Result<(), String> {
        let chunk = one_chunk(seq, bytes, ipc::OUTBOX_CHUNKS)?;
        // A hello is said again by the agent itself until its verdict comes.
        if seq != HANDSHAKE {
            self.replies.borrow_mut().sent(seq, &chunk);
        }
        self.outbox.put(chunk).wait().map_err(err("cannot publish"))
    }

    fn wait(&self, timeout: Duration) {
        if !self.stash.borrow().is_empty() {
            return;
        }
        if let Ok(Some(s)) = self.inbox.recv_timeout(timeout) {
            self.stash.borrow_mut().push_back(s.payload().to_bytes().into_owned());
        }
    }

    /// The next message not read before; a repeat of the one answered
    /// last is answered again on the way.
    fn recv(&self, buf: &mut Vec<u8>) -> Result<bool, String> {
        loop {
            let next = self.stash.borrow_mut().pop_front();
            let chunk = match next {
                Some(c) => c,
                None => match self.inbox.try_recv().map_err(err("cannot receive"))? {
                    Some(s) => s.payload().to_bytes().into_owned(),
                    None => return Ok(false),
                },
            };
            // A verdict is read whenever it comes: it answers no wake-up.
            let Some(seq) = seq_of(&chunk).filter(|&s| s != HANDSHAKE) else {
                *buf = chunk;
                return Ok(true);
            };
            match self.replies.borrow_mut().came(seq) {
                Incoming::New => {
                    *buf = chunk;
                    return Ok(true);
                }
                Incoming::Answered(answer) => self.outbox.put(answer.to_vec()).wait().map_err(err("cannot publish"))?,
                Incoming::Old => {}
            }
        }
    }

    fn world_alive(&self) -> bool {
        while let Ok(Some(s)) = self.world.try_recv() {
            self.world_up.set(s.kind() == SampleKind::Put);
        }
        self.world_up.get()
    }
}
