//! The deterministic simulation test's speed: RUNS faulty cases (default
//! 100,000) on every core, REPS times (default 3), median wall time.
//!
//!     cargo bench --workspace --bench vopr
//!
//! Target: at least 100,000 faulty runs in at most 60 s on 2 cores.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use gridswarm::vopr::{self, Worlds};

fn env(name: &str, default: u64) -> u64 {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

fn main() {
    let (runs, reps) = (env("RUNS", 100_000), env("REPS", 3));
    let worlds = Worlds::default();
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let mut walls = Vec::new();
    for rep in 0..reps {
        let next = AtomicU64::new(0);
        let robot_rounds = AtomicU64::new(0);
        let t0 = Instant::now();
        std::thread::scope(|s| {
            for _ in 0..threads {
                s.spawn(|| loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= runs {
                        return;
                    }
                    let case = vopr::case(rep + 1, i);
                    let r = worlds.run(&case);
                    robot_rounds.fetch_add(r.robot_rounds, Ordering::Relaxed);
                });
            }
        });
        let wall = t0.elapsed().as_secs_f64();
        let rr = robot_rounds.load(Ordering::Relaxed) as f64;
        println!("rep {rep}: {runs} runs in {wall:.1} s on {threads} threads, {:.2} M robot-rounds/s", rr / wall / 1e6);
        walls.push(wall);
    }
    walls.sort_by(f64::total_cmp);
    println!("median: {:.1} s for {runs} runs", walls[walls.len() / 2]);
}
