//! Random maps through the `gridswarm` binary: `check random:...` passes or
//! fails as asked, every command takes them, and `experiment --maps K`
//! writes which map every number is from and shows the spread over maps.

use std::fs;

mod common;
use common::{assert_ok, gridswarm, scratch, text};

#[test]
fn check_passes_random_maps_and_fails_the_broken_one() {
    let o = gridswarm(&["check", "random:5"]);
    assert_ok(&o);
    let out = text(&o.stdout);
    assert!(out.starts_with("scenario random:5: triangular grid"), "{out}");
    assert!(!out.contains("FAILS"), "{out}");

    let o = gridswarm(&["check", "random:5,break=3.1.3"]);
    assert_eq!(o.status.code(), Some(3));
    assert_eq!(text(&o.stdout).lines().filter(|l| l.starts_with("FAILS")).count(), 1, "{}", text(&o.stdout));
    assert!(text(&o.stderr).contains("fails check(s) 3.1.3\n"), "{}", text(&o.stderr));

    let o = gridswarm(&["check", "random:5,density=2"]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(text(&o.stderr), "error: random:5,density=2: density: must be 0 to 0.4, got 2\n");
}

#[test]
fn simulate_takes_a_random_map_and_the_help_names_the_syntax() {
    let o = gridswarm(&["simulate", "--scenario", "random:2,size=25x18", "--robots", "4", "--json"]);
    assert_ok(&o);
    let v: serde_json::Value = serde_json::from_str(&text(&o.stdout)).unwrap();
    assert_eq!(v["scenario"], "random:2,size=25x18", "{v}");
    let help = text(&gridswarm(&["check", "--help"]).stdout);
    assert!(
        help.contains("random:SEED[,size=WxH][,density=F][,passage=M][,targets=N][,robots=N][,break=ID]"),
        "{help}"
    );
}

#[test]
fn maps_write_the_map_column_and_the_spread() {
    let out = scratch("sweep");
    let o = gridswarm(&[
        "experiment",
        "--scenario",
        "random:11,targets=4",
        "--maps",
        "3",
        "--runs",
        "4",
        "--robots",
        "1,3",
        "--algorithms",
        "ru,repulsive",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_ok(&o);
    let stdout = text(&o.stdout);
    assert!(stdout.contains("maps: 3 (random:11,targets=4 .. random:13,targets=4)"), "{stdout}");
    assert!(stdout.contains("per-map spread of mean search time: widest"), "{stdout}");
    // Short: the pooled table, not a row per map.
    assert!(stdout.lines().count() < 30, "{stdout}");

    let results = fs::read_to_string(out.join("results.csv")).unwrap();
    let header: Vec<&str> = results.lines().next().unwrap().split(',').collect();
    let map_col = header.iter().position(|&h| h == "map").expect("a map column");
    let label_col = header.iter().position(|&h| h == "label").expect("a label column");
    // Counted from the quoted label (it may hold commas): the references follow.
    let maps: Vec<String> = results
        .lines()
        .skip(1)
        .map(|l| l.rsplit('"').next().unwrap().split(',').nth(map_col - label_col).unwrap().to_string())
        .collect();
    assert_eq!(header[map_col + 1..map_col + 4], ["oracle_reference_s", "oracle_runs", "lower_bound_s"]);
    // 2 algorithms x 2 counts: 4 pooled rows, then 4 per map.
    assert_eq!(maps.len(), 16);
    assert!(maps[..4].iter().all(|m| m == "all"), "{maps:?}");
    for k in 0..3 {
        assert_eq!(maps[4 + 4 * k..8 + 4 * k], [k.to_string(), k.to_string(), k.to_string(), k.to_string()]);
    }
    // The pooled cell holds every map's runs.
    assert!(results.lines().nth(1).unwrap().starts_with("ru,1,12,"), "{results}");

    let runs = fs::read_to_string(out.join("runs.csv")).unwrap();
    let run_map = runs.lines().next().unwrap().split(',').position(|h| h == "map").expect("a map column in runs.csv");
    assert_eq!(runs.lines().count(), 1 + 3 * 2 * 2 * 4);
    assert_eq!(runs.lines().last().unwrap().split(',').nth(run_map), Some("2"));
    let seeds: std::collections::HashSet<&str> = runs.lines().skip(1).map(|l| l.split(',').nth(3).unwrap()).collect();
    // Common random numbers: the algorithms share seeds; every map, robot
    // count and run index has its own.
    assert_eq!(seeds.len(), 3 * 2 * 4, "a seed per map, count and run");

    let maps_csv = fs::read_to_string(out.join("maps.csv")).unwrap();
    assert!(maps_csv.lines().nth(3).unwrap().starts_with("2,\"random:13,targets=4\","), "{maps_csv}");

    let html = fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("<title>Fig. 7 sweep: 3 random maps from random:11,targets=4</title>"), "title");
    assert!(html.contains("<h2>Per-map spread</h2>") && html.contains("<th>median (s)</th>"));
    assert!(html.contains("<td>random:12,targets=4</td>"));
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["per_map_spread"].as_array().unwrap().len(), 4);
    assert_eq!(summary["per_map_spread"][0]["maps"], 3);
    // How the robots were reached, as every run's summary says it.
    assert_eq!(summary["transport"]["name"], "in-process");
    assert_eq!(summary["transport"]["security"]["mode"], "local");
}

#[test]
fn maps_need_a_random_scenario() {
    let o = gridswarm(&["experiment", "--scenario", "paper", "--maps", "2", "--runs", "1"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o.stderr).starts_with("error: --maps needs a random scenario"), "{}", text(&o.stderr));
    let o = gridswarm(&["experiment", "--grids", "--maps", "2"]);
    assert_eq!(o.status.code(), Some(2));
}
