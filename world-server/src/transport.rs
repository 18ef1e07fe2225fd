//! The world's iceoryx2 ports behind [`WorldTransport`], by delegation:
//! what the ports do is `link`'s; a robot's liveness is its process on
//! this host (`/proc`), then iceoryx2's node list when `/proc` cannot tell.
//! The zenoh side is [`gridswarm::net::ZenohWorld`].

use std::time::Duration;

use gridswarm::ipc;
use gridswarm::transport::WorldTransport;
use iceoryx2::config::Config;

use crate::link::{self, Ports};

pub struct Iceoryx2<'a> {
    pub ports: &'a Ports,
    pub config: &'a Config,
}

impl WorldTransport for Iceoryx2<'_> {
    fn post(&self, r: usize, seq: u64, bytes: &[u8]) -> Result<(), String> {
        self.ports.post(r, seq, bytes)
    }

    fn notify(&self, r: usize) -> bool {
        self.ports.notify(r)
    }

    fn wait(&self, timeout: Duration, woke: &mut Vec<usize>) {
        self.ports.wait(timeout, woke)
    }

    fn recv(&self, r: usize, buf: &mut Vec<u8>) -> Result<bool, String> {
        self.ports.recv(r, buf)
    }

    fn liveness(&self, _r: usize, pid: u32) -> Option<bool> {
        ipc::pid_liveness(pid)
    }

    fn gone(&self) -> Vec<usize> {
        link::dead_nodes(self.config)
    }

    fn mistagged(&self) -> u64 {
        self.ports.mistagged()
    }
}
