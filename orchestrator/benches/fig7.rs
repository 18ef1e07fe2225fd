//! The Fig. 7 sweep as a benchmark: 4 algorithms (lfp, ru, sequential,
//! repulsive), 1 to 13 robots, 500 runs each, `paper` scenario, on every
//! core. Target: under 5 s wall (issue 8). Prints each repetition and the median.
//!
//! `cargo bench -p gridswarm-orchestrator --bench fig7` (REPS=N to change
//! the number of repetitions, default 5).

use gridswarm_orchestrator::experiment::{self, ExperimentOptions};

fn main() {
    let reps: usize = std::env::var("REPS").ok().and_then(|s| s.parse().ok()).unwrap_or(5);
    let out = std::env::temp_dir().join(format!("gridswarm-bench-{}", std::process::id()));
    let opts = ExperimentOptions::fig7(500, out.clone());
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
    println!("median wall (sweep + output): {:.2} s (target < 5 s)", median(&mut walls));
    println!("median rate: {:.2} M robot-rounds/s", median(&mut rates) / 1e6);
}

fn median(xs: &mut [f64]) -> f64 {
    xs.sort_by(|a, b| a.total_cmp(b));
    xs[xs.len() / 2]
}
