//! Issue 21's delay curve: collisions per 10^6 moves and unsure stays
//! against radio delay and jitter, fault-free and with faults.
//! `cargo run --release --example delay -- RUNS [SEED]`
//!
//! Each cell runs RUNS searches on `paper` with 13 robots, the algorithms
//! that avoid collisions taking turns (RU's robots are particles), seeds
//! drawn from SEED. "faults" adds, at times drawn from the seed, a crash,
//! a freeze of 5 rounds and a robot slow by 300 ms for good. Delays run
//! from inside the 50 ms exchange window, past it (robots widen their
//! window from the maps' send times), to past the widest window a robot
//! may choose (1.05 s), where the promise is stays, not collisions. With
//! zero collisions in a cell, the rule of three bounds the rate below
//! `3 / moves` at 95% confidence: that column says what a zero means.
use gridswarm::engine;
use gridswarm::outcome::RunConfig;
use gridswarm::params::Situation;
use gridswarm::policy::Policy;
use gridswarm::rng::{derive, mix};
use gridswarm::scenario::Scenario;
use gridswarm::sim::{Fault, FaultKind, Radio};

const DELAYS_MS: [u64; 12] = [0, 25, 45, 50, 55, 100, 200, 400, 800, 1000, 1200, 2000];
const POLICIES: [Policy; 4] = [Policy::Repulsive, Policy::Escape, Policy::Frontier, Policy::Sequential];
const ROBOTS: usize = 13;

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let Some(runs) = a.first().and_then(|s| s.parse::<u64>().ok()) else {
        eprintln!("usage: delay RUNS [SEED]");
        std::process::exit(2);
    };
    let seed: u64 = a.get(1).and_then(|s| s.parse().ok()).unwrap_or(1);
    let sc = Scenario::builtin("paper").expect("built in");
    let world = sc.world();
    let starts = sc.start_vertices(&world, ROBOTS).expect("paper holds 13 robots");
    println!(
        "delay_ms,jitter_ms,faults,runs,moves,collisions,per_1e6_moves,zero_means_below_per_1e6,unsure_per_robot_round,complete"
    );
    for delay in DELAYS_MS {
        for jitter in if delay == 0 { vec![0] } else { vec![0, delay / 2] } {
            for faults in [false, true] {
                let (mut moves, mut collisions, mut unsure, mut robot_rounds, mut complete) = (0, 0, 0, 0, 0);
                for i in 0..runs {
                    let s = derive(seed, i ^ delay << 20 ^ jitter << 40 ^ (faults as u64) << 62);
                    let mut cfg = RunConfig::new(POLICIES[(i % 4) as usize], s, Situation::One);
                    cfg.radio = Radio { delay: delay * 1000, jitter: jitter * 1000, ..Radio::default() };
                    cfg.max_rounds = 1500;
                    if faults {
                        cfg.faults = some_faults(s);
                    }
                    let r = engine::run(&world, &starts, &cfg);
                    moves += r.protocol.moves;
                    collisions += r.collisions as u64;
                    unsure += r.protocol.unsure;
                    robot_rounds += r.robot_rounds;
                    complete += r.complete as u64;
                }
                let per = |n: u64| 1e6 * n as f64 / moves.max(1) as f64;
                println!(
                    "{delay},{jitter},{},{runs},{moves},{collisions},{:.1},{:.1},{:.4},{:.3}",
                    if faults { "crash+freeze+slow" } else { "none" },
                    per(collisions),
                    per(3),
                    unsure as f64 / robot_rounds.max(1) as f64,
                    complete as f64 / runs as f64
                );
            }
        }
    }
}

/// A crash, a freeze of 5 rounds and a robot slow by 300 ms for good, on
/// three robots and at rounds drawn from `s`.
fn some_faults(s: u64) -> Vec<Fault> {
    let robot = |k: u64| (mix(s ^ k) % ROBOTS as u64) as usize;
    let round = |k: u64| 1 + (mix(s ^ k ^ 0x5eed) % 30) as u32;
    let offset = |k: u64| mix(s ^ k ^ 0x0ff5) % 1_500_000;
    let (crashed, frozen, slow) = (robot(1), robot(2), robot(3));
    let at = round(2);
    vec![
        Fault { robot: crashed, round: round(1), offset: offset(1), kind: FaultKind::Crash },
        Fault { robot: frozen, round: at, offset: offset(2), kind: FaultKind::Freeze },
        Fault { robot: frozen, round: at + 5, offset: offset(3), kind: FaultKind::Thaw },
        Fault { robot: slow, round: round(3), offset: 0, kind: FaultKind::Slow(300_000) },
    ]
}
