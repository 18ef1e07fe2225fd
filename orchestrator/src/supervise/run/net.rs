//! How a distributed run's processes reach each other: iceoryx2 (the
//! default, nothing to set) or zenoh, where the world listens and the
//! agents connect to it; on one machine at 127.0.0.1 on a free port, so
//! the run needs no network and two runs never meet. With
//! `remote_agents` the orchestrator starts and follows the world only:
//! the agents are started by hand, on any hosts, with the run's key.
//!
//! zenoh's links are mutual TLS with the run's credentials: those given
//! (`--credentials`), or, on one machine, credentials the run makes for
//! itself in its private folder. Plain TCP only with `--insecure`, on
//! loopback unless `--insecure-network` says otherwise.

use std::net::TcpListener;
use std::path::PathBuf;

use gridswarm::transport::{self, Guard, Transport};

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
    /// zenoh: the hosts the world's certificate names, when the run makes
    /// its own credentials (in the folder `--credentials` gives the processes).
    pub own_credentials: Option<Vec<String>>,
    /// zenoh: how the links are protected (none for iceoryx2).
    pub guard: Option<Guard>,
}

#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct NetOptions {
    pub transport: Transport,
    /// zenoh: the world's endpoints [default: tcp/127.0.0.1:<a free port>,
    /// or scouting with remote agents].
    pub listen: Vec<String>,
    /// zenoh: the run's key; the agents are started by hand with it.
    pub remote_agents: Option<String>,
    /// zenoh: the credentials folder (`gridswarm credentials`) [default:
    /// made for the run, with agents on this machine].
    pub credentials: Option<PathBuf>,
    /// zenoh: plain TCP, on loopback only unless `insecure_network`.
    pub insecure: bool,
    pub insecure_network: bool,
}

impl NetOptions {
    /// Refuses settings that mean nothing for the transport.
    pub fn check(&self) -> Result<()> {
        let zenoh_only = !self.listen.is_empty() || self.remote_agents.is_some() || self.credentials.is_some();
        if self.transport == Transport::Iceoryx2 && (zenoh_only || self.insecure) {
            return Err(Error::Usage(
                "--listen, --remote-agents, --credentials and --insecure need --transport zenoh (iceoryx2 is one \
                 machine's shared memory)"
                    .into(),
            ));
        }
        if let Some(key) = &self.remote_agents {
            transport::check_key(key).map_err(|e| Error::Usage(format!("--remote-agents: {e}")))?;
        }
        for e in &self.listen {
            transport::check_endpoint(e).map_err(|e| Error::Usage(format!("--listen: {e}")))?;
        }
        if self.transport == Transport::Zenoh {
            self.guard()?;
        }
        Ok(())
    }

    /// How zenoh's links are protected, checked against the endpoints.
    fn guard(&self) -> Result<Guard> {
        let guard = match (&self.credentials, self.insecure) {
            (Some(_), true) => return Err(Error::Usage("--credentials and --insecure exclude each other".into())),
            (None, true) => Guard::Plain { network: self.insecure_network },
            (None, false) if self.remote_agents.is_some() => {
                return Err(Error::Usage(
                    "agents on other hosts need the run's credentials: --credentials DIR (`gridswarm credentials` \
                     makes them), or --insecure for plain TCP"
                        .into(),
                ))
            }
            _ => Guard::Tls,
        };
        // On one machine without --listen the world listens on loopback.
        if !self.listen.is_empty() || self.remote_agents.is_some() {
            guard.check("--listen", &self.listen).map_err(Error::Usage)?;
        }
        Ok(guard)
    }

    /// The world-server's and every agent's extra arguments for a run
    /// whose iceoryx2 prefix is `prefix` and whose private folder (where
    /// it makes its own credentials) is `run_dir`.
    pub fn args(&self, prefix: &str, run_dir: &std::path::Path) -> Result<Launch> {
        let agents_here = self.remote_agents.is_none();
        if self.transport == Transport::Iceoryx2 {
            return Ok(Launch { agents_here, ..Default::default() });
        }
        let guard = self.guard()?;
        let mut world = vec!["--transport".to_string(), "zenoh".into()];
        world.extend(match (guard, &self.credentials) {
            (Guard::Tls, Some(dir)) => vec!["--credentials".to_string(), dir.to_string_lossy().into_owned()],
            (Guard::Tls, None) => vec!["--credentials".to_string(), run_dir.to_string_lossy().into_owned()],
            (Guard::Plain { network: false }, _) => vec!["--insecure".into()],
            (Guard::Plain { network: true }, _) => vec!["--insecure".into(), "--insecure-network".into()],
        });
        let mut agent = world.clone();
        let listen: Vec<String> = match (&self.remote_agents, self.listen.is_empty()) {
            (_, false) => self.listen.clone(),
            (Some(_), true) => Vec::new(),
            (None, true) => vec![format!("{}/127.0.0.1:{}", guard.link(), free_port()?)],
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
        let own_credentials = (guard == Guard::Tls && self.credentials.is_none()).then(|| hosts_of(&listen));
        Ok(Launch { world, agents: agent, agents_here, endpoints: listen, own_credentials, guard: Some(guard) })
    }
}

/// The hosts of `endpoints`, for the world's certificate.
fn hosts_of(endpoints: &[String]) -> Vec<String> {
    let host = |e: &String| {
        let addr = e.split(['?', '#']).next()?.split_once('/')?.1;
        let host = addr.rsplit_once(':')?.0;
        Some(host.trim_start_matches('[').trim_end_matches(']').to_string())
    };
    endpoints.iter().filter_map(host).collect()
}

/// What to run on each agent's host, for `--remote-agents KEY`: its setup
/// file (`gridswarm setup`, the run's settings), then the agent.
pub fn hand_hint(key: &str, opts: &super::RunOptions, plan: &super::Plan) -> String {
    // An agent reaches a world listening on every address at one of them.
    let connect: String =
        opts.net.listen.iter().map(|e| format!(" --connect {}", e.replace("0.0.0.0", "WORLD_HOST"))).collect();
    let security = match &opts.net.credentials {
        Some(dir) => format!(" --credentials {}", dir.display()),
        None if opts.net.insecure_network => " --insecure --insecure-network".into(),
        None => " --insecure".into(),
    };
    let mut settings = String::new();
    if let Some(s) = opts.situation {
        settings += &format!(" --situation {}", if s == gridswarm::params::Situation::One { 1 } else { 2 });
    }
    if let Some(r) = opts.retries {
        settings += &format!(" --retries {r}");
    }
    if let Some(s) = opts.slot {
        settings += &format!(" --slot {}", s.name());
    }
    if let Some(o) = opts.order {
        settings += &format!(" --order {}", o.name());
    }
    format!(
        "waiting for {} robot-agents; on their hosts run, once for each robot number K ({}):\n  \
         gridswarm setup --key {key} --scenario {} --seed {} --algorithm {}{settings} --robots {} --robot K --out robot-K.json\n  \
         robot-agent --transport zenoh --prefix {key}{connect}{security} --setup robot-K.json{}",
        plan.robots,
        gridswarm::agreement::robot_range(plan.robots),
        opts.scenario,
        opts.seed,
        opts.algorithm,
        plan.robots,
        if opts.net.credentials.is_some() {
            "\n(each host needs ca.pem and its robots' robot-K.pem and robot-K.key from the credentials folder)"
        } else {
            ""
        }
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
    use std::path::Path;

    use super::*;

    #[test]
    fn iceoryx2_takes_no_endpoints() {
        let o = NetOptions::default();
        assert!(o.check().is_ok());
        let l = o.args("gs1x1_", Path::new("/tmp/d")).unwrap();
        assert!(l.world.is_empty() && l.agents.is_empty() && l.agents_here);
        let o = NetOptions { listen: vec!["tcp/127.0.0.1:7447".into()], ..Default::default() };
        assert!(o.check().is_err_and(|e| e.to_string().contains("need --transport zenoh")));
    }

    #[test]
    fn zenoh_on_one_machine_listens_on_loopback_over_tls_with_credentials_of_its_own() {
        let o = NetOptions { transport: Transport::Zenoh, ..Default::default() };
        let l = o.args("gs1x1_", Path::new("/tmp/d")).unwrap();
        let Launch { world, agents: agent, agents_here, endpoints, own_credentials, guard } = l;
        assert!(agents_here);
        let at = world.iter().position(|a| a == "--listen").unwrap();
        assert!(world[at + 1].starts_with("tls/127.0.0.1:"));
        assert_eq!(agent, ["--transport", "zenoh", "--credentials", "/tmp/d", "--connect", &world[at + 1]]);
        assert!(world.ends_with(&["--key".into(), "gs1x1_".into()]));
        assert_eq!(endpoints, [world[at + 1].clone()]);
        assert_eq!((own_credentials, guard), (Some(vec!["127.0.0.1".to_string()]), Some(Guard::Tls)));
        let o = NetOptions { insecure: true, ..o };
        let l = o.args("gs1x1_", Path::new("/tmp/d")).unwrap();
        assert!(l.agents.starts_with(&["--transport".into(), "zenoh".into(), "--insecure".into()]), "{:?}", l.agents);
        assert!(l.endpoints[0].starts_with("tcp/127.0.0.1:") && l.own_credentials.is_none());
    }

    #[test]
    fn plain_tcp_needs_insecure_and_stays_on_loopback_unless_asked() {
        let o = |listen: &str, insecure: bool, network: bool| NetOptions {
            transport: Transport::Zenoh,
            listen: vec![listen.into()],
            remote_agents: Some("lab".into()),
            insecure,
            insecure_network: network,
            ..Default::default()
        };
        let err = |o: NetOptions| o.check().unwrap_err().to_string();
        assert!(err(o("tcp/127.0.0.1:1", false, false)).contains("--credentials DIR"));
        assert!(o("tcp/127.0.0.1:1", true, false).check().is_ok());
        assert!(err(o("tcp/0.0.0.0:7447", true, false)).contains("--insecure-network"));
        assert!(o("tcp/0.0.0.0:7447", true, true).check().is_ok());
        let tls = NetOptions { credentials: Some("keys".into()), ..o("tcp/0.0.0.0:7447", false, false) };
        assert!(err(tls.clone()).contains("plain TCP"));
        assert!(NetOptions { listen: vec!["tls/0.0.0.0:7447".into()], ..tls }.check().is_ok());
        let ice = NetOptions { insecure: true, ..Default::default() };
        assert!(err(ice).contains("need --transport zenoh"));
    }

    #[test]
    fn remote_agents_need_a_plain_key_and_scout_without_endpoints() {
        let mut o = NetOptions {
            transport: Transport::Zenoh,
            remote_agents: Some("lab/1".into()),
            insecure: true,
            insecure_network: true,
            ..Default::default()
        };
        assert!(o.check().is_err());
        o.remote_agents = Some("lab1".into());
        assert!(o.check().is_ok());
        let l = o.args("gs1x1_", Path::new("/tmp/d")).unwrap();
        assert!(!l.agents_here);
        assert!(!l.world.contains(&"--listen".to_string()), "scouting: {:?}", l.world);
        assert!(l.world.windows(3).any(|w| w == ["--key", "lab1", "--remote-agents"]), "{:?}", l.world);
    }
}
