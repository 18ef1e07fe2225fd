//! `world-server`: the physical world of a distributed run (issue "One
//! process per robot"). It builds the world from the scenario, creates every
//! iceoryx2 service of the run with room for every robot, prints `ready`,
//! waits for every robot-agent's hello, then plays rounds (see `server.rs`)
//! and writes the run's report where `--report` says.
//!
//! Talking to the orchestrator, on stdout: `ready` once the services exist;
//! `round K` when it pauses at the start of round K (`--pause-at`), after
//! which it waits for one line `go` on stdin (the orchestrator injects
//! failures meanwhile); with `--progress`, `tick K` at the start of every
//! other round; `done` after the report is written. Errors are one
//! `error: ...` line on stderr and exit status 1.

mod link;
mod server;

use std::io::{BufRead, Write};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use gridswarm::ipc;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;

use crate::server::{Server, Settings};

#[derive(Parser, Debug)]
#[command(
    name = "world-server",
    about = "gridswarm's physical world for a run of one process per robot"
)]
struct Args {
    /// The run's iceoryx2 prefix (gs<pid>x<hex>_), made by the orchestrator.
    #[arg(long)]
    prefix: String,
    /// Built-in scenario or TOML file.
    #[arg(long, default_value = "paper")]
    scenario: String,
    #[arg(long, default_value = "repulsive")]
    algorithm: Policy,
    /// Number of robots [default: the scenario's].
    #[arg(long)]
    robots: Option<usize>,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// 1 or 2 [default: the scenario's].
    #[arg(long)]
    situation: Option<u8>,
    #[arg(long, default_value_t = 100_000)]
    max_rounds: u32,
    /// A robot silent this long while nothing it waits for is missing is declared failed.
    #[arg(long, default_value_t = 2000)]
    suspect_ms: u64,
    /// After this much silence, check whether the processes waited for are alive.
    #[arg(long, default_value_t = 20)]
    check_ms: u64,
    /// Rounds at whose start to pause for failure injection, comma-separated.
    #[arg(long, value_delimiter = ',')]
    pause_at: Vec<u32>,
    /// How long to wait for every robot's hello, in milliseconds [default: 30 s + 100 ms a robot].
    #[arg(long)]
    hello_timeout_ms: Option<u64>,
    /// Print `tick K` at the start of every round that does not pause (for
    /// the orchestrator, so it can say in which round the world died).
    #[arg(long)]
    progress: bool,
    /// Where to write the run's report (JSON).
    #[arg(long)]
    report: PathBuf,
}

fn say(line: &str) -> Result<(), String> {
    let mut out = std::io::stdout().lock();
    writeln!(out, "{line}")
        .and_then(|_| out.flush())
        .map_err(|e| format!("cannot write to stdout: {e}"))
}

fn run(args: Args) -> Result<(), String> {
    ipc::quiet_logs();
    let nofile = ipc::raise_nofile_limit();
    let config = ipc::config(&args.prefix)?;
    let mut scenario = Scenario::load(&args.scenario).map_err(|e| e.to_string())?;
    if let Some(s) = args.situation {
        scenario.situation = Situation::from_number(s)
            .ok_or_else(|| format!("situation must be 1 or 2, got {s}"))?;
    }
    if !args.algorithm.on_grid() {
        return Err(format!("algorithm `{}` does not move on the grid; the distributed engine runs grid policies only", args.algorithm));
    }
    let robots = args.robots.unwrap_or(scenario.robots);
    if robots == 0 || robots > ipc::MAX_ROBOTS {
        return Err(format!(
            "robots must be in 1..={}, got {robots}",
            ipc::MAX_ROBOTS
        ));
    }
    let world = scenario.world();
    let starts = scenario
        .start_vertices(&world, robots)
        .map_err(|e| e.to_string())?;
    // About six descriptors a robot; say so plainly rather than fail inside iceoryx2.
    if (nofile as usize) < 8 * robots + 64 {
        eprintln!("warning: open-file limit {nofile} may be too low for {robots} robots");
    }

    let node = link::world_node(&config)?;
    let services = link::Services::create(&node, robots)?;
    let limits = gridswarm::protocol::Limits {
        vertices: world.grid.len(),
        targets: world.targets.len(),
        robots,
    };
    let ports = link::WorldPorts::new(&services, ipc::max_message_len(&limits))?;
    let waitset = iceoryx2::prelude::WaitSetBuilder::new()
        .signal_handling_mode(iceoryx2::prelude::SignalHandlingMode::Disabled)
        .create::<iceoryx2::prelude::ipc::Service>()
        .map_err(|e| format!("cannot create the wait set: {e:?}"))?;
    let _guard = waitset
        .attach_notification(&ports.listener)
        .map_err(|e| format!("cannot attach the listener: {e:?}"))?;
    let mut link = link::IoxLink::new(&config, &ports, &waitset);
    say("ready")?;

    let settings = Settings {
        policy: args.algorithm,
        situation: scenario.situation,
        seed: args.seed,
        max_rounds: args.max_rounds,
        check: Duration::from_millis(args.check_ms.max(1)),
        suspect: Duration::from_millis(args.suspect_ms.max(1)),
        hello_timeout: Duration::from_millis(
            args.hello_timeout_ms
                .unwrap_or(30_000 + 100 * robots as u64),
        ),
    };
    let mut server = Server::new(&world, &starts, settings);
    server.hello(&mut link).map_err(|e| e.to_string())?;
    let mut pauses: Vec<u32> = args.pause_at.clone();
    pauses.sort_unstable();
    pauses.dedup();
    let progress = args.progress;
    let stdin = std::io::stdin();
    let mut line = String::new();
    loop {
        if pauses.binary_search(&server.round()).is_ok() {
            say(&format!("round {}", server.round()))?;
            line.clear();
            let n = stdin
                .lock()
                .read_line(&mut line)
                .map_err(|e| format!("cannot read stdin: {e}"))?;
            if n == 0 {
                return Err(format!(
                    "stdin closed while paused in round {}",
                    server.round()
                ));
            }
            if line.trim() != "go" {
                return Err(format!("expected `go` on stdin, got `{}`", line.trim()));
            }
            server.paused();
        } else if progress {
            say(&format!("tick {}", server.round()))?;
        }
        if !server.play_round(&mut link) {
            break;
        }
    }
    let ended_by = if server.stopped() {
        "stop"
    } else if server.alive_count() == 0 {
        "no_robots"
    } else {
        "max_rounds"
    };
    let report = server.report(ended_by, ipc::open_fds(), ipc::peak_rss_kib());
    let text =
        serde_json::to_string(&report).map_err(|e| format!("cannot encode the report: {e}"))?;
    std::fs::write(&args.report, text)
        .map_err(|e| format!("cannot write `{}`: {e}", args.report.display()))?;
    say("done")?;
    Ok(())
}

fn main() -> ExitCode {
    let args = match Args::try_parse() {
        Ok(a) => a,
        Err(e) if !e.use_stderr() => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            let rendered = e.to_string();
            eprintln!(
                "{}",
                rendered
                    .lines()
                    .find(|l| !l.trim().is_empty())
                    .unwrap_or("error: bad arguments")
            );
            return ExitCode::from(2);
        }
    };
    match run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
