//! How a distributed run's processes reach each other: iceoryx2 (the
//! default, nothing to set) or zenoh, where the world listens on TCP and
//! the agents connect to it; on one machine at 127.0.0.1 on a free port,
//! so the run needs no network and two runs never meet. With
//! `remote_agents` the orchestrator starts and follows the world only:
//! the agents are started by hand, on any hosts, with the run's key.

use std::net::TcpListener;

use gridswarm::transport::{self, Transport};

use crate::error::{Error, Result};

/// How long the world waits for agents started by hand: people type.
const HAND_HELLO_MS: u64 = 600_000;

/// The extra arguments of the run's processes.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Launch {
    pub world: Vec<String>,
    pub agents: Vec<String>,
    /// Whether the orchestrator starts the agents.
    pub agents_here: bool,
    /// zenoh: the endpoints the world listens on (none: scouting).
    pub endpoints: Vec<String>,
}

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct NetOptions {
    pub transport: Transport,
    /// zenoh: the world's endpoints [default: tcp/127.0.0.1:<a free port>,
    /// or scouting with remote agents].
    pub listen: Vec<String>,
    /// zenoh: the run's key; the agents are started by hand with it.
    pub remote_agents: Option<String>,
}

impl NetOptions {
    /// Refuses settings that mean nothing for the transport.
    pub fn check(&self) -> Result<()> {
        if self.transport == Transport::Iceoryx2 && (!self.listen.is_empty() || self.remote_agents.is_some()) {
            return Err(Error::Usage(
                "--listen and --remote-agents need --transport zenoh (iceoryx2 is one machine's shared memory)".into(),
            ));
        }
        if let Some(key) = &self.remote_agents {
            transport::check_key(key).map_err(|e| Error::Usage(format!("--remote-agents: {e}")))?;
        }
        for e in &self.listen {
            transport::check_endpoint(e).map_err(|e| Error::Usage(format!("--listen: {e}")))?;
        }
        Ok(())
    }

    /// The world-server's and every agent's extra arguments for a run
    /// whose iceoryx2 prefix is `prefix`.
    pub fn args(&self, prefix: &str) -> Result<Launch> {
        let agents_here = self.remote_agents.is_none();
        if self.transport == Transport::Iceoryx2 {
            return Ok(Launch { agents_here, ..Default::default() });
        }
        let mut world = vec!["--transport".to_string(), "zenoh".into()];
        let mut agent = world.clone();
        let listen: Vec<String> = match (&self.remote_agents, self.listen.is_empty()) {
            (_, false) => self.listen.clone(),
            (Some(_), true) => Vec::new(),
            (None, true) => vec![format!("tcp/127.0.0.1:{}", free_port()?)],
        };
        for e in &listen {
            world.extend(["--listen".to_string(), e.clone()]);
            agent.extend(["--connect".to_string(), e.clone()]);
        }
        match &self.remote_agents {
            Some(key) => world.extend(
                ["--key", key, "--remote-agents", "--hello-timeout-ms", &HAND_HELLO_MS.to_string()].map(String::from),
            ),
            None => world.extend(["--key".to_string(), prefix.to_string()]),
        }
        Ok(Launch { world, agents: agent, agents_here, endpoints: listen })
    }
}

/// What to run on each agent's host, for `--remote-agents KEY`.
pub fn hand_hint(key: &str, opts: &super::RunOptions, plan: &super::Plan) -> String {
    // An agent reaches a world listening on every address at one of them.
    let connect: String =
        opts.net.listen.iter().map(|e| format!(" --connect {}", e.replace("0.0.0.0", "WORLD_HOST"))).collect();
    let mut extra = String::new();
    if let Some(s) = opts.situation {
        extra += &format!(" --situation {}", if s == gridswarm::params::Situation::One { 1 } else { 2 });
    }
    if let Some(r) = opts.retries {
        extra += &format!(" --retries {r}");
    }
    if let Some(s) = opts.slot {
        extra += &format!(" --slot {}", s.name());
    }
    format!(
        "waiting for {} robot-agents; on their hosts run, once for each robot number K ({}):\n  \
         robot-agent --transport zenoh --prefix {key}{connect} --scenario {} --seed {} --algorithm {}{extra} --robot K",
        plan.robots,
        gridswarm::agreement::robot_range(plan.robots),
        opts.scenario,
        opts.seed,
        opts.algorithm
    )
}

/// A TCP port of 127.0.0.1 free now. The world binds it an instant later;
/// another process taking it meanwhile makes the world fail, loudly.
fn free_port() -> Result<u16> {
    let l = TcpListener::bind("127.0.0.1:0")
        .map_err(|e| Error::Run(format!("cannot find a free port on 127.0.0.1: {e}")))?;
    l.local_addr().map(|a| a.port()).map_err(|e| Error::Run(format!("cannot find a free port on 127.0.0.1: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iceoryx2_takes_no_endpoints() {
        let o = NetOptions::default();
        assert!(o.check().is_ok());
        let l = o.args("gs1x1_").unwrap();
        assert!(l.world.is_empty() && l.agents.is_empty() && l.agents_here);
        let o = NetOptions { listen: vec!["tcp/127.0.0.1:7447".into()], ..Default::default() };
        assert!(o.check().is_err_and(|e| e.to_string().contains("need --transport zenoh")));
    }

    #[test]
    fn zenoh_on_one_machine_listens_on_loopback_and_agents_connect_there() {
        let o = NetOptions { transport: Transport::Zenoh, ..Default::default() };
        let Launch { world, agents: agent, agents_here, endpoints } = o.args("gs1x1_").unwrap();
        assert!(agents_here);
        let at = world.iter().position(|a| a == "--listen").unwrap();
        assert!(world[at + 1].starts_with("tcp/127.0.0.1:"));
        assert_eq!(agent, ["--transport", "zenoh", "--connect", &world[at + 1]]);
        assert!(world.ends_with(&["--key".into(), "gs1x1_".into()]));
        assert_eq!(endpoints, [world[at + 1].clone()]);
    }

    #[test]
    fn remote_agents_need_a_plain_key_and_scout_without_endpoints() {
        let mut o =
            NetOptions { transport: Transport::Zenoh, remote_agents: Some("lab/1".into()), ..Default::default() };
        assert!(o.check().is_err());
        o.remote_agents = Some("lab1".into());
        assert!(o.check().is_ok());
        let l = o.args("gs1x1_").unwrap();
        assert!(!l.agents_here);
        assert!(!l.world.contains(&"--listen".to_string()), "scouting: {:?}", l.world);
        assert!(l.world.windows(3).any(|w| w == ["--key", "lab1", "--remote-agents"]), "{:?}", l.world);
    }
}
