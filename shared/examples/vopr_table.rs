//! The simulation test's cases as a table, one line per case, to study
//! what the test counts rather than what it forbids:
//! `cargo run --release --example vopr_table -- SEED FIRST COUNT`.
//! Columns: index, scenario, robots, algorithm, in_bound, loss, delay_ms,
//! slow_ms (the largest), failing robots, ended_by, rounds, wall ms.
use std::time::Instant;

use gridswarm::sim::FaultKind;
use gridswarm::vopr::{self, Worlds};

fn main() {
    let a: Vec<u64> = std::env::args().skip(1).map(|s| s.parse().expect("SEED FIRST COUNT")).collect();
    let worlds = Worlds::default();
    println!("index,scenario,robots,algorithm,in_bound,loss,delay_ms,slow_ms,failing,ended_by,rounds,wall_ms");
    for i in a[1]..a[1] + a[2] {
        let case = vopr::case(a[0], i);
        let t0 = Instant::now();
        let r = worlds.run(&case);
        let c = &case.config;
        let slow = c.faults.iter().filter_map(|f| if let FaultKind::Slow(t) = f.kind { Some(t / 1000) } else { None });
        println!(
            "{i},{},{},{},{},{},{},{},{},{},{},{:.1}",
            case.scenario,
            case.robots,
            c.policy.name(),
            case.in_bound(),
            c.radio.loss,
            (c.radio.delay + c.radio.jitter) / 1000,
            slow.max().unwrap_or(0),
            c.failing_robots().count(),
            r.protocol.ended_by,
            r.rounds,
            t0.elapsed().as_secs_f64() * 1e3
        );
    }
}
