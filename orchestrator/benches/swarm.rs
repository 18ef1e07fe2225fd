//! A big team in-process (issue 10): ROBOTS robots (10,000 by default) on
//! a random map with room for them, for ROUNDS rounds (1,000 by default),
//! repulsive policy, one run on one core; and, in the same process for the
//! ratio, a tenth of the Fig. 7 sweep (50 runs a cell) on every core. Goal:
//! 10,000 robots for 1,000 rounds in under 30 s. Prints wall time, rounds
//! done and robot-rounds per second of both.
//!
//! `cargo bench --workspace --bench swarm` (ROBOTS, ROUNDS,
//! SCENARIO and SEED to change the run).

use gridswarm::engine::Prepared;
use gridswarm::outcome::RunConfig;
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;
use gridswarm_orchestrator::experiment::{self, ExperimentOptions};

/// The largest square random map `MAX_ROBOT_VERTICES` allows 10,000 robots.
const SCENARIO: &str = "random:1,size=180x180";

fn env<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name).ok().and_then(|s| s.parse().ok()).unwrap_or(default)
}

fn main() {
    let robots: usize = env("ROBOTS", 10_000);
    let rounds: u32 = env("ROUNDS", 1000);
    let seed: u64 = env("SEED", 1);
    let scenario: String = env("SCENARIO", SCENARIO.to_string());

    let t = std::time::Instant::now();
    let s = Scenario::load(&scenario).expect("the scenario loads");
    let world = s.world();
    let starts = s.start_vertices(&world, robots).expect("the map has room");
    let setup = t.elapsed().as_secs_f64();
    let mut cfg = RunConfig::new(Policy::Repulsive, seed, s.situation);
    cfg.max_rounds = rounds;
    cfg.measure_coverage = false;
    cfg.record_trajectories = false;
    let t = std::time::Instant::now();
    let r = Prepared::new(&world).run(&starts, &cfg, &s.lfp);
    let wall = t.elapsed().as_secs_f64();
    let done = r.rounds as f64 * robots as f64;
    println!(
        "swarm: {robots} robots on {scenario} ({} vertices), seed {seed}: {} rounds ({}) in {wall:.1} s \
         (setup {setup:.1} s), {:.3} s a round, {:.0} k robot-rounds/s on one core",
        world.grid.len(),
        r.rounds,
        if r.complete { "complete" } else { "cut off" },
        wall / r.rounds.max(1) as f64,
        done / wall / 1e3,
    );

    let out = std::env::temp_dir().join(format!("gridswarm-bench-swarm-{}", std::process::id()));
    let opts = ExperimentOptions::fig7(50, out.clone());
    let (sweep, _) = experiment::run(&opts).expect("the sweep runs");
    let _ = std::fs::remove_dir_all(&out);
    let cores = rayon::current_num_threads() as f64;
    let rate = sweep.robot_rounds as f64 / sweep.wall_time_s;
    println!(
        "fig7 (50 runs a cell): {:.2} s, {:.0} k robot-rounds/s on {cores} cores ({:.0} k a core); \
         swarm / fig7 per core: {:.3}",
        sweep.wall_time_s,
        rate / 1e3,
        rate / cores / 1e3,
        (done / wall) / (rate / cores)
    );
}
