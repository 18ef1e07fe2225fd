//! Deterministic simulation testing of the robots' protocol, in the manner
//! of FoundationDB's simulation tests and TigerBeetle's VOPR: one `u64`
//! names a case (scenario, robots, algorithm, situation, radio faults and
//! robot faults at random simulated times), the in-process engine runs it,
//! and [`check`] tests what must hold whatever the faults:
//!
//! - no collision and no refused move;
//! - liveness: every slot closes within its limit (robots time out, the
//!   clock never has to force a slot shut), and the search ends within
//!   [`MAX_ROUNDS`] rounds except in rare cases the algorithms themselves
//!   cannot end (see [`Violation::Endless`]), which the test counts;
//! - every crash becomes known to each robot that waited on it.
//!
//! Faults: crash, freeze (with or without a thaw), slowness, all at any
//! moment including mid-chain; frames delayed, jittered (reordered) and
//! duplicated. Not loss: under loss the guarantees are probabilistic, and
//! `experiment radio` measures them instead. A failing case prints a
//! `gridswarm simulate` command line that replays it exactly.

use crate::outcome::{RunConfig, RunResult};
use crate::params::Situation;
use crate::policy::Policy;
use crate::rng::{derive, mix};
use crate::sim::{schedule, Fault, FaultKind, Radio, Time};

/// The scenario every case runs on (a built-in, so a reproducer needs no file).
pub const SCENARIO: &str = "small";
/// A case that has not ended after this many rounds fails the termination check.
pub const MAX_ROUNDS: u32 = 5000;
/// Delay plus jitter stays below this (µs), under the exchange window minus
/// a hop: a map always arrives within the exchange it belongs to.
pub const MAX_LATENESS: Time = 40_000;

/// One generated case.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    pub number: u64,
    pub robots: usize,
    pub config: RunConfig,
}

/// A uniform draw in `0..n` from case `number`'s stream, position `k`.
fn draw(number: u64, k: u64, n: u64) -> u64 {
    mix(derive(number, k)) % n.max(1)
}

fn chance(number: u64, k: u64, p: f64) -> bool {
    (draw(number, k, 1 << 30) as f64) < p * (1u64 << 30) as f64
}

/// Case `number` of the simulation test seeded with `seed`.
pub fn case(seed: u64, index: u64) -> Case {
    let number = derive(seed, index);
    let robots = 2 + draw(number, 1, 7) as usize;
    let policy = [Policy::Repulsive, Policy::Sequential, Policy::Escape][draw(number, 2, 3) as usize];
    let situation = if draw(number, 3, 2) == 0 { Situation::One } else { Situation::Two };
    let mut cfg = RunConfig::new(policy, draw(number, 4, u64::MAX), situation);
    cfg.max_rounds = MAX_ROUNDS;
    cfg.record_trajectories = false;
    cfg.measure_coverage = false;
    let delay = if chance(number, 5, 0.5) { draw(number, 6, MAX_LATENESS / 2) } else { 0 };
    let jitter = if chance(number, 7, 0.5) { draw(number, 8, MAX_LATENESS - delay) } else { 0 };
    let dup = if chance(number, 9, 0.3) { draw(number, 10, 1000) as f64 / 2000.0 } else { 0.0 };
    cfg.radio = Radio { loss: 0.0, delay, jitter, dup };
    cfg.faults = faults(number, robots);
    Case { number, robots, config: cfg }
}

/// Up to three crashes or freezes of distinct robots (never all of them),
/// and sometimes a slow robot, at random rounds and offsets.
fn faults(number: u64, robots: usize) -> Vec<Fault> {
    let mut out = Vec::new();
    let failing = draw(number, 20, 4).min(robots as u64 - 1);
    let mut taken: Vec<usize> = Vec::new();
    for i in 0..failing {
        let k = 100 + 10 * i;
        let mut robot = draw(number, k, robots as u64) as usize;
        while taken.contains(&robot) {
            robot = (robot + 1) % robots;
        }
        taken.push(robot);
        let round = draw(number, k + 1, 30) as u32;
        let offset = draw(number, k + 2, 1_500_000);
        let kind = if chance(number, k + 3, 0.5) { FaultKind::Crash } else { FaultKind::Freeze };
        out.push(Fault { robot, round, offset, kind });
        if kind == FaultKind::Freeze && chance(number, k + 4, 0.7) {
            let wake = round + 1 + draw(number, k + 5, 8) as u32;
            out.push(Fault { robot, round: wake, offset: draw(number, k + 6, 1_500_000), kind: FaultKind::Thaw });
        }
    }
    if chance(number, 30, 0.3) {
        let robot = draw(number, 31, robots as u64) as usize;
        let round = draw(number, 32, 20) as u32;
        let late = 1000 * (1 + draw(number, 33, 800));
        out.push(Fault { robot, round, offset: draw(number, 34, 1_000_000), kind: FaultKind::Slow(late) });
        if chance(number, 35, 0.5) {
            out.push(Fault {
                robot,
                round: round + 1 + draw(number, 36, 10) as u32,
                offset: 0,
                kind: FaultKind::Slow(0),
            });
        }
    }
    out
}

impl Case {
    /// The `gridswarm simulate` command that replays this case.
    pub fn command(&self) -> String {
        let c = &self.config;
        let mut cmd = format!(
            "cargo run --release --bin gridswarm -- simulate --scenario {SCENARIO} --robots {} --algorithm {} --seed {} --situation {} --max-rounds {}",
            self.robots,
            c.policy.name(),
            c.seed,
            c.situation.number(),
            c.max_rounds
        );
        let r = &c.radio;
        if r.delay > 0 || r.jitter > 0 {
            cmd += &format!(" --delay {}:{}", r.delay as f64 / 1000.0, r.jitter as f64 / 1000.0);
        }
        if r.dup > 0.0 {
            cmd += &format!(" --dup {}", r.dup);
        }
        for a in schedule::to_args(&c.faults) {
            cmd += " ";
            cmd += &a;
        }
        cmd
    }
}

/// What a finished case broke, if anything.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Violation {
    /// Safety, slot liveness or failure detection: must never happen.
    Broken(String),
    /// The search did not end within [`MAX_ROUNDS`]. The algorithms are
    /// random walks over visited vertices once the vertices they know of
    /// are visited or out of reach: survivors that never met the bodies
    /// walling off the last unvisited vertices can wander (rule (2) pairs
    /// ping-pong, and `escape` robots can block each other's first step).
    /// Counted and bounded by the test, not forbidden.
    Endless,
}

/// What must hold of a finished case.
pub fn check(r: &RunResult, suspect_rounds: u32) -> Result<(), Violation> {
    let p = &r.protocol;
    let broken = |s: String| Err(Violation::Broken(s));
    if r.collisions > 0 {
        return broken(format!("{} collision(s)", r.collisions));
    }
    if p.refused > 0 {
        return broken(format!("{} refused move(s)", p.refused));
    }
    if p.forced_slots > 0 {
        return broken(format!("{} slot(s) closed at their limit", p.forced_slots));
    }
    for f in &p.failures {
        if !f.unaware.is_empty() {
            return broken(format!(
                "robots {:?} waited on failed robot {} and had not declared it {} rounds later",
                f.unaware,
                f.robot,
                suspect_rounds + 1
            ));
        }
    }
    if p.ended_by == "max_rounds" {
        return Err(Violation::Endless);
    }
    Ok(())
}
