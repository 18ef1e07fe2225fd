//! The protocol's deterministic simulation test (see `gridswarm::vopr`):
//! randomized faulty runs, every one checked for collisions, refused moves,
//! slot liveness, failure detection and termination. `VOPR_RUNS` (default
//! 100,000) and `VOPR_SEED` (default 1) set its size and seed;
//! scripts/soak.sh runs it at greater length. A failing case prints the
//! command that replays it.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use gridswarm::sim::FaultKind;
use gridswarm::vopr::{self, Violation, Worlds};

/// Endless searches allowed per 10,000 runs (see `Violation::Endless`)
/// among the cases the design bounds: on `small`, inside the stated bound
/// ([`vopr::Case::in_bound`]), robots slow by at most 0.8 s, `escape` aside (its robots can block each
/// other's first step for good, a weakness of that policy left to its own
/// issue). Measured at 100,000 cases, seed 1: 0 of 31,151, since survivors
/// step to what the bodies leave them and failures are checked by sonar
/// (8 before).
const ENDLESS_PER_10K: u64 = 1;
/// Endless searches allowed per 10,000 among all the other cases: crashes
/// and freezes on bigger maps and teams, RU, frames past the window, loss.
/// This bound only keeps the rate from growing. Measured: 2,286 of 68,849
/// (3.3%) at 100,000 cases, seed 1 (5.4% before survivors' steps).
const ENDLESS_BEYOND_PER_10K: u64 = 450;
/// Point 3's round bound: among cases with crashes or freezes and nothing
/// else wrong ([`vopr::Case::measures_liveness`]), one in this many also
/// runs its survivors' twin (fault-free, only the robots left running).
const LIVENESS_SAMPLE: u64 = 8;
/// The 95th percentile of a sampled run's rounds over its survivors'
/// twin's may not pass this (issue 21's goal: 1.5).
const LIVENESS_P95: f64 = 1.5;
/// Fewer samples than this give too loose a percentile to hold to the goal
/// (a short run of the test prints it only).
const LIVENESS_MIN_SAMPLES: usize = 500;

fn env(name: &str, default: u64) -> u64 {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

#[derive(Default)]
struct Tally {
    robot_rounds: AtomicU64,
    crashes: AtomicU64,
    detected: AtomicU64,
    broken: Mutex<std::collections::BTreeMap<&'static str, u64>>,
    failures: Mutex<Vec<String>>,
    /// Endless cases, and whether each is one of those the design bounds.
    endless: Mutex<Vec<(bool, String)>>,
    bounded: AtomicU64,
    /// Sampled runs' rounds over their survivors' twins', with their reproducers.
    liveness: Mutex<Vec<(f64, String)>>,
}

impl Tally {
    fn record(&self, i: u64, seed: u64, case: &vopr::Case, r: &gridswarm::outcome::RunResult, suspect_rounds: u32) {
        self.robot_rounds.fetch_add(r.robot_rounds, Ordering::Relaxed);
        for f in r.protocol.failures.iter().filter(|f| f.kind == "crash") {
            self.crashes.fetch_add(1, Ordering::Relaxed);
            self.detected.fetch_add(f.detected_round.is_some() as u64, Ordering::Relaxed);
        }
        let bounded = bounded(case);
        self.bounded.fetch_add(bounded as u64, Ordering::Relaxed);
        match vopr::check(case, r, suspect_rounds) {
            Ok(()) => {}
            Err(Violation::Endless) => {
                self.endless.lock().unwrap().push((bounded, format!("case {i} (seed {seed}): {}", case.command())));
            }
            Err(Violation::Broken { kind, why }) => {
                *self.broken.lock().unwrap().entry(kind).or_default() += 1;
                let mut f = self.failures.lock().unwrap();
                if f.len() < 20 {
                    f.push(format!("case {i} (seed {seed}): {why}\n  replay: {}", case.command()));
                }
            }
        }
    }
}

#[test]
fn faulty_runs_never_collide_always_end_and_detect_every_crash() {
    let runs = env("VOPR_RUNS", 100_000);
    let seed = env("VOPR_SEED", 1);
    let worlds = Worlds::default();
    let next = AtomicU64::new(0);
    let tally = Tally::default();
    let t0 = Instant::now();
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::Relaxed);
                if i >= runs {
                    return;
                }
                let case = vopr::case(seed, i);
                let r = worlds.run(&case);
                let suspect_rounds = worlds.world(case.scenario, case.slot, case.order).1.params.suspect_rounds;
                tally.record(i, seed, &case, &r, suspect_rounds);
                if i % LIVENESS_SAMPLE == 0 && case.measures_liveness() {
                    let twin = worlds.run(&case.twin(case.robots - case.gone()));
                    if twin.protocol.ended_by != "max_rounds" {
                        let ratio = r.rounds as f64 / twin.rounds.max(1) as f64;
                        tally
                            .liveness
                            .lock()
                            .unwrap()
                            .push((ratio, format!("case {i} (seed {seed}): {}", case.command())));
                    }
                }
            });
        }
    });
    println!(
        "{runs} runs in {:.1} s ({:.2} M robot-rounds); {} crashes, {} declared by a robot",
        t0.elapsed().as_secs_f64(),
        tally.robot_rounds.load(Ordering::Relaxed) as f64 / 1e6,
        tally.crashes.load(Ordering::Relaxed),
        tally.detected.load(Ordering::Relaxed)
    );
    let bounded_runs = tally.bounded.load(Ordering::Relaxed);
    let (strict, beyond): (Vec<_>, Vec<_>) = tally.endless.into_inner().unwrap().into_iter().partition(|e| e.0);
    println!(
        "endless searches: {} of {bounded_runs} bounded cases (allowed {ENDLESS_PER_10K} per 10,000), {} of the {} \
         others (allowed {ENDLESS_BEYOND_PER_10K} per 10,000)",
        strict.len(),
        beyond.len(),
        runs - bounded_runs
    );
    for e in strict.iter().chain(beyond.iter().take(20)) {
        println!("  {}", e.1);
    }
    let (p95, samples) = liveness(tally.liveness.into_inner().unwrap());
    let f = tally.failures.into_inner().unwrap();
    let broken = tally.broken.into_inner().unwrap();
    assert!(f.is_empty(), "failing cases {broken:?}, the first {}:\n{}", f.len(), f.join("\n"));
    assert!(
        strict.len() as u64 * 10_000 <= ENDLESS_PER_10K * bounded_runs.max(10_000),
        "{} endless searches in {bounded_runs} bounded runs",
        strict.len()
    );
    assert!(
        beyond.len() as u64 * 10_000 <= ENDLESS_BEYOND_PER_10K * (runs - bounded_runs).max(10_000),
        "{} endless searches in {} runs beyond the bounds",
        beyond.len(),
        runs - bounded_runs
    );
    assert!(
        samples < LIVENESS_MIN_SAMPLES || p95 <= LIVENESS_P95,
        "rounds over the survivors' twin's: p95 {p95:.2} of {samples} sampled runs, more than {LIVENESS_P95}"
    );
}

/// Prints the sampled runs' rounds over their survivors' twins' (quantiles
/// and the worst cases) and returns the 95th percentile and their number.
fn liveness(mut v: Vec<(f64, String)>) -> (f64, usize) {
    if v.is_empty() {
        return (0.0, 0);
    }
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    let q = |p: f64| v[((v.len() as f64 - 1.0) * p).round() as usize].0;
    println!(
        "rounds over the survivors' twin's, {} sampled runs: median {:.2}, p90 {:.2}, p95 {:.2}, p99 {:.2}, max {:.2}",
        v.len(),
        q(0.5),
        q(0.9),
        q(0.95),
        q(0.99),
        q(1.0)
    );
    for (ratio, case) in v.iter().rev().take(3) {
        println!("  {ratio:.1}x: {case}");
    }
    (q(0.95), v.len())
}

/// The cases the old test ran (robots slow by at most 0.8 s), whose
/// endless rate the design bounds.
fn bounded(case: &vopr::Case) -> bool {
    let slow = |f: &gridswarm::sim::Fault| matches!(f.kind, FaultKind::Slow(t) if t > 800_000);
    case.scenario == "small"
        && case.in_bound()
        && case.config.policy != gridswarm::policy::Policy::Escape
        && !case.config.faults.iter().any(slow)
}

#[test]
fn cases_are_reproducible_and_varied() {
    assert_eq!(vopr::case(1, 7), vopr::case(1, 7));
    assert_ne!(vopr::case(1, 7), vopr::case(2, 7));
    let cases: Vec<_> = (0..400).map(|i| vopr::case(3, i)).collect();
    assert!(cases.iter().any(|c| c.config.faults.iter().any(|f| f.kind == FaultKind::Crash)));
    assert!(cases.iter().any(|c| c.config.faults.iter().any(|f| f.kind == FaultKind::Thaw)));
    assert!(cases.iter().any(|c| c.config.radio.dup > 0.0 && c.config.radio.jitter > 0));
    // Every reach the issue asks for: each scenario and grid algorithm, big
    // teams, robots slow by seconds, frames past the window, loss.
    for (sc, _) in vopr::SCENARIOS {
        assert!(cases.iter().any(|c| c.scenario == sc), "no case on {sc}");
    }
    for p in (0..vopr::POLICIES.len()).map(vopr::policy) {
        assert!(cases.iter().any(|c| c.config.policy == p), "no case of {p}");
    }
    assert!(cases.iter().any(|c| c.robots > 40));
    let slow = |c: &vopr::Case| c.config.faults.iter().any(|f| matches!(f.kind, FaultKind::Slow(t) if t > 5_000_000));
    assert!(cases.iter().any(slow));
    assert!(cases.iter().any(|c| c.config.radio.delay > vopr::MAX_LATENESS));
    assert!(cases.iter().any(|c| c.config.radio.loss > 0.0 && c.config.failing_robots().count() > 0));
    assert!(cases.iter().filter(|c| c.in_bound()).count() > cases.len() / 2);
    let fixed = cases.iter().filter(|c| c.slot == gridswarm::params::SlotRule::Fixed).count();
    assert!(fixed > cases.len() / 5 && fixed < cases.len() / 2, "{fixed} of {} under the fixed slot", cases.len());
    let local = cases.iter().filter(|c| c.order == gridswarm::params::Order::Local).count();
    assert!(local > cases.len() / 5 && local < cases.len() / 2, "{local} of {} under the local order", cases.len());
    assert!(cases[0].command().starts_with("cargo run --release --bin gridswarm -- simulate --scenario "));
}
