//! Issue 21's dense teams, measured: fault-free searches on `large` at
//! several team sizes under both choice orders (`params.order`), and for
//! each the unsure stays and time-outs per robot-round and the mean
//! simulated length of a round (search time over rounds played).
//! `cargo run --release --example dense -- SEEDS [ROBOTS...] [--algorithm NAME]`
//! (robots default to 13 200 1000). Prints one CSV line per run, then the
//! medians over seeds of each order and team size, and the ratio of each
//! team's median round length to the smallest team's.
use gridswarm::engine;
use gridswarm::outcome::{RunConfig, RunResult};
use gridswarm::params::Order;
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;

struct Row {
    order: Order,
    robots: usize,
    unsure: f64,
    timeouts: f64,
    round_s: f64,
}

fn run(order: Order, robots: usize, seed: u64, policy: Policy) -> RunResult {
    let mut sc = Scenario::builtin("large").expect("built in");
    sc.params.order = order;
    let world = sc.world();
    let starts = sc.start_vertices(&world, robots).expect("large holds the team");
    engine::run(&world, &starts, &RunConfig::new(policy, seed, sc.situation))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut policy = Policy::Repulsive;
    if let Some(k) = args.iter().position(|a| a == "--algorithm") {
        let Some(p) = args.get(k + 1).and_then(|s| s.parse().ok()) else {
            eprintln!("--algorithm: a grid algorithm's name");
            std::process::exit(2);
        };
        policy = p;
        args.drain(k..k + 2);
    }
    let parsed: Option<Vec<usize>> = args.iter().map(|s| s.parse().ok()).collect();
    let Some((&seeds, counts)) = parsed.as_deref().and_then(|v| v.split_first()).filter(|(&s, _)| s > 0) else {
        eprintln!("usage: dense SEEDS [ROBOTS...] [--algorithm NAME]");
        std::process::exit(2);
    };
    let counts = if counts.is_empty() { vec![13, 200, 1000] } else { counts.to_vec() };
    println!("order,robots,seed,rounds,robot_rounds,unsure,timeouts,forced_slots,mean_round_s,ended_by");
    let mut rows = Vec::new();
    for order in [Order::Paper, Order::Local] {
        for &n in &counts {
            for seed in 1..=seeds as u64 {
                let r = run(order, n, seed, policy);
                let p = &r.protocol;
                let rr = r.robot_rounds.max(1) as f64;
                let round_s = r.search_time_s / r.rounds.max(1) as f64;
                println!(
                    "{},{n},{seed},{},{},{},{},{},{round_s:.3},{}",
                    order.name(),
                    r.rounds,
                    r.robot_rounds,
                    p.unsure,
                    p.timeouts,
                    p.forced_slots,
                    p.ended_by
                );
                rows.push(Row {
                    order,
                    robots: n,
                    unsure: p.unsure as f64 / rr,
                    timeouts: p.timeouts as f64 / rr,
                    round_s,
                });
            }
        }
    }
    println!("\norder,robots,median unsure per robot-round,median timeouts per robot-round,median round s,ratio");
    for order in [Order::Paper, Order::Local] {
        let of = |n: usize, f: fn(&Row) -> f64| {
            median(rows.iter().filter(|r| r.order == order && r.robots == n).map(f).collect())
        };
        let base = of(counts[0], |r| r.round_s);
        for &n in &counts {
            let round = of(n, |r| r.round_s);
            println!(
                "{},{n},{:.4},{:.4},{round:.3},{:.3}",
                order.name(),
                of(n, |r| r.unsure),
                of(n, |r| r.timeouts),
                round / base
            );
        }
    }
}
