//! `gridswarm experiment failures` and `gridswarm experiment scale` (issue
//! "See what the robots did"): small runs of the real binaries, one process
//! per robot, inside the CI budget. Their files exist and parse; bad input
//! is one `error:` line.

use std::fs;
use std::path::Path;
use std::process::Output;

use gridswarm_e2e::*;

fn run(args: &[&str]) -> Output {
    gridswarm().args(args).output().expect("gridswarm runs")
}

/// CSV rows as header name -> cell maps.
fn csv_rows(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().expect("a header").split(',').map(String::from).collect();
    let rows: Vec<Vec<String>> = lines.map(|l| l.split(',').map(String::from).collect()).collect();
    for r in &rows {
        assert_eq!(r.len(), header.len(), "row {r:?} against header {header:?}");
    }
    (header, rows)
}

fn cell<'a>(header: &[String], row: &'a [String], name: &str) -> &'a str {
    let k = header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name} in {header:?}"));
    &row[k]
}

fn num(header: &[String], row: &[String], name: &str) -> f64 {
    let c = cell(header, row, name);
    c.parse().unwrap_or_else(|_| panic!("{name} = `{c}` is not a number"))
}

fn assert_svg(path: &Path, labels: &[&str]) {
    let svg = fs::read_to_string(path).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap_or_else(|e| panic!("{}: not XML: {e}", path.display()));
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    let texts: Vec<&str> = doc.descendants().filter(|n| n.has_tag_name("text")).filter_map(|n| n.text()).collect();
    for l in labels {
        assert!(texts.iter().any(|t| t.contains(l)), "{l} missing from {}: {texts:?}", path.display());
    }
}

fn assert_report(path: &Path, words: &[&str]) {
    let html = fs::read_to_string(path).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>"));
    assert!(html.trim_end().ends_with("</html>"));
    assert!(html.contains("<svg"), "the figure is inlined");
    assert!(html.contains("<table>"));
    assert!(!html.contains("<script"), "no script");
    assert!(!html.contains("<?xml"));
    for w in words {
        assert!(html.contains(w), "{w} missing from {}", path.display());
    }
}

/// The columns of `failures-runs.csv` that depend on the seed only, not on timing.
fn deterministic_runs(path: &Path) -> Vec<String> {
    let (h, rows) = csv_rows(path);
    rows.iter()
        .map(|r| {
            ["survivor_step", "killed", "run", "seed", "complete", "rounds", "collisions", "failures_injected"]
                .map(|c| cell(&h, r, c).to_string())
                .join(",")
        })
        .collect()
}

#[test]
fn a_small_failures_experiment() {
    let _s = serial();
    let dir = scratch("failures");
    let out = dir.join("a");
    let args = [
        "experiment",
        "failures",
        "--robots",
        "5",
        "--killed",
        "0-1",
        "--runs",
        "2",
        "--seed",
        "3",
        "--engine",
        "distributed",
    ];
    let o = run(&[&args[..], &["--out", out.to_str().unwrap()]].concat());
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_only_progress(&text(&o.stderr), "in a pipe: progress lines, no run output");
    let stdout = text(&o.stdout);
    assert!(stdout.contains("engine distributed") && stdout.contains("detected"), "{stdout}");

    let (h, rows) = csv_rows(&out.join("failures.csv"));
    // The paper's rules, then the survivor step, each at 0 and 1 killed.
    assert_eq!(rows.len(), 4);
    for (i, r) in rows.iter().enumerate() {
        let k = i % 2;
        assert_eq!(cell(&h, r, "survivor_step"), ["off", "on"][i / 2]);
        assert_eq!(num(&h, r, "killed"), k as f64);
        assert_eq!(num(&h, r, "runs"), 2.0);
        assert_eq!(num(&h, r, "completion_rate"), 1.0);
        assert_eq!(num(&h, r, "collisions"), 0.0);
        assert!(num(&h, r, "mean_search_time_s") > 0.0);
        // Robots declare a dead robot only if one of them expected to hear
        // it again (the world no longer tells): some kills go undeclared.
        assert!(num(&h, r, "failures_detected") <= num(&h, r, "failures_injected"));
        assert_eq!(num(&h, r, "failures_injected"), k as f64 * 2.0, "one kill per run, each applied");
    }
    assert_eq!(cell(&h, &rows[0], "mean_detection_delay_s"), "", "nothing killed, no delay");
    if num(&h, &rows[1], "failures_detected") > 0.0 {
        assert!(num(&h, &rows[1], "mean_detection_delay_rounds") >= 0.0);
        assert!(num(&h, &rows[1], "mean_detection_delay_s") > 0.0);
    }
    assert_eq!(csv_rows(&out.join("failures-runs.csv")).1.len(), 8);
    // The paper's rules ran on the scenario written beside the results.
    assert!(out.join("scenario-survivor-step-off.toml").is_file());
    assert_svg(&out.join("failures.svg"), &["robots killed", "Search time", "Detection delay"]);
    assert_report(&out.join("report.html"), &["Failures: paper scenario, 5 robots", "failures.csv", "seed_derivation"]);

    // The same seed, the same runs (what depends on timing aside).
    let again = dir.join("b");
    let o = run(&[&args[..], &["--out", again.to_str().unwrap()]].concat());
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(
        deterministic_runs(&out.join("failures-runs.csv")),
        deterministic_runs(&again.join("failures-runs.csv"))
    );
}

#[test]
fn a_small_scale_experiment() {
    let _s = serial();
    let out = scratch("scale");
    let o = run(&["experiment", "scale", "--robots", "3,6", "--runs", "1", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_only_progress(&text(&o.stderr), "in a pipe: progress lines only");
    // It names the folder asked for, not the staging folder it wrote first.
    assert!(text(&o.stdout).contains(&format!("provenance.json in {}\n", out.display())), "{}", text(&o.stdout));
    let (h, rows) = csv_rows(&out.join("scale.csv"));
    assert_eq!(rows.len(), 2);
    for (r, n) in rows.iter().zip([3.0, 6.0]) {
        assert_eq!(num(&h, r, "robots"), n);
        assert_eq!(cell(&h, r, "scenario"), "paper");
        assert_eq!(num(&h, r, "completed_runs"), 1.0);
        for c in ["round_wall_p50_ms", "round_wall_p99_ms", "inproc_ms_per_round", "agent_peak_rss_max_kib"] {
            assert!(num(&h, r, c) > 0.0, "{c}");
        }
        assert!(num(&h, r, "round_wall_p99_ms") >= num(&h, r, "round_wall_p50_ms"));
        assert_eq!(cell(&h, r, "inproc_same_rounds"), "true", "the two engines run the same search");
    }
    assert_svg(&out.join("scale.svg"), &["robots", "Wall time per round", "Peak memory"]);
    assert_report(&out.join("report.html"), &["Scaling", "scale.csv", "in_process"]);
    // Each count's runs have the sweeps' round budget, 100 rounds a vertex
    // the team can reach, not the fixed 100,000 of a lone `run`.
    let p: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("provenance.json")).unwrap()).unwrap();
    let per_count = p["parameters"]["round_budget"]["per_count"].as_array().expect("a budget per count");
    assert_eq!(per_count.len(), 2, "{p}");
    for c in per_count {
        let (va, rounds) = (c["va"].as_u64().unwrap(), c["rounds"].as_u64().unwrap());
        assert!(va > 0 && rounds == 100 * va && rounds < 100_000, "{c}");
    }
    assert_eq!(p["parameters"]["max_rounds"], per_count[1]["rounds"], "{p}");
}

#[test]
fn bad_input_is_one_error() {
    let _s = serial();
    let out = scratch("bad");
    let o = out.to_str().unwrap();
    for args in [
        &["experiment", "failures", "--robots", "5", "--killed", "5", "--out", o][..],
        &["experiment", "failures", "--killed", "x", "--out", o],
        &["experiment", "failures", "--killed", "3-1", "--out", o],
        &["experiment", "failures", "--algorithm", "lfp", "--out", o],
        &["experiment", "failures", "--runs", "0", "--out", o],
        &["experiment", "failures", "--scenario", "no-such-scenario", "--out", o],
        &["experiment", "scale", "--robots", "0", "--out", o],
        &["experiment", "scale", "--scenario", "no-such-scenario", "--out", o],
        &["experiment", "--runs", "5", "failures"],
        &["experiment", "nonsense"],
    ] {
        let r = run(args);
        let err = text(&r.stderr);
        assert!(!r.status.success(), "{args:?} succeeded");
        // One line of ours, or clap's whole usage message (one error, its
        // suggestions and the pointer to --help).
        assert!(err.lines().count() == 1 || err.trim_end().ends_with("try '--help'."), "{args:?}: {err}");
        assert_eq!(err.matches("error: ").count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{args:?}: {err}");
        assert!(!err.contains("panicked"));
    }
    assert!(fs::read_dir(&out).unwrap().next().is_none(), "no files written on bad input");
}

/// Off a terminal an experiment's stderr holds its progress lines (one at
/// least, the last when it ends) and nothing else.
fn assert_only_progress(err: &str, what: &str) {
    assert!(err.lines().count() >= 1, "{what}: {err}");
    assert!(err.lines().all(|l| l.starts_with("progress: ")), "{what}: {err}");
}
