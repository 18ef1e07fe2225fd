//! A choice rule of one's own, in one file, run by both engines.
//!
//! `sweep` sends each robot to the adjacent unvisited vertex lowest on the
//! map (then leftmost), and, when there is none, to a random visited one.
//! The decision core still does sensing, maps, the priority order and
//! collision avoidance: the rule only picks one of the candidates it gets.
//!
//! ```text
//! # in-process, like `gridswarm simulate` (same flags, same files):
//! my_rule simulate --scenario paper --robots 5 --seed 3 --out sim-dir
//! # one process per robot: this program is the robots' agent
//! gridswarm run --agent-bin target/release/examples/my_rule --algorithm sweep --robots 5 --seed 3 --out run-dir
//! ```
//! Both write the same trajectories (tests/tests/custom_rule.rs checks it).

use std::process::ExitCode;

use gridswarm_orchestrator::faults::FaultPlan;
use gridswarm_orchestrator::simulate::{simulate, SimulateOptions};
use gridswarm_robot::choice::{self, ChoiceRule, Factory, RuleRng, View};
use gridswarm_robot::grid::VertexId;

struct Sweep;

impl ChoiceRule for Sweep {
    fn choose(&mut self, view: &View<'_>, rng: &mut RuleRng) -> Option<VertexId> {
        let (unvisited, visited) = view.split();
        let low = |v: &VertexId| {
            let p = view.grid.position(*v);
            (p.y, p.x)
        };
        match unvisited.iter().min_by(|a, b| low(a).partial_cmp(&low(b)).unwrap_or(std::cmp::Ordering::Equal)) {
            Some(&v) => Some(v),
            None => choice::uniform(rng, &visited),
        }
    }
}

const RULES: &[(&str, Factory)] = &[("sweep", || Box::new(Sweep))];

/// `simulate [--scenario S] [--robots N] [--seed K] [--out DIR]`: one
/// in-process run of `sweep`, its summary on stdout.
fn simulate_here(args: &[String]) -> Result<String, String> {
    let mut opts = SimulateOptions {
        scenario: "paper".into(),
        algorithm: "sweep".parse()?,
        robots: None,
        seed: 1,
        situation: None,
        out: None,
        json: true,
        max_rounds: None,
        faults: FaultPlan::default(),
        view: Default::default(),
    };
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let value = it.next().ok_or_else(|| format!("{flag} needs a value"))?;
        let bad = |e: std::num::ParseIntError| format!("{flag}: {e}");
        match flag.as_str() {
            "--scenario" => opts.scenario = value.clone(),
            "--robots" => opts.robots = Some(value.parse().map_err(bad)?),
            "--seed" => opts.seed = value.parse().map_err(bad)?,
            "--out" => opts.out = Some(value.into()),
            _ => return Err(format!("unknown flag {flag}")),
        }
    }
    simulate(&opts).map(|(text, _complete)| text).map_err(|e| e.to_string())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) != Some("simulate") {
        // Started by `gridswarm run --agent-bin` (or asked --list-rules).
        return robot_agent::main_with(RULES);
    }
    for &(name, factory) in RULES {
        if let Err(e) = choice::register(name, factory) {
            eprintln!("error: {e}");
            return ExitCode::from(2);
        }
    }
    match simulate_here(&args[1..]) {
        Ok(text) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
