//! The distributed engine at scale, measured by `gridswarm experiment scale`:
//! for N = 13 (`paper`) and 50, 100, 200 (`large`), REPS runs of `gridswarm
//! run` each, reporting medians of wall time per round (p50, p99), start-up,
//! peak RSS of one agent and of the world-server, the world's open file
//! descriptors, and the in-process engine's wall time per round on the same
//! runs with the ratio, and messages and wake-ups per robot per round.
//!
//!     cargo build --release --workspace
//!     cargo bench --workspace --bench distributed
//!
//! REPS (default 3) and SIZES (default 13,50,100,200) override the plan.

use std::process::Command;

fn main() {
    let reps = std::env::var("REPS").unwrap_or_else(|_| "3".into());
    let sizes = std::env::var("SIZES").unwrap_or_else(|_| "13,50,100,200".into());
    let out = std::env::temp_dir().join(format!("gridswarm-bench-scale-{}", std::process::id()));
    // The command itself, so the world-server and agents are found beside it.
    let status = Command::new(env!("CARGO_BIN_EXE_gridswarm"))
        .args(["experiment", "scale", "--robots", &sizes, "--runs", &reps, "--seed", "1"])
        .arg("--out")
        .arg(&out)
        .status()
        .expect("gridswarm runs");
    let _ = std::fs::remove_dir_all(&out);
    assert!(status.success(), "gridswarm experiment scale failed");
}
