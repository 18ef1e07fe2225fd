//! Hostile scenario files (issue 11): every reproducer of the issue, and
//! the limits of `gridswarm::scenario::limits`, refused while the file is
//! read, with an error that names the field, the value and the limit, and
//! quickly. The files are in `fixtures/hostile/`; each says what it expects
//! on a line `# expect: FIELD | LIMIT | VALUE`. The big ones are made here.

#[path = "common/cpu.rs"]
mod cpu;

use std::path::{Path, PathBuf};
use std::time::Duration;

use gridswarm::scenario::limits;
use gridswarm::scenario::{Scenario, ScenarioError};

/// CPU time: far above what refusing a file takes (microseconds to a few
/// hundred milliseconds for a megabyte of TOML), far below the seconds to
/// hours the same files took before the limits.
const QUICK: Duration = Duration::from_secs(2);

fn fixtures() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/hostile");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    files
}

/// The `# expect: FIELD | LIMIT | VALUE` line of a fixture.
fn expectation(text: &str, file: &Path) -> (String, String, String) {
    let line = text
        .lines()
        .find_map(|l| l.strip_prefix("# expect:"))
        .unwrap_or_else(|| panic!("{}: no `# expect:` line", file.display()));
    let parts: Vec<String> = line.split('|').map(|p| p.trim().to_string()).collect();
    assert_eq!(parts.len(), 3, "{}: `# expect: FIELD | LIMIT | VALUE`", file.display());
    (parts[0].clone(), parts[1].clone(), parts[2].clone())
}

/// Parses `text`, expecting a refusal within [`QUICK`].
fn refused(text: &str, source: &str) -> ScenarioError {
    let (result, took) = cpu::timed(|| Scenario::parse(text, source));
    assert!(took < QUICK, "{source}: took {took:?} to answer");
    match result {
        Ok(s) => panic!("{source}: accepted ({} obstacles, a = {})", s.obstacles.len(), s.params.a),
        Err(e) => e,
    }
}

#[test]
fn every_fixture_is_refused_naming_field_value_and_limit() {
    let files = fixtures();
    assert!(files.len() >= 6, "fixtures missing: {files:?}");
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        let (field, limit, value) = expectation(&text, &file);
        let e = refused(&text, &file.display().to_string());
        let shown = e.to_string();
        assert_eq!(e.field, field, "{shown}");
        assert!(e.message.contains(&limit), "{}: no limit {limit} in: {shown}", file.display());
        assert!(e.message.contains(&value), "{}: no value {value} in: {shown}", file.display());
        assert!(e.line().is_some(), "{}: no line in: {shown}", file.display());
        assert!(!shown.contains('\n'), "{shown}");
        // The same through the loader the commands use.
        let loaded = Scenario::load(file.to_str().unwrap()).unwrap_err();
        assert_eq!(loaded.field, field);
    }
}

/// A square area of side `side` with `n` corners: a staircase along its
/// bottom edge, every step a corner, the rest a square (simple by construction).
fn many_corners(n: usize) -> String {
    let steps = (n - 2) / 2;
    let w = 100.0 / steps as f64;
    let mut pts = Vec::with_capacity(n);
    for k in 0..steps {
        let x = k as f64 * w;
        let y = if k % 2 == 0 { 0.0 } else { 0.5 };
        pts.push(format!("[{x}, {y}]"));
        pts.push(format!("[{}, {y}]", x + w));
    }
    pts.push("[100, 100]".into());
    pts.push("[0, 100]".into());
    format!("targets = [[50, 50]]\n[area]\npolygon = [{}]\n", pts.join(", "))
}

#[test]
fn a_hundred_thousand_corner_area_is_refused_at_once() {
    // Issue 11: it aborted after 57 s, allocating 15 GB.
    let text = many_corners(100_000);
    let e = refused(&text, "corners.toml");
    assert_eq!(e.field, "area.polygon");
    assert!(e.message.contains("100000") && e.message.contains("MAX_CORNERS = 1000"), "{e}");
}

#[test]
fn counts_beyond_their_limits_are_refused() {
    let square = "[area]\npolygon = [[0, 0], [300, 0], [300, 300], [0, 300]]\n";
    let targets: Vec<String> = (0..=limits::MAX_TARGETS).map(|k| format!("[{}, 1]", 1.0 + (k % 290) as f64)).collect();
    let e = refused(&format!("targets = [{}]\n{square}", targets.join(",")), "targets.toml");
    assert_eq!(e.field, "targets");
    assert!(e.message.contains("MAX_TARGETS = 10000"), "{e}");

    let one = "[[obstacles]]\ncircle = { center = [5, 5], radius = 1 }\n";
    let e = refused(&format!("{square}{}", one.repeat(limits::MAX_OBSTACLES + 1)), "obstacles.toml");
    assert_eq!(e.field, "obstacles");
    assert!(e.message.contains("MAX_OBSTACLES = 20000"), "{e}");

    // Fine apart, too much together: 458,000 vertices each tested against 9000 targets.
    let big = "[area]\npolygon = [[0, 0], [630, 0], [630, 630], [0, 630]]\n";
    let targets: Vec<String> = (0..9000).map(|k| format!("[{}, 1]", 1 + k % 620)).collect();
    let e = refused(&format!("targets = [{}]\n{big}", targets.join(",")), "work.toml");
    assert_eq!(e.field, "area.polygon");
    assert!(e.message.contains("MAX_VERTEX_WORK = 4e9"), "{e}");

    let e = refused(&format!("robots = 65536\n{square}"), "robots.toml");
    assert_eq!(e.field, "robots");
    assert!(e.message.contains("MAX_ROBOTS = 65535"), "{e}");
}

#[test]
fn every_range_and_time_has_a_finite_sane_bound() {
    let base = "[area]\npolygon = [[0, 0], [20, 0], [20, 16], [0, 16]]\n";
    for (key, bad) in [
        ("a", "1e9"),
        ("a", "1e-9"),
        ("r_rob", "100"),
        ("r_safe", "1e300"),
        ("r_so", "1e300"),
        ("r_c", "1e300"),
        ("t_trans", "1e308"),
        ("t_choice", "1e9"),
        ("t_exchange", "1e-9"),
        ("t_wait", "1e308"),
    ] {
        let e = refused(&format!("{base}[params]\n{key} = {bad}\n"), "p.toml");
        assert_eq!(e.field, format!("params.{key}"), "{e}");
        assert!(e.message.contains("MAX_") || e.message.contains("MIN_"), "{e}");
    }
    for (key, bad) in
        [("scale", "1e300"), ("max_step", "1e300"), ("turn", "1e300"), ("max_steer", "nan"), ("micro_steps", "0")]
    {
        let e = refused(&format!("{base}[lfp]\n{key} = {bad}\n"), "l.toml");
        assert_eq!(e.field, format!("lfp.{key}"), "{e}");
    }
}

#[test]
fn a_robot_count_from_the_command_line_obeys_the_limits_too() {
    let s = Scenario::load("paper").unwrap();
    let w = s.world();
    let e = s.start_vertices(&w, limits::MAX_ROBOTS + 1).unwrap_err();
    assert_eq!(e.field, "robots");
    assert!(e.message.contains("MAX_ROBOTS"), "{e}");
}

#[test]
fn every_builtin_and_the_biggest_random_options_are_admitted() {
    for name in gridswarm::scenario::BUILTIN {
        limits::admit(&Scenario::load(name).unwrap()).unwrap();
    }
    // The largest options `random:` accepts pass its own admission, which
    // is the scenario's (the map itself is drawn in the random_maps tests).
    let spec = gridswarm::scenario::random::Spec::parse("random:1,size=400x400,density=0.4,targets=1000,robots=1000");
    spec.unwrap();
}

#[test]
fn a_sample_of_the_largest_admitted_map_is_read_quickly() {
    // Right under MAX_RASTER_CELLS, the binding limit on a square at a = 1:
    // reading (not building) stays instant.
    let side = 630.0;
    let text = format!("targets = [[5, 5]]\n[area]\npolygon = [[0, 0], [{side}, 0], [{side}, {side}], [0, {side}]]\n");
    let (s, took) = cpu::timed(|| Scenario::parse(&text, "big.toml").unwrap());
    assert!(took < QUICK, "{took:?}");
    limits::admit(&s).unwrap();
}

#[test]
fn the_scenario_reference_lists_every_limit_with_its_value() {
    let doc = include_str!("../../docs/scenario-format.md");
    let floats = [
        ("MAX_COORD", limits::MAX_COORD),
        ("MIN_A", limits::MIN_A),
        ("MAX_A", limits::MAX_A),
        ("MAX_SENSING_SIDES", limits::MAX_SENSING_SIDES),
        ("MAX_RADIO_SIDES", limits::MAX_RADIO_SIDES),
        ("MIN_TIME", limits::MIN_TIME),
        ("MAX_TIME", limits::MAX_TIME),
        ("MAX_FRAME_VERTICES", limits::MAX_FRAME_VERTICES),
        ("MAX_RASTER_CELLS", limits::MAX_RASTER_CELLS),
        ("MAX_VERTEX_WORK", limits::MAX_VERTEX_WORK),
        ("MAX_ROBOT_VERTICES", limits::MAX_ROBOT_VERTICES),
        ("MAX_LFP_GAIN", limits::MAX_LFP_GAIN),
        ("MAX_FLIGHT_SIDES", limits::MAX_FLIGHT_SIDES),
        ("MAX_TURN_SIGMA", limits::MAX_TURN_SIGMA),
        ("MAX_SEARCH_WORK", limits::MAX_SEARCH_WORK),
    ];
    let counts = [
        ("MAX_CORNERS", limits::MAX_CORNERS),
        ("MAX_TOTAL_CORNERS", limits::MAX_TOTAL_CORNERS),
        ("MAX_OBSTACLES", limits::MAX_OBSTACLES),
        ("MAX_TARGETS", limits::MAX_TARGETS),
        ("MAX_ROBOTS", limits::MAX_ROBOTS),
        ("MAX_MICRO_STEPS", limits::MAX_MICRO_STEPS as usize),
        ("AREA_CORNER_WEIGHT", limits::AREA_CORNER_WEIGHT),
    ];
    let rows =
        floats.iter().map(|(n, v)| (*n, limits::show(*v))).chain(counts.iter().map(|(n, v)| (*n, v.to_string())));
    for (name, value) in rows {
        let row = format!("| `{name}` | {value} |");
        assert!(doc.contains(&row), "docs/scenario-format.md has no row {row}");
    }
    // And no row for a constant that does not exist.
    let listed = doc.lines().filter(|l| l.starts_with("| `M") || l.starts_with("| `AREA")).count();
    assert_eq!(listed, floats.len() + counts.len());
}

/// Issue 23: a point is `[x, y]`, exactly two numbers, wherever a point
/// is written; a longer or shorter array is an error naming the field.
#[test]
fn points_have_exactly_two_numbers() {
    let area = "[area]\npolygon = [[0, 0], [10, 0], [10, 10], [0, 10]]\n";
    let cases = [
        ("targets = [[5, 5, \"x\"]]\n".to_string() + area, "targets"),
        ("targets = [[5, 5, 1]]\n".to_string() + area, "targets"),
        ("targets = [[5]]\n".to_string() + area, "targets"),
        ("[area]\npolygon = [[0, 0], [10, 0, \"x\"], [10, 10], [0, 10]]\n".to_string(), "area.polygon"),
        (format!("{area}[[obstacles]]\ncircle = {{ center = [5, 5, 0], radius = 1 }}\n"), "obstacles"),
        (format!("{area}[[obstacles]]\nrect = {{ min = [2, 2], max = [3, 3, 3] }}\n"), "obstacles"),
        (format!("{area}[starts]\npoints = [[1, 1], [2, 1, []]]\n"), "starts.points"),
        (format!("{area}[starts]\nborder = {{ from = [0, 0, 0] }}\n"), "starts.border"),
    ];
    for (text, field) in cases {
        let e = refused(&text, "points.toml");
        let shown = e.to_string();
        assert!(e.field.starts_with(field), "{text}: {shown}");
        assert!(e.message.contains("exactly two numbers"), "{text}: {shown}");
        assert!(e.line().is_some(), "{shown}");
    }
    // Two numbers, integers or not, still read.
    Scenario::parse(&format!("targets = [[5, 5.5]]\n{area}"), "ok.toml").unwrap();
}
