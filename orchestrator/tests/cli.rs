//! End-to-end tests of the `gridswarm` binary: outputs exist, parse, and are
//! reproducible; bad input fails with one `error:` line, never a panic.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn gridswarm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gridswarm")).args(args).output().expect("the binary runs")
}

fn gridswarm_env(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_gridswarm"));
    c.args(args);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("the binary runs")
}

/// A fresh directory for one test, under cargo's per-target temp dir.
fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli").join(name);
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn assert_ok(o: &Output) {
    assert!(o.status.success(), "exit {:?}\nstdout:\n{}\nstderr:\n{}", o.status, stdout(o), stderr(o));
}

/// Fails cleanly: non-zero, an `error:` line, no panic.
fn assert_clean_error(o: &Output) -> String {
    let err = stderr(o);
    assert!(!o.status.success(), "succeeded:\n{}", stdout(o));
    assert!(err.lines().any(|l| l.starts_with("error: ")), "no `error:` line in {err:?}");
    assert!(!err.contains("panicked"), "panic: {err}");
    err
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn simulate_json_is_one_object_with_the_fields() {
    let o = gridswarm(&["simulate", "--json", "--robots", "3", "--seed", "2"]);
    assert_ok(&o);
    let out = stdout(&o);
    assert_eq!(out.trim_end().lines().count(), 1, "{out}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    for k in [
        "algorithm",
        "robots",
        "seed",
        "situation",
        "rounds",
        "search_time_s",
        "targets_found",
        "targets_total",
        "collisions",
        "coverage",
        "complete",
        "scenario",
        "grid",
        "params",
    ] {
        assert!(v.get(k).is_some(), "missing {k} in {v}");
    }
    assert_eq!(v["algorithm"], "repulsive");
    assert_eq!(v["robots"], 3);
    assert_eq!(v["seed"], 2);
    assert_eq!(v["scenario"], "paper");
    assert!(v["params"]["r_st"].is_f64());
}

#[test]
fn simulate_out_writes_reproducible_files() {
    let d = scratch("simulate_out");
    let (a, b, c) = (d.join("a"), d.join("b/nested"), d.join("c"));
    for (dir, seed) in [(&a, "1"), (&b, "1"), (&c, "2")] {
        let o = gridswarm(&["simulate", "--robots", "4", "--seed", seed, "--out", path(dir)]);
        assert_ok(&o);
        assert!(stdout(&o).contains("routes.svg"), "{}", stdout(&o));
    }
    for f in ["summary.json", "trajectories.jsonl", "routes.svg"] {
        assert!(a.join(f).is_file(), "{f} missing");
    }
    let ta = fs::read(a.join("trajectories.jsonl")).unwrap();
    assert_eq!(ta, fs::read(b.join("trajectories.jsonl")).unwrap(), "same seed, different trajectories");
    assert_ne!(ta, fs::read(c.join("trajectories.jsonl")).unwrap(), "another seed, same trajectories");

    // Round-major, robot order, and every robot every round.
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(a.join("summary.json")).unwrap()).unwrap();
    let rounds = summary["rounds"].as_u64().unwrap() as usize;
    let lines: Vec<serde_json::Value> =
        String::from_utf8(ta).unwrap().lines().map(|l| serde_json::from_str(l).expect("JSON line")).collect();
    assert_eq!(lines.len(), 4 * (rounds + 1));
    for (n, l) in lines.iter().enumerate() {
        assert_eq!(l["round"].as_u64().unwrap() as usize, n / 4);
        assert_eq!(l["robot"].as_u64().unwrap() as usize, n % 4);
        assert!(l["vertex"].is_array() && l["x"].is_f64() && l["y"].is_f64());
    }

    let svg = fs::read_to_string(a.join("routes.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("routes.svg is XML");
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    for r in 1..=4 {
        let id = format!("robot-{r}");
        assert!(doc.descendants().any(|n| n.attribute("id") == Some(id.as_str())), "{id} missing");
    }
}

#[test]
fn simulate_lfp_leaves_the_grid_reproducibly() {
    let d = scratch("simulate_lfp");
    let (a, b) = (d.join("a"), d.join("b"));
    for dir in [&a, &b] {
        let o = gridswarm(&["simulate", "--algorithm", "lfp", "--robots", "2", "--json", "--out", path(dir)]);
        assert_ok(&o);
        let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
        assert_eq!(v["algorithm"], "lfp");
        assert!(v["lfp"]["beta"].is_f64(), "LFP constants missing from {v}");
    }
    let t = fs::read_to_string(a.join("trajectories.jsonl")).unwrap();
    assert_eq!(t, fs::read_to_string(b.join("trajectories.jsonl")).unwrap());
    // Continuous motion: after the start, poses are off the grid.
    assert!(t.lines().skip(2).any(|l| l.contains("\"vertex\":null")), "{}", &t[..t.len().min(400)]);
    roxmltree::Document::parse(&fs::read_to_string(a.join("routes.svg")).unwrap()).expect("routes.svg is XML");
}

#[test]
fn small_experiment_writes_tables_figure_and_claims() {
    let d = scratch("experiment");
    let (one, many) = (d.join("one-thread"), d.join("default-threads"));
    let args = |out: &Path| -> Vec<String> {
        ["experiment", "--runs", "5", "--robots", "1-3", "--seed", "3", "--out", path(out)]
            .iter()
            .map(|s| s.to_string())
            .collect()
    };
    let a1: Vec<String> = args(&one);
    let o = gridswarm_env(&a1.iter().map(String::as_str).collect::<Vec<_>>(), &[("RAYON_NUM_THREADS", "1")]);
    assert_ok(&o);
    let text = stdout(&o);
    assert!(text.contains("Claim (a)") && text.contains("Claim (b)") && text.contains("Claim (c)"), "{text}");
    // 1-3 robots cannot say anything about 9-13 robots.
    assert!(text.contains("Claim (b) RU > LFP in mean search time for 9 to 13 robots: not evaluated"), "{text}");

    let csv = fs::read_to_string(one.join("results.csv")).unwrap();
    let mut lines = csv.lines();
    assert!(lines.next().unwrap().starts_with(
        "algorithm,robots,runs,completed_runs,mean_search_time_s,std_search_time_s,ci95_s,mean_rounds,mean_collisions"
    ));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 4 * 3, "{csv}");
    for alg in ["lfp", "ru", "sequential", "repulsive"] {
        assert_eq!(rows.iter().filter(|r| r.starts_with(&format!("{alg},"))).count(), 3);
    }
    assert!(rows.iter().all(|r| r.split(',').nth(2) == Some("5")));

    let svg = fs::read_to_string(one.join("fig7.svg")).unwrap();
    roxmltree::Document::parse(&svg).expect("fig7.svg is XML");
    for f in ["claims.txt", "summary.json", "runs.csv"] {
        assert!(one.join(f).is_file(), "{f} missing");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(one.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["claims"].as_array().unwrap().len(), 3);
    assert!(summary["params"]["a"].is_f64());

    // Seeds depend on the run, not on the thread that ran it.
    let a2 = args(&many);
    assert_ok(&gridswarm(&a2.iter().map(String::as_str).collect::<Vec<_>>()));
    assert_eq!(csv, fs::read_to_string(many.join("results.csv")).unwrap());
    assert_eq!(fs::read(one.join("runs.csv")).unwrap(), fs::read(many.join("runs.csv")).unwrap());
}

#[test]
fn grids_compares_three_lattices() {
    let d = scratch("grids");
    let o = gridswarm(&["experiment", "--grids", "--out", path(&d)]);
    assert_ok(&o);
    let csv = fs::read_to_string(d.join("grids.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows[0], "grid,degree,frame_vertices,accessible,va,detected_fraction,undetected_area_m2");
    assert_eq!(rows.len(), 4);
    for (row, name) in rows[1..].iter().zip(["triangular", "square", "hexagonal"]) {
        assert!(row.starts_with(name), "{row}");
        let f: f64 = row.split(',').nth(5).unwrap().parse().unwrap();
        assert!((0.0..=1.0).contains(&f), "{row}");
    }
}

#[test]
fn check_paper_holds() {
    let o = gridswarm(&["check", "paper"]);
    assert_ok(&o);
    assert!(stdout(&o).contains("assumptions"), "{}", stdout(&o));
    assert_ok(&gridswarm(&["check"]));
}

#[test]
fn check_fails_when_an_assumption_fails() {
    let d = scratch("check_weak");
    let f = d.join("weak.toml");
    // Sonar shorter than a + r_safe breaks Assumption 2.4; the scenario is
    // otherwise valid, so it still runs (with a warning).
    fs::write(&f, "[area]\npolygon = [[0, 0], [12, 0], [12, 9], [0, 9]]\n\n[params]\nr_so = 1.0\n").unwrap();
    let o = gridswarm(&["check", path(&f)]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    assert!(stdout(&o).contains("FAILS 2.4"), "{}", stdout(&o));
    let err = assert_clean_error(&o);
    assert!(err.contains("2.4"), "{err}");
    let o = gridswarm(&["simulate", "--scenario", path(&f), "--robots", "2"]);
    assert_ok(&o);
    assert!(stderr(&o).contains("warning: 2.4"), "{}", stderr(&o));
}

#[test]
fn check_bad_file_names_the_field() {
    let d = scratch("check_bad");
    let f = d.join("bad.toml");
    fs::write(&f, BAD_SCENARIO).unwrap();
    let o = gridswarm(&["check", path(&f)]);
    let err = assert_clean_error(&o);
    assert!(err.contains(BAD_FIELD), "field not named: {err}");
}

#[test]
fn bad_input_fails_cleanly() {
    let d = scratch("bad_input");
    let cases: Vec<Vec<String>> = vec![
        vec!["simulate".into(), "--algorithm".into(), "nosuch".into()],
        vec!["simulate".into(), "--robots".into(), "0".into()],
        vec!["simulate".into(), "--scenario".into(), "nosuch-scenario".into()],
        vec!["experiment".into(), "--robots".into(), "0".into()],
        vec!["experiment".into(), "--robots".into(), "5-2".into()],
        vec!["experiment".into(), "--runs".into(), "0".into()],
        vec!["experiment".into(), "--algorithms".into(), "ru,nosuch".into()],
        vec!["check".into(), "nosuch-scenario".into()],
        vec!["check".into(), path(&d.join("missing.toml")).into()],
        // A file where the directory should be.
        {
            let file = d.join("file");
            fs::write(&file, "x").unwrap();
            vec!["simulate".into(), "--out".into(), path(&file.join("sub")).into()]
        },
    ];
    for args in cases {
        let o = gridswarm(&args.iter().map(String::as_str).collect::<Vec<_>>());
        let err = assert_clean_error(&o);
        assert_eq!(err.lines().count(), 1, "{args:?}: more than one line: {err}");
    }
    let err = assert_clean_error(&gridswarm(&["simulate", "--algorithm", "nosuch"]));
    assert!(err.contains("nosuch"), "{err}");
    let err = assert_clean_error(&gridswarm(&["experiment", "--robots", "5-2"]));
    assert!(err.contains("5-2"), "{err}");
}

/// A scenario whose only fault is one field, which the error must name.
const BAD_SCENARIO: &str = "\
[area]
polygon = [[0, 0], [20, 0], [20, 16], [0, 16]]

[[obstacles]]
circle = { center = [10, 8], radius = \"big\" }
";
const BAD_FIELD: &str = "obstacles[0].circle.radius";
