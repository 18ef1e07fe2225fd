//! The distributed engine at scale: for N = 13 (`paper`) and 50, 100, 200
//! (`large`), runs `gridswarm run --json` REPS times and reports the median
//! of: wall time per round (p50, p99), start-up, peak RSS of one agent and
//! of the world-server, the world's open file descriptors, and the ratio of
//! distributed to in-process wall time per round, the in-process engine being
//! timed on the same run in this process.
//!
//!     cargo build --release --workspace
//!     cargo bench -p gridswarm-orchestrator --bench distributed
//!
//! REPS (default 3) and SIZES (default 13,50,100,200) override the plan.

use std::process::Command;
use std::time::Instant;

use gridswarm::engine;
use gridswarm::outcome::RunConfig;
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;
use serde_json::Value;

fn main() {
    let reps: usize = std::env::var("REPS").ok().and_then(|s| s.parse().ok()).unwrap_or(3);
    let sizes: Vec<usize> = std::env::var("SIZES")
        .unwrap_or_else(|_| "13,50,100,200".into())
        .split(',')
        .map(|s| s.trim().parse().expect("SIZES is a comma-separated list of robot counts"))
        .collect();
    let bin = env!("CARGO_BIN_EXE_gridswarm");
    println!("| N | scenario | rounds | round p50 ms | round p99 ms | start-up ms | agent RSS MiB | world RSS MiB | world fds | in-process ms/round | ratio |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for &n in &sizes {
        let scenario = if n <= 13 { "paper" } else { "large" };
        let mut rows: Vec<[f64; 8]> = Vec::new();
        for rep in 0..reps {
            let seed = 1 + rep as u64;
            let out = Command::new(bin)
                .args(["run", "--scenario", scenario, "--robots", &n.to_string(), "--seed", &seed.to_string(), "--json"])
                .output()
                .expect("gridswarm runs");
            assert!(out.status.success(), "gridswarm run failed: {}", String::from_utf8_lossy(&out.stderr));
            let v: Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
            let f = |path: &[&str]| path.iter().fold(&v, |v, k| &v[*k]).as_f64().unwrap_or(f64::NAN);
            let rounds = f(&["rounds"]);
            let inproc = in_process_ms_per_round(scenario, n, seed);
            let startup = f(&["startup_ms", "world_ready"]) + f(&["startup_ms", "agents_spawned"]) + f(&["startup_ms", "all_hello"]);
            rows.push([
                rounds,
                f(&["round_wall_ms", "p50"]),
                f(&["round_wall_ms", "p99"]),
                startup,
                f(&["agent_peak_rss_kib", "max"]) / 1024.0,
                f(&["world_peak_rss_kib"]) / 1024.0,
                f(&["world_fds"]),
                inproc,
            ]);
        }
        let m = |k: usize| median(rows.iter().map(|r| r[k]).collect());
        println!(
            "| {n} | {scenario} | {:.0} | {:.2} | {:.2} | {:.0} | {:.1} | {:.1} | {:.0} | {:.3} | {:.0}x |",
            m(0),
            m(1),
            m(2),
            m(3),
            m(4),
            m(5),
            m(6),
            m(7),
            m(1) / m(7)
        );
    }
}

/// Wall time per round of the in-process engine on the same run.
fn in_process_ms_per_round(scenario: &str, n: usize, seed: u64) -> f64 {
    let s = Scenario::load(scenario).expect("built-in scenario");
    let world = s.world();
    let starts = s.start_vertices(&world, n).expect("room for the robots");
    let mut cfg = RunConfig::new(Policy::Repulsive, seed, s.situation);
    cfg.record_trajectories = false;
    cfg.measure_coverage = false;
    let t = Instant::now();
    let r = engine::run(&world, &starts, &cfg);
    t.elapsed().as_secs_f64() * 1e3 / r.rounds.max(1) as f64
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(|a, b| a.total_cmp(b));
    xs[xs.len() / 2]
}
