//! `run`'s transport flags: iceoryx2 or zenoh, the world's endpoints, and
//! agents started by hand on other hosts.

use gridswarm::transport::Transport;

use crate::run::NetOptions;

#[derive(clap::Args, Debug, Clone)]
pub struct TransportFlags {
    /// How the world reaches the robots: iceoryx2 (shared memory, this
    /// machine) or zenoh (TCP, any network; on one machine at 127.0.0.1).
    #[arg(long, default_value = "iceoryx2")]
    pub transport: Transport,
    /// zenoh: an endpoint the world listens on, e.g. tcp/0.0.0.0:7447
    /// [default: tcp/127.0.0.1 on a free port; with --remote-agents, scouting]; repeatable.
    #[arg(long, value_name = "ENDPOINT")]
    pub listen: Vec<String>,
    /// zenoh: start the world only; the agents are started by hand, on
    /// any hosts, with `robot-agent --transport zenoh --prefix KEY ...`
    /// (the command is printed; README: "Running on several machines").
    #[arg(long, value_name = "KEY")]
    pub remote_agents: Option<String>,
}

impl TransportFlags {
    pub fn options(&self) -> NetOptions {
        NetOptions { transport: self.transport, listen: self.listen.clone(), remote_agents: self.remote_agents.clone() }
    }
}
