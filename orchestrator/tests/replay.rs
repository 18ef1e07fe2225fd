//! The run directory (`world.json`, `rounds.csv`, `replay.html`), the
//! series the replay page shows, `gridswarm replay DIR` and its errors, and
//! the experiments' `report.html`. The page itself is tested in a real
//! browser in `browser.rs`.

use std::fs;
use std::path::Path;
use std::process::Output;

use gridswarm::outcome::RunConfig;
use gridswarm::params::{RuCollisions, Situation};
use gridswarm::policy::Policy;
use gridswarm::scenario::Scenario;
use gridswarm_orchestrator::contract::Runner;
use gridswarm_orchestrator::replay::{self, Recorded};
use gridswarm_orchestrator::rundir::{self, RunRecord};
use serde_json::{json, Value};

mod common;
use common::{assert_ok, gridswarm, scratch, text};

/// Non-zero exit, exactly one `error:` line that mentions `needle`, no panic.
fn assert_clean_error(o: &Output, needle: &str) {
    let err = text(&o.stderr);
    assert!(!o.status.success(), "succeeded: {}", text(&o.stdout));
    assert!(!err.contains("panicked"), "panic: {err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(lines[0].starts_with("error: ") && lines[0].contains(needle), "{err}");
}

/// Runs `policy` on the paper scenario in-process and writes its directory.
fn run_dir(
    dir: &Path,
    policy: Policy,
    robots: usize,
    seed: u64,
    situation: Situation,
) -> gridswarm::outcome::RunResult {
    let mut scenario = Scenario::builtin("paper").unwrap();
    scenario.situation = situation;
    let world = scenario.world();
    let starts = scenario.start_vertices(&world, robots).unwrap();
    let mut cfg = RunConfig::new(policy, seed, situation);
    cfg.max_rounds = 5000;
    let result = Runner::new(&world, scenario.lfp).run(&starts, &cfg);
    let record = RunRecord {
        scenario: &scenario,
        world: &world,
        starts: &starts,
        lfp: &scenario.lfp,
        result: &result,
        extra: json!({ "max_rounds": 5000 }),
    };
    let written = rundir::write_run_dir(dir, &record).unwrap();
    let names: Vec<String> = written.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
    assert_eq!(
        names,
        ["summary.json", "trajectories.jsonl", "routes.svg", "world.json", "rounds.csv", "replay.html"],
        "{names:?}"
    );
    result
}

#[test]
fn series_agree_with_the_engine() {
    let d = scratch("series");
    // RU collides (the series must count what the referee counted); the
    // others stay collision-free; situation 2 runs until Va is covered.
    for (k, (policy, situation)) in [
        (Policy::Ru, Situation::One),
        (Policy::Repulsive, Situation::Two),
        (Policy::Sequential, Situation::One),
        (Policy::Lfp, Situation::One),
    ]
    .into_iter()
    .enumerate()
    {
        let dir = d.join(format!("{k}"));
        let result = run_dir(&dir, policy, 6, 3 + k as u64, situation);
        let rec = Recorded::load(&dir).unwrap();
        let s = replay::series(&rec);
        let rounds = result.rounds as usize;
        assert_eq!(rec.rounds(), rounds);
        assert_eq!(s.time_s.len(), rounds + 1);
        assert!(s.time_exact);
        assert_eq!(s.time_s[0], 0.0);
        // The clock is the engine's, slot by slot; the search ends inside
        // the last slot (at the stop that ends it), or at its end.
        assert!((s.time_s[rounds] - result.round_end_times_s[rounds - 1]).abs() < 1e-6, "{policy:?}");
        let t = result.search_time_s;
        assert!(s.time_s[rounds - 1] <= t + 1e-6 && t <= s.time_s[rounds] + 1e-6, "{policy:?}: {t}");
        assert!(s.time_s.windows(2).all(|w| w[1] >= w[0]));
        assert_eq!(*s.found.last().unwrap() as usize, result.targets_found, "{policy:?}");
        assert!(s.found.windows(2).all(|w| w[1] >= w[0]));
        assert!(s.detected.windows(2).all(|w| w[1] >= w[0]));
        let coverage = result.coverage.unwrap();
        let last = *s.detected.last().unwrap();
        if policy == Policy::Lfp {
            // Poses are written to 6 decimals; the raster may differ by a sample or so.
            assert!((last - coverage).abs() < 1e-3, "{last} vs {coverage}");
            // The engine tests the bent path's sub-steps, the replay the
            // round's straight net motion: either may see a pair the other
            // misses (seed 6 with isotropic turning: replay 1, engine 0).
            assert!(
                s.collisions.len().abs_diff(result.collisions as usize) <= 2,
                "{} vs {}",
                s.collisions.len(),
                result.collisions
            );
        } else if policy == Policy::Ru {
            assert_eq!(last, coverage, "{policy:?}");
            // Under back-off robots that collide back off and the poses show
            // only the collisions of robots that got through; per pair
            // stacked robots are charged again unseen; per event (the
            // default) the poses show every collision counted.
            assert!(
                s.collisions.len() as u32 <= result.collisions,
                "{} > {}: {:?}",
                s.collisions.len(),
                result.collisions,
                &s.collisions[..s.collisions.len().min(5)]
            );
        } else {
            assert_eq!(last, coverage, "{policy:?}");
            assert_eq!(s.collisions.len() as u32, result.collisions, "{policy:?}");
        }
        if policy == Policy::Ru {
            assert!(result.collisions > 0, "this seed of RU should collide");
        }
        assert!(s.collisions.iter().all(|&(k, i, j)| k < rounds && i < j && j < 6));
        // rounds.csv carries the engine's count of every round, which the
        // page counts: back-off collisions included.
        let counts = rec.round_collisions.clone().expect("rounds.csv has the collisions column");
        assert_eq!(counts.len(), rounds);
        assert_eq!(counts.iter().sum::<u32>(), result.collisions, "{policy:?}");
        assert_eq!(replay::data(&rec)["collision_counts"], json!(counts));
        let reading = gridswarm::params::Params::default().ru_collisions;
        if policy == Policy::Ru && reading == RuCollisions::PerEvent {
            assert_eq!(s.collisions.len() as u32, result.collisions, "every event is on the poses");
        }
        let backs_off = reading == RuCollisions::BackOff;
        if policy == Policy::Ru && backs_off {
            assert!(
                s.collisions.len() < result.collisions as usize,
                "this seed should back off unseen: {} marks",
                s.collisions.len()
            );
        }
    }
}

#[test]
fn page_is_self_contained_and_carries_the_data() {
    let d = scratch("page");
    let result = run_dir(&d, Policy::Repulsive, 4, 1, Situation::One);
    let html = fs::read_to_string(d.join("replay.html")).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>"));
    for forbidden in ["http://", "https://", "<link", "src=", "@import", "url("] {
        // The SVG namespace is the one URL allowed, and only the report has SVG.
        assert!(!html.contains(forbidden), "the page refers to something outside it: {forbidden}");
    }
    assert!(html.contains("id=\"replay-state\"") && html.contains("<canvas id=\"view\""));
    let start = html.find("<script id=\"replay-data\" type=\"application/json\">").unwrap();
    let body = &html[start..];
    let json_text = &body[body.find('>').unwrap() + 1..body.find("</script>").unwrap()];
    let data: Value = serde_json::from_str(json_text).unwrap();
    assert_eq!(data["meta"]["robots"], 4);
    assert_eq!(data["meta"]["rounds"], result.rounds);
    assert_eq!(data["traj"]["mode"], "v");
    assert_eq!(data["traj"]["lens"].as_array().unwrap().len(), 4);
    assert_eq!(data["series"]["detected"].as_array().unwrap().len(), result.rounds as usize + 1);
    // Rewriting from the files gives the same page.
    let o = gridswarm(&["replay", d.to_str().unwrap()]);
    assert_ok(&o);
    assert_eq!(text(&o.stdout).trim(), d.join("replay.html").display().to_string());
    assert_eq!(fs::read_to_string(d.join("replay.html")).unwrap(), html);
}

#[test]
fn simulate_out_writes_the_world_and_the_page() {
    let d = scratch("simulate");
    let o = gridswarm(&["simulate", "--robots", "3", "--seed", "4", "--out", d.to_str().unwrap()]);
    assert_ok(&o);
    for f in ["summary.json", "trajectories.jsonl", "routes.svg", "world.json", "rounds.csv", "replay.html"] {
        assert!(d.join(f).is_file(), "{f} missing");
        assert!(text(&o.stdout).contains(f), "{f} not reported");
    }
    let w: Value = serde_json::from_str(&fs::read_to_string(d.join("world.json")).unwrap()).unwrap();
    assert_eq!(w["format"], "gridswarm-world 1");
    assert_eq!(w["scenario"], "paper");
    assert_eq!(w["starts"].as_array().unwrap().len(), 3);
    let s: Value = serde_json::from_str(&fs::read_to_string(d.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["max_rounds"], 100000);
    assert_eq!(s["starts"], w["starts"]);
    let rounds = s["rounds"].as_u64().unwrap() as usize;
    assert_eq!(fs::read_to_string(d.join("rounds.csv")).unwrap().lines().count(), rounds + 1);
}

#[test]
fn replay_errors_name_the_file() {
    let d = scratch("errors");
    let missing = d.join("nothing-here");
    assert_clean_error(&gridswarm(&["replay", missing.to_str().unwrap()]), "not a directory");

    let run = d.join("run");
    assert_ok(&gridswarm(&["simulate", "--robots", "2", "--out", run.to_str().unwrap()]));
    let copy = |name: &str| {
        let c = d.join(name);
        fs::create_dir_all(&c).unwrap();
        for f in ["world.json", "trajectories.jsonl", "summary.json", "rounds.csv"] {
            fs::copy(run.join(f), c.join(f)).unwrap();
        }
        c
    };

    let c = copy("no-world");
    fs::remove_file(c.join("world.json")).unwrap();
    assert_clean_error(&gridswarm(&["replay", c.to_str().unwrap()]), "world.json`: no such file");

    let c = copy("bad-world");
    fs::write(c.join("world.json"), "{ \"format\": 1 }").unwrap();
    assert_clean_error(&gridswarm(&["replay", c.to_str().unwrap()]), "world.json`: not a gridswarm world file");

    let c = copy("bad-line");
    let t = fs::read_to_string(c.join("trajectories.jsonl")).unwrap();
    let mut lines: Vec<&str> = t.lines().collect();
    lines[2] = "{\"round\":1,\"robot\":0,oops}";
    fs::write(c.join("trajectories.jsonl"), lines.join("\n")).unwrap();
    assert_clean_error(&gridswarm(&["replay", c.to_str().unwrap()]), "trajectories.jsonl`: line 3:");

    let c = copy("gap");
    let t = fs::read_to_string(c.join("trajectories.jsonl")).unwrap();
    let kept: Vec<&str> = t.lines().enumerate().filter(|(n, _)| *n != 2).map(|(_, l)| l).collect();
    fs::write(c.join("trajectories.jsonl"), kept.join("\n")).unwrap();
    assert_clean_error(&gridswarm(&["replay", c.to_str().unwrap()]), "robot 0 round 2 follows round 0");

    let c = copy("bad-summary");
    fs::write(c.join("summary.json"), "[1,").unwrap();
    assert_clean_error(&gridswarm(&["replay", c.to_str().unwrap()]), "summary.json`: not JSON");

    let c = copy("bad-failures");
    let mut s: Value = serde_json::from_str(&fs::read_to_string(c.join("summary.json")).unwrap()).unwrap();
    s["failures_detected"] = json!([{ "robot": 9, "round": 1 }]);
    fs::write(c.join("summary.json"), s.to_string()).unwrap();
    assert_clean_error(&gridswarm(&["replay", c.to_str().unwrap()]), "failures_detected: robot 9");

    let c = copy("short-rounds");
    fs::write(c.join("rounds.csv"), "round,end_time_s\n0,1.0\n").unwrap();
    assert_clean_error(&gridswarm(&["replay", c.to_str().unwrap()]), "rounds.csv`: 1 rounds, but");

    // Without rounds.csv the clock is spread evenly: still a page.
    let c = copy("no-rounds");
    fs::remove_file(c.join("rounds.csv")).unwrap();
    assert_ok(&gridswarm(&["replay", c.to_str().unwrap()]));
    let rec = Recorded::load(&c).unwrap();
    assert!(!replay::series(&rec).time_exact);
}

#[test]
fn failures_and_refused_moves_are_read_from_the_summary() {
    let d = scratch("events");
    run_dir(&d, Policy::Repulsive, 3, 2, Situation::One);
    let path = d.join("summary.json");
    let mut s: Value = serde_json::from_str(&fs::read_to_string(&path).unwrap()).unwrap();
    // As the distributed engine writes them (gridswarm::ipc::Detection).
    s["failures_detected"] = json!([{ "robot": 1, "round": 4, "at": [1, 1], "cause": "death",
                                       "detected_by": [0, 2], "at_ms": 12.5 }]);
    s["refused_moves"] = json!([{ "robot": 2, "round": 3 }]);
    fs::write(&path, s.to_string()).unwrap();
    let rec = Recorded::load(&d).unwrap();
    assert_eq!(rec.failures.len(), 1);
    assert_eq!((rec.failures[0].robot, rec.failures[0].round), (1, 4));
    assert_eq!(rec.refused.len(), 1);
    assert_eq!(rec.refused_total, Some(1));
    // A bare count is a total, with nothing to mark.
    s["refused_moves"] = json!(7);
    fs::write(&path, s.to_string()).unwrap();
    let rec = Recorded::load(&d).unwrap();
    assert!(rec.refused.is_empty());
    assert_eq!(rec.refused_total, Some(7));
    let data = replay::data(&rec);
    assert_eq!(data["failures"], json!([1, 4]));
    assert_eq!(data["refused_total"], 7);
}

#[test]
fn simulated_failures_are_marked_from_their_declaration() {
    let d = scratch("simulated-failures");
    let o = gridswarm(&["simulate", "--robots", "6", "--seed", "3", "--kill", "2@4+0.3", "--out", d.to_str().unwrap()]);
    assert_ok(&o);
    let s: Value = serde_json::from_str(&fs::read_to_string(d.join("summary.json")).unwrap()).unwrap();
    let declared = s["failures"][0]["detected_round"].as_u64().expect("the crash is declared") as u32;
    assert!(s.get("failures_detected").is_none());
    let rec = Recorded::load(&d).unwrap();
    assert_eq!(rec.failures.len(), 1);
    assert_eq!((rec.failures[0].robot, rec.failures[0].round), (2, declared));
    assert_eq!(rec.refused_total, Some(0));
}

#[test]
fn experiment_writes_a_report_and_is_quiet_in_a_pipe() {
    let d = scratch("experiment");
    let o = gridswarm(&["experiment", "--runs", "3", "--robots", "1-2", "--out", d.to_str().unwrap()]);
    assert_ok(&o);
    // stderr is a pipe here: no progress bar, progress lines instead.
    let err = text(&o.stderr);
    assert!(!err.contains("eta"), "{err}");
    assert!(err.lines().count() >= 1 && err.lines().all(|l| l.starts_with("progress: ")), "{err}");
    assert!(text(&o.stdout).contains("report.html"));
    let html = fs::read_to_string(d.join("report.html")).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>") && html.trim_end().ends_with("</html>"));
    assert!(html.contains("<svg") && html.contains("</svg>"), "the figure is inlined");
    assert!(html.contains("<table>") && html.contains("</table>"));
    for needle in ["Claim (a)", "Claim (b)", "Claim (c)", "params.r_c", "lfp.beta", "seed_derivation"] {
        assert!(html.contains(needle), "{needle} missing");
    }
    // 4 algorithms x 2 robot counts, then the sensitivity to the readings:
    // RU's two other collision charges, LFP's two other turning laws
    // (uniform, sigma 0.5) and other repulsion range x 2 robot counts.
    assert_eq!(html.matches("<tr><td>").count(), 8 + 5 * 2);
    assert!(html.contains("Sensitivity to the readings"));
    assert!(!html.contains("<script"));
    assert!(!html.replace("http://www.w3.org/2000/svg", "").contains("http"), "only the SVG namespace is a URL");
    // Balanced sections: a cheap check that the page is well formed.
    for tag in ["section", "table", "figure", "svg", "div"] {
        assert_eq!(html.matches(&format!("<{tag}")).count(), html.matches(&format!("</{tag}>")).count(), "{tag}");
    }
}

#[test]
fn grids_writes_its_report() {
    let d = scratch("grids");
    let o = gridswarm(&["experiment", "--grids", "--out", d.to_str().unwrap()]);
    assert_ok(&o);
    let html = fs::read_to_string(d.join("grids.html")).unwrap();
    for needle in ["<table>", "triangular", "square", "hexagonal", "detected fraction"] {
        assert!(html.contains(needle), "{needle} missing");
    }
}
