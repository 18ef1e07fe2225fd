//! A ROS map_server map end to end (issue 24, item 2): drawn by the test
//! as map.yaml + a plain PGM + its sidecar, then `gridswarm check`,
//! `simulate` and `run` (world-server and robot-agents over iceoryx2, each
//! reading the map itself) on it, and `export-map` in both forms.

use std::fs;
use std::path::Path;

use gridswarm_e2e::*;
use serde_json::Value;

/// A 12 x 8 m room of 10 cm pixels (plain PGM, top row first): unknown
/// outside, walls, a 1 x 1 m pillar, a 2 x 0.5 m shelf.
fn draw(dir: &Path) -> String {
    let (w, h) = (130usize, 90usize);
    let mut px = vec![205u8; w * h];
    let mut set = |x0: usize, y0: usize, x1: usize, y1: usize, v: u8| {
        for y in y0..y1 {
            px[y * w + x0..y * w + x1].fill(v);
        }
    };
    set(3, 3, w - 3, h - 3, 0);
    set(5, 5, w - 5, h - 5, 254);
    set(40, 30, 50, 40, 0);
    set(80, 60, 100, 65, 0);
    let rows: Vec<String> = px.chunks(w).map(|r| r.iter().map(u8::to_string).collect::<Vec<_>>().join(" ")).collect();
    fs::write(dir.join("room.pgm"), format!("P2\n# drawn by tests/maps.rs\n{w} {h}\n255\n{}\n", rows.join("\n")))
        .unwrap();
    let yaml = "image: room.pgm\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
    fs::write(dir.join("room.yaml"), yaml).unwrap();
    let sidecar =
        "robots = 3\ntargets = [[2.0, 2.0], [10.0, 6.0], [6.0, 7.0]]\n[starts]\nborder = { from = [0.5, 0.5] }\n";
    fs::write(dir.join("room.gridswarm.toml"), sidecar).unwrap();
    dir.join("room.yaml").to_str().unwrap().to_string()
}

fn json(out: &std::process::Output) -> Value {
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{e}: {}", text(&out.stdout)))
}

#[test]
fn a_ros_map_is_checked_simulated_and_run_by_processes() {
    let _s = serial();
    let dir = scratch("rosmap");
    let map = draw(&dir);

    let out = ok(&["check", &map]);
    let shown = text(&out.stdout);
    assert!(shown.contains("scenario room: triangular grid, a = 1 m, 3 targets, 2 obstacles, 3 robots"), "{shown}");
    assert!(shown.contains("as read:") && shown.contains("image 130 x 90 pixels of 0.1 m"), "{shown}");
    assert!(shown.contains("merged into 2 obstacles (8 corners)"), "{shown}");

    let sim = dir.join("sim");
    let sim_out = search(&["simulate", "--scenario", &map, "--seed", "4", "--json", "--out", sim.to_str().unwrap()]);
    let simulated = json(&sim_out);
    assert_eq!((&simulated["complete"], &simulated["targets_found"]), (&Value::Bool(true), &serde_json::json!(3)));

    let run = dir.join("run");
    let args = ["run", "--json", "--scenario", &map, "--seed", "4", "--out", run.to_str().unwrap()];
    let v = finished(&gridswarm().args(args).output().unwrap(), &args);
    assert_no_leftovers(v["ipc_prefix"].as_str().unwrap());
    assert_eq!(v["engine"], "distributed");
    // Every robot-agent read the map itself and agreed on its hash.
    assert_eq!(v["agreement"]["scenario"], simulated["agreement"]["scenario"]);
    assert_eq!(v["agreement"]["scenario"]["name"], "room");
    for key in ["complete", "rounds", "targets_found", "collisions"] {
        assert_eq!(v[key], simulated[key], "{key}");
    }
    let traj = |d: &Path| fs::read(d.join("trajectories.jsonl")).unwrap();
    assert!(traj(&run) == traj(&sim), "the engines' trajectories differ on the map");
}

#[test]
fn export_map_writes_any_scenario_in_both_forms_and_lists_the_files() {
    let dir = scratch("export-map");
    let out = dir.join("r.yaml");
    let o = ok(&["export-map", "random:5", "--format", "yaml", "--out", out.to_str().unwrap()]);
    let said = text(&o.stdout);
    for f in ["r.yaml", "r.pgm", "r.gridswarm.toml"] {
        assert!(dir.join(f).is_file() && said.contains(f), "{f}: {said}");
    }
    let back = dir.join("back.toml");
    ok(&["export-map", out.to_str().unwrap(), "--format", "toml", "--out", back.to_str().unwrap()]);
    // The TOML of the map is that map: checked alike (the pixel steps of
    // slanted edges may fail 3.1.3 in both: exit 3 is a report too).
    let (a, b) = (search(&["check", out.to_str().unwrap()]), search(&["check", back.to_str().unwrap()]));
    assert_eq!(a.status.code(), b.status.code());
    let tail = |o: &std::process::Output| text(&o.stdout).split("assumptions:").nth(1).unwrap().to_string();
    assert_eq!(tail(&a), tail(&b));
    // Bad input: a usage error (2), an unreadable map (1).
    let bad = gridswarm().args(["export-map", "paper", "--format", "png"]).output().unwrap();
    assert_eq!(bad.status.code(), Some(2), "{}", text(&bad.stderr));
    let e = gridswarm().args(["export-map", "paper", "--format", "yaml", "--resolution", "0"]).output().unwrap();
    assert_eq!(e.status.code(), Some(2), "{}", text(&e.stderr));
    let missing = dir.join("none.yaml");
    let e = gridswarm().args(["check", missing.to_str().unwrap()]).output().unwrap();
    assert_eq!(e.status.code(), Some(1));
    assert!(text(&e.stderr).contains("none.yaml: cannot read map file"), "{}", text(&e.stderr));
}
