//! The world's iceoryx2 side: it creates every service of the run (so the
//! limits are the world's, with room for every robot) and implements
//! [`Link`] over them.

use std::time::Duration;

use gridswarm::ipc::{
    self, names, BytesPublisher, BytesService, BytesSubscriber, EventService, Listener, Notifier,
    Svc,
};
use iceoryx2::config::Config;
use iceoryx2::prelude::*;

use crate::server::Link;

pub fn world_node(config: &Config) -> Result<Node<Svc>, String> {
    ipc::create_node(config, names::WORLD_NODE)
}

/// Every service of a run, created by the world.
pub struct Services {
    robots: usize,
    outs: Vec<BytesService>,
    ins: Vec<BytesService>,
    wakes: Vec<EventService>,
    world_wake: EventService,
}

impl Services {
    pub fn create(node: &Node<Svc>, robots: usize) -> Result<Self, String> {
        let mut s = Services {
            robots,
            outs: Vec::with_capacity(robots),
            ins: Vec::with_capacity(robots),
            wakes: Vec::with_capacity(robots),
            world_wake: ipc::create_event(node, &names::world_wake(), robots, robots.max(1))?,
        };
        for i in 0..robots {
            s.outs.push(ipc::create_bytes(
                node,
                &names::robot_out(i),
                ipc::OUTBOX_BUFFER,
            )?);
            s.ins.push(ipc::create_bytes(
                node,
                &names::robot_in(i),
                ipc::inbox_buffer(robots),
            )?);
            s.wakes
                .push(ipc::create_event(node, &names::robot_wake(i), 1, 1)?);
        }
        Ok(s)
    }
}

/// The world's ports.
pub struct WorldPorts {
    outs: Vec<BytesSubscriber>,
    ins: Vec<BytesPublisher>,
    wakes: Vec<Notifier>,
    pub listener: Listener,
}

impl WorldPorts {
    pub fn new(s: &Services, max_len: usize) -> Result<Self, String> {
        let mut p = WorldPorts {
            outs: Vec::with_capacity(s.robots),
            ins: Vec::with_capacity(s.robots),
            wakes: Vec::with_capacity(s.robots),
            listener: s
                .world_wake
                .listener_builder()
                .create()
                .map_err(|e| format!("cannot create the world's listener: {e:?}"))?,
        };
        for i in 0..s.robots {
            p.outs
                .push(ipc::bytes_subscriber(&s.outs[i], ipc::OUTBOX_BUFFER)?);
            p.ins.push(ipc::bytes_publisher(&s.ins[i], max_len)?);
            p.wakes.push(
                s.wakes[i]
                    .notifier_builder()
                    .create()
                    .map_err(|e| format!("cannot create notifier {i}: {e:?}"))?,
            );
        }
        Ok(p)
    }
}

pub struct IoxLink<'a> {
    config: &'a Config,
    ports: &'a WorldPorts,
    waitset: &'a WaitSet<Svc>,
    dirty: Vec<bool>,
    dirty_list: Vec<usize>,
    /// Sends that failed (a robot's inbox gone): counted, never fatal.
    pub send_errors: u64,
}

impl<'a> IoxLink<'a> {
    pub fn new(config: &'a Config, ports: &'a WorldPorts, waitset: &'a WaitSet<Svc>) -> Self {
        let n = ports.ins.len();
        IoxLink {
            config,
            ports,
            waitset,
            dirty: vec![false; n],
            dirty_list: Vec::with_capacity(n),
            send_errors: 0,
        }
    }
}

impl Link for IoxLink<'_> {
    fn post(&mut self, robot: usize, bytes: &[u8]) {
        if ipc::publish(&self.ports.ins[robot], bytes).is_err() {
            self.send_errors += 1;
        }
    }

    fn wake(&mut self, robot: usize) {
        if !self.dirty[robot] {
            self.dirty[robot] = true;
            self.dirty_list.push(robot);
        }
    }

    fn flush(&mut self) {
        for &k in &self.dirty_list {
            self.dirty[k] = false;
            if self.ports.wakes[k].notify().is_err() {
                self.send_errors += 1;
            }
        }
        self.dirty_list.clear();
    }

    fn wait(&mut self, timeout: Duration, woke: &mut Vec<usize>) {
        let _ = self
            .waitset
            .wait_and_process_once_with_timeout(|_| CallbackProgression::Continue, timeout);
        let _ = self
            .ports
            .listener
            .try_wait(|ev| woke.push(ev.id.as_value()));
    }

    fn recv(&mut self, robot: usize, buf: &mut Vec<u8>) -> bool {
        ipc::receive(&self.ports.outs[robot], buf).unwrap_or(false)
    }

    fn dead_robots(&mut self) -> Vec<usize> {
        match ipc::list_nodes(self.config) {
            Ok(nodes) => nodes
                .iter()
                .filter(|n| n.dead)
                .filter_map(|n| names::robot_of_node(&n.name))
                .collect(),
            Err(_) => Vec::new(),
        }
    }
}
