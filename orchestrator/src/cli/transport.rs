//! `run`'s transport flags: iceoryx2 or zenoh, the world's endpoints,
//! agents started by hand on other hosts, and how zenoh's links are
//! protected.

use std::path::PathBuf;

use gridswarm::transport::Transport;

use crate::run::NetOptions;

#[derive(clap::Args, Debug, Clone)]
pub struct TransportFlags {
    /// How the world reaches the robots: iceoryx2 (shared memory, this
    /// machine) or zenoh (TCP, any network; on one machine at 127.0.0.1).
    #[arg(long, default_value = "iceoryx2")]
    pub transport: Transport,
    /// zenoh: an endpoint the world listens on, e.g. tls/0.0.0.0:7447
    /// [default: 127.0.0.1 on a free port]; repeatable.
    #[arg(long, value_name = "ENDPOINT")]
    pub listen: Vec<String>,
    /// zenoh: start the world only; the agents are started by hand, on
    /// any hosts, each with its setup file (`gridswarm setup --key KEY
    /// ...`) and `robot-agent --transport zenoh --prefix KEY --setup FILE
    /// ...` (the commands are printed; README: "Running on several machines").
    #[arg(long, value_name = "KEY")]
    pub remote_agents: Option<String>,
    /// zenoh: the run's credentials folder (`gridswarm credentials`):
    /// mutual TLS on tls/ endpoints, each robot admitted to its own key
    /// expressions only [default: on one machine, credentials made for the
    /// run; with --remote-agents, needed unless --insecure].
    #[arg(long, value_name = "DIR")]
    pub credentials: Option<PathBuf>,
    /// zenoh: plain TCP (tcp/ endpoints), nobody authenticated, nothing
    /// encrypted: anyone who reaches the port can read, join and disturb
    /// the run. On loopback only.
    #[arg(long)]
    pub insecure: bool,
    /// zenoh: with --insecure, plain TCP on other addresses too (and
    /// scouting, without --listen).
    #[arg(long, requires = "insecure")]
    pub insecure_network: bool,
}

impl TransportFlags {
    pub fn options(&self) -> NetOptions {
        NetOptions {
            transport: self.transport,
            listen: self.listen.clone(),
            remote_agents: self.remote_agents.clone(),
            credentials: self.credentials.clone(),
            insecure: self.insecure,
            insecure_network: self.insecure_network,
        }
    }
}
