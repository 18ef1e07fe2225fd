//! The world's iceoryx2 side: it creates every service of the run (so the
//! limits are the world's, with room for every robot) and holds its ports:
//! a publisher into every robot's inbox, a subscriber on every group's
//! outbox, one notifier that wakes one robot at a time, and one listener
//! the robots notify.
//!
//! A group's outbox carries the chunks of several robots, tagged with
//! their numbers; the world takes them off in arrival order and keeps each
//! robot's in its own queue until it asks for that robot's.

use std::cell::{Cell, RefCell};
use std::collections::VecDeque;
use std::time::Duration;

use gridswarm::ipc::outbox::{self, OutboxService, OutboxSubscriber};
use gridswarm::ipc::wake::Waker;
use gridswarm::ipc::{self, names, BytesPublisher, BytesService, EventService, Listener, Svc};
use gridswarm::wire;
use iceoryx2::config::Config;
use iceoryx2::prelude::*;

pub fn world_node(config: &Config) -> Result<Node<Svc>, String> {
    ipc::create_node(config, names::WORLD_NODE)
}

/// Every service of a run, created by the world.
pub struct Services {
    robots: usize,
    outs: Vec<OutboxService>,
    ins: Vec<BytesService>,
    wake: EventService,
    world_wake: EventService,
}

impl Services {
    pub fn create(node: &Node<Svc>, robots: usize) -> Result<Self, String> {
        let mut s = Services {
            robots,
            outs: Vec::with_capacity(outbox::groups(robots)),
            ins: Vec::with_capacity(robots),
            wake: ipc::wake::create(node, robots)?,
            world_wake: ipc::create_event(node, &names::world_wake(), robots, outbox::groups(robots).max(1))?,
        };
        for g in 0..outbox::groups(robots) {
            let writers = outbox::members(g, robots);
            s.outs.push(outbox::create(node, &names::group_out(g), writers, ipc::OUTBOX_CHUNKS)?);
        }
        for i in 0..robots {
            s.ins.push(ipc::create_bytes(node, &names::robot_in(i), ipc::INBOX_CHUNKS)?);
        }
        Ok(s)
    }
}

/// The world's ports.
pub struct Ports {
    outs: Vec<OutboxSubscriber>,
    /// Chunks taken off a group's outbox, by robot, not asked for yet.
    pending: RefCell<Vec<VecDeque<Vec<u8>>>>,
    mistagged: Cell<u64>,
    /// The groups whose robots notified, and a chunk being sorted (reused).
    groups: RefCell<Vec<usize>>,
    scratch: RefCell<Vec<u8>>,
    ins: Vec<BytesPublisher>,
    waker: Waker,
    listener: Listener,
}

impl Ports {
    pub fn new(s: &Services) -> Result<Self, String> {
        let listener = s
            .world_wake
            .listener_builder()
            .create()
            .map_err(|e| format!("cannot create the world's listener: {e:?}"))?;
        let mut p = Ports {
            outs: Vec::with_capacity(s.outs.len()),
            pending: RefCell::new(vec![VecDeque::new(); s.robots]),
            mistagged: Cell::new(0),
            groups: RefCell::new(Vec::new()),
            scratch: RefCell::new(Vec::with_capacity(ipc::CHUNK_BYTES)),
            ins: Vec::with_capacity(s.robots),
            waker: Waker::new(&s.wake, s.robots)?,
            listener,
        };
        for out in &s.outs {
            p.outs.push(outbox::subscriber(out, ipc::OUTBOX_CHUNKS)?);
        }
        for i in 0..s.robots {
            p.ins.push(ipc::bytes_publisher(&s.ins[i], ipc::CHUNK_BYTES)?);
        }
        Ok(p)
    }

    /// Puts one message (numbered `seq`) into robot `r`'s inbox, in chunks.
    pub fn post(&self, r: usize, seq: u64, bytes: &[u8]) -> Result<(), String> {
        let n = wire::chunk_count(bytes.len(), ipc::CHUNK_BYTES);
        if n > ipc::INBOX_CHUNKS {
            return Err(format!(
                "a message of {} bytes for robot {r} needs {n} chunks; its inbox holds {}",
                bytes.len(),
                ipc::INBOX_CHUNKS
            ));
        }
        let mut res = Ok(());
        wire::chunks(seq, bytes, ipc::CHUNK_BYTES, |c| {
            if res.is_ok() {
                res = ipc::publish(&self.ins[r], c).map_err(|e| format!("robot {r}'s inbox: {e}"));
            }
        });
        res
    }

    /// Wakes robot `r`; false if its listener was not reached: no
    /// connection to it (e.g. out of descriptors, or its process gone) or
    /// a send that failed ([`Waker::wake`]).
    pub fn notify(&self, r: usize) -> bool {
        self.waker.wake(r).is_ok()
    }

    /// Waits up to `timeout` for robots to notify; pushes the ids of the
    /// robots that may have written. A robot notifies with its group's
    /// number ([`outbox::group_of`]): iceoryx2 looks at every possible
    /// event id on each wake-up of the world, so ids by robot cost a
    /// thousand atomic swaps a wake-up at 1,000 robots, by group 32.
    pub fn wait(&self, timeout: Duration, woke: &mut Vec<usize>) {
        let mut groups = self.groups.borrow_mut();
        groups.clear();
        let _ = self.listener.timed_wait(|ev| groups.push(ev.id.as_value()), timeout);
        let mut pending = self.pending.borrow_mut();
        let mut scratch = self.scratch.borrow_mut();
        let robots = pending.len();
        for &g in groups.iter().filter(|&&g| g < self.outs.len()) {
            let members = g * outbox::OUTBOX_GROUP..g * outbox::OUTBOX_GROUP + outbox::members(g, robots);
            if self.drain_group(g, &mut pending, &mut scratch).is_err() {
                // Each robot's own `recv` then meets the error.
                woke.extend(members);
                continue;
            }
            // Chunks a `recv` took off earlier count too: their robot's
            // notification may be the one that arrives now.
            woke.extend(members.filter(|&r| !pending[r].is_empty()));
        }
    }

    /// Takes the next chunk of robot `r`'s outbox into `buf`, if any. An
    /// error is a connection to a publisher of its group that failed.
    pub fn recv(&self, r: usize, buf: &mut Vec<u8>) -> Result<bool, String> {
        let mut pending = self.pending.borrow_mut();
        if pending[r].is_empty() {
            self.drain_group(outbox::group_of(r), &mut pending, buf)?;
        }
        match pending[r].pop_front() {
            Some(chunk) => {
                *buf = chunk;
                Ok(true)
            }
            None => Ok(false),
        }
    }

    /// Moves every chunk waiting in group `g`'s outbox to its robot's queue.
    /// A chunk tagged with a robot outside the group is dropped and counted
    /// ([`Ports::mistagged`]): a robot writes only under its own number.
    fn drain_group(&self, g: usize, pending: &mut [VecDeque<Vec<u8>>], scratch: &mut Vec<u8>) -> Result<(), String> {
        while let Some(from) = outbox::receive(&self.outs[g], scratch)? {
            let from = from as usize;
            if from < pending.len() && outbox::group_of(from) == g {
                pending[from].push_back(scratch.clone());
            } else {
                self.mistagged.set(self.mistagged.get() + 1);
            }
        }
        Ok(())
    }

    /// Chunks dropped because their tag named no robot of their group.
    pub fn mistagged(&self) -> u64 {
        self.mistagged.get()
    }
}

/// Robots whose iceoryx2 node is dead (its process gone), by robot number.
pub fn dead_nodes(config: &Config) -> Vec<usize> {
    match ipc::list_nodes(config) {
        Ok(nodes) => nodes.iter().filter(|n| n.dead).filter_map(|n| names::robot_of_node(&n.name)).collect(),
        Err(_) => Vec::new(),
    }
}
