//! Maps and parameters that cannot mislead (issue 36, part 7), through the
//! binary: a parameter set that lets robots collide by geometry is refused,
//! a collision under an algorithm that promises none never exits 0, a map
//! without targets in situation 1 is an error naming the fix, and
//! `map-setup` writes a sidecar sized for the robot.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::{gridswarm, scratch, text};

fn code(o: &Output) -> Option<i32> {
    o.status.code()
}

/// A square room 8 m across with one target and the given `[params]` lines.
fn room(dir: &Path, name: &str, params: &str) -> String {
    let path = dir.join(format!("{name}.toml"));
    let toml = format!(
        "name = \"{name}\"\nrobots = 3\ntargets = [[3.0, 3.0]]\n[area]\npolygon = [[0, 0], [8, 0], [8, 8], [0, 8]]\n\
         [params]\n{params}\n"
    );
    fs::write(&path, toml).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn robots_on_adjacent_vertices_within_2_r_safe_fail_check_and_are_refused() {
    let d = scratch("s0");
    // The reproducer: adjacent vertices exactly 2 r_safe apart. It
    // passed `check`, and `simulate` counted collisions and exited 0.
    let tight = room(&d, "tight", "a = 0.5\nr_rob = 0.2\nr_safe = 0.25");
    let o = gridswarm(&["check", &tight]);
    assert_eq!(code(&o), Some(3), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    let line = out.lines().find(|l| l.contains(" S0 ")).unwrap_or_else(|| panic!("{out}"));
    assert!(line.starts_with("FAILS"), "{line}");
    assert!(line.contains("a = 0.5, r_safe = 0.25: robots on adjacent vertices are 0.500 m apart"), "{line}");
    assert!(line.contains("passes one on a vertex off it 0.433 m away"), "{line}");
    assert!(line.contains("not more than 2 r_safe = 0.500"), "{line}");
    assert!(out.contains("fix S0"), "{out}");

    // simulate and run refuse it (exit 4) before anything runs or is written.
    let run_dir = d.join("run");
    for cmd in ["simulate", "run"] {
        let o = gridswarm(&[cmd, "--scenario", &tight, "--out", run_dir.to_str().unwrap()]);
        let err = text(&o.stderr);
        assert_eq!(code(&o), Some(4), "{cmd}: {err}");
        assert!(err.starts_with("error: refused: S0"), "{cmd}: {err}");
        assert!(err.contains("robots on adjacent vertices are 0.500 m apart"), "{cmd}: {err}");
        assert!(!run_dir.exists(), "{cmd} wrote {}", run_dir.display());
    }
    // RU's robots are particles charged for every collision: it runs, warned.
    let o = gridswarm(&["simulate", "--scenario", &tight, "--algorithm", "ru"]);
    assert!(matches!(code(&o), Some(0 | 3)), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("warning: S0"), "{}", text(&o.stderr));

    // The smallest whole centimetre S0 allows at r_safe = 0.25 (a > 0.577).
    let o = gridswarm(&["check", &room(&d, "roomy", "a = 0.58\nr_rob = 0.2\nr_safe = 0.25")]);
    let out = text(&o.stdout);
    assert!(out.lines().any(|l| l.starts_with("ok    S0")), "{out}");
    let o = gridswarm(&["check", &room(&d, "narrow", "a = 0.57\nr_rob = 0.2\nr_safe = 0.25")]);
    assert!(text(&o.stdout).lines().any(|l| l.starts_with("FAILS S0")), "{}", text(&o.stdout));
}

#[test]
fn a_collision_under_a_collision_free_algorithm_never_ends_complete_with_exit_0() {
    // Half the frames lost: the protocol cannot keep its promise, and this
    // run collides 11 times though it finds every target.
    let args = ["simulate", "--robots", "13", "--seed", "1", "--loss", "0.5", "--max-rounds", "400"];
    let o = gridswarm(&args);
    assert_eq!(code(&o), Some(4), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert!(out.lines().nth(1).unwrap().starts_with("COLLIDED, search complete (stop:"), "{out}");
    assert!(text(&o.stderr).contains("error: robots collided under an algorithm that promises"), "{}", text(&o.stderr));
    let o = gridswarm(&[&args[..], &["--json"]].concat());
    assert_eq!(code(&o), Some(4));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["complete"] == true && v["collisions"].as_u64().unwrap() > 0, "{v}");
    // The same radio without loss: no collision, complete, exit 0.
    let o = gridswarm(&["simulate", "--robots", "13", "--seed", "1", "--max-rounds", "400"]);
    assert_eq!(code(&o), Some(0), "{}", text(&o.stderr));
    // RU charges its collisions and promises none away: they are its results.
    let o = gridswarm(&["simulate", "--algorithm", "ru", "--robots", "13", "--seed", "1", "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["collisions"].as_u64().unwrap() > 0, "{v}");
    assert_eq!(code(&o), Some(if v["complete"] == true { 0 } else { 3 }));
}

/// A plain PGM: a room of free pixels inside a wall, unknown around.
fn pgm(w: usize, h: usize) -> Vec<u8> {
    let mut out = format!("P2\n{w} {h}\n255\n").into_bytes();
    for y in 0..h {
        for x in 0..w {
            let edge = x < 2 || y < 2 || x >= w - 2 || y >= h - 2;
            let v = if edge { 0 } else { 254 };
            out.extend(format!("{v} ").as_bytes());
        }
        out.push(b'\n');
    }
    out
}

/// A ROS map (room.yaml + room.pgm) of 5 x 4 m, without a sidecar.
fn ros_map(dir: &Path) -> PathBuf {
    fs::write(dir.join("room.pgm"), pgm(100, 80)).unwrap();
    let yaml = dir.join("room.yaml");
    fs::write(
        &yaml,
        "image: room.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
    )
    .unwrap();
    yaml
}

#[test]
fn situation_1_without_targets_is_an_error_naming_the_fix() {
    let d = scratch("no-targets");
    let yaml = ros_map(&d);
    let map = yaml.to_str().unwrap();
    let side = d.join("room.gridswarm.toml");
    // It printed "complete ... after 1 rounds ... 0 moves" and exited 0.
    for args in [
        &["simulate", "--scenario", map][..],
        &["run", "--scenario", map],
        &["experiment", "--scenario", map, "--runs", "1", "--robots", "1"],
    ] {
        let o = gridswarm(args);
        let err = text(&o.stderr);
        assert_eq!(code(&o), Some(1), "{args:?}: {err}");
        assert!(err.starts_with("error: situation 1 needs targets: scenario `room` has none"), "{err}");
        assert!(err.contains(&format!("to its sidecar {}", side.display())), "{err}");
        assert!(err.contains("or use --situation 2"), "{err}");
    }
    let o = gridswarm(&["check", map]);
    assert_eq!(code(&o), Some(3));
    assert!(text(&o.stdout)
        .contains("FAILS targets  every target within r_st of a vertex of Va: no targets in situation 1"));
    // The fix it names works.
    let o = gridswarm(&["simulate", "--scenario", map, "--situation", "2", "--json"]);
    assert_eq!(code(&o), Some(0), "{}", text(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["rounds"].as_u64().unwrap() > 1, "{v}");
}

/// The TurtleBot3 map, copied into `dir` with its sidecar.
fn turtlebot(dir: &Path) -> String {
    let from = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/tests/fixtures/turtlebot3_world");
    for f in ["map.yaml", "map.pgm", "map.gridswarm.toml"] {
        fs::copy(from.join(f), dir.join(f)).unwrap();
    }
    dir.join("map.yaml").to_string_lossy().into_owned()
}

#[test]
fn map_setup_writes_a_sidecar_sized_for_the_robot_and_never_overwrites_unasked() {
    let d = scratch("map-setup");
    let map = turtlebot(&d);
    let side = d.join("map.gridswarm.toml");
    let before = fs::read(&side).unwrap();
    let o = gridswarm(&["map-setup", &map, "--robot-radius", "0.105"]);
    assert_eq!(code(&o), Some(1));
    assert!(text(&o.stderr).contains("exists: map-setup replaces a sidecar only with --force"), "{}", text(&o.stderr));
    assert_eq!(fs::read(&side).unwrap(), before, "untouched");

    let o = gridswarm(&["map-setup", &map, "--robot-radius", "0.105", "--force"]);
    let out = text(&o.stdout);
    assert_eq!(code(&o), Some(0), "{out}{}", text(&o.stderr));
    assert!(
        out.contains("r_safe 0.126 a 0.3 r_so 0.426 r_st 0.5 r_c 0.621 (m); W_pass = a + 2 r_safe = 0.552"),
        "{out}"
    );
    // The notch in the arena's wall, 0.3 m deep at this reading.
    assert!(out.contains("passages the robot cannot take (narrower than W_pass"), "{out}");
    assert!(out.contains("0.300 m, the robot fits, the grid need not pass"), "{out}");
    assert!(out.lines().filter(|l| l.starts_with("ok ")).count() == 11, "{out}");
    let written = fs::read_to_string(&side).unwrap();
    for k in ["a = 0.3\n", "r_rob = 0.105\n", "r_safe = 0.126\n", "r_c = 0.621\n", "sliver = 0.552\n"] {
        assert!(written.contains(k), "{k:?} in {written}");
    }
    // Its targets and starts are kept, and the map reads and checks with it.
    assert!(written.contains("targets = [[-0.55, -0.55], [0.55, 0.55], [0.55, -0.55]]"), "{written}");
    assert_eq!(code(&gridswarm(&["check", &map])), Some(0));
    // No temporary file is left beside it.
    let names: Vec<String> = fs::read_dir(&d).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    assert_eq!(names.len(), 3, "{names:?}");

    // Elsewhere with --out; a map without a sidecar gets situation 2.
    let bare = scratch("map-setup-bare");
    let yaml = ros_map(&bare);
    let out_file = bare.join("sized.toml");
    let o =
        gridswarm(&["map-setup", yaml.to_str().unwrap(), "--robot-radius", "0.2", "--out", out_file.to_str().unwrap()]);
    // r_st = a + r_safe, the least 3.1.1 allows, does not reach this
    // room's corners from the lattice as it falls: written, and said (3).
    let out = text(&o.stdout);
    assert_eq!(code(&o), Some(3), "{out}{}", text(&o.stderr));
    assert!(out.contains("FAILS 3.1.2") && out.contains("fix 3.1.2") && out.contains("wrote "), "{out}");
    let written = fs::read_to_string(&out_file).unwrap();
    assert!(written.contains("situation = 2") && written.contains("a = 0.56\n"), "{written}");
    assert!(!bare.join("room.gridswarm.toml").exists());
    // Not a map; a radius that is no length.
    assert_eq!(code(&gridswarm(&["map-setup", "paper", "--robot-radius", "0.2"])), Some(2));
    assert_eq!(code(&gridswarm(&["map-setup", &map, "--robot-radius", "-1"])), Some(2));
}
