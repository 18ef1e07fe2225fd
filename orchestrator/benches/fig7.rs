//! The Fig. 7 sweep as a benchmark: 4 algorithms (lfp, ru, sequential,
//! repulsive), 1 to 13 robots, 500 runs each, `paper` scenario, on every
//! core. Target: under 5 s wall (issue 8). Prints each repetition and the median.
//!
//! `cargo bench --workspace --bench fig7` (REPS=N to change
//! the number of repetitions, default 5).
//!
//! With MAPS=K, issue 8's random-map sweep instead: K maps
//! (`random:1` at its default size, 20 x 16 m, and its K - 1 successors, as `experiment --maps K` makes them), 6
//! algorithms (lfp, ru, sequential, repulsive, escape, frontier), 1 to 13
//! robots, RUNS runs each (default 100). Target with K = 20: under 30 s.

use gridswarm_orchestrator::experiment::{self, ExperimentOptions};

fn main() {
    let reps: usize = std::env::var("REPS").ok().and_then(|s| s.parse().ok()).unwrap_or(5);
    let out = std::env::temp_dir().join(format!("gridswarm-bench-{}", std::process::id()));
    let opts = match std::env::var("MAPS").ok().and_then(|s| s.parse().ok()) {
        Some(maps) => random_maps(maps, out.clone()),
        None => ExperimentOptions::fig7(500, out.clone()),
    };
    let target = if opts.maps.is_some() { 30 } else { 5 };
    println!("threads: {}", rayon::current_num_threads());
    let mut walls = Vec::new();
    let mut rates = Vec::new();
    for rep in 0..reps {
        let t = std::time::Instant::now();
        let (sweep, _) = experiment::run(&opts).expect("the sweep runs");
        let total = t.elapsed().as_secs_f64();
        let rate = sweep.robot_rounds as f64 / sweep.wall_time_s;
        println!(
            "rep {rep}: sweep {:.2} s, with output {:.2} s, {} robot-rounds, {:.2} M robot-rounds/s",
            sweep.wall_time_s,
            total,
            sweep.robot_rounds,
            rate / 1e6
        );
        walls.push(total);
        rates.push(rate);
    }
    let _ = std::fs::remove_dir_all(&out);
    println!("median wall (sweep + output): {:.2} s (target < {target} s)", median(&mut walls));
    println!("median rate: {:.2} M robot-rounds/s", median(&mut rates) / 1e6);
}

fn random_maps(maps: u32, out: std::path::PathBuf) -> ExperimentOptions {
    let runs = std::env::var("RUNS").ok().and_then(|s| s.parse().ok()).unwrap_or(100);
    let algorithms = "lfp,ru,sequential,repulsive,escape,frontier";
    ExperimentOptions {
        scenario: "random:1".into(),
        algorithms: algorithms.split(',').map(|a| a.parse().expect("known algorithm")).collect(),
        maps: Some(maps),
        ..ExperimentOptions::fig7(runs, out)
    }
}

fn median(xs: &mut [f64]) -> f64 {
    xs.sort_by(|a, b| a.total_cmp(b));
    xs[xs.len() / 2]
}
