//! `robot-agent`: one robot of a distributed run, in its own process. It
//! holds only its [`RobotSetup`] (grid frame, parameters, identity, policy,
//! seed; never obstacles or targets), runs the robot's radio protocol
//! ([`Peer`]) and nothing else: no algorithm is written here.
//!
//! It reaches the world over iceoryx2 (the services the world-server
//! created; the default) or zenoh (`--transport zenoh`: a client of the
//! world's router, at `--connect` or found by scouting), says hello, then
//! loops: sleep until the world posts; read the world's [`Wake`] (all its chunks);
//! decode every frame it carries ([`protocol::decode`]; a bad one becomes a
//! `Malformed` note and is skipped); call [`Peer::wake`]; encode the frames
//! to send; publish its answer and notify the world. On `End` it exits 0;
//! if the world is gone (its process, or over zenoh its liveliness token;
//! checked whenever the world is quiet for `--world-timeout-ms`, or when a
//! notification of it reaches no one) it exits 3.
//!
//! Its hello presents the run's agreement as it holds it (key, scenario
//! hash, seed, algorithm, situation, parameters, protocol version;
//! [`gridswarm_robot::agreement`]), and it waits for the world's verdict before
//! it does anything else, saying hello again every [`HELLO_AGAIN`] until
//! the verdict comes (a lost message over zenoh). Refused (it differs from
//! the world, its robot number is outside the team or taken), it prints
//! the world's reason, `robot-agent K: error: refused by the world: ...`,
//! and exits 2; so it does if the world calls the run off later.
//!
//! Its setup comes from a file the orchestrator wrote (`--setup`): by
//! `gridswarm run` for the agents it starts, by `gridswarm setup` for an
//! agent started by hand on another host; like flashing firmware. It never
//! reads a scenario: it links the robot's crate and a transport, not the
//! world's crate. Errors: one line `robot-agent K: error: ...`, exit status 1;
//! the orchestrator ends the run on them (a wake-up of a live world that
//! reaches no one is one: the run would otherwise crawl on time-outs).
//!
//! It is a library so that a researcher's program can be the agent of its
//! own choice rules: [`main_with`] registers them, then runs as
//! `robot-agent` does (`gridswarm run --agent-bin PATH` starts it). With
//! `--list-rules` it prints the grid algorithms it runs, one a line.
//!
//! Testing hook: with `GRIDSWARM_AGENT_HANG=R@K` in its environment, robot
//! R stops itself (SIGSTOP) on the readings of slot K, before answering:
//! a live process that has gone silent, which no fault schedule makes.
//! A comma-separated list (`2@2,5@9`) stops several robots, each once.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use gridswarm_robot::agreement::Agreement;
use gridswarm_robot::choice::registry::{self, Factory};
use gridswarm_robot::grid::Grid;
use gridswarm_robot::io::{Note, Output};
use gridswarm_robot::peer::Peer;
use gridswarm_robot::policy::Policy;
use gridswarm_robot::protocol::{self, Frame, Limits};
use gridswarm_robot::setup::{RobotSetup, SetupFile};
use gridswarm_robot::wire::{
    self, AgentOutput, Assembler, Bytes, Hello, ToAgent, ToWorld, Verdict, Wake, WireLimits, WireSend, HANDSHAKE,
};
use gridswarm_transport::ipc::{self, names};
use gridswarm_transport::net::{NetConfig, Security, ZenohAgent};
use gridswarm_transport::{AgentTransport, Transport};
use iceoryx2::prelude::*;

#[derive(Parser, Debug)]
#[command(name = "robot-agent", about = "One gridswarm robot of a run of one process per robot")]
struct Args {
    /// Print the grid algorithms this agent runs, one a line, and exit.
    #[arg(long, exclusive = true)]
    list_rules: bool,
    /// The run's iceoryx2 prefix, made by the orchestrator; over zenoh, the
    /// run's key (the world's `--key`).
    #[arg(long, required_unless_present = "list_rules")]
    prefix: Option<String>,
    /// This robot's setup and the run's agreement (JSON, a `SetupFile`:
    /// `gridswarm setup` writes one for an agent started by hand).
    #[arg(long, required_unless_present = "list_rules")]
    setup: Option<PathBuf>,
    /// The world-server's process id, checked when the world goes quiet
    /// (iceoryx2; over zenoh the world's liveliness token tells).
    #[arg(long, required_if_eq("transport", "iceoryx2"))]
    world_pid: Option<u32>,
    /// How the world is reached: iceoryx2 (this machine) or zenoh (any network).
    #[arg(long, default_value = "iceoryx2")]
    transport: Transport,
    /// zenoh: the world's endpoint (e.g. tcp/10.0.0.1:7447); repeatable.
    /// Without one, the world is found by multicast scouting.
    #[arg(long, value_name = "ENDPOINT")]
    connect: Vec<String>,
    /// zenoh: the run's credentials folder (`gridswarm credentials`), with
    /// `ca.pem` and this robot's `robot-K.pem` and `robot-K.key`: mutual
    /// TLS on a `tls/` endpoint.
    #[arg(long, value_name = "DIR")]
    credentials: Option<PathBuf>,
    /// zenoh: plain TCP, nobody authenticated, nothing encrypted; to a
    /// loopback endpoint only.
    #[arg(long)]
    insecure: bool,
    /// zenoh: with --insecure, plain TCP beyond loopback too (or scouting).
    #[arg(long, requires = "insecure")]
    insecure_network: bool,
    /// zenoh: a link silent this long is lost (the world's host gone), ms.
    #[arg(long, default_value_t = gridswarm_transport::net::DEFAULT_LEASE_MS, value_parser = clap::value_parser!(u64).range(100..))]
    lease_ms: u64,
    /// zenoh: how long to wait for the world to appear, ms.
    #[arg(long, default_value_t = 60_000)]
    connect_timeout_ms: u64,
    /// Quiet time after which the world's liveness is checked, ms.
    #[arg(long, default_value_t = 500)]
    world_timeout_ms: u64,
}

enum Exit {
    Done,
    WorldGone,
    /// The world refused this agent, for this reason.
    Refused(String),
}

/// How often an agent says hello again while no verdict has come.
pub const HELLO_AGAIN: Duration = Duration::from_secs(2);

/// The error of a wake-up of the world that reached no one.
const UNREACHABLE: &str = "cannot notify the world: its listener cannot be reached";

/// The agent's iceoryx2 ports.
struct Ports {
    inbox: ipc::BytesSubscriber,
    /// Its group's outbox, shared with other robots; chunks carry `robot`.
    outbox: ipc::outbox::OutboxPublisher,
    robot: u32,
    listener: ipc::Listener,
    notifier: ipc::Notifier,
}

impl Ports {
    fn open(node: &Node<ipc::Svc>, robot: usize) -> Result<Self, String> {
        let inbox = ipc::open_bytes(node, &names::robot_in(robot), ipc::INBOX_CHUNKS)?;
        let outbox = ipc::outbox::open(node, &names::group_out(ipc::outbox::group_of(robot)), ipc::OUTBOX_CHUNKS)?;
        let wake = ipc::open_event(node, &names::robots_wake())?;
        let world_wake = ipc::open_event(node, &names::world_wake())?;
        Ok(Ports {
            inbox: ipc::bytes_subscriber(&inbox, ipc::INBOX_CHUNKS)?,
            outbox: ipc::outbox::publisher(&outbox)?,
            robot: robot as u32,
            listener: ipc::wake::listener(&wake, robot)?,
            notifier: world_wake
                .notifier_builder()
                // Its group's number: the world reads the group's outbox.
                .default_event_id(EventId::new(ipc::outbox::group_of(robot)))
                .create()
                .map_err(|e| format!("cannot create notifier: {e:?}"))?,
        })
    }

    /// Publishes one message in chunks and wakes the world.
    fn send(&self, seq: u64, bytes: &[u8]) -> Result<(), String> {
        let n = wire::chunk_count(bytes.len(), ipc::CHUNK_BYTES);
        if n > ipc::OUTBOX_CHUNKS {
            return Err(format!("an answer of {} bytes does not fit the outbox ({n} chunks)", bytes.len()));
        }
        let mut res = Ok(());
        wire::chunks(seq, bytes, ipc::CHUNK_BYTES, |c| {
            if res.is_ok() {
                res = ipc::outbox::publish(&self.outbox, self.robot, c);
            }
        });
        res?;
        // iceoryx2 reports a listener it could not reach (out of
        // descriptors, or the world gone) as zero notified, not an error.
        match self.notifier.notify() {
            Ok(n) if n > 0 => Ok(()),
            Ok(_) => Err(UNREACHABLE.into()),
            Err(e) => Err(format!("cannot notify the world: {e:?}")),
        }
    }
}

/// What the agent does with a message of the world.
enum Step {
    Answer(AgentOutput),
    Exit(Exit),
    Nothing,
}

/// One robot: its protocol state and what it checks the world's words against.
struct Agent<'g> {
    peer: Peer<'g>,
    /// Its hello's: the world's verdicts name it.
    nonce: u64,
    /// The slot on whose readings to stop itself (testing hook).
    hang_at: Option<u32>,
    limits: WireLimits,
    frame_limits: Limits,
    out: Output<Frame>,
}

impl Agent<'_> {
    /// What to do with one message of the world.
    fn answer(&mut self, seq: u64, bytes: &[u8]) -> Step {
        match wire::decode_to_agent(bytes, &self.limits) {
            Ok(ToAgent::End) => Step::Exit(Exit::Done),
            Ok(ToAgent::Wake(w)) => Step::Answer(self.wake(w)),
            // The world called the run off.
            Ok(ToAgent::Verdict(Verdict { nonce, refusal: Some(why) })) if nonce == self.nonce => {
                Step::Exit(Exit::Refused(why))
            }
            // Another claimant's verdict, or a repeat of this one's.
            Ok(ToAgent::Verdict(_)) => Step::Nothing,
            // An answer still goes back, or the world would wait for it.
            Err(_) if seq != HANDSHAKE => {
                Step::Answer(AgentOutput { seq, notes: vec![Note::Malformed], ..Default::default() })
            }
            Err(_) => Step::Nothing,
        }
    }

    fn wake(&mut self, w: Wake) -> AgentOutput {
        if w.tick.as_ref().zip(self.hang_at).is_some_and(|(t, k)| t.round >= k) {
            self.hang_at = None;
            // SAFETY: raise(2) on this process.
            unsafe {
                libc::raise(libc::SIGSTOP);
            }
        }
        let mut frames = Vec::with_capacity(w.frames.len());
        let mut malformed = 0;
        for f in &w.frames {
            match protocol::decode(&f.bytes.0, &self.frame_limits) {
                Ok(frame) => frames.push((f.from, f.at, frame)),
                Err(_) => malformed += 1,
            }
        }
        self.peer.wake(w.now, w.tick.as_ref(), frames.iter().map(|(from, at, f)| (*from, *at, f)), &mut self.out);
        let o = &mut self.out;
        let mut notes = std::mem::take(&mut o.notes);
        notes.extend(std::iter::repeat_n(Note::Malformed, malformed));
        AgentOutput {
            seq: w.seq,
            send: o
                .send
                .drain(..)
                .map(|t| WireSend { bytes: Bytes(protocol::encode(&t.payload)), ready: t.ready, copies: t.copies })
                .collect(),
            motor: o.motor,
            alarm: o.alarm,
            listen: o.listen,
            notes,
        }
    }
}

/// `GRIDSWARM_AGENT_HANG=R@K[,R@K...]`: the slot at which robot R stops itself.
fn hang_at(robot: usize) -> Option<u32> {
    let v = std::env::var("GRIDSWARM_AGENT_HANG").ok()?;
    v.split(',').find_map(|one| {
        let (r, k) = one.split_once('@')?;
        (r.trim().parse::<usize>().ok()? == robot).then_some(())?;
        k.trim().parse().ok()
    })
}

fn read_setup(path: &PathBuf) -> Result<(RobotSetup, Agreement), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read `{}`: {e}", path.display()))?;
    let file = parse_setup(&text).map_err(|e| format!("`{}`: {e}", path.display()))?;
    // A policy travels by name: this agent must have the rule.
    registry::runnable(file.setup.policy)?;
    // Presented as run: what the setup holds, not a declared copy of it.
    let agreement = file.agreement();
    Ok((file.setup, agreement))
}

/// A setup file's text; one of the old form, whose agreement was a
/// declared copy beside the setup (and could differ from it), is refused
/// by name.
fn parse_setup(text: &str) -> Result<SetupFile, String> {
    let v: serde_json::Value = serde_json::from_str(text).map_err(|e| e.to_string())?;
    if v.get("agreement").is_some() {
        return Err("it has an `agreement` section beside its `setup`, an older gridswarm's form whose \
                    agreement could differ from what the robot runs: write it again with `gridswarm setup`"
            .into());
    }
    serde_json::from_value(v).map_err(|e| e.to_string())
}

/// The names of the grid algorithms this process can run.
fn rule_names() -> Vec<&'static str> {
    let built_in = Policy::ALL.into_iter().filter(|p| p.on_grid()).map(Policy::name);
    built_in
        .chain(registry::custom_names().into_iter().filter(|n| n.parse().is_ok_and(|p| registry::runnable(p).is_ok())))
        .collect()
}

fn run(args: &Args, setup: &RobotSetup, agreement: &Agreement) -> Result<Exit, String> {
    ipc::quiet_logs();
    let Some(prefix) = &args.prefix else {
        return Err("--prefix is needed".into());
    };
    let robot = setup.id as usize;
    match args.transport {
        Transport::Iceoryx2 => {
            let Some(world_pid) = args.world_pid else {
                return Err("--world-pid is needed".into());
            };
            let config = ipc::config(prefix)?;
            let node = ipc::create_node(&config, &names::robot_node(robot))?;
            let ports = Ports::open(&node, robot)?;
            serve(args, setup, agreement, &Iceoryx2 { ports, world_pid })
        }
        Transport::Zenoh => {
            let mut net = NetConfig::new(prefix, security_of(args)?);
            net.connect.clone_from(&args.connect);
            net.lease_ms = args.lease_ms;
            net.connect_timeout = Duration::from_millis(args.connect_timeout_ms);
            serve(args, setup, agreement, &ZenohAgent::open(&net, robot)?)
        }
    }
}

/// The protection `--credentials` or `--insecure` asks for.
fn security_of(args: &Args) -> Result<Security, String> {
    Security::from_flags(args.credentials.as_deref(), args.insecure, args.insecure_network, "--connect", &args.connect)
}

/// The robot's life once it reaches the world: hello, the world's
/// verdict, then one answer per message until `End` or the world is gone.
fn serve(args: &Args, setup: &RobotSetup, agreement: &Agreement, link: &dyn AgentTransport) -> Result<Exit, String> {
    let grid: Grid = setup.grid();
    // This robot's maps and the maps it decodes read one table of edge masks.
    let _masks = gridswarm_robot::map::tiles::SharedMasks::new(grid.len());
    let robot = setup.id as usize;
    let mut agent = Agent {
        peer: Peer::new(&grid, setup.peer_config()),
        nonce: nonce(),
        hang_at: hang_at(robot),
        limits: WireLimits::for_robot(grid.len(), setup.targets_total),
        frame_limits: Limits::for_robot(grid.len(), setup.targets_total),
        out: Output::default(),
    };
    let hello = Hello {
        agreement: agreement.clone(),
        robot: setup.id as u32,
        pid: std::process::id(),
        host: host_name(),
        nonce: agent.nonce,
    };
    let hello = wire::encode_to_world(&ToWorld::Hello(Box::new(hello)));
    let mut asm = Assembler::new(ipc::INBOX_CHUNKS * ipc::CHUNK_BYTES);
    let mut buf = Vec::with_capacity(ipc::CHUNK_BYTES);
    let timeout = Duration::from_millis(args.world_timeout_ms.max(1));
    if let Some(exit) = handshake(&agent, link, &hello, (&mut asm, &mut buf), timeout)? {
        return Ok(exit);
    }
    // The first wake-up may have come with the verdict: read before waiting.
    let mut first = true;
    loop {
        if !first {
            link.wait(timeout);
        }
        let mut got = false;
        while link.recv(&mut buf)? {
            got = true;
            let Ok(Some((seq, bytes))) = asm.push(&buf) else { continue };
            match agent.answer(seq, bytes) {
                Step::Answer(o) => link.send(seq, &wire::encode_to_world(&ToWorld::Output(o)))?,
                Step::Exit(exit) => return Ok(exit),
                Step::Nothing => {}
            }
        }
        // Quiet after a wait: is the world still there?
        if !got && !first && !link.world_alive() {
            return Ok(Exit::WorldGone);
        }
        first = false;
    }
}

/// Says hello until the world's verdict on it comes: `None` accepted,
/// otherwise how the agent ends. Everything else the world says meanwhile
/// (wake-ups of another claimant of this robot number) is not its own;
/// what comes after its verdict is left for the loop. The world does not
/// wake it for its verdict: it looks every `timeout` (`--world-timeout-ms`).
fn handshake(
    agent: &Agent,
    link: &dyn AgentTransport,
    hello: &[u8],
    (asm, buf): (&mut Assembler, &mut Vec<u8>),
    timeout: Duration,
) -> Result<Option<Exit>, String> {
    let mut said: Option<std::time::Instant> = None;
    loop {
        if said.is_none_or(|t| t.elapsed() >= HELLO_AGAIN) {
            link.send(HANDSHAKE, hello)?;
            said = Some(std::time::Instant::now());
        }
        link.wait(timeout.min(HELLO_AGAIN));
        let mut got = false;
        while link.recv(buf)? {
            got = true;
            let Ok(Some((_, bytes))) = asm.push(buf) else { continue };
            match wire::decode_to_agent(bytes, &agent.limits) {
                Ok(ToAgent::Verdict(v)) if v.nonce == agent.nonce => return Ok(v.refusal.map(Exit::Refused)),
                Ok(ToAgent::End) => return Ok(Some(Exit::Done)),
                _ => {}
            }
        }
        if !got && !link.world_alive() {
            return Ok(Some(Exit::WorldGone));
        }
    }
}

/// A number drawn once per process (std's per-process random hash keys,
/// with the process id and the time): tells its claims from another's.
fn nonce() -> u64 {
    use std::hash::{BuildHasher, Hasher};
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u32(std::process::id());
    h.write_u128(std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos()));
    h.finish()
}

/// This host's name (its UTS namespace's), for the world's messages.
fn host_name() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname").map_or_else(|_| "?".into(), |s| s.trim().to_string())
}

/// The iceoryx2 ports behind [`AgentTransport`]; the world's liveness is
/// its process on this host.
struct Iceoryx2 {
    ports: Ports,
    world_pid: u32,
}

impl AgentTransport for Iceoryx2 {
    fn send(&self, seq: u64, bytes: &[u8]) -> Result<(), String> {
        self.ports.send(seq, bytes)
    }

    fn wait(&self, timeout: Duration) {
        let _ = self.ports.listener.timed_wait(|_| {}, timeout);
    }

    fn recv(&self, buf: &mut Vec<u8>) -> Result<bool, String> {
        ipc::receive(&self.ports.inbox, buf)
    }

    fn world_alive(&self) -> bool {
        ipc::pid_alive(self.world_pid)
    }
}

/// The setup and agreement from `--setup`.
fn setup_of(args: &Args) -> Result<(RobotSetup, Agreement), String> {
    match &args.setup {
        Some(path) => read_setup(path),
        None => Err("--setup is needed".into()),
    }
}

/// The agent's whole program, with `rules` (name, factory) registered
/// first: `robot-agent` is `main_with(&[])`.
pub fn main_with(rules: &[(&str, Factory)]) -> ExitCode {
    for &(name, factory) in rules {
        if let Err(e) = registry::register(name, factory) {
            eprintln!("robot-agent: error: {e}");
            return ExitCode::from(2);
        }
    }
    let args = match Args::try_parse() {
        Ok(a) => a,
        Err(e) if !e.use_stderr() => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(2);
        }
    };
    if args.list_rules {
        for n in rule_names() {
            println!("{n}");
        }
        return ExitCode::SUCCESS;
    }
    if args.transport == Transport::Zenoh {
        if let Err(e) = security_of(&args) {
            eprintln!("robot-agent: error: {e}");
            return ExitCode::from(2);
        }
    }
    let (setup, agreement) = match setup_of(&args) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("robot-agent: error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let world_pid = args.world_pid.unwrap_or(0);
    // Unreachable because the world died: that is not this robot's error.
    let result = match run(&args, &setup, &agreement) {
        Err(e) if e == UNREACHABLE && !ipc::pid_alive(world_pid) => Ok(Exit::WorldGone),
        r => r,
    };
    match result {
        Ok(Exit::Done) => ExitCode::SUCCESS,
        Ok(Exit::WorldGone) => {
            eprintln!("robot-agent {}: the world-server is gone", setup.id);
            ExitCode::from(ipc::EXIT_WORLD_GONE as u8)
        }
        Ok(Exit::Refused(why)) => {
            eprintln!("robot-agent {}: error: refused by the world: {}", setup.id, why.replace('\n', "; "));
            ExitCode::from(2)
        }
        Err(e) => {
            eprintln!("robot-agent {}: error: {}", setup.id, e.replace('\n', "; "));
            ExitCode::FAILURE
        }
    }
}
