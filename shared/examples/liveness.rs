//! Issue 21's liveness goal, measured: with up to three crashes or freezes
//! (and nothing else wrong), how many rounds a run takes against its
//! fault-free twin (same scenario, team, algorithm and seed, no faults),
//! and against its survivors' twin (the same, fault-free, with only as
//! many robots as are left running at the end: a team cut from 4 robots to
//! 1 cannot search as fast as 4, whatever the protocol does).
//! `cargo run --release --example liveness -- SEED COUNT [ALGORITHM]`
//! Cases are the simulation test's (`vopr::case`) with their radio made
//! perfect and slow robots dropped, and RU left out (its robots are
//! particles, with no failure detection to speak of); runs whose twin does
//! not end are left out and counted. Prints the ratios' quantiles, by
//! scenario and overall, and the worst cases with their reproducers; and
//! the same with every `cut_off` run counted only until its median
//! survivor's last move (from the trajectories): how much of the tail is
//! the wait for the last survivor to halt (BENCHMARKS.md); and the
//! survivors' twin against the fault-free twin: what the robots lost costs
//! a team that searched without faults from the start.
use gridswarm::policy::Policy;
use gridswarm::sim::{FaultKind, Radio};
use gridswarm::vopr::{self, Case, Worlds};

/// One faulty run against its two twins.
struct Row {
    scenario: &'static str,
    ended_by: String,
    rounds: u32,
    twin: u32,
    survivors_twin: u32,
    /// `cut_off` runs: the round after the median survivor's last move.
    median_halt: Option<u32>,
    command: String,
}

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let (Some(seed), Some(count)) = (a.first().and_then(|s| s.parse().ok()), a.get(1).and_then(|s| s.parse().ok()))
    else {
        eprintln!("usage: liveness SEED COUNT [ALGORITHM]");
        std::process::exit(2);
    };
    let only = a.get(2).cloned();
    let worlds = Worlds::default();
    let mut rows: Vec<Row> = Vec::new();
    let mut twin_endless = 0;
    for i in 0..count {
        let mut case = vopr::case(seed, i);
        let c = &mut case.config;
        if c.policy == Policy::Ru || only.as_deref().is_some_and(|p| p != c.policy.name()) {
            continue;
        }
        c.radio = Radio::default();
        c.faults.retain(|f| !matches!(f.kind, FaultKind::Slow(_)));
        if c.faults.is_empty() {
            continue;
        }
        case.config.record_trajectories = true;
        let faulty = worlds.run(&case);
        case.config.record_trajectories = false;
        let Some(twin) = fault_free(&worlds, &case, case.robots) else {
            twin_endless += 1;
            continue;
        };
        let survivors = case.robots - case.gone();
        let Some(survivors_twin) = fault_free(&worlds, &case, survivors) else {
            twin_endless += 1;
            continue;
        };
        let (scenario, ended_by, rounds) = (case.scenario, faulty.protocol.ended_by.clone(), faulty.rounds);
        let median_halt = (ended_by == "cut_off").then(|| median_last_move(&case, &faulty.trajectories));
        rows.push(Row { scenario, ended_by, rounds, twin, survivors_twin, median_halt, command: case.command() });
    }
    println!("fault-free twins that did not end (cases left out): {twin_endless}");
    let full = |r: &Row| r.rounds as f64 / r.twin.max(1) as f64;
    let survivors = |r: &Row| r.rounds as f64 / r.survivors_twin.max(1) as f64;
    table("rounds / fault-free twin's", &rows, full);
    table("rounds / survivors' twin's", &rows, survivors);
    let median = |r: &Row| r.median_halt.unwrap_or(r.rounds) as f64 / r.survivors_twin.max(1) as f64;
    table("rounds / survivors' twin's, cut_off runs until their median survivor's last move", &rows, median);
    // No protocol undoes the loss of robots: a smaller team, fault-free,
    // against the whole team (the goal's 1.5 as written needs this too).
    let smaller = |r: &Row| r.survivors_twin as f64 / r.twin.max(1) as f64;
    table("survivors' twin's rounds / fault-free twin's", &rows, smaller);
    rows.sort_by(|x, y| survivors(x).total_cmp(&survivors(y)));
    for r in rows.iter().rev().take(5) {
        println!(
            "{:.1}x survivors' twin ({} rounds, twin {}, survivors' twin {}, {}): {}",
            survivors(r),
            r.rounds,
            r.twin,
            r.survivors_twin,
            r.ended_by,
            r.command
        );
    }
}

/// The round after the median survivor's last move: robots that crash,
/// or freeze and never thaw, are not survivors.
fn median_last_move(case: &Case, traj: &[Vec<gridswarm::outcome::Pose>]) -> u32 {
    let faults = &case.config.faults;
    let gone = |r: usize| {
        let last = faults.iter().filter(|f| f.robot == r).max_by_key(|f| (f.round, f.offset));
        last.is_some_and(|f| f.kind != FaultKind::Thaw)
    };
    let mut last: Vec<u32> = (0..traj.len())
        .filter(|&r| !gone(r))
        .map(|r| (1..traj[r].len()).filter(|&k| traj[r][k].vertex != traj[r][k - 1].vertex).max().unwrap_or(0) as u32)
        .collect();
    last.sort();
    last.get(last.len() / 2).map_or(0, |&k| k + 1)
}

/// The rounds of `case` without faults, with `robots` robots, if it ends.
fn fault_free(worlds: &Worlds, case: &Case, robots: usize) -> Option<u32> {
    let r = worlds.run(&case.twin(robots));
    (r.protocol.ended_by != "max_rounds").then_some(r.rounds)
}

/// The quantiles of `ratio` over `rows`, by scenario and overall.
fn table(title: &str, rows: &[Row], ratio: impl Fn(&Row) -> f64) {
    let q = |v: &[f64], p: f64| v[((v.len() as f64 - 1.0) * p).round() as usize];
    println!("{title}\nscenario,cases,median,p90,p95,p99,max,endless");
    let mut names: Vec<&str> = rows.iter().map(|r| r.scenario).collect();
    names.sort();
    names.dedup();
    names.push("all");
    for name in names {
        let of = |r: &&Row| name == "all" || r.scenario == name;
        let mut v: Vec<f64> = rows.iter().filter(of).map(&ratio).collect();
        v.sort_by(f64::total_cmp);
        let endless = rows.iter().filter(of).filter(|r| r.ended_by == "max_rounds").count();
        let (n, max) = (v.len(), v[v.len() - 1]);
        let (m, p90, p95, p99) = (q(&v, 0.5), q(&v, 0.9), q(&v, 0.95), q(&v, 0.99));
        println!("{name},{n},{m:.2},{p90:.2},{p95:.2},{p99:.2},{max:.2},{endless}");
    }
}
