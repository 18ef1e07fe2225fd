//! The work budget of `simulate` (issue 11 item 1): without `--max-rounds`,
//! a big map or a big team gets a round limit lowered to fit
//! `MAX_SEARCH_WORK`, ends incomplete at it with exit status 3 and says
//! which limit stopped it and how to raise it; `--max-rounds` goes past it.
//! The rounds reached are asserted, not the wall time.

use std::process::Output;

use gridswarm::scenario::limits::{DEFAULT_MAX_ROUNDS, MAX_SEARCH_WORK};

mod common;
use common::{gridswarm, scratch, text};

/// The JSON summary of a run that ended incomplete (exit status 3).
fn incomplete(o: &Output) -> serde_json::Value {
    assert_eq!(o.status.code(), Some(3), "stdout:\n{}\nstderr:\n{}", text(&o.stdout), text(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("one JSON object")
}

/// A run cut by the budget: its own limit, below the default, reached.
fn assert_cut_by_budget(o: &Output) -> u64 {
    let s = incomplete(o);
    let limit = s["max_rounds"].as_u64().expect("max_rounds");
    assert!(limit >= 1 && limit < DEFAULT_MAX_ROUNDS as u64, "{s}");
    assert_eq!(s["rounds"].as_u64(), Some(limit), "{s}");
    assert_eq!(s["ended_by"], "max_rounds", "{s}");
    let err = text(&o.stderr);
    let note = format!(
        "note: stopped at the round limit {limit} set by the work budget MAX_SEARCH_WORK = {MAX_SEARCH_WORK:e}"
    );
    assert!(err.contains(&note), "{err}");
    assert!(err.contains("--max-rounds N"), "{err}");
    limit
}

#[test]
fn three_robots_on_the_biggest_random_map_stop_at_the_budget() {
    // On main this ran the whole 100,000 rounds.
    let o = gridswarm(&["simulate", "--scenario", "random:1,size=400x400", "--robots", "3", "--json"]);
    let limit = assert_cut_by_budget(&o);
    assert!(limit > 10_000, "a sparse team keeps a useful search: {limit}");
}

#[test]
fn ten_thousand_robots_stop_at_the_budget_after_a_few_rounds() {
    // 0.4 s of CPU a round on main, for 100,000 rounds.
    let o = gridswarm(&["simulate", "--scenario", "random:1,size=180x180", "--robots", "10000", "--json"]);
    let limit = assert_cut_by_budget(&o);
    assert!(limit < 10, "{limit}");
}

#[test]
fn the_command_line_may_ask_for_more_than_the_budget() {
    let args = ["simulate", "--scenario", "random:1,size=180x180", "--robots", "2000", "--json"];
    let limit = assert_cut_by_budget(&gridswarm(&args));
    let more = (limit + 2).to_string();
    let o = gridswarm(&[&args[..], &["--max-rounds", &more]].concat());
    let s = incomplete(&o);
    assert_eq!(s["rounds"].as_u64(), Some(limit + 2), "{s}");
    assert_eq!(s["max_rounds"].as_u64(), Some(limit + 2), "{s}");
    assert!(!text(&o.stderr).contains("MAX_SEARCH_WORK"), "{}", text(&o.stderr));
}

#[test]
fn the_paper_map_keeps_the_whole_default() {
    // Fig. 7's largest team: the budget must not touch it.
    let o = gridswarm(&["simulate", "--robots", "13", "--json"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(s["max_rounds"].as_u64(), Some(DEFAULT_MAX_ROUNDS as u64), "{s}");
    assert!(!text(&o.stderr).contains("MAX_SEARCH_WORK"));
}

#[test]
fn a_team_whose_one_round_passes_the_budget_is_refused_before_it_runs() {
    // 2,000 robots all in one radio range: 23 s for one round on main.
    let file = std::env::temp_dir().join(format!("budget-one-range-{}.toml", std::process::id()));
    let toml = "name = \"one range\"\nrobots = 2000\nsituation = 2\ngrid = \"triangular\"\n\
                [params]\na = 1.0\nr_rob = 0.25\nr_safe = 0.30\nr_c = 300.0\n\
                [area]\npolygon = [[0, 0], [100, 0], [100, 100], [0, 100]]\n\
                [starts]\nborder = { from = [0, 0] }\n";
    std::fs::write(&file, toml).unwrap();
    let o = gridswarm(&["simulate", "--scenario", file.to_str().unwrap(), "--json"]);
    let _ = std::fs::remove_file(&file);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(err.contains("above the work budget MAX_SEARCH_WORK") && err.contains("--max-rounds N"), "{err}");
}

#[test]
fn every_rule_of_a_big_team_stops_at_the_budget() {
    // LFP looks at every pair of robots each micro-step: on main it had the
    // grid's 5 rounds (9 s of CPU); escape and frontier kept each robot's
    // search space (14 and 6.7 GB on main) and now share it.
    for (rule, most) in [("lfp", 2), ("escape", 9), ("frontier", 9)] {
        let o = gridswarm(&[
            "simulate",
            "--scenario",
            "random:1,size=180x180",
            "--robots",
            "10000",
            "--algorithm",
            rule,
            "--json",
        ]);
        let limit = assert_cut_by_budget(&o);
        assert!(limit <= most, "{rule}: {limit}");
    }
}

/// Issue 23: `large` with `r_c = 1000`, where every one of its 50 robots
/// hears every other. On a perfect radio the budget grants 1,493 rounds
/// (3.1 s of CPU measured, 2.8 s predicted); an impaired radio made the
/// same rounds up to 8 times dearer (25 s at `--dup 0.5`), and now counts
/// for it: the rounds granted fall by `IMPAIRED_FRAME_WORK x (1 + dup)`
/// on the frames' share.
#[test]
fn a_radio_heard_by_everyone_is_budgeted_and_an_impaired_one_dearer() {
    use gridswarm::scenario::limits::{frame_factor, hearable, round_limit, round_work};
    let large =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/scenarios/large.toml")).unwrap();
    let wide = large.replacen("[params]\n", "[params]\nr_c = 1000\n", 1);
    assert_ne!(wide, large, "large.toml has a [params] table");
    let dir = scratch("radio_range");
    let file = dir.join("large-rc1000.toml");
    std::fs::write(&file, wide).unwrap();
    let path = file.to_str().unwrap();
    let perfect = assert_cut_by_budget(&gridswarm(&["simulate", "--scenario", path, "--json"]));
    let dup = assert_cut_by_budget(&gridswarm(&["simulate", "--scenario", path, "--dup", "0.5", "--json"]));
    // What the budget predicts, from the same counts.
    let world = gridswarm::scenario::Scenario::load(path).unwrap().world();
    let heard = hearable(50, 1000.0, 1.0, world.grid.lattice.kind);
    let rounds = |f| round_limit(round_work(50, world.grid.len() as f64, heard, f)).unwrap() as u64;
    assert_eq!(perfect, rounds(1.0));
    assert_eq!(dup, rounds(frame_factor(false, 0.5)));
    assert!((1000..2000).contains(&perfect) && dup * 6 < perfect, "{perfect} {dup}");
    std::fs::remove_dir_all(&dir).unwrap();
}
