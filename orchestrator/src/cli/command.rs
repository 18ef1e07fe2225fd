//! The `gridswarm` command line as a library call: parses arguments, calls
//! the library, and turns every error into one `error: ...` line on stderr
//! (a usage error keeps clap's whole message: its suggestions and the usage
//! line). [`main_with`] is the whole tool; given choice rules of one's own,
//! it is the whole tool with them as algorithms of every command
//! (robot-agent/examples/my_rule.rs). It never runs a command itself.
//!
//! Exit status ([`EXIT_STATUS`]): 0 success; 1 an error (bad scenario,
//! unwritable output, a failed child, a signal, ...); 2 a usage error
//! (unknown algorithm, bad robot range, ...); 3 the search ended incomplete
//! (`simulate`, `run`) or `check` found an assumption that does not hold;
//! 4 robots collided under an algorithm that promises they never do, or
//! its parameters would let them (`check`'s S0) and the search was refused;
//! 5 the search went past a stated bound and stalled (`past_bound`).

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use crate::error::{EXIT_COLLISION, EXIT_INCOMPLETE};
use crate::experiment::{self, ExperimentOptions, DEFAULT_ALGORITHMS, DEFAULT_OUT, DEFAULT_ROBOTS, DEFAULT_RUNS};
use crate::failures::{self, FailuresOptions};
use crate::faults::{FaultFlags, RunBase};
use crate::grids::{self, GridsOptions};
use crate::progress::Ticker;
use crate::radio::{self, RadioOptions};
use crate::readings::{self, ReadingsOptions};
use crate::robots::{RobotCounts, MAX_ROBOTS};
use crate::scale::{self, ScaleOptions};
use crate::settings::Setting;
use crate::simulate::{self, SimulateOptions};
use crate::sweep::{Engine, ProtocolOptions};
use crate::{check, Error};
use clap::{Parser, Subcommand};
use gridswarm::choice::Factory;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::scenario::limits::DEFAULT_MAX_ROUNDS;
use gridswarm::scenario::StartRule;

#[derive(Parser, Debug)]
#[command(name = "gridswarm", version, about = "Decentralized multi-robot search on a grid (Yang, CCC 2017)")]
#[command(after_help = EXIT_STATUS)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// One search in-process: a summary, or one JSON object; with --out, its files.
    /// Takes the same failure and radio flags as `run`.
    Simulate {
        #[command(flatten)]
        scenario: ScenarioArg,
        /// repulsive, sequential, ru, lfp, escape, frontier, frontier-coord, frontier-sensed,
        /// frontier-sensed-coord or oracle (a reference planner).
        #[arg(long, default_value = "repulsive")]
        algorithm: Policy,
        /// Number of robots [default: the scenario's].
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..=MAX_ROBOTS as i64))]
        robots: Option<u32>,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// 1: the number of targets is known; 2: it is not [default: the scenario's].
        #[arg(long, value_parser = clap::value_parser!(u8).range(1..=2))]
        situation: Option<u8>,
        /// Write summary.json, trajectories.jsonl, routes.svg, world.json, rounds.csv and
        /// replay.html here (created if missing).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print exactly one JSON object instead of the summary.
        #[arg(long)]
        json: bool,
        /// A run not stopped after this many rounds ends incomplete [default: 100000, fewer on
        /// big maps and teams: the work budget MAX_SEARCH_WORK, docs/scenario-format.md "Limits"].
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
        max_rounds: Option<u32>,
        #[command(flatten)]
        faults: FaultFlags,
        #[command(flatten)]
        view: crate::cli::view::ViewFlags,
    },
    /// The Monte Carlo sweep of Fig. 7 and its claims; with --grids, the
    /// lattice comparison of Sec. 3 instead; `readings` for the claims over
    /// the paper's open readings; `failures`, `radio` and `scale` for the
    /// protocol under crashes, radio loss and growing robot counts.
    ///
    /// Writes results.csv, runs.csv (each with the runs' metrics),
    /// coverage.csv, fig7.svg, claims.txt, summary.json and report.html
    /// (grids.csv and grids.html with --grids) in --out, and prints the
    /// table and claims.
    #[command(args_conflicts_with_subcommands = true)]
    Experiment {
        #[command(subcommand)]
        kind: Option<ExperimentKind>,
        #[command(flatten)]
        scenario: ScenarioArg,
        /// Comma-separated algorithms (repulsive, sequential, ru, lfp, escape, frontier,
        /// frontier-coord, frontier-sensed, frontier-sensed-coord, oracle).
        #[arg(long, value_delimiter = ',', default_value = DEFAULT_ALGORITHMS, conflicts_with = "grids")]
        algorithms: Vec<Policy>,
        /// Robot counts: `1-13`, `5` or `1,3,5`.
        #[arg(long, default_value = DEFAULT_ROBOTS, conflicts_with = "grids")]
        robots: RobotCounts,
        /// Runs per (algorithm, robot count).
        #[arg(long, default_value_t = DEFAULT_RUNS, value_parser = clap::value_parser!(u32).range(1..), conflicts_with = "grids")]
        runs: u32,
        /// Base seed; each run's seed derives from it, the robot count and the run index (the same for every algorithm: common random numbers).
        #[arg(long, default_value_t = 1, conflicts_with = "grids")]
        seed: u64,
        /// 1: the number of targets is known; 2: it is not [default: the scenario's].
        #[arg(long, value_parser = clap::value_parser!(u8).range(1..=2), conflicts_with = "grids")]
        situation: Option<u8>,
        /// Output directory (created if missing).
        /// Where to write [default: experiment-out, or grids-out with --grids].
        #[arg(long)]
        out: Option<PathBuf>,
        /// A run not stopped after this many rounds ends incomplete and is left out of the means
        /// [default: the round budget, 100 rounds per vertex the team can reach, at most 100000].
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..), conflicts_with = "grids")]
        max_rounds: Option<u32>,
        /// Compare the triangular, square and hexagonal lattices on the map (Sec. 3).
        #[arg(long)]
        grids: bool,
        /// Average over K random maps: map k is --scenario random:SEED,OPTIONS with seed SEED + k
        /// (needs a random scenario); results.csv, runs.csv and maps.csv say which map a number is
        /// from, report.html shows the spread over maps.
        #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(1..=100_000), conflicts_with = "grids")]
        maps: Option<u32>,
        /// Print every claim's evidence, not only its verdict (claims.txt always has it).
        #[arg(long, conflicts_with = "grids")]
        verbose: bool,
        /// Where the robots start: `fixed` (the scenario's [starts], Fig. 5) or `random` (drawn
        /// from each run's seed, the same layout for every algorithm of a run index).
        #[arg(long, value_name = "RULE", default_value_t = StartRule::Fixed, conflicts_with = "grids")]
        starts: StartRule,
        /// Sweep a scenario key: `KEY=V1,V2,...` for any [params] or [lfp] key (e.g. t_wait=1,2,4 or
        /// turn=0.5,uniform). Repeat for a grid: every combination is swept with the same seeds,
        /// and every output has a column per key.
        #[arg(long, value_name = "KEY=V1,V2,...", conflicts_with_all = ["grids", "maps"])]
        set: Vec<Setting>,
    },
    /// Repeat the command that wrote DIR from its provenance (the recorded command line and
    /// scenario text, not the scenario file) into a new folder, and check that the outputs
    /// that must repeat (results.csv, runs.csv, trajectories.jsonl, ...) have the same bytes.
    /// Exits 1 naming every file that differs. A folder is data: the rerun executes only
    /// gridswarm itself, writes only into its own folder and serves nothing, unless its own
    /// --agent-bin and --live ask.
    Rerun {
        /// A folder written by simulate --out, run --out or an experiment.
        dir: PathBuf,
        /// Where to write the rerun [default: DIR/rerun].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Run the agent program the recorded command names; it must be this same PATH
        /// (a rerun never executes a program named only by the folder).
        #[arg(long, value_name = "PATH")]
        agent_bin: Option<PathBuf>,
        /// Serve the rerun live at ADDR [default: 127.0.0.1:8765], for a recorded simulate or
        /// run (a recorded --live is not served without it).
        #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = crate::live::DEFAULT_ADDR,
              value_parser = crate::live::parse_addr)]
        live: Option<std::net::SocketAddr>,
    },
    /// Write (or rewrite) DIR/replay.html, the page that plays a run back,
    /// from the files a run wrote there; prints the page's path.
    Replay {
        /// A directory written by `simulate --out` (world.json, trajectories.jsonl, summary.json).
        dir: PathBuf,
    },
    /// One search with one process per robot (world-server + robot-agents
    /// over iceoryx2), with failure injection; the same files as `simulate`.
    Run {
        #[command(flatten)]
        scenario: ScenarioArg,
        /// repulsive, sequential, ru, escape, frontier, frontier-coord, frontier-sensed,
        /// frontier-sensed-coord, or one --agent-bin lists (grid policies only).
        #[arg(long, default_value = "repulsive")]
        algorithm: Policy,
        /// Number of robots [default: the scenario's].
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..=gridswarm::ipc::MAX_ROBOTS as i64))]
        robots: Option<u32>,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Write summary.json, trajectories.jsonl, routes.svg (and the replay files) here.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print exactly one JSON object instead of the summary.
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        distributed: Distributed,
        #[command(flatten)]
        faults: FaultFlags,
        /// The robots' program instead of robot-agent: one made with
        /// `robot_agent::main_with` and its own choice rules, whose names
        /// `--algorithm` then accepts.
        #[arg(long)]
        agent_bin: Option<PathBuf>,
        #[command(flatten)]
        net: crate::cli::transport::TransportFlags,
        #[command(flatten)]
        view: crate::cli::view::ViewFlags,
    },
    /// Validate a scenario and report which of the paper's assumptions hold.
    ///
    /// Also S0: robots on the lattice (adjacent, passing a vertex, or more than 2a apart and
    /// moving at once) stay more than 2 r_safe apart; simulate and run refuse a set that fails
    /// it under a collision-free algorithm (exit 4).
    ///
    /// Every command's --scenario takes a built-in name, a TOML file, a ROS map_server map
    /// (NAME.yaml with its image; docs/scenario-format.md), or a random map, generated from
    /// its seed alone (the same text gives the same map everywhere):
    ///
    ///   random:SEED[,size=WxH][,density=F][,passage=M][,targets=N][,robots=N][,break=ID]
    ///
    ///   size      area of about W x H metres, 8 to 400 each [20x16]
    ///   density   share of the area covered by obstacles, 0 to 0.4 [0.15]
    ///   passage   narrowest gap between obstacles and walls, m, >= W_pass = 1.6 [2]
    ///   targets   number of targets (situation 1) [9]
    ///   robots    default robot count [3]
    ///   break     an assumption to break on purpose: 2.4 (r_so), 2.5 (r_c), 3.1.1 (r_st),
    ///             3.1.2 (a pocket no vertex sees; coverage fails with it) or 3.1.3 (one
    ///             passage `passage` wide, default 1 m); every other check still passes
    ///
    /// e.g. `gridswarm check random:5` or `random:7,size=30x20,density=0.2,break=3.1.2`.
    #[command(verbatim_doc_comment)]
    Check {
        /// Built-in scenario, TOML file, map (NAME.yaml) or random:SEED[,options].
        #[arg(default_value = "paper")]
        scenario: String,
    },
    /// Make the certificates of a zenoh run across machines (mutual TLS):
    /// an authority, the world's, one per robot (README: "Running on
    /// several machines").
    Credentials(crate::cli::credentials::CredentialsArgs),
    /// Write one robot's setup file for a robot-agent started by hand on another host
    /// (`robot-agent --setup FILE`): its grid frame, parameters and number, and the run's
    /// agreement, exactly as `run` writes them for the agents it starts (README: "Running on
    /// several machines").
    Setup(crate::cli::setup::SetupArgs),
    /// Write a scenario (built-in, TOML file, map or random:SEED,...) as a scenario file
    /// (--format toml) or as a ROS map_server map (--format yaml: NAME.yaml, NAME.pgm and
    /// NAME.gridswarm.toml with the targets, starts and parameters); lists the files written.
    ExportMap {
        /// Built-in scenario, TOML file, map (NAME.yaml) or random:SEED[,options].
        scenario: String,
        #[arg(long, value_enum)]
        format: crate::cli::export::MapFormat,
        /// The file to write (for yaml, the .yaml; the others go beside it) [default: NAME.yaml
        /// or NAME.toml in the current folder, NAME from the scenario's name].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Pixel side of the map's image, m [default: a / 10].
        #[arg(long, value_parser = positive_length)]
        resolution: Option<f64>,
    },
    /// Write a map's sidecar sized for a robot: r_rob, r_safe = 1.2 r_rob, a the smallest whole
    /// centimetre meeting S0, r_so, r_st and r_c from the assumptions, [map] sliver = W_pass;
    /// says which passages the robot cannot take and checks the map as the sidecar reads it.
    /// Keeps the map's sidecar's other keys (targets, starts, ...). Exits 3 if a check fails.
    MapSetup {
        /// The map (NAME.yaml).
        map: String,
        /// The robot's radius, m.
        #[arg(long, value_parser = positive_length)]
        robot_radius: f64,
        /// The file to write [default: NAME.gridswarm.toml beside the map, the sidecar it reads].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Replace the file if it exists.
        #[arg(long)]
        force: bool,
    },
}

/// A length > 0 (m) from the command line.
fn positive_length(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("`{s}` is not a length > 0 (m)")),
    }
}

/// The protocol experiments (`gridswarm experiment KIND`).
#[derive(Subcommand, Debug)]
enum ExperimentKind {
    /// Runs with 0, 1, 2, ... robots crashed at random times inside rounds:
    /// completion, search time, detection delay, false suspicions, rejoins,
    /// retransmissions, collisions and unsure stays against the number killed.
    ///
    /// Writes failures.csv, failures-runs.csv, failures.svg and report.html
    /// in --out and prints the table.
    Failures {
        #[command(flatten)]
        protocol: ProtocolArgs,
        /// Number of robots (the paper's Fig. 7 goes up to 13).
        #[arg(long, default_value_t = failures::DEFAULT_ROBOTS, value_parser = clap::value_parser!(u32).range(1..=MAX_ROBOTS as i64))]
        robots: u32,
        /// Numbers of robots to kill: `0-3`, `2` or `0,2,4`.
        #[arg(long, default_value = failures::DEFAULT_KILLED)]
        killed: failures::Killed,
        /// Runs per number killed [default: 500 in-process, 10 distributed].
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
        runs: Option<u32>,
        /// Base seed; run r with k killed has seed derive(derive(seed, k), r).
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Output directory (created if missing).
        #[arg(long, default_value = failures::DEFAULT_OUT)]
        out: PathBuf,
    },
    /// The protocol on a lossy radio: loss P × robot counts × retransmissions,
    /// each run many times: collisions per 10^6 moves, completion, search
    /// time, retransmissions, time-outs and unsure stays, false suspicions.
    ///
    /// Writes radio.csv, radio-runs.csv, radio.svg and report.html in --out
    /// and prints the table.
    Radio {
        #[command(flatten)]
        protocol: ProtocolArgs,
        /// Loss probabilities per transmission per link, each 0 to 1.
        #[arg(long, default_value = radio::DEFAULT_LOSS)]
        loss: radio::Losses,
        /// Robot counts: `4,8,13`, `5` or `3-6`.
        #[arg(long, default_value = radio::DEFAULT_ROBOTS)]
        robots: RobotCounts,
        /// Retransmission counts (extra copies of every frame).
        #[arg(long, default_value = radio::DEFAULT_RETRIES)]
        retries: radio::RetryCounts,
        /// Runs per point [default: 100 in-process, 3 distributed].
        #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
        runs: Option<u32>,
        /// Base seed; run r with N robots has seed derive(derive(seed, N), r) for every loss and retries.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Output directory (created if missing).
        #[arg(long, default_value = radio::DEFAULT_OUT)]
        out: PathBuf,
    },
    /// The Fig. 7 sweep over a grid of the paper's open readings (RU's
    /// collision charge, LFP's turning law), the three claims evaluated
    /// under every combination and seed, and the region where all three hold.
    ///
    /// Writes readings.csv, cells.csv, claims.txt, readings.svg (the heat
    /// map), summary.json and report.html in --out and prints the verdicts.
    Readings {
        #[command(flatten)]
        scenario: ScenarioArg,
        /// Robot counts: `1-13`, `5` or `1,3,5`.
        #[arg(long, default_value = DEFAULT_ROBOTS)]
        robots: RobotCounts,
        /// Runs per (algorithm, reading, robot count) and seed.
        #[arg(long, default_value_t = DEFAULT_RUNS, value_parser = clap::value_parser!(u32).range(2..))]
        runs: u32,
        /// Base seeds, comma-separated: the whole grid under each (e.g. 1,2,3,4,5 checks that verdicts survive a change of seed).
        #[arg(long, value_delimiter = ',', default_value = "1")]
        seeds: Vec<u64>,
        /// RU's readings of "one extra move time per collision": per-event, per-pair, back-off.
        #[arg(long, value_delimiter = ',', default_value = readings::DEFAULT_RU, value_parser = readings::parse_ru)]
        ru: Vec<gridswarm::params::RuCollisions>,
        /// LFP's turning laws: sigmas of the normal turn (rad) and/or `uniform`.
        #[arg(long, value_delimiter = ',', default_value = readings::DEFAULT_TURNS, value_parser = readings::parse_turn)]
        turns: Vec<gridswarm::lfp::Turn>,
        #[command(flatten)]
        distributed: Distributed,
        /// Where the robots start: `fixed` (the scenario's [starts]) or `random` (drawn from
        /// each run's seed, the same layout for every curve of a run index).
        #[arg(long, value_name = "RULE", default_value_t = StartRule::Fixed)]
        starts: StartRule,
        /// Output directory (created if missing).
        #[arg(long, default_value = readings::DEFAULT_OUT)]
        out: PathBuf,
    },
    /// Distributed runs at growing robot counts: wall time per round
    /// (p50/p99), start-up and memory against N, next to the in-process
    /// engine timed on the same runs.
    ///
    /// Writes scale.csv, scale-runs.csv, scale.svg and report.html in --out
    /// and prints the table.
    Scale {
        /// Robot counts: `13,50,100,200`, `5` or `3-6`.
        #[arg(long, default_value = scale::DEFAULT_ROBOTS)]
        robots: RobotCounts,
        /// Runs per robot count.
        #[arg(long, default_value_t = scale::DEFAULT_RUNS, value_parser = clap::value_parser!(u32).range(1..))]
        runs: u32,
        /// Base seed; run r with N robots has seed derive(derive(seed, N), r).
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Scenario for every count [default: paper up to 13 robots, large above].
        #[arg(long)]
        scenario: Option<String>,
        /// repulsive, sequential, ru, escape or frontier (grid policies only).
        #[arg(long, default_value = "repulsive")]
        algorithm: Policy,
        #[command(flatten)]
        distributed: Distributed,
        /// Output directory (created if missing).
        #[arg(long, default_value = scale::DEFAULT_OUT)]
        out: PathBuf,
        /// What carries the messages: iceoryx2 or zenoh (mutual TLS on 127.0.0.1).
        #[arg(long, default_value = "iceoryx2")]
        transport: gridswarm::transport::Transport,
    },
}

/// The exit codes, for every command's --help.
const EXIT_STATUS: &str = "Exit status:
  0  success: the search completed (simulate, run); the command did its work (experiments, replay, check)
  1  error: bad scenario or value, unwritable output, a failed child process, too low an open-file
     limit, interrupted by SIGINT, SIGTERM, SIGHUP or SIGQUIT
  2  usage error: unknown flag or algorithm, a value out of range, faults that do not fit the run, flags
     that do not fit together (e.g. run --algorithm lfp, --listen without --transport zenoh,
     --insecure off loopback without --insecure-network), a
     robot-agent the world refuses (its seed, scenario, ... differ from the world's)
  3  the search ended incomplete (simulate, run: every robot failed, cut off, a stop that knew
     targets unfound (exhausted) or came on an incomplete search (false_stop), or the round limit
     reached, --max-rounds or simulate's work budget; its outputs are written), or `check` found a
     failing assumption (or `map-setup` wrote a sidecar with which one fails)
  4  robots collided under an algorithm that promises they never do (simulate, run: every grid
     algorithm but ru; its outputs are written), or the run was refused because the parameters let
     them (check S0 fails: robots on adjacent vertices, or passing or moving at once, within 2 r_safe)
  5  the search went past a stated bound (radio delay, a slow robot; ARCHITECTURE.md \"Bounds\") and
     no robot moved for 50 rounds (simulate, run: ended_by past_bound, its line names the bound and
     the robots; its outputs are written)";

/// Writes to stdout without `print!`'s panic on a closed pipe
/// (`gridswarm experiment | head` must not end in a panic).
fn emit(text: &str) {
    let mut out = std::io::stdout().lock();
    let _ = out.write_all(text.as_bytes()).and_then(|()| out.flush());
}

fn situation(n: Option<u8>) -> Option<Situation> {
    n.and_then(Situation::from_number)
}

/// The settings every protocol run takes, whichever command starts it.
#[derive(clap::Args, Debug)]
struct Distributed {
    /// 1: the number of targets is known; 2: it is not [default: the scenario's].
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=2))]
    situation: Option<u8>,
    /// A run not stopped after this many rounds ends incomplete [default: 100000; `experiment
    /// readings`, `failures`, `radio` and `scale`: the round budget, 100 rounds per vertex the
    /// team can reach, at most 100000; `failures` and `radio` take their largest team's].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    max_rounds: Option<u32>,
}

impl Distributed {
    /// The round limit of a command without a round budget of its own.
    fn max_rounds(&self) -> u32 {
        self.max_rounds.unwrap_or(DEFAULT_MAX_ROUNDS)
    }
}

/// What `experiment failures` and `experiment radio` both take.
#[derive(clap::Args, Debug)]
struct ProtocolArgs {
    #[command(flatten)]
    scenario: ScenarioArg,
    /// repulsive, sequential, ru, escape or frontier (grid policies only).
    #[arg(long, default_value = "repulsive")]
    algorithm: Policy,
    #[command(flatten)]
    distributed: Distributed,
    /// Which engine runs the runs.
    #[arg(long, value_enum, default_value_t = Engine::InProcess)]
    engine: Engine,
}

impl ProtocolArgs {
    fn options(self, runs: Option<u32>, seed: u64, out: PathBuf) -> ProtocolOptions {
        ProtocolOptions {
            scenario: self.scenario.scenario,
            algorithm: self.algorithm,
            runs,
            seed,
            situation: situation(self.distributed.situation),
            max_rounds: self.distributed.max_rounds,
            engine: self.engine,
            out,
            progress: experiment::stderr_is_terminal(),
        }
    }
}

/// The map a command searches.
#[derive(clap::Args, Debug)]
struct ScenarioArg {
    /// Built-in scenario (paper, open, cave, large, small, comb), a TOML file, a ROS map_server map
    /// (NAME.yaml), or a random map random:SEED[,options] (see `gridswarm check --help`).
    #[arg(long, default_value = "paper")]
    scenario: String,
}

fn experiment_kind(kind: ExperimentKind) -> Result<String, Error> {
    let progress = experiment::stderr_is_terminal();
    Ok(match kind {
        ExperimentKind::Failures { protocol, robots, killed, runs, seed, out } => {
            let opts = FailuresOptions {
                protocol: protocol.options(runs, seed, out),
                robots: Some(robots as usize),
                killed: killed.0,
            };
            failures::run(&opts)?.1
        }
        ExperimentKind::Radio { protocol, loss, robots, retries, runs, seed, out } => {
            let opts = RadioOptions {
                protocol: protocol.options(runs, seed, out),
                loss: loss.0,
                robots: robots.0,
                retries: retries.0,
            };
            radio::run(&opts)?.1
        }
        ExperimentKind::Readings { scenario, robots, runs, seeds, ru, turns, distributed: d, starts, out } => {
            let opts = ReadingsOptions {
                scenario: scenario.scenario,
                robots: robots.0,
                runs,
                seeds,
                ru,
                turns,
                situation: situation(d.situation),
                max_rounds: d.max_rounds,
                out,
                starts,
                progress,
            };
            readings::run(&opts)?.1
        }
        ExperimentKind::Scale { robots, runs, seed, scenario, algorithm, distributed: d, out, transport } => {
            let opts = ScaleOptions {
                robots: robots.0,
                runs,
                seed,
                scenario,
                algorithm,
                situation: situation(d.situation),
                max_rounds: d.max_rounds,
                out,
                progress,
                transport,
            };
            scale::run(&opts)?.1
        }
    })
}

fn run(cli: Cli) -> Result<ExitCode, Error> {
    // Off a terminal no bar is drawn: an experiment prints a progress line
    // every 10 s instead, and a last one when it ends (progress.rs).
    let quiet = matches!(cli.command, Command::Experiment { .. }) && !experiment::stderr_is_terminal();
    let _ticker = quiet.then(|| Ticker::start(Instant::now()));
    match cli.command {
        Command::Simulate {
            scenario: ScenarioArg { scenario },
            algorithm,
            robots,
            seed,
            situation: s,
            out,
            json,
            max_rounds,
            faults,
            view,
        } => {
            let opts = SimulateOptions {
                scenario,
                algorithm,
                robots: robots.map(|r| r as usize),
                seed,
                situation: situation(s),
                out,
                json,
                max_rounds,
                faults: faults.plan(),
                view,
            };
            let (text, status) = simulate::simulate(&opts)?;
            emit(&text);
            return Ok(finished(status));
        }
        Command::Experiment { kind: Some(kind), .. } => emit(&experiment_kind(kind)?),
        Command::Experiment { scenario: ScenarioArg { scenario }, out, grids: true, .. } => {
            let out = out.unwrap_or_else(|| PathBuf::from(grids::DEFAULT_OUT));
            let (_, text) = grids::run(&GridsOptions { scenario, out })?;
            emit(&text);
        }
        Command::Experiment {
            scenario: ScenarioArg { scenario },
            algorithms,
            robots,
            runs,
            seed,
            situation: s,
            out,
            max_rounds,
            grids: false,
            kind: None,
            maps,
            verbose,
            starts,
            set,
        } => {
            let opts = ExperimentOptions {
                scenario,
                algorithms,
                robots: robots.0,
                runs,
                seed,
                situation: situation(s),
                out: out.unwrap_or_else(|| PathBuf::from(DEFAULT_OUT)),
                max_rounds,
                progress: experiment::stderr_is_terminal(),
                maps,
                verbose,
                starts,
                set,
            };
            let (_, text) = experiment::run(&opts)?;
            emit(&text);
        }
        Command::Rerun { dir, out, agent_bin, live } => {
            let allowed = crate::provenance::recorded::Allowed { agent_bin, live };
            let outcome = crate::provenance::rerun::rerun(&dir, out.as_deref(), &allowed)?;
            emit(&outcome.text());
            let differing = outcome.differing();
            if !differing.is_empty() {
                return Err(Error::Run(format!(
                    "the rerun of `{}` in `{}` differs from it: {}",
                    dir.display(),
                    outcome.out.display(),
                    differing.join(", ")
                )));
            }
            emit(&format!(
                "rerun of {} in {}: {} outputs the same byte for byte\n",
                dir.display(),
                outcome.out.display(),
                outcome.compared.len()
            ));
        }
        Command::Replay { dir } => {
            emit(&format!("{}\n", crate::replay::write(&dir)?.display()));
        }
        Command::Run {
            scenario: ScenarioArg { scenario },
            algorithm,
            robots,
            seed,
            distributed: d,
            out,
            json,
            faults,
            agent_bin: _,
            net,
            view,
        } => {
            let base = RunBase {
                scenario,
                algorithm,
                robots: robots.map(|r| r as usize),
                seed,
                situation: situation(d.situation),
                max_rounds: d.max_rounds(),
                out,
                json,
            };
            let plan = faults.plan();
            plan.check_scenario(&base)?;
            let opts = crate::run::RunOptions { net: net.options(), view, ..plan.run_options(base) };
            let (text, status) = crate::run::run(&opts)?;
            emit(&text);
            return Ok(finished(status));
        }
        Command::Credentials(args) => emit(&crate::cli::credentials::run(&args)?),
        Command::Setup(args) => emit(&crate::cli::setup::write(&args)?),
        Command::ExportMap { scenario, format, out, resolution } => {
            let opts = crate::cli::export::ExportOptions { scenario, format, out, resolution };
            emit(&crate::cli::export::export(&opts)?);
        }
        Command::MapSetup { map, robot_radius, out, force } => {
            let opts = crate::cli::map_setup::MapSetupOptions { map, robot_radius, out, force };
            let (text, holds) = crate::cli::map_setup::run(&opts)?;
            emit(&text);
            if !holds {
                return Ok(ExitCode::from(EXIT_INCOMPLETE));
            }
        }
        Command::Check { scenario } => {
            let outcome = check::check(&scenario)?;
            emit(&outcome.text);
            if !outcome.all_hold() {
                eprintln!("error: scenario `{scenario}` fails check(s) {}", outcome.failing_ids());
                return Ok(ExitCode::from(EXIT_INCOMPLETE));
            }
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// A search's exit status ([`crate::error::search_status`]), said on
/// stderr too when robots collided (the summary alone would read complete).
fn finished(status: u8) -> ExitCode {
    if status == EXIT_COLLISION {
        eprintln!(
            "error: robots collided under an algorithm that promises they never do (`collisions` in the \
             summary); `gridswarm check` says whether the parameters let them (S0)"
        );
    }
    ExitCode::from(status)
}

/// The `gridswarm` command with `rules` (name, factory) as algorithms
/// besides the built-in ones, for `simulate`, `experiment` and the rest;
/// `main_with(&[])` is `gridswarm` itself. Call it first thing in `main`.
pub fn main_with(rules: &[(&str, Factory)]) -> ExitCode {
    crate::provenance::begin(std::env::args_os());
    // From the first line: a signal at any moment ends the command with one
    // line and exit status 1, its unfinished folders removed.
    if let Err(e) = crate::launch::handle_signals() {
        eprintln!("error: {e}");
        return ExitCode::FAILURE;
    }
    // Before parsing: a rule's name is a value `--algorithm` accepts.
    for &(name, factory) in rules {
        if let Err(e) = gridswarm::choice::register(name, factory) {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    }
    // Before parsing: the agent's algorithms are names `--algorithm` accepts.
    if let Err(e) = crate::cli::agents::from_args(&std::env::args_os().collect::<Vec<_>>()) {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => {
            // --help and --version: clap's own output, success.
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) if e.kind() == clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            // No subcommand: the help is the answer, but the call still failed.
            let _ = e.print();
            return ExitCode::from(2);
        }
        Err(e) => {
            // Clap's whole message: what is wrong, its suggestions ("a
            // similar argument exists"), the usage line and where to get help.
            let _ = e.print();
            return ExitCode::from(2);
        }
    };
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;
    use std::any::TypeId;

    use crate::provenance::recorded::{guards, COMMANDS, EXPERIMENTS};

    /// Every option of a command a rerun repeats that names a file, a
    /// folder or a socket address is one the rerun guards: a new one would
    /// otherwise reach outside the rerun's folder from a results folder.
    #[test]
    fn every_path_or_address_a_rerun_repeats_is_guarded() {
        let cli = Cli::command();
        let mut commands: Vec<&clap::Command> = COMMANDS.iter().map(|c| cli.find_subcommand(c).unwrap()).collect();
        let experiment = cli.find_subcommand("experiment").unwrap();
        commands.extend(EXPERIMENTS.iter().map(|k| experiment.find_subcommand(k).unwrap()));
        let (path, addr) = (TypeId::of::<PathBuf>(), TypeId::of::<std::net::SocketAddr>());
        let mut seen = 0;
        for c in commands {
            for a in c.get_arguments().filter(|a| a.get_long().is_some()) {
                let t = a.get_value_parser().type_id();
                if t == path || t == addr {
                    seen += 1;
                    let flag = format!("--{}", a.get_long().unwrap());
                    assert!(guards(&flag), "`{} {flag}` names a path or an address a rerun passes on", c.get_name());
                }
            }
        }
        assert!(seen >= 8, "the outs, --agent-bin, --mcap, --live and --credentials: {seen}");
    }
}
