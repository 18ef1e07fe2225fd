//! gridswarm's transports: how the world-server and the robot-agents of a
//! distributed run reach each other, and nothing of the world. The world
//! posts a message into robot `r`'s inbox and wakes it, waits for any
//! robot's answer and reads it back; a robot waits for its inbox, reads it
//! and answers. Messages are [`gridswarm_robot::wire`] bytes in
//! [`gridswarm_robot::wire::chunks`]: the transport carries them and never
//! decodes one, and neither the decision core nor the radio protocol knows
//! which transport runs underneath.
//!
//! Two implementations: iceoryx2 (shared memory, one machine, the default:
//! [`ipc`], under the world-server's and the agent's `Ports`) and zenoh
//! (any network, [`net`], feature `zenoh`). Both ends of each are here:
//! they are one protocol (names, chunk limits, repeats), and neither end
//! needs the world. The crate depends on the robot's crate for the
//! messages' framing only, and never on `gridswarm`, the world's crate, so
//! a robot-agent links the robot and a transport and cannot name a world.
//!
//! Liveness is the transport's too: iceoryx2 knows a robot by its process
//! on this host, zenoh by a liveliness token that vanishes with its
//! session (a dead process, or a host lost once its lease runs out). Either
//! way the world learns only that the robot is gone for physics; the robots
//! find out from silence, as with any failure.

use std::time::Duration;

pub mod credentials;
pub mod ipc;
#[cfg(feature = "zenoh")]
pub mod net;
pub mod nofile;

/// Which transport a distributed run uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Transport {
    /// Shared memory between processes of one machine.
    #[default]
    Iceoryx2,
    /// zenoh over mutual TLS (or, `--insecure`, plain TCP): processes on
    /// any hosts that reach each other.
    Zenoh,
}

impl Transport {
    pub const ALL: [Transport; 2] = [Transport::Iceoryx2, Transport::Zenoh];

    pub fn name(self) -> &'static str {
        match self {
            Transport::Iceoryx2 => "iceoryx2",
            Transport::Zenoh => "zenoh",
        }
    }
}

impl std::fmt::Display for Transport {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Transport {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Transport::ALL
            .into_iter()
            .find(|t| t.name() == s)
            .ok_or_else(|| format!("unknown transport `{s}` (expected iceoryx2 or zenoh)"))
    }
}

/// A run key (the root of a zenoh run's key expressions): letters,
/// digits, `_`, `-`, `.`, so it is one chunk of a key expression and can
/// hold no wildcard.
pub fn check_key(key: &str) -> Result<(), String> {
    let ok = !key.is_empty()
        && key.len() <= 100
        && key.bytes().all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'.'));
    if ok {
        Ok(())
    } else {
        Err(format!("`{key}` is not a run key (1 to 100 letters, digits, `_`, `-`, `.`)"))
    }
}

/// A zenoh endpoint this build can use: `tcp/HOST:PORT` or
/// `tls/HOST:PORT`, optionally with zenoh's `?metadata` or `#config` after
/// it (TCP and TLS are the only links built in). Checked before zenoh
/// sees it: zenoh's own error is a debug dump naming its source files.
pub fn check_endpoint(e: &str) -> Result<(), String> {
    parse_endpoint(e).map(|_| ())
}

/// An endpoint's link (`tcp`, `tls`) and host.
fn parse_endpoint(e: &str) -> Result<(&str, &str), String> {
    let bare = e.split(['?', '#']).next().unwrap_or("");
    let parsed = bare.split_once('/').filter(|(link, _)| matches!(*link, "tcp" | "tls")).and_then(|(link, addr)| {
        let (host, port) = addr.rsplit_once(':')?;
        let ok = !host.is_empty()
            && !host.chars().any(|c| c.is_control() || c.is_whitespace())
            && port.parse::<u16>().is_ok();
        ok.then_some((link, host))
    });
    parsed.ok_or_else(|| {
        format!(
            "`{}` is not an endpoint: expected tls/HOST:PORT or tcp/HOST:PORT, e.g. tls/0.0.0.0:7447",
            e.escape_default()
        )
    })
}

/// Whether `host` (an endpoint's) is this machine's loopback.
fn loopback(host: &str) -> bool {
    let ip = host.trim_start_matches('[').trim_end_matches(']');
    host == "localhost" || ip.parse::<std::net::IpAddr>().is_ok_and(|a| a.is_loopback())
}

/// How a zenoh run's links are protected.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Guard {
    /// Mutual TLS with the run's certificates (`--credentials`), the
    /// world admitting each robot to its own key expressions only.
    Tls,
    /// Plain TCP, nobody authenticated and nothing encrypted
    /// (`--insecure`): on loopback only, unless `network`
    /// (`--insecure-network`).
    Plain { network: bool },
}

impl Guard {
    /// The link its endpoints use.
    pub fn link(self) -> &'static str {
        match self {
            Guard::Tls => "tls",
            Guard::Plain { .. } => "tcp",
        }
    }

    /// Checks the `endpoints` flag `flag` gave (none: multicast scouting,
    /// the network) against the guard.
    pub fn check(self, flag: &str, endpoints: &[String]) -> Result<(), String> {
        if endpoints.is_empty() {
            return match self {
                Guard::Tls => Err(format!(
                    "with --credentials give {flag} tls/HOST:PORT: multicast scouting is not used with TLS"
                )),
                Guard::Plain { network: false } => Err(format!(
                    "without {flag} the world is found by multicast scouting, on the network: with --insecure \
                     that needs --insecure-network too"
                )),
                Guard::Plain { network: true } => Ok(()),
            };
        }
        for e in endpoints {
            let (link, host) = parse_endpoint(e).map_err(|err| format!("{flag}: {err}"))?;
            let shown = e.escape_default();
            match (self, link) {
                (Guard::Tls, "tcp") => {
                    return Err(format!(
                        "{flag} `{shown}` is plain TCP: with --credentials the links are TLS, tls/HOST:PORT \
                         (plain TCP only with --insecure)"
                    ))
                }
                (Guard::Plain { .. }, "tls") => {
                    return Err(format!("{flag} `{shown}`: a TLS link needs --credentials DIR"))
                }
                (Guard::Plain { network: false }, _) if !loopback(host) => {
                    return Err(format!(
                        "{flag} `{shown}` is not loopback: --insecure is plain TCP that anyone who reaches it can \
                         read, join and disturb, so it is allowed on 127.0.0.1, ::1 and localhost only, unless \
                         --insecure-network is given too (or use --credentials)"
                    ))
                }
                _ => {}
            }
        }
        Ok(())
    }
}

/// The world's side: one inbox per robot, one queue of answers.
pub trait WorldTransport {
    /// Puts one message (numbered `seq`) into robot `r`'s inbox, in chunks.
    fn post(&self, r: usize, seq: u64, bytes: &[u8]) -> Result<(), String>;
    /// Wakes robot `r` to read its inbox; false if the transport knows that
    /// nobody listens there.
    fn notify(&self, r: usize) -> bool;
    /// Waits up to `timeout` for robots to answer; pushes their ids.
    fn wait(&self, timeout: Duration, woke: &mut Vec<usize>);
    /// Takes the next chunk robot `r` sent into `buf`, if any. An error is
    /// a connection to the robot that failed.
    fn recv(&self, r: usize, buf: &mut Vec<u8>) -> Result<bool, String>;
    /// Whether robot `r` (process `pid`, as its hello said) is still there:
    /// `Some(false)` gone, `None` when this quick check cannot tell.
    fn liveness(&self, r: usize, pid: u32) -> Option<bool>;
    /// The robots known to be gone, by the transport's thorough check
    /// (asked only when [`WorldTransport::liveness`] cannot tell).
    fn gone(&self) -> Vec<usize>;
    /// Messages it dropped as not its robots' (a chunk tagged with a robot
    /// outside its service's group): counted with the run's dropped frames.
    fn mistagged(&self) -> u64 {
        0
    }
    /// Takes into `buf` the next chunk sent under a robot number outside
    /// the team, if one came, and returns that number: an agent started
    /// with a wrong `--robot`, whom the world refuses. iceoryx2 has no
    /// services for such a robot, so nothing ever comes there.
    fn stranger(&self, _buf: &mut Vec<u8>) -> Option<usize> {
        None
    }
    /// Puts one message (a refusal) into the inbox of robot `r` outside
    /// the team, once.
    fn post_stranger(&self, r: usize, _bytes: &[u8]) -> Result<(), String> {
        Err(format!("robot {r} has no inbox"))
    }
}

/// A robot's side: its inbox, its answers, and whether the world is there.
pub trait AgentTransport {
    /// Sends one message (numbered `seq`) to the world, in chunks, and wakes it.
    fn send(&self, seq: u64, bytes: &[u8]) -> Result<(), String>;
    /// Sleeps until the world posts something, or `timeout`.
    fn wait(&self, timeout: Duration);
    /// Takes the next chunk of the inbox into `buf`, if any.
    fn recv(&self, buf: &mut Vec<u8>) -> Result<bool, String>;
    /// False once the world is known to be gone.
    fn world_alive(&self) -> bool;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transports_parse_by_name_and_nothing_else() {
        for t in Transport::ALL {
            assert_eq!(t.name().parse::<Transport>(), Ok(t));
        }
        assert_eq!(Transport::default(), Transport::Iceoryx2);
        assert!("Zenoh".parse::<Transport>().unwrap_err().contains("unknown transport `Zenoh`"));
        assert!("".parse::<Transport>().is_err());
    }

    #[test]
    fn keys_are_one_plain_chunk() {
        assert!(check_key("gs12x00ab12_").is_ok());
        assert!(check_key("lab-run.3").is_ok());
        for bad in ["", "a/b", "a*", "**", "$x", "a b", &"k".repeat(101)] {
            assert!(check_key(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn endpoints_are_tcp_or_tls_host_port() {
        for good in ["tcp/127.0.0.1:7447", "tcp/[::1]:7447", "tcp/world.lab:1#iface=eth0", "tcp/h:0?x=1", "tls/h:7"] {
            assert_eq!(check_endpoint(good), Ok(()), "{good}");
        }
        for bad in ["garbage", "tcp/", "tcp/:7447", "tcp/host", "tcp/host:99999", "udp/h:1", "tcp/h\n:1", "quic/h:1"] {
            let err = check_endpoint(bad).unwrap_err();
            assert!(err.contains("expected tls/HOST:PORT or tcp/HOST:PORT"), "{bad}: {err}");
        }
        assert!(check_endpoint("tcp/h\u{1b}:1").unwrap_err().contains("\\u{1b}"), "escaped");
    }

    #[test]
    fn plain_tcp_stays_on_loopback_unless_the_network_is_asked_for() {
        let e = |s: &str| vec![s.to_string()];
        let plain = Guard::Plain { network: false };
        for lo in ["tcp/127.0.0.1:1", "tcp/127.9.0.1:1", "tcp/[::1]:1", "tcp/localhost:1"] {
            assert_eq!(plain.check("--listen", &e(lo)), Ok(()), "{lo}");
        }
        for far in ["tcp/0.0.0.0:7447", "tcp/10.0.0.1:1", "tcp/[::]:1", "tcp/world.lab:1"] {
            let err = plain.check("--listen", &e(far)).unwrap_err();
            assert!(err.contains("not loopback") && err.contains("--insecure-network"), "{far}: {err}");
            assert_eq!(Guard::Plain { network: true }.check("--listen", &e(far)), Ok(()));
        }
        assert!(plain.check("--connect", &[]).unwrap_err().contains("scouting"));
        assert!(plain.check("--listen", &e("tls/127.0.0.1:1")).unwrap_err().contains("needs --credentials"));
        assert!(Guard::Tls.check("--listen", &e("tcp/127.0.0.1:1")).unwrap_err().contains("plain TCP"));
        assert!(Guard::Tls.check("--listen", &[]).is_err());
        assert_eq!(Guard::Tls.check("--listen", &e("tls/0.0.0.0:7447")), Ok(()));
    }
}
