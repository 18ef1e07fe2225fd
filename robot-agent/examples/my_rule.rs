//! A choice rule of one's own, in one file: this program is the whole
//! `gridswarm` tool with the rule as one more algorithm, and the robots'
//! agent for `gridswarm run`.
//!
//! `sweep` sends each robot to the adjacent unvisited vertex lowest on the
//! map (then leftmost), and, when there is none, to a random visited one.
//! The decision core still does sensing, maps, the priority order and
//! collision avoidance: the rule only picks one of the candidates it gets.
//!
//! ```text
//! cargo build --release --workspace --examples
//! # every command of gridswarm, with `sweep` among the algorithms:
//! target/release/examples/my_rule simulate --scenario paper --algorithm sweep --robots 5 --seed 3 --out sim-dir
//! target/release/examples/my_rule experiment --algorithms sweep,sequential --robots 1-13 --runs 100
//! # one process per robot: this program is the robots' agent
//! # (GRIDSWARM_BIN_DIR: where world-server is, as this program is not beside it)
//! GRIDSWARM_BIN_DIR=target/release target/release/examples/my_rule run \
//!     --agent-bin target/release/examples/my_rule --algorithm sweep --robots 5 --seed 3 --out run-dir
//! ```
//! The in-process and distributed runs write the same trajectories
//! (tests/tests/custom_rule.rs checks it).

use std::process::ExitCode;

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

fn main() -> ExitCode {
    // The agent takes only flags (`--setup FILE ...`, `--list-rules`); the
    // tool starts with a command (`simulate`, `experiment`, ...).
    let first = std::env::args().nth(1).unwrap_or_default();
    let tool = !first.starts_with('-') || ["-h", "--help", "-V", "--version"].contains(&first.as_str());
    if tool {
        gridswarm_orchestrator::main_with(RULES)
    } else {
        robot_agent::main_with(RULES)
    }
}
