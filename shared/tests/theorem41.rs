//! Theorem 4.1 against rule (2) as the text reads it (docs/paper.md,
//! "Theorem 4.1: a counter-example"). With every robot in radio range of
//! every other, `p_ave` moves with the team, and the farthest visited
//! candidate from it can be the vertex a robot just left: once no robot
//! has an unvisited candidate the team shuttles between two vertices each
//! and the search never ends. The proof assumes robots "randomly choose"
//! among visited neighbours; `visited_choice = "random-biased"` does, and
//! ends.

use gridswarm::engine;
use gridswarm::outcome::{RunConfig, RunResult};
use gridswarm::params::{Situation, VisitedChoice};
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;

const ROBOTS: usize = 9;
const SEED: u64 = 11;
/// Five times what the search takes at `r_c = 5` (about 50 rounds).
const ROUNDS: u32 = 250;

/// `paper` with `r_c = 30` (every robot in range of every other; `check`
/// passes every assumption), 9 robots of rule (2), situation 1.
fn run(visited_choice: VisitedChoice) -> RunResult {
    let mut s = Scenario::builtin("paper").unwrap();
    s.params.r_c = 30.0;
    s.params.visited_choice = visited_choice;
    let world = s.world();
    let starts = s.start_vertices(&world, ROBOTS).unwrap();
    let mut cfg = RunConfig::new(Policy::Repulsive, SEED, Situation::One);
    cfg.max_rounds = ROUNDS;
    cfg.measure_coverage = false;
    engine::run(&world, &starts, &cfg)
}

#[test]
fn rule_two_as_written_shuttles_for_ever_in_radio_range() {
    let r = run(VisitedChoice::Farthest);
    let replay = format!(
        "replay: gridswarm experiment --set r_c=30 --algorithms repulsive --robots {ROBOTS} --runs 100 --seed 11 --max-rounds 2000"
    );
    assert!(!r.complete && r.rounds == ROUNDS, "ended after {} rounds; {replay}", r.rounds);
    assert!(r.targets_found < r.targets_total, "{replay}");
    // Over the last 100 rounds the team repeats itself every 4 rounds,
    // every robot moving every round: most between two vertices.
    let at = |k: usize, t: usize| r.trajectories[k][t].vertex.unwrap();
    let end = r.rounds as usize;
    let mut shuttles = 0;
    for k in 0..ROBOTS {
        for t in end - 100..=end {
            assert_eq!(at(k, t), at(k, t - 4), "robot {k} left its cycle at round {t}; {replay}");
            assert_ne!(at(k, t), at(k, t - 1), "robot {k} stood still at round {t}; {replay}");
        }
        let mut seen: Vec<_> = (end - 4..end).map(|t| at(k, t)).collect();
        seen.sort_by_key(|c| (c.i, c.j));
        seen.dedup();
        shuttles += usize::from(seen.len() == 2);
    }
    assert!(shuttles >= ROBOTS - 2, "{shuttles} robots shuttle between two vertices; {replay}");
}

#[test]
fn the_proofs_random_choice_among_visited_vertices_ends_the_same_search() {
    let r = run(VisitedChoice::Uniform);
    assert!(r.complete, "not done in {ROUNDS} rounds");
    assert_eq!(r.targets_found, r.targets_total);
}
