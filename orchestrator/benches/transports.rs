//! The same runs over both transports, side by side: `gridswarm experiment
//! scale` over iceoryx2, then over zenoh (TCP on 127.0.0.1), with the same
//! seeds at N = 13 (`paper`) and 50 (`large`), in one invocation on one
//! machine; prints each transport's round p50/p99 and the zenoh/iceoryx2
//! ratios, and checks that both took the same rounds (the same searches).
//!
//!     cargo bench --workspace --bench transports
//!
//! REPS (default 3) and SIZES (default 13,50) override the plan.

use std::path::Path;
use std::process::Command;

const TRANSPORTS: [&str; 2] = ["iceoryx2", "zenoh"];

/// (robots, median rounds, round p50 ms, round p99 ms) per row of scale.csv.
fn rows(dir: &Path) -> Vec<(u64, f64, f64, f64)> {
    let text = std::fs::read_to_string(dir.join("scale.csv")).expect("scale.csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    let (n, rounds, p50, p99) =
        (col("robots"), col("median_rounds"), col("round_wall_p50_ms"), col("round_wall_p99_ms"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let num = |k: usize| f[k].parse::<f64>().unwrap_or(f64::NAN);
            (f[n].parse().expect("robots"), num(rounds), num(p50), num(p99))
        })
        .collect()
}

fn main() {
    let reps = std::env::var("REPS").unwrap_or_else(|_| "3".into());
    let sizes = std::env::var("SIZES").unwrap_or_else(|_| "13,50".into());
    let base = std::env::temp_dir().join(format!("gridswarm-bench-transports-{}", std::process::id()));
    let mut measured = Vec::new();
    for t in TRANSPORTS {
        let out = base.join(t);
        let status = Command::new(env!("CARGO_BIN_EXE_gridswarm"))
            .args(["experiment", "scale", "--robots", &sizes, "--runs", &reps, "--seed", "1", "--transport", t])
            .arg("--out")
            .arg(&out)
            .status()
            .expect("gridswarm runs");
        assert!(status.success(), "gridswarm experiment scale --transport {t} failed");
        measured.push(rows(&out));
    }
    let _ = std::fs::remove_dir_all(&base);
    println!("\nsame seeds, {reps} run(s) per count, medians over runs");
    println!("| N | rounds | iceoryx2 p50 (ms) | iceoryx2 p99 (ms) | zenoh p50 (ms) | zenoh p99 (ms) | zenoh/iceoryx2 p50 | zenoh/iceoryx2 p99 |");
    println!("|---|---|---|---|---|---|---|---|");
    for (i, z) in measured[0].iter().zip(&measured[1]) {
        assert_eq!((i.0, i.1), (z.0, z.1), "both transports ran the same searches");
        println!(
            "| {} | {:.0} | {:.3} | {:.3} | {:.3} | {:.3} | {:.2} | {:.2} |",
            i.0,
            i.1,
            i.2,
            i.3,
            z.2,
            z.3,
            z.2 / i.2,
            z.3 / i.3
        );
    }
}
