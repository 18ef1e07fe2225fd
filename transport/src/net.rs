//! The zenoh transport (feature `zenoh`): the distributed engine's messages
//! over any network, for world-server and robot-agents on separate hosts.
//! The world is a zenoh router (it listens), each robot a client
//! connected to it: the same star as iceoryx2, so the world still carries
//! every frame and decides its fate from the seed, and a run is the same
//! byte for byte whichever transport carries it.
//!
//! Key expressions are rooted at the run's key, `gridswarm/<key>/`, so two
//! runs on one network never cross: `in/<r>` (the world to robot `r`),
//! `out/<r>` (robot `r` to the world), liveliness tokens `alive/<r>` (a
//! robot) and `world`. A token vanishes with its session: a process that
//! dies at once (its TCP connection closes), a lost host once its lease
//! ([`NetConfig::lease_ms`]) runs out. The world reads that as a dead
//! robot, for physics only; robots learn of each other only from silence.
//!
//! A session can drop and come back (a lease run out under a starved
//! CPU, a flapping link), losing what was put meanwhile: the world puts a
//! message again while its answer is missing, and a robot answers a repeat
//! with the answer it sent ([`retry`]), so the run goes on as if nothing
//! was lost.
//!
//! Endpoints are zenoh's (`tls/10.0.0.1:7447`). With neither `listen` nor
//! `connect`, the robots find the world by multicast scouting (plain TCP
//! only); with either, scouting is off, so a run on one machine never
//! touches the network.
//!
//! A run is protected by zenoh's own means ([`secure`]): mutual TLS with
//! the run's certificates, and access control in the world's router that
//! lets robot `K` speak and hear only as robot `K`. Plain TCP, which
//! anyone who reaches the endpoint can read and join, is [`Security::Plain`]
//! (`--insecure`), for loopback unless asked otherwise
//! ([`crate::Guard`]).

mod agent;
mod retry;
mod secure;
mod world;

pub use agent::ZenohAgent;
pub use world::ZenohWorld;

use std::time::Duration;

use crate::credentials::{Credentials, Holder};
use crate::ipc;
use crate::Guard;
use gridswarm_robot::wire;

/// How a run's links are protected.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Security {
    /// Plain TCP: nobody is authenticated, nothing is encrypted.
    Plain,
    /// Mutual TLS with these credentials, and the world's access control.
    Tls(Credentials),
}

impl Security {
    /// The protection the command line asks for (`--credentials DIR`, or
    /// `--insecure` with `network` for `--insecure-network`), with the
    /// `endpoints` that `flag` gave checked against it. One of the two is
    /// needed: nothing goes on the network unprotected by default.
    pub fn from_flags(
        credentials: Option<&std::path::Path>,
        insecure: bool,
        network: bool,
        flag: &str,
        endpoints: &[String],
    ) -> Result<Security, String> {
        let (security, guard) = match (credentials, insecure) {
            (Some(dir), false) => (Security::Tls(Credentials::new(dir)), Guard::Tls),
            (None, true) => (Security::Plain, Guard::Plain { network }),
            (Some(_), true) => return Err("--credentials and --insecure exclude each other".into()),
            (None, false) => {
                return Err("zenoh needs --credentials DIR (mutual TLS: `gridswarm credentials` makes the folder) \
                            or --insecure (plain TCP, on loopback only)"
                    .into())
            }
        };
        guard.check(flag, endpoints)?;
        Ok(security)
    }
}

/// Where a process of the run meets the others.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NetConfig {
    /// The run's key: the root of its key expressions.
    pub key: String,
    /// Endpoints to listen on (the world's; a robot's stay empty).
    pub listen: Vec<String>,
    /// Endpoints to connect to (a robot's: the world's).
    pub connect: Vec<String>,
    /// How long a silent link lives: a lost host is found this late.
    pub lease_ms: u64,
    /// How long a robot waits for the world to appear.
    pub connect_timeout: Duration,
    pub security: Security,
}

/// The default lease: long enough for a process starved of CPU on a busy
/// machine to send its keep-alive (every quarter lease), short enough that
/// a lost host stalls the run only that long.
pub const DEFAULT_LEASE_MS: u64 = 2_000;

impl NetConfig {
    pub fn new(key: &str, security: Security) -> Self {
        NetConfig {
            security,
            key: key.to_string(),
            listen: Vec::new(),
            connect: Vec::new(),
            lease_ms: DEFAULT_LEASE_MS,
            connect_timeout: Duration::from_secs(60),
        }
    }

    /// Whether robots and world find each other by multicast scouting.
    pub fn scouting(&self) -> bool {
        self.listen.is_empty() && self.connect.is_empty()
    }

    fn root(&self) -> Result<String, String> {
        crate::check_key(&self.key)?;
        Ok(format!("gridswarm/{}", self.key))
    }

    /// zenoh's configuration for `holder`: the world a router for
    /// `robots` robots, a robot a client.
    fn zenoh(&self, holder: Holder, robots: usize) -> Result<zenoh::Config, String> {
        let mut c = zenoh::Config::default();
        let mut set = |k: &str, v: String| c.insert_json5(k, &v).map_err(|e| format!("zenoh setting {k} = {v}: {e}"));
        let mode = if holder == Holder::World { "router" } else { "client" };
        set("mode", quote(mode)?)?;
        if let Security::Tls(creds) = &self.security {
            for (k, v) in secure::tls(creds, holder)? {
                set(k, v)?;
            }
            if holder == Holder::World {
                set("access_control", secure::access(&self.root()?, robots))?;
            }
        }
        set("scouting/multicast/enabled", self.scouting().to_string())?;
        // Robots talk to the world only: nothing to gossip about.
        set("scouting/gossip/enabled", "false".into())?;
        if !self.listen.is_empty() {
            set("listen/endpoints", list(&self.listen)?)?;
        }
        if !self.connect.is_empty() {
            set("connect/endpoints", list(&self.connect)?)?;
        }
        if mode == "client" {
            // Agents started by hand may come up before the world.
            set("connect/timeout_ms", self.connect_timeout.as_millis().to_string())?;
        }
        set("transport/link/tx/lease", self.lease_ms.max(100).to_string())?;
        Ok(c)
    }
}

/// A JSON string of `s`, which may hold no quote, backslash or control.
fn quote(s: &str) -> Result<String, String> {
    if s.chars().any(|c| c == '"' || c == '\\' || c.is_control()) {
        return Err(format!("`{s}` is not a zenoh endpoint"));
    }
    Ok(format!("\"{s}\""))
}

fn list(items: &[String]) -> Result<String, String> {
    for e in items {
        crate::check_endpoint(e)?;
    }
    let quoted: Result<Vec<String>, String> = items.iter().map(|s| quote(s)).collect();
    Ok(format!("[{}]", quoted?.join(",")))
}

/// `bytes` as the one chunk of message `seq` (zenoh fragments big
/// payloads itself), refusing what iceoryx2 would refuse, so that a run
/// that fits one transport fits the other.
fn one_chunk(seq: u64, bytes: &[u8], max_chunks: usize) -> Result<Vec<u8>, String> {
    let n = wire::chunk_count(bytes.len(), ipc::CHUNK_BYTES);
    if n > max_chunks {
        return Err(format!("a message of {} bytes needs {n} chunks; the limit is {max_chunks}", bytes.len()));
    }
    let mut chunk = Vec::new();
    wire::chunks(seq, bytes, bytes.len() + wire::CHUNK_HEADER, |c| chunk = c.to_vec());
    Ok(chunk)
}

/// A publisher of the run's messages on `key`. It blocks rather than drops
/// when the link is full, and sends at once, unbatched: a round is a chain
/// of round trips.
fn publisher(session: &zenoh::Session, key: String, what: &str) -> Result<zenoh::pubsub::Publisher<'static>, String> {
    use zenoh::Wait;
    session
        .declare_publisher(key)
        .congestion_control(zenoh::qos::CongestionControl::Block)
        .express(true)
        .wait()
        .map_err(err(what))
}

fn err(what: &str) -> impl Fn(zenoh::Error) -> String + '_ {
    move |e| format!("zenoh: {what}: {e}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_root_the_run() {
        assert!(NetConfig::new("a/**", Security::Plain).root().is_err_and(|e| e.contains("not a run key")));
        assert_eq!(NetConfig::new("k", Security::Plain).root().unwrap(), "gridswarm/k");
    }

    #[test]
    fn scouting_only_without_endpoints() {
        let mut n = NetConfig::new("k", Security::Plain);
        assert!(n.scouting());
        n.connect = vec!["tcp/127.0.0.1:7447".into()];
        assert!(!n.scouting());
        let c = n.zenoh(Holder::Robot(0), 1).unwrap();
        assert_eq!(c.get_json("scouting/multicast/enabled").unwrap(), "false");
        assert!(c.get_json("connect/endpoints").unwrap().contains("tcp/127.0.0.1:7447"));
        n.connect = vec!["tcp/\"x".into()];
        assert!(n.zenoh(Holder::Robot(0), 1).is_err());
        n.connect = vec!["nonsense".into()];
        assert!(n.zenoh(Holder::Robot(0), 1).is_err(), "zenoh checks the endpoint's syntax");
    }

    #[test]
    fn tls_names_the_holder_s_files_and_the_world_denies_all_but_each_robot_s_own_keys() {
        let dir = std::env::temp_dir().join(format!("gs-net-tls-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir(&dir).unwrap();
        let creds = Credentials::new(&dir);
        for f in [creds.ca(), creds.of(Holder::World).0, creds.of(Holder::Robot(2)).0] {
            std::fs::write(f, "x").unwrap();
        }
        for k in [creds.of(Holder::World).1, creds.of(Holder::Robot(2)).1] {
            use std::os::unix::fs::OpenOptionsExt;
            std::fs::OpenOptions::new().write(true).create(true).mode(0o600).open(k).unwrap();
        }
        let mut n = NetConfig::new("k", Security::Tls(creds));
        n.listen = vec!["tls/127.0.0.1:7447".into()];
        let robot = n.zenoh(Holder::Robot(2), 0).unwrap();
        let get = |c: &zenoh::Config, k: &str| c.get_json(k).unwrap();
        assert!(get(&robot, "transport/link/tls/connect_certificate").contains("robot-2.pem"));
        assert_eq!(get(&robot, "transport/link/tls/enable_mtls"), "true");
        assert_eq!(get(&robot, "access_control/enabled"), "false", "a robot is no router");
        let world = n.zenoh(Holder::World, 3).unwrap();
        assert!(get(&world, "transport/link/tls/listen_private_key").contains("world.key"));
        assert_eq!(get(&world, "access_control/default_permission"), "\"deny\"");
        let acl = get(&world, "access_control");
        for allowed in ["gridswarm/k/out/2", "gridswarm/k/alive/0", "gridswarm/k/in/1", "robot-2"] {
            assert!(acl.contains(allowed), "{allowed} in {acl}");
        }
        assert!(!acl.contains("gridswarm/k/**") && !acl.contains("out/3"), "{acl}");
        assert!(n.zenoh(Holder::Robot(1), 0).unwrap_err().contains("robot 1's"), "robot 1 has no files");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
