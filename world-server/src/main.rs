//! `world-server`: the physical world of a distributed run, and nothing
//! else: sensors, the radio medium (it carries frames as opaque bytes),
//! the clock, motors and the collision referee. It runs the same
//! discrete-event kernel as the in-process engine ([`gridswarm::sim`]),
//! with every robot in a `robot-agent` process ([`remote::Remote`]),
//! reached over iceoryx2 (one machine, the default) or zenoh (`--transport
//! zenoh`: it listens on `--listen` endpoints, or is found by scouting). It
//! never reads a frame, never tells a robot that another failed, never
//! waits for the protocol: everything a robot knows it sensed or heard.
//!
//! Talking to the orchestrator, on stdout: `ready` once the services exist;
//! `fault K` when the world pauses at fault `K` of the run's schedule, after
//! which it waits for one line `go` on stdin (the orchestrator signals the
//! robot's process meanwhile); with `--progress`, `tick K` at the start of
//! every slot and `alive` every second while it waits for robots; `done`
//! after the report is written. Errors are one
//! `error: ...` line on stderr and exit status 1; usage errors clap's
//! message and exit status 2, and so is a robot-agent refused because it
//! does not agree with the world's run (its `error:` line names what
//! differs on both sides: [`remote`]). A run whose descriptors the open-file limit
//! cannot hold is refused before any service exists; a signal ends the
//! world after removing the run's files ([`signals`]).

mod link;
mod remote;
mod signals;
mod transport;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use clap::Parser;
use gridswarm::agreement::{Agreement, ScenarioId};
use gridswarm::ipc::{self, RunFile, RunReport};
use gridswarm::net::{NetConfig, Security, ZenohWorld};
use gridswarm::outcome::RunResult;
use gridswarm::scenario::Scenario;
use gridswarm::sim::watch::Tape;
use gridswarm::sim::Kernel;
use gridswarm::transport::{Transport, WorldTransport};
use gridswarm::wire::WireLimits;
use gridswarm::world::World;

use crate::remote::{say, Failure, Patience, Remote};

#[derive(Parser, Debug)]
#[command(name = "world-server", about = "gridswarm's physical world for a run of one process per robot")]
struct Args {
    /// The run's iceoryx2 prefix (gs<pid>x<hex>_), made by the orchestrator.
    #[arg(long)]
    prefix: String,
    /// The run (JSON: scenario, robots, retries, config).
    #[arg(long)]
    run: PathBuf,
    /// Where to write the run's report (JSON).
    #[arg(long)]
    report: PathBuf,
    /// Print `tick K` at the start of every slot.
    #[arg(long)]
    progress: bool,
    /// Silence after which the world checks whether silent robots still exist, ms.
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u64).range(1..))]
    check_ms: u64,
    /// A live robot silent this long ends the run with an error, seconds.
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u64).range(1..))]
    silence_s: u64,
    /// How long to wait for every robot's hello, ms [default: 30 s + 100 ms a robot].
    #[arg(long)]
    hello_timeout_ms: Option<u64>,
    /// How robots are reached: iceoryx2 (this machine) or zenoh (any network).
    #[arg(long, default_value = "iceoryx2")]
    transport: Transport,
    /// zenoh: an endpoint to listen on (e.g. tcp/10.0.0.1:7447); repeatable.
    /// With neither --listen nor --connect, robots find the world by scouting.
    #[arg(long, value_name = "ENDPOINT")]
    listen: Vec<String>,
    /// zenoh: an endpoint to connect to (e.g. a zenoh router's); repeatable.
    #[arg(long, value_name = "ENDPOINT")]
    connect: Vec<String>,
    /// zenoh: the run's key, which agents give too [default: the prefix].
    #[arg(long)]
    key: Option<String>,
    /// zenoh: a link silent this long is lost (a robot's host gone), ms.
    #[arg(long, default_value_t = gridswarm::net::DEFAULT_LEASE_MS, value_parser = clap::value_parser!(u64).range(100..))]
    lease_ms: u64,
    /// zenoh: the run's credentials folder (`gridswarm credentials`):
    /// mutual TLS on `tls/` endpoints, each robot admitted to its own key
    /// expressions only.
    #[arg(long, value_name = "DIR")]
    credentials: Option<PathBuf>,
    /// zenoh: plain TCP, nobody authenticated, nothing encrypted; on
    /// loopback endpoints only.
    #[arg(long)]
    insecure: bool,
    /// zenoh: with --insecure, plain TCP beyond loopback too.
    #[arg(long, requires = "insecure")]
    insecure_network: bool,
    /// The agents run on other hosts: their process ids mean nothing here,
    /// so their memory and CPU are not measured.
    #[arg(long)]
    remote_agents: bool,
    /// Record what the world sees (frames, faults, slots, sensor readings)
    /// on a tape here as it happens (`gridswarm run --mcap`, `--live`).
    #[arg(long, value_name = "FILE")]
    watch: Option<PathBuf>,
}

/// What the world serves: the run file, its world, start vertices and
/// the scenario's id (taken before the run's overrides).
type Loaded = (RunFile, World, Vec<u32>, ScenarioId);

/// The run file, its world and start vertices.
fn load(path: &PathBuf) -> Result<Loaded, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read `{}`: {e}", path.display()))?;
    let run: RunFile = serde_json::from_str(&text).map_err(|e| format!("`{}`: {e}", path.display()))?;
    let mut scenario = Scenario::load(&run.scenario).map_err(|e| e.to_string())?;
    let id = ScenarioId::of(&scenario);
    if let Some(r) = run.retries {
        scenario.params.retries = r;
    }
    if let Some(s) = run.slot {
        scenario.params.slot = s;
    }
    if let Some(o) = run.order {
        scenario.params.order = o;
    }
    scenario.situation = run.config.situation;
    if !run.config.policy.on_grid() {
        return Err(format!(
            "algorithm `{}` does not move on the grid; the distributed engine runs grid policies only",
            run.config.policy
        ));
    }
    if run.robots == 0 || run.robots > ipc::MAX_ROBOTS {
        return Err(format!("robots must be 1 to {}, got {}", ipc::MAX_ROBOTS, run.robots));
    }
    gridswarm::sim::schedule::check(&run.config.faults, run.robots)?;
    let world = scenario.world();
    let starts = scenario.starts_by(&world, run.robots, run.starts, run.config.seed).map_err(|e| e.to_string())?;
    Ok((run, world, starts, id))
}

fn run(args: Args) -> Result<(), Failure> {
    let t0 = Instant::now();
    ipc::quiet_logs();
    let config = ipc::config(&args.prefix)?;
    // Dropped last, after the ports: then nothing of the run is in use.
    let _orphan = signals::end_cleanly_on_signals(signals::Cleanup {
        prefix: args.prefix.clone(),
        run_dir: signals::run_dir_of(&args.run, &args.prefix),
    })?;
    let loaded = load(&args.run)?;
    let robots = loaded.0.robots;
    if args.transport == Transport::Zenoh {
        let endpoints = [&args.listen[..], &args.connect[..]].concat();
        let security = Security::from_flags(
            args.credentials.as_deref(),
            args.insecure,
            args.insecure_network,
            "--listen",
            &endpoints,
        )?;
        let mut net = NetConfig::new(key(&args), security);
        net.listen.clone_from(&args.listen);
        net.connect.clone_from(&args.connect);
        net.lease_ms = args.lease_ms;
        let zenoh = ZenohWorld::open(&net, robots)?;
        let res = serve(&args, &zenoh, loaded, t0);
        if zenoh.repeats() > 0 {
            // A session that dropped and came back, or a robot starved of CPU.
            eprintln!("warning: {} message(s) put again to robots that had not answered", zenoh.repeats());
        }
        return res;
    }
    // Running out of descriptors midway would look like dead robots.
    gridswarm::nofile::ensure(gridswarm::nofile::needed(robots), &format!("a world of {robots} robots"))?;
    let node = link::world_node(&config)?;
    let services = link::Services::create(&node, robots)?;
    let ports = link::Ports::new(&services)?;
    serve(&args, &transport::Iceoryx2 { ports: &ports, config: &config }, loaded, t0)
}

/// The run key agents present: zenoh's `--key`, or the prefix.
fn key(args: &Args) -> &str {
    args.key.as_deref().unwrap_or(&args.prefix)
}

/// Runs the world over `link` once it is up, and writes the report.
fn serve(args: &Args, link: &dyn WorldTransport, (run, world, starts, id): Loaded, t0: Instant) -> Result<(), Failure> {
    let robots = run.robots;
    say("ready")?;
    let limits = WireLimits::for_world(robots, world.grid.len(), world.targets.len());
    let patience = Patience {
        check: Duration::from_millis(args.check_ms),
        limit: Duration::from_secs(args.silence_s),
        progress: args.progress,
    };
    let c = &run.config;
    // Derived as each agent derives its own, from the setup it would hand a robot.
    let agreement = Agreement::of(key(args), id, &c.robot_setup(&world, 0, robots));
    let mut remote = Remote::new(link, agreement.clone(), limits, patience, c.faults.clone());
    remote.hello(Duration::from_millis(args.hello_timeout_ms.unwrap_or(30_000 + 100 * robots as u64)))?;
    let startup_ms = t0.elapsed().as_secs_f64() * 1e3;
    let cpu0 = ipc::cpu_ms_of(std::process::id());
    let mut cfg = run.config.clone();
    cfg.record_trajectories = true;
    let result = match &args.watch {
        Some(path) => {
            let file = std::fs::File::create(path).map_err(|e| format!("cannot write `{}`: {e}", path.display()))?;
            let mut tape = Tape::new(std::io::BufWriter::new(file));
            let result = Kernel::<std::rc::Rc<[u8]>>::new(&world, &starts, &cfg).watched(&mut tape).run(&mut remote);
            tape.finish().map_err(|e| format!("cannot write `{}`: {e}", path.display()))?;
            result
        }
        None => Kernel::new(&world, &starts, &cfg).run(&mut remote),
    };
    remote.finish_rounds();
    if let Some(e) = remote.failed.take() {
        remote.end();
        return Err(e.into());
    }
    let world_cpu_ms = ipc::cpu_ms_of(std::process::id()) - cpu0;
    // Measured before `End`, while every agent still runs.
    let local = if args.remote_agents { &[][..] } else { remote.pids() };
    let agent_peak_rss_kib = local.iter().map(|&p| ipc::peak_rss_kib_of(p)).collect();
    let agent_cpu_ms = local.iter().map(|&p| ipc::cpu_ms_of(p)).collect();
    let world_fds = ipc::open_fds();
    remote.end();
    let report = RunReport {
        vertices: vertices(&world, &result),
        round_end_times_s: result.round_end_times_s.clone(),
        result,
        round_wall_ms: std::mem::take(&mut remote.round_wall_ms),
        startup_ms,
        paused_ms: remote.paused_total.as_secs_f64() * 1e3,
        world_fds,
        world_peak_rss_kib: ipc::peak_rss_kib(),
        world_cpu_ms,
        agent_peak_rss_kib,
        agent_cpu_ms,
        died: remote.died(),
        dropped: remote.dropped + link.mistagged(),
        liveness_checks: remote.liveness_checks,
        wake_batches: remote.batches,
        largest_wake_bytes: remote.largest_wake,
        agreement,
    };
    let text = serde_json::to_string(&report).map_err(|e| format!("cannot encode the report: {e}"))?;
    std::fs::write(&args.report, text).map_err(|e| format!("cannot write `{}`: {e}", args.report.display()))?;
    Ok(say("done")?)
}

/// `vertices[r][k]`: robot `r`'s vertex at the start of round `k`.
fn vertices(world: &World, result: &RunResult) -> Vec<Vec<u32>> {
    let id = |p: &gridswarm::outcome::Pose| p.vertex.and_then(|c| world.grid.id_of(c)).unwrap_or(u32::MAX);
    result.trajectories.iter().map(|t| t.iter().map(id).collect()).collect()
}

fn main() -> ExitCode {
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
    match run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Refused(e)) => {
            eprintln!("error: {}", e.replace('\n', "; "));
            ExitCode::from(2)
        }
        Err(Failure::Other(e)) => {
            eprintln!("error: {}", e.replace('\n', "; "));
            ExitCode::FAILURE
        }
    }
}
