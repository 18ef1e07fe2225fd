//! Provenance and `gridswarm rerun`: every output folder says what made
//! it, and a rerun from that record alone (not from the scenario file,
//! which may have changed) repeats the deterministic outputs byte for byte,
//! or names the file that differs.

mod common;

use std::fs;
use std::path::Path;

use common::{assert_ok, gridswarm, scratch, text};
use serde_json::Value;

fn summary(dir: &Path) -> Value {
    serde_json::from_slice(&fs::read(dir.join("summary.json")).unwrap()).unwrap()
}

/// A small sweep: 2 algorithms, 2 robot counts, 3 runs, random starts.
fn sweep(dir: &Path, scenario: &str) {
    let out = dir.to_str().unwrap();
    let args = ["experiment", "--scenario", scenario, "--algorithms", "ru,repulsive", "--robots", "2,3"];
    assert_ok(&gridswarm(&[&args[..], &["--runs", "3", "--starts", "random", "--out", out]].concat()));
}

#[test]
fn a_sweep_records_its_provenance_and_reruns_byte_for_byte_from_it() {
    let d = scratch("sweep");
    // A scenario file, changed after the sweep: the rerun must not read it.
    let file = d.join("mine.toml");
    assert_ok(&gridswarm(&["export-map", "paper", "--format", "toml", "--out", file.to_str().unwrap()]));
    let out = d.join("out");
    sweep(&out, file.to_str().unwrap());
    fs::write(&file, "this is no scenario").unwrap();

    let p = &summary(&out)["provenance"];
    assert_eq!(p["version"], env!("CARGO_PKG_VERSION"));
    let commit = p["commit"].as_str().unwrap();
    assert!(commit == "unknown" || (commit.len() == 40 && commit.bytes().all(|b| b.is_ascii_hexdigit())), "{commit}");
    let cmd: Vec<&str> = p["command"].as_array().unwrap().iter().map(|a| a.as_str().unwrap()).collect();
    assert_eq!(&cmd[1..3], ["experiment", "--scenario"]);
    assert!(cmd.ends_with(&["--out", out.to_str().unwrap()]), "{cmd:?}");
    assert_eq!(p["scenario"]["sha3_256"].as_str().unwrap().len(), 64);
    assert!(p["scenario"]["content"].as_str().unwrap().contains("[area]"), "the scenario's full text");
    assert_eq!(p["seeds"]["base"], 1);
    assert_eq!(p["starts"]["rule"], "random");
    assert_eq!(p["parameters"]["runs"], 3);
    assert!(p["started_at"].as_str().unwrap() <= p["ended_at"].as_str().unwrap());
    let report = fs::read_to_string(out.join("report.html")).unwrap();
    assert!(report.contains("Provenance") && report.contains(commit), "the report carries it");

    let o = gridswarm(&["rerun", out.to_str().unwrap()]);
    assert_ok(&o);
    let said = text(&o.stdout);
    for f in ["results.csv", "runs.csv", "claims.txt"] {
        assert!(said.contains(&format!("same     {f}\n")), "{said}");
        assert_eq!(fs::read(out.join(f)).unwrap(), fs::read(out.join("rerun").join(f)).unwrap(), "{f}");
    }
    assert!(said.contains("3 outputs the same byte for byte"), "{said}");
}

#[test]
fn a_tampered_results_csv_is_named_as_different() {
    let d = scratch("tampered");
    let out = d.join("out");
    sweep(&out, "paper");
    let csv = fs::read_to_string(out.join("results.csv")).unwrap();
    let mut lines: Vec<&str> = csv.lines().collect();
    let changed = lines[2].replacen(",3,", ",2,", 1);
    assert_ne!(changed, lines[2]);
    lines[2] = &changed;
    fs::write(out.join("results.csv"), lines.join("\n") + "\n").unwrap();
    let again = d.join("again");
    let o = gridswarm(&["rerun", out.to_str().unwrap(), "--out", again.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stderr));
    assert!(
        text(&o.stdout).contains("DIFFERS  results.csv (from line 3 on)\nsame     runs.csv\n"),
        "{}",
        text(&o.stdout)
    );
    // Off a terminal the rerun's sweep also says how far it got.
    let stderr = text(&o.stderr);
    let err = stderr.lines().filter(|l| !l.starts_with("progress: ")).collect::<Vec<_>>().join("\n");
    assert!(
        err.starts_with("error: the rerun of") && err.trim_end().ends_with("differs from it: results.csv"),
        "{err}"
    );
    assert!(again.join("results.csv").is_file(), "--out is where the rerun went");
}

#[test]
fn random_starts_change_the_runs_and_fixed_stays_the_default() {
    let d = scratch("starts");
    let (fixed, random) = (d.join("fixed"), d.join("random"));
    let args = ["experiment", "--algorithms", "ru,repulsive", "--robots", "3", "--runs", "4", "--out"];
    assert_ok(&gridswarm(&[&args[..], &[fixed.to_str().unwrap()]].concat()));
    sweep(&random, "paper");
    assert_eq!(summary(&fixed)["starts"], "fixed");
    assert_eq!(summary(&random)["starts"], "random");
    let runs = |dir: &Path| fs::read_to_string(dir.join("runs.csv")).unwrap();
    let three = |s: String| s.lines().filter(|l| l.contains(",3,")).map(str::to_string).collect::<Vec<_>>();
    assert_ne!(three(runs(&fixed))[..3], three(runs(&random))[..3], "drawn layouts, other runs");
}

#[test]
fn a_folder_without_provenance_or_a_scale_sweep_is_refused_clearly() {
    let d = scratch("refused");
    let o = gridswarm(&["rerun", d.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("holds no provenance"), "{}", text(&o.stderr));
    fs::write(d.join("provenance.json"), r#"{"command": ["gridswarm", "experiment", "scale"], "scenario": null}"#)
        .unwrap();
    let o = gridswarm(&["rerun", d.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o.stderr).contains("wall-clock measurements"), "{}", text(&o.stderr));
}

#[test]
fn simulate_records_its_starts_and_reruns() {
    let out = scratch("simulate").join("out");
    let o =
        gridswarm(&["simulate", "--robots", "4", "--seed", "5", "--starts", "random", "--out", out.to_str().unwrap()]);
    assert_ok(&o);
    let s = summary(&out);
    assert_eq!(s["provenance"]["starts"]["vertices"], s["starts"]);
    assert_eq!(s["provenance"]["seeds"]["seed"], 5);
    let o = gridswarm(&["rerun", out.to_str().unwrap()]);
    assert_ok(&o);
    assert!(text(&o.stdout).contains("same     trajectories.jsonl\n"), "{}", text(&o.stdout));
}

#[test]
fn a_set_sweep_has_a_column_per_key_shares_its_seeds_and_reruns_byte_for_byte() {
    let out = scratch("set").join("out");
    let args = ["experiment", "--runs", "3", "--robots", "2,3", "--algorithms", "sequential"];
    let set = ["--set", "t_trans=5.6,8", "--set", "r_st=1.3,1.2", "--out", out.to_str().unwrap()];
    let o = gridswarm(&[&args[..], &set[..]].concat());
    assert_ok(&o);
    assert!(
        text(&o.stdout).starts_with("scenario paper, 3 runs per cell, base seed 1, 4 combinations of t_trans, r_st")
    );

    let results = fs::read_to_string(out.join("results.csv")).unwrap();
    let head = results.lines().next().unwrap();
    assert!(
        head.contains(",map,oracle_reference_s,oracle_runs,lower_bound_s,") && head.ends_with(",t_trans,r_st"),
        "{head}"
    );
    assert_eq!(results.lines().count(), 1 + 4 * 2, "a row per combination and robot count");
    let runs = fs::read_to_string(out.join("runs.csv")).unwrap();
    let rows: Vec<Vec<&str>> = runs.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 4 * 2 * 3);
    let col = |k: &str| runs.lines().next().unwrap().split(',').position(|h| h == k).unwrap();
    let (tc, rc) = (col("t_trans"), col("r_st"));
    // Every combination runs on the same seeds; the values change the runs.
    let of = |t: &str, r: &str| rows.iter().filter(|x| x[tc] == t && x[rc] == r).collect::<Vec<_>>();
    let (a, b) = (of("5.6", "1.3"), of("8", "1.3"));
    assert_eq!(a.len(), 6);
    assert!(a.iter().zip(&b).all(|(x, y)| x[3] == y[3]), "common random numbers");
    assert!(a.iter().zip(&b).all(|(x, y)| x[4].parse::<f64>().unwrap() < y[4].parse::<f64>().unwrap()));

    let s = summary(&out);
    assert_eq!(s["set"][1]["values"], serde_json::json!(["1.3", "1.2"]));
    assert_eq!((s["cells"][2]["t_trans"].as_f64(), s["cells"][2]["r_st"].as_f64()), (Some(5.6), Some(1.2)));
    assert_eq!(s["combinations"][3]["params"]["t_trans"], 8.0);
    assert_eq!(s["provenance"]["parameters"]["set"], s["set"]);
    let report = fs::read_to_string(out.join("report.html")).unwrap();
    assert!(report.contains("t_trans=8, r_st=1.2"));

    let o = gridswarm(&["rerun", out.to_str().unwrap()]);
    assert_ok(&o);
    for f in ["results.csv", "runs.csv", "claims.txt"] {
        assert_eq!(fs::read(out.join(f)).unwrap(), fs::read(out.join("rerun").join(f)).unwrap(), "{f}");
    }
}

#[test]
fn a_bad_set_names_its_key_and_exits_2() {
    let out = scratch("badset").join("out");
    for (set, said) in [
        ("nope=1", "`nope` is no [params] or [lfp] key"),
        ("t_wait=1,soon", "--set t_wait=soon: invalid type"),
        ("turn=sideways", "--set turn=sideways: invalid value"),
        ("t_wait", "is not KEY=V1,V2"),
    ] {
        let o =
            gridswarm(&["experiment", "--runs", "1", "--robots", "2", "--set", set, "--out", out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{set}");
        assert!(text(&o.stderr).contains(said), "{set}: {}", text(&o.stderr));
        assert!(!out.exists(), "nothing written for {set}");
    }
}
