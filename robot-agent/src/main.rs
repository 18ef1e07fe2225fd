//! `robot-agent`: one robot of a distributed run (issue "One process per
//! robot"). It wraps the decision core (`gridswarm::robot::Robot`) with
//! iceoryx2 I/O and nothing else: no algorithm is written here.
//!
//! It opens the services the world-server created, says hello, then reacts
//! to what arrives in its inbox, sleeping on its wake-up event in between:
//!
//! - `Tick`: `moved` (the world's odometry), `sense`; in situation 1 the
//!   targets it just found go out as a broadcast; then its map, as it is
//!   right after sensing, to its radio neighbours (through the world).
//! - `Relay`: targets, maps and choices of others, fed to the core.
//! - `ExchangeDone`: the stop test (rules 3/4): `Stop`, or choose as soon as
//!   the core is ready; later `Choice` and `Failed` messages may make it ready.
//! - `Failed`: a neighbour declared failed, fed to the core.
//! - `Deposed`: this robot was declared failed (it was too slow, or frozen).
//!   It stops for good: it sends nothing more and exits with status 0. The
//!   world already treats its vertex as blocked, so stopping is what keeps
//!   everyone else's picture true.
//! - `End`: the search is over; exit 0.
//!
//! If nothing arrives for `--world-timeout-ms`, it checks that the world's
//! process is still there; if not, it exits with status 3. The robot's start
//! vertex is where the first `Tick` says it stands, so an agent never builds
//! the world (the grid frame is all a robot may hold, ARCHITECTURE.md).

use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use gridswarm::grid::Grid;
use gridswarm::ipc::{self, names};
use gridswarm::lattice::Lattice;
use gridswarm::map::RobotId;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::protocol::{
    decode_from_world, encode_to_world, FromWorld, Limits, Message, ToWorld,
};
use gridswarm::robot::{Robot, RobotConfig, Sensing};
use gridswarm::scenario::Scenario;
use iceoryx2::prelude::*;

#[derive(Parser, Debug)]
#[command(
    name = "robot-agent",
    about = "One gridswarm robot of a run of one process per robot"
)]
struct Args {
    /// The run's iceoryx2 prefix, made by the orchestrator.
    #[arg(long)]
    prefix: String,
    /// This robot's number.
    #[arg(long)]
    robot: usize,
    #[arg(long, default_value = "paper")]
    scenario: String,
    #[arg(long, default_value = "repulsive")]
    algorithm: Policy,
    /// Number of robots in the run [default: the scenario's].
    #[arg(long)]
    robots: Option<usize>,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    #[arg(long)]
    situation: Option<u8>,
    /// The world-server's process id, checked when the world goes quiet.
    #[arg(long)]
    world_pid: Option<u32>,
    /// Quiet time after which the world's liveness is checked.
    #[arg(long, default_value_t = 500)]
    world_timeout_ms: u64,
    /// Testing: take this long over every round's sensing, like a robot on
    /// a loaded machine (so the world suspects it while it still runs).
    #[arg(long, hide = true)]
    slow_ms: Option<u64>,
}

enum Exit {
    /// `End` or `Deposed`: a clean stop.
    Done,
    WorldGone,
}

struct Agent<'g> {
    id: RobotId,
    cfg: RobotConfig,
    grid: &'g Grid,
    robot: Option<Robot<'g>>,
    round: u32,
    exchange_done: bool,
    decided: bool,
    out: Vec<BytesOut>,
}

/// A message waiting to go out, encoded.
type BytesOut = Vec<u8>;

impl<'g> Agent<'g> {
    fn radio(&mut self, m: Message) {
        self.out.push(encode_to_world(&ToWorld::Radio(m)));
    }

    /// Handles one message from the world; `Some` when the agent must stop.
    fn handle(&mut self, m: FromWorld) -> Option<Exit> {
        match m {
            FromWorld::Tick {
                round,
                at,
                open,
                occupied,
                targets,
                neighbours,
            } => {
                if self.robot.is_some() && round <= self.round {
                    return None;
                }
                let robot = self
                    .robot
                    .get_or_insert_with(|| Robot::new(self.grid, self.cfg, at));
                // Step 6 of the last round, as the world executed it.
                robot.moved(at);
                robot.sense(
                    round,
                    &Sensing {
                        open,
                        occupied,
                        targets: &targets,
                        neighbours: &neighbours,
                    },
                );
                self.round = round;
                self.exchange_done = false;
                self.decided = false;
                let map = robot.map().clone();
                if self.cfg.situation == Situation::One && !targets.is_empty() {
                    self.radio(Message::Targets {
                        round,
                        from: self.id,
                        targets,
                    });
                }
                self.radio(Message::Map {
                    round,
                    from: self.id,
                    at,
                    map,
                });
            }
            FromWorld::Relay(m) => {
                if m.round() != self.round {
                    return None;
                }
                let robot = self.robot.as_mut()?;
                match m {
                    Message::Targets { targets, .. } if self.cfg.situation == Situation::One => {
                        robot.learn_targets(&targets)
                    }
                    Message::Map { from, at, map, .. } => {
                        robot.receive_map(from, at, &map);
                    }
                    Message::Choice { from, next, .. } => {
                        robot.receive_choice(from, next);
                        self.try_choose();
                    }
                    _ => {}
                }
            }
            FromWorld::ExchangeDone { round } if round == self.round && self.robot.is_some() => {
                self.exchange_done = true;
                let robot = self.robot.as_mut().expect("checked");
                if robot.stop_rule().is_some() {
                    self.decided = true;
                    self.radio(Message::Stop {
                        round,
                        from: self.id,
                    });
                } else {
                    self.try_choose();
                }
            }
            FromWorld::Failed {
                round,
                robot: who,
                at,
            } if round == self.round => {
                if let Some(robot) = self.robot.as_mut() {
                    robot.declare_failed(who, at);
                    self.try_choose();
                }
            }
            FromWorld::Deposed { .. } | FromWorld::End { .. } => return Some(Exit::Done),
            _ => {}
        }
        None
    }

    /// Step 5: choose and announce as soon as every input has arrived.
    fn try_choose(&mut self) {
        if !self.exchange_done || self.decided {
            return;
        }
        let Some(robot) = self.robot.as_mut() else {
            return;
        };
        if let Some(next) = robot.choose() {
            self.decided = true;
            let round = self.round;
            self.radio(Message::Choice {
                round,
                from: self.id,
                next,
            });
        }
    }
}

fn run(args: Args) -> Result<Exit, String> {
    ipc::quiet_logs();
    let config = ipc::config(&args.prefix)?;
    let mut scenario = Scenario::load(&args.scenario).map_err(|e| e.to_string())?;
    if let Some(s) = args.situation {
        scenario.situation = Situation::from_number(s)
            .ok_or_else(|| format!("situation must be 1 or 2, got {s}"))?;
    }
    let n = args.robots.unwrap_or(scenario.robots);
    if args.robot >= n {
        return Err(format!(
            "robot {} does not exist in a run of {n}",
            args.robot
        ));
    }
    // The frame World::new builds, without the world's obstacles and targets.
    let (lo, hi) = scenario.area.bounding_box();
    let grid = Grid::new(Lattice::new(scenario.grid, scenario.params.a), lo, hi);
    let limits = Limits {
        vertices: grid.len(),
        targets: scenario.targets.len(),
        robots: n,
    };
    let id = args.robot as RobotId;
    let cfg = RobotConfig {
        id,
        policy: args.algorithm,
        situation: scenario.situation,
        targets_total: scenario.targets.len(),
        r_safe: scenario.params.r_safe,
        seed: args.seed,
    };

    let node = ipc::create_node(&config, &names::robot_node(args.robot))?;
    let inbox_svc = ipc::open_bytes(&node, &names::robot_in(args.robot), ipc::inbox_buffer(n))?;
    let outbox_svc = ipc::open_bytes(&node, &names::robot_out(args.robot), ipc::OUTBOX_BUFFER)?;
    let wake_svc = ipc::open_event(&node, &names::robot_wake(args.robot))?;
    let world_wake_svc = ipc::open_event(&node, &names::world_wake())?;
    let inbox = ipc::bytes_subscriber(&inbox_svc, ipc::inbox_buffer(n))?;
    let outbox = ipc::bytes_publisher(&outbox_svc, ipc::max_message_len(&limits))?;
    let listener = wake_svc
        .listener_builder()
        .create()
        .map_err(|e| format!("cannot create listener: {e:?}"))?;
    let notifier = world_wake_svc
        .notifier_builder()
        .default_event_id(EventId::new(args.robot))
        .create()
        .map_err(|e| format!("cannot create notifier: {e:?}"))?;
    let waitset = WaitSetBuilder::new()
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Svc>()
        .map_err(|e| format!("cannot create wait set: {e:?}"))?;
    let _guard = waitset
        .attach_notification(&listener)
        .map_err(|e| format!("cannot attach listener: {e:?}"))?;

    let send = |bytes: &[u8]| -> Result<(), String> { ipc::publish(&outbox, bytes) };
    send(&encode_to_world(&ToWorld::Hello {
        robot: id,
        pid: std::process::id(),
    }))?;
    notifier
        .notify()
        .map_err(|e| format!("cannot notify the world: {e:?}"))?;

    let mut agent = Agent {
        id,
        cfg,
        grid: &grid,
        robot: None,
        round: 0,
        exchange_done: false,
        decided: false,
        out: Vec::with_capacity(4),
    };
    let timeout = Duration::from_millis(args.world_timeout_ms.max(1));
    let mut buf = Vec::with_capacity(1024);
    loop {
        let mut woke = false;
        let _ = waitset.wait_and_process_once_with_timeout(
            |_| {
                woke = true;
                CallbackProgression::Continue
            },
            timeout,
        );
        let _ = listener.try_wait(|_| {});
        let mut got = false;
        let mut ticked = false;
        while ipc::receive(&inbox, &mut buf)? {
            got = true;
            let Ok(m) = decode_from_world(&buf, &limits) else {
                continue;
            };
            ticked |= matches!(m, FromWorld::Tick { .. });
            if let Some(exit) = agent.handle(m) {
                return Ok(exit);
            }
        }
        if let (true, Some(ms)) = (ticked, args.slow_ms) {
            std::thread::sleep(Duration::from_millis(ms));
        }
        if !agent.out.is_empty() {
            for bytes in agent.out.drain(..) {
                send(&bytes)?;
            }
            notifier
                .notify()
                .map_err(|e| format!("cannot notify the world: {e:?}"))?;
        }
        if !got && !woke {
            let world_alive = match args.world_pid {
                Some(pid) => ipc::pid_alive(pid),
                // No pid given: ask iceoryx2 whether the world's node lives.
                None => ipc::list_nodes(&config)
                    .map(|nodes| nodes.iter().any(|n| n.name == names::WORLD_NODE && !n.dead))
                    .unwrap_or(true),
            };
            if !world_alive {
                return Ok(Exit::WorldGone);
            }
        }
    }
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
    let robot = args.robot;
    match run(args) {
        Ok(Exit::Done) => ExitCode::SUCCESS,
        Ok(Exit::WorldGone) => {
            eprintln!("robot-agent {robot}: the world-server is gone");
            ExitCode::from(ipc::EXIT_WORLD_GONE as u8)
        }
        Err(e) => {
            eprintln!("robot-agent {robot}: error: {e}");
            ExitCode::FAILURE
        }
    }
}
