//! Issue 21's liveness goal, measured: with up to three crashes or freezes
//! (and nothing else wrong), how many rounds a run takes against its
//! fault-free twin (same scenario, team, algorithm and seed, no faults).
//! `cargo run --release --example liveness -- SEED COUNT [ALGORITHM]`
//! Cases are the simulation test's (`vopr::case`) with their radio made
//! perfect and slow robots dropped, and RU left out (its robots are
//! particles, with no failure detection to speak of); runs whose twin does
//! not end are left out and counted. Prints the ratio's quantiles, by
//! scenario and overall, and the worst cases with their reproducers.
use gridswarm::engine;
use gridswarm::policy::Policy;
use gridswarm::sim::{FaultKind, Radio};
use gridswarm::vopr::{self, Worlds};

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let (Some(seed), Some(count)) = (a.first().and_then(|s| s.parse().ok()), a.get(1).and_then(|s| s.parse().ok()))
    else {
        eprintln!("usage: liveness SEED COUNT [ALGORITHM]");
        std::process::exit(2);
    };
    let only = a.get(2).cloned();
    let worlds = Worlds::default();
    let mut rows: Vec<(f64, &'static str, String, u32, u32, String)> = Vec::new();
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
        let (w, starts) = worlds.of(&case);
        let faulty = engine::run(&w.1, &starts, &case.config);
        let mut twin_cfg = case.config.clone();
        twin_cfg.faults.clear();
        let twin = engine::run(&w.1, &starts, &twin_cfg);
        if twin.protocol.ended_by == "max_rounds" {
            twin_endless += 1;
            continue;
        }
        let ratio = faulty.rounds as f64 / twin.rounds.max(1) as f64;
        rows.push((ratio, case.scenario, faulty.protocol.ended_by.clone(), faulty.rounds, twin.rounds, case.command()));
    }
    rows.sort_by(|x, y| x.0.total_cmp(&y.0));
    let q = |v: &[f64], p: f64| v[((v.len() as f64 - 1.0) * p).round() as usize];
    println!("scenario,cases,median,p90,p95,p99,max,endless");
    let mut names: Vec<&str> = rows.iter().map(|r| r.1).collect();
    names.sort();
    names.dedup();
    names.push("all");
    for name in names {
        let v: Vec<f64> = rows.iter().filter(|r| name == "all" || r.1 == name).map(|r| r.0).collect();
        let endless = rows.iter().filter(|r| (name == "all" || r.1 == name) && r.2 == "max_rounds").count();
        println!(
            "{name},{},{:.2},{:.2},{:.2},{:.2},{:.2},{endless}",
            v.len(),
            q(&v, 0.5),
            q(&v, 0.9),
            q(&v, 0.95),
            q(&v, 0.99),
            v[v.len() - 1]
        );
    }
    println!("fault-free twins that did not end (left out): {twin_endless}");
    for r in rows.iter().rev().take(5) {
        println!("{:.1}x ({} rounds, twin {}, {}): {}", r.0, r.3, r.4, r.2, r.5);
    }
}
