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
        ("MAX_PERIMETER_SIDES", limits::MAX_PERIMETER_SIDES),
        ("MAX_COVER_WORK", limits::MAX_COVER_WORK),
        ("MAX_PAIR_WORK", limits::MAX_PAIR_WORK),
    ];
    let counts = [
        ("MAX_CORNERS", limits::MAX_CORNERS),
        ("MAX_TOTAL_CORNERS", limits::MAX_TOTAL_CORNERS),
        ("MAX_OBSTACLES", limits::MAX_OBSTACLES),
        ("MAX_TARGETS", limits::MAX_TARGETS),
        ("MAX_ROBOTS", limits::MAX_ROBOTS),
        ("MAX_MICRO_STEPS", limits::MAX_MICRO_STEPS as usize),
        ("AREA_CORNER_WEIGHT", limits::AREA_CORNER_WEIGHT),
        ("MAX_FILE_BYTES", gridswarm::scenario::MAX_FILE_BYTES as usize),
        ("MAX_IMAGE_BYTES", gridswarm::scenario::MAX_IMAGE_BYTES as usize),
        ("MAX_IMAGE_PIXELS", gridswarm::scenario::occupancy::MAX_IMAGE_PIXELS),
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

// Issue 23: maps whose checks were quadratic. Each is made here, at most
// 1 MB of TOML, and either refused at admission with the limit named or
// admitted and checked; the CPU bound is the 5 s, a failure guard
// only (most take a fraction of it).

/// `n` four-corner obstacles, one TOML table each, in a `w` x `h` area.
fn quads(w: f64, h: f64, quads: impl Iterator<Item = [(f64, f64); 4]>) -> String {
    let mut s = format!("[area]\npolygon = [[0, 0], [{w}, 0], [{w}, {h}], [0, {h}]]\n");
    for q in quads {
        let pts: Vec<String> = q.iter().map(|(x, y)| format!("[{x:.2}, {y:.2}]")).collect();
        s += &format!("[[obstacles]]\npolygon = [{}]\n", pts.join(", "));
    }
    assert!(s.len() as u64 <= gridswarm::scenario::MAX_FILE_BYTES, "{} bytes", s.len());
    s
}

/// Parses and, if admitted, builds the world and checks every assumption,
/// as `gridswarm check` does; the error if refused.
fn admitted_or_refused(text: &str, source: &str) -> Result<gridswarm::assumptions::Report, ScenarioError> {
    let (result, took) = cpu::timed(|| {
        let s = Scenario::parse(text, source)?;
        let w = s.world();
        let starts = s.start_vertices(&w, s.robots)?;
        Ok(gridswarm::assumptions::check(&s, &w, &starts))
    });
    assert!(took < Duration::from_secs(5), "{source}: took {took:?} of CPU");
    result
}

#[test]
fn eight_thousand_crowded_quads_are_refused_naming_the_pair_limit() {
    // 1 cm quads 3 cm apart: 32 million pairs within 3a. check took 85 s
    // and 2.8 GB on the machine and aborted under a 2 GB cap.
    let text = quads(
        40.0,
        40.0,
        (0..8000).map(|k| {
            let (x, y) = (5.0 + (k % 100) as f64 * 0.03, 5.0 + (k / 100) as f64 * 0.03);
            [(x, y), (x + 0.01, y), (x + 0.01, y + 0.01), (x, y + 0.01)]
        }),
    );
    let e = admitted_or_refused(&text, "crowded.toml").unwrap_err();
    assert_eq!(e.field, "obstacles", "{e}");
    assert!(e.message.contains("MAX_PAIR_WORK = 5e7"), "{e}");
}

#[test]
fn two_thousand_thin_quads_in_rows_are_admitted_and_checked() {
    // 5 cm x 50 cm quads 10 cm apart: 350,000 passages, all measured.
    let text = quads(
        30.0,
        30.0,
        (0..2000).map(|k| {
            let (x, y) = (5.0 + (k % 100) as f64 * 0.1, 5.0 + (k / 100) as f64 * 0.8);
            [(x, y), (x + 0.05, y), (x + 0.05, y + 0.5), (x, y + 0.5)]
        }),
    );
    let report = admitted_or_refused(&text, "rows.toml").unwrap();
    let passages = report.get("3.1.3").unwrap();
    assert!(!passages.holds && passages.detail.contains("narrowest of 347718 passages"), "{passages:?}");
}

#[test]
fn long_and_diagonal_slivers_are_refused_by_their_length_and_boxes() {
    // 8,000 slivers 596 m long: 9.5 million grid sides of edge (25 s).
    let text = quads(
        600.0,
        600.0,
        (0..8000).map(|k| {
            let y = 2.0 + k as f64 * 0.07;
            [(2.0, y), (598.0, y), (598.0, y + 0.02), (2.0, y + 0.02)]
        }),
    );
    let e = admitted_or_refused(&text, "long.toml").unwrap_err();
    assert!(e.message.contains("MAX_PERIMETER_SIDES = 2e5"), "{e}");
    // 450 diagonal slivers 212 m long: short enough, but each box holds
    // 23,000 m^2 of vertices to test (12 s).
    let text = quads(
        800.0,
        160.0,
        (0..450).map(|k| {
            let o = 2.0 + k as f64 * 0.5;
            [(o, 2.0), (o + 0.02, 2.0), (o + 150.02, 152.0), (o + 150.0, 152.0)]
        }),
    );
    let e = admitted_or_refused(&text, "diagonal.toml").unwrap_err();
    assert!(e.message.contains("MAX_COVER_WORK = 1e7"), "{e}");
    // 80 of them fit every limit, and are checked.
    let text = quads(
        800.0,
        160.0,
        (0..80).map(|k| {
            let o = 2.0 + k as f64 * 0.5;
            [(o, 2.0), (o + 0.02, 2.0), (o + 150.02, 152.0), (o + 150.0, 152.0)]
        }),
    );
    admitted_or_refused(&text, "diagonal80.toml").unwrap();
}

/// `k` combs of `corners` corners each, teeth `pitch` apart, one above
/// the other 1 m apart.
fn zigzags(k: usize, corners: usize, pitch: f64) -> String {
    let mut s = format!("[area]\npolygon = [[0, 0], [220, 0], [220, {}], [0, {0}]]\n", 20 + k);
    let teeth = (corners - 2) / 2;
    let p = if pitch >= 0.4 { 1 } else { 2 };
    for j in 0..k {
        let y0 = 3.0 + j as f64;
        let mut pts = Vec::with_capacity(corners);
        for t in 0..teeth {
            let x = 3.0 + t as f64 * pitch;
            pts.push(format!("[{x:.p$},{y0}]"));
            pts.push(format!("[{:.p$},{}]", x + pitch / 2.0, y0 + 0.5));
        }
        pts.push(format!("[{:.p$},{}]", 3.0 + teeth as f64 * pitch, y0 - 0.3));
        pts.push(format!("[3,{}]", y0 - 0.3));
        s += &format!("[[obstacles]]\npolygon=[{}]\n", pts.join(","));
    }
    assert!(s.len() as u64 <= gridswarm::scenario::MAX_FILE_BYTES, "{} bytes", s.len());
    s
}

#[test]
fn zigzag_polygons_of_a_thousand_corners_are_checked_or_refused_in_bounds() {
    // Ten, 100 m long: every pocket, passage and edge measured.
    let report = admitted_or_refused(&zigzags(10, 1000, 0.2), "zigzag10.toml").unwrap();
    assert!(report.get("3.1.2").unwrap().detail.contains("of 4984 pocket apexes"), "{report}");
    // Ninety 200 m long (992 KB) took 15 s and 1.25 GB: refused.
    let e = admitted_or_refused(&zigzags(90, 1000, 0.4), "zigzag90.toml").unwrap_err();
    assert!(e.message.contains("MAX_COVER_WORK") || e.message.contains("MAX_PAIR_WORK"), "{e}");
}

#[test]
fn many_pockets_are_each_matched_to_va_quickly() {
    // 190 stars of 300 corners, 28,500 pocket apexes over a 620 m map:
    // every apex against every vertex of Va took 16.7 s.
    let mut s = "[area]\npolygon = [[0, 0], [620, 0], [620, 620], [0, 620]]\n".to_string();
    for j in 0..190 {
        let (cx, cy) = (20.0 + (j % 14) as f64 * 43.0, 20.0 + (j / 14) as f64 * 43.0);
        let pts: Vec<String> = (0..300)
            .map(|t| {
                let (ang, r) = (std::f64::consts::TAU * t as f64 / 300.0, if t % 2 == 0 { 4.0 } else { 3.0 });
                format!("[{:.2},{:.2}]", cx + r * ang.cos(), cy + r * ang.sin())
            })
            .collect();
        s += &format!("[[obstacles]]\npolygon=[{}]\n", pts.join(","));
    }
    assert!(s.len() as u64 <= gridswarm::scenario::MAX_FILE_BYTES);
    let report = admitted_or_refused(&s, "stars.toml").unwrap();
    assert!(report.get("3.1.2").unwrap().detail.contains("of 28504 pocket apexes"), "{report}");
}

#[test]
fn many_start_points_and_targets_beside_many_corners_are_read_quickly() {
    // 100 stars of 200 corners, 8,000 targets and 50,000 start points:
    // each point was tested against every obstacle, and each start point
    // against every earlier one (65,535 points: 11.8 s of check).
    let mut s = "robots = 3\n".to_string();
    let targets: Vec<String> =
        (0..8_000).map(|k| format!("[{}.5,{}.5]", (k % 250) * 2 + 3, (k / 250) * 2 + 3)).collect();
    s += &format!("targets=[{}]\n", targets.join(","));
    s += "[area]\npolygon = [[0, 0], [600, 0], [600, 600], [0, 600]]\n";
    for j in 0..100 {
        let (cx, cy) = (10.0 + (j % 50) as f64 * 11.5, 550.0 + (j / 50) as f64 * 30.0);
        let pts: Vec<String> = (0..200)
            .map(|t| {
                let (ang, r) = (std::f64::consts::TAU * t as f64 / 200.0, if t % 2 == 0 { 4.0 } else { 3.5 });
                format!("[{:.2},{:.2}]", cx + r * ang.cos(), cy + r * ang.sin())
            })
            .collect();
        s += &format!("[[obstacles]]\npolygon=[{}]\n", pts.join(","));
    }
    let starts: Vec<String> = (0..50_000).map(|k| format!("[{},{}]", (k % 250) * 2 + 3, (k / 250) * 2 + 3)).collect();
    s += &format!("[starts]\npoints=[{}]\n", starts.join(","));
    assert!(s.len() as u64 <= gridswarm::scenario::MAX_FILE_BYTES, "{} bytes", s.len());
    let (parsed, took) = cpu::timed(|| Scenario::parse(&s, "points.toml"));
    assert!(took < QUICK, "{took:?}");
    let parsed = parsed.unwrap();
    assert_eq!((parsed.targets.len(), parsed.obstacles.len()), (8_000, 100));
    // A start point inside a star, and two on one vertex, are still found.
    let inside = s.replace("[starts]\npoints=[[3,3],", "[starts]\npoints=[[10,550],");
    let e = refused(&inside, "inside.toml");
    assert!(e.field == "starts.points[0]" && e.message.contains("not accessible"), "{e}");
    let twice = s.replace("[starts]\npoints=[[3,3],", "[starts]\npoints=[[5,3],");
    let e = refused(&twice, "twice.toml");
    assert!(e.field == "starts.points[1]" && e.message.contains("like starts.points[0]"), "{e}");
}
