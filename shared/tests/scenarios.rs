//! Scenario files and the assumption checker, end to end: the built-ins
//! parse and meet every assumption, bad files fail with the field and the
//! line named, and start vertices are placed as documented.

use gridswarm::assumptions::{self, Report};
use gridswarm::geometry::{Point, Shape};
use gridswarm::grid::VertexId;
use gridswarm::lattice::LatticeKind;
use gridswarm::params::Situation;
use gridswarm::scenario::{Scenario, ScenarioError, Starts, BUILTIN};
use gridswarm::world::World;

fn report(s: &Scenario, robots: usize) -> (World, Vec<VertexId>, Report) {
    let w = s.world();
    let starts = s.start_vertices(&w, robots).unwrap_or_else(|e| panic!("{e}"));
    let r = assumptions::check(s, &w, &starts);
    (w, starts, r)
}

fn parse_err(text: &str) -> ScenarioError {
    match Scenario::parse(text, "bad.toml") {
        Ok(s) => panic!("parsed but should not have: {s:?}"),
        Err(e) => {
            let shown = e.to_string();
            assert!(!shown.contains('\n'), "error is not one line: {shown:?}");
            assert!(shown.starts_with("bad.toml:"), "{shown}");
            e
        }
    }
}

/// The 1-based line of the first occurrence of `needle` in `text`.
fn line_of(text: &str, needle: &str) -> usize {
    text[..text.find(needle).expect("needle")].matches('\n').count() + 1
}

const BASE: &str = "\
name = \"t\"
robots = 2
targets = [[2, 2], [8, 8]]
[area]
polygon = [[0, 0], [10, 0], [10, 10], [0, 10]]
";

#[test]
fn builtins_parse_and_meet_every_assumption() {
    assert_eq!(Scenario::default_name(), "paper");
    assert_eq!(BUILTIN, &["paper", "open", "cave", "large", "small", "comb"]);
    for &name in BUILTIN {
        let s = Scenario::builtin(name).expect(name);
        assert_eq!(s.name, name);
        assert_eq!(Scenario::load(name).unwrap(), s);
        let (w, _, r) = report(&s, s.robots);
        assert!(r.all_hold(), "{name}:\n{r}");
        assert_eq!(r.get("targets").map(|c| c.holds), Some(true));
        // Every target is detectable from Va.
        let va = w.reachable_from(&s.start_vertices(&w, 1).unwrap());
        for (t, &p) in s.targets.iter().enumerate() {
            let seen = (0..w.grid.len() as VertexId)
                .any(|v| va[v as usize] && (w.grid.position(v) - p).norm() <= w.params.r_st);
            assert!(seen, "{name}: target {t} at {p:?} not detectable");
        }
    }
}

#[test]
fn report_lists_every_check_once() {
    let s = Scenario::builtin("paper").unwrap();
    let (_, _, r) = report(&s, 3);
    let ids: Vec<&str> = r.checks.iter().map(|c| c.id).collect();
    assert_eq!(ids, ["2.4", "2.5", "r_safe", "S0", "3.1.1", "3.1.2", "3.1.3", "Va", "starts", "targets", "coverage"]);
    let text = r.to_string();
    assert_eq!(text.lines().count(), r.checks.len());
    assert!(text.lines().all(|l| l.starts_with("ok ")), "{text}");
    assert!(text.contains("r_so = 1.30 >= a + r_safe = 1.30"), "{text}");
    assert!(text.contains("r_c = 2.05 >= 2a + r_safe - r_rob = 2.05"), "{text}");
}

#[test]
fn s0_fails_where_geometry_alone_brings_robots_within_2_r_safe() {
    // Issue 36's reproducer: adjacent vertices exactly 2 r_safe apart.
    let with = |a: f64, r_safe: f64| {
        let mut s = Scenario::parse(BASE, "t.toml").unwrap();
        s.params = gridswarm::params::Params::derived(a, 0.2, r_safe);
        report(&s, 2).2.get("S0").unwrap().clone()
    };
    let c = with(0.5, 0.25);
    assert!(!c.holds, "{c:?}");
    assert!(c.detail.contains("robots on adjacent vertices are 0.500 m apart"), "{c:?}");
    assert!(c.detail.contains("passes one on a vertex off it 0.433 m away"), "{c:?}");
    assert!(c.detail.ends_with("not more than 2 r_safe = 0.500"), "{c:?}");
    // a = 0.51 has no collision in that run, but a robot passing another
    // along an edge comes within sqrt(3)/2 a = 0.442 < 0.5: the premise of
    // the safety argument (ARCHITECTURE.md "Safety", S0) fails.
    assert!(!with(0.51, 0.25).holds);
    assert!(with(0.58, 0.25).holds && !with(0.57, 0.25).holds);
    let ok = with(1.0, 0.3);
    assert!(ok.holds && ok.detail.contains("0.866 m away, more than 2 r_safe = 0.600"), "{ok:?}");
}

#[test]
fn the_lattices_nearest_approaches_are_what_s0_says() {
    use gridswarm::assumptions::Spacing;
    use gridswarm::lattice::Lattice;
    let s = Spacing::of(Lattice::new(LatticeKind::Triangular, 1.0));
    assert!((s.adjacent - 1.0).abs() < 1e-12 && (s.passing - 3f64.sqrt() / 2.0).abs() < 1e-12, "{s:?}");
    // Robots more than 2a apart (sqrt(7) a at the nearest) can end on
    // adjacent vertices, a apart, and come no closer: the lattice colouring
    // (Lattice::class) rests on this.
    assert!((s.apart - 1.0).abs() < 1e-12, "{s:?}");
    let sq = Spacing::of(Lattice::new(LatticeKind::Square, 2.0));
    assert!((sq.adjacent - 2.0).abs() < 1e-12 && (sq.passing - 2.0).abs() < 1e-12, "{sq:?}");
    let hex = Spacing::of(Lattice::new(LatticeKind::Hexagonal, 1.0));
    assert!((hex.adjacent - 1.0).abs() < 1e-12 && hex.passing > 0.8 && hex.apart > 0.0, "{hex:?}");
}

#[test]
fn situation_1_without_targets_fails_the_targets_check() {
    let mut s = Scenario::parse(BASE, "t.toml").unwrap();
    s.targets.clear();
    let c = report(&s, 2).2.get("targets").unwrap().clone();
    assert!(!c.holds && c.detail.contains("no targets in situation 1"), "{c:?}");
    s.situation = Situation::Two;
    assert!(report(&s, 2).2.get("targets").unwrap().holds);
}

#[test]
fn paper_has_what_the_brief_asks() {
    let s = Scenario::builtin("paper").unwrap();
    assert_eq!((s.robots, s.situation, s.grid), (3, Situation::One, LatticeKind::Triangular));
    assert_eq!(s.targets.len(), 9);
    assert!(matches!(s.starts, Starts::Border { .. }));
    assert!(s.obstacles.iter().any(|o| matches!(o, Shape::Circle(_))));
    let reflex = |pts: &[Point], sign: f64| {
        let n = pts.len();
        (0..n).any(|k| {
            let (u, v) = (pts[k] - pts[(k + n - 1) % n], pts[(k + 1) % n] - pts[k]);
            sign * (u.x * v.y - u.y * v.x) < 0.0
        })
    };
    // A concave obstacle, and a concave part of the boundary.
    assert!(s.obstacles.iter().any(|o| match o {
        Shape::Polygon(p) => reflex(&p.points, p.signed_area().signum()),
        _ => false,
    }));
    assert!(reflex(&s.area.points, s.area.signed_area().signum()));
    let (lo, hi) = s.area.bounding_box();
    assert!((hi.x - lo.x - 20.0).abs() < 2.0 && (hi.y - lo.y - 16.0).abs() < 2.5);
}

#[test]
fn cave_passages_hold_with_equality() {
    let s = Scenario::builtin("cave").unwrap();
    let (_, _, r) = report(&s, 3);
    let c = r.get("3.1.3").unwrap();
    assert!(c.holds, "{r}");
    assert!(c.detail.contains("1.600 >= W_pass = 1.600"), "{}", c.detail);
}

#[test]
fn paper_starts_for_13_robots_are_distinct_and_in_va() {
    let s = Scenario::builtin("paper").unwrap();
    let w = s.world();
    let starts = s.start_vertices(&w, 13).unwrap();
    assert_eq!(starts.len(), 13);
    let va = w.reachable_from(&starts[..1]);
    for (k, &v) in starts.iter().enumerate() {
        assert!(va[v as usize], "robot {k} outside Va");
        assert!(!starts[..k].contains(&v), "robot {k} shares a vertex");
    }
    // Deterministic, and a prefix of the placement for more robots.
    assert_eq!(s.start_vertices(&w, 13).unwrap(), starts);
    assert_eq!(s.start_vertices(&w, 5).unwrap(), starts[..5]);
    // The first robot is at the border vertex nearest the bottom-left corner.
    assert!((w.grid.position(starts[0]) - Point::new(0.5, 0.866)).norm() < 0.01);
}

#[test]
fn large_has_room_for_200_robots_along_the_border() {
    let t = std::time::Instant::now();
    let s = Scenario::builtin("large").unwrap();
    let w = s.world();
    let built = t.elapsed();
    let accessible = w.accessible_vertices().count();
    assert!(accessible >= 5000, "{accessible} accessible vertices");
    assert_eq!(s.robots, 50);
    let starts = s.start_vertices(&w, 200).unwrap();
    assert_eq!(starts.len(), 200);
    let reach = w.params.a + w.params.r_safe + 1e-9;
    for (k, &v) in starts.iter().enumerate() {
        assert!(w.is_accessible(v));
        assert!(!starts[..k].contains(&v), "robot {k} shares a vertex");
        // A chain: each vertex is one traversable edge from one taken before.
        if k > 0 {
            assert!(starts[..k].iter().any(|&u| w.can_move(u, v)), "robot {k} is not next to an earlier one");
        }
        // Along the area's border, not pushed inland.
        assert!(w.area.boundary_distance(w.grid.position(v)) <= reach, "robot {k} is off the border");
    }
    // Generous: the test profile is not the release profile.
    assert!(built.as_secs_f64() < 5.0, "large took {built:?} to build");
}

#[test]
fn points_starts_snap_to_vertices() {
    let text = format!("{BASE}[starts]\npoints = [[1.1, 0.9], [3, 1], [5, 1]]\n");
    let s = Scenario::parse(&text, "t.toml").unwrap();
    let w = s.world();
    let v = s.start_vertices(&w, 2).unwrap();
    assert_eq!(v, vec![w.grid.nearest(Point::new(1.1, 0.9)).unwrap(), w.grid.nearest(Point::new(3.0, 1.0)).unwrap()]);
    assert_eq!(s.start_vertices(&w, 3).unwrap().len(), 3);
    let e = s.start_vertices(&w, 4).unwrap_err();
    assert_eq!(e.field, "starts.points");
    assert!(e.to_string().contains("3 start points for 4 robots"), "{e}");
}

#[test]
fn defaults_and_optional_tables() {
    let s = Scenario::parse(BASE, "dir/t.toml").unwrap();
    assert_eq!(s.params, gridswarm::params::Params::default());
    assert_eq!(s.lfp, gridswarm::lfp::LfpParams::default());
    assert_eq!(s.starts, Starts::Border { from: Point::new(0.0, 0.0) });
    assert_eq!((s.situation, s.grid), (Situation::One, LatticeKind::Triangular));
    let text = "robots = 1\ngrid = \"hexagonal\"\nsituation = 2\n[params]\na = 2\nr_st = 3\n[area]\npolygon = [[0, 0], [10, 0], [0, 10]]\n[lfp]\nbeta = 1.2\n";
    let s = Scenario::parse(text, "dir/tri.toml").unwrap();
    assert_eq!(s.name, "tri");
    assert_eq!((s.grid, s.situation), (LatticeKind::Hexagonal, Situation::Two));
    assert_eq!((s.params.a, s.params.r_st, s.params.r_so), (2.0, 3.0, 2.3));
    assert_eq!(s.lfp.beta, 1.2);
    let s = Scenario::parse(&format!("{BASE}[[obstacles]]\nrect = {{ min = [4, 4], max = [6, 5] }}\n"), "t").unwrap();
    assert!(matches!(&s.obstacles[0], Shape::Polygon(p) if p.points.len() == 4 && p.signed_area() == 2.0));
}

#[test]
fn unknown_field_names_field_and_line() {
    let text = format!("{BASE}[params]\na = 1.0\nr_sfae = 0.3\n");
    let e = parse_err(&text);
    assert_eq!(e.field, "params.r_sfae");
    assert_eq!(e.line(), Some(line_of(&text, "r_sfae")));
    let shown = e.to_string();
    assert!(
        shown.starts_with(&format!("bad.toml:{}:1: params.r_sfae: unknown field `r_sfae`", line_of(&text, "r_sfae"))),
        "{shown}"
    );

    let text = format!("colour = \"red\"\n{BASE}");
    let e = parse_err(&text);
    assert_eq!((e.field.as_str(), e.line()), ("colour", Some(1)));

    let text = format!("{BASE}[[obstacles]]\ncircle = {{ center = [5, 5], radius = 1, height = 2 }}\n");
    let e = parse_err(&text);
    assert_eq!(e.field, "obstacles[0].circle.height");
    assert_eq!(e.line(), Some(line_of(&text, "height")));

    let e = parse_err(&format!("{BASE}[lfp]\nbogus = 1\n"));
    assert_eq!(e.field, "lfp.bogus");
}

#[test]
fn wrong_type_names_field_and_line() {
    let text = BASE.replace("robots = 2", "robots = \"two\"");
    let e = parse_err(&text);
    assert_eq!((e.field.as_str(), e.line()), ("robots", Some(2)));
    assert!(e.message.contains("invalid type"), "{e}");

    let text = format!("{BASE}[[obstacles]]\npolygon = [[1, 1], [2, 1], [2]]\n");
    let e = parse_err(&text);
    assert_eq!(e.field, "obstacles[0].polygon[2]");
    assert_eq!(e.line(), Some(line_of(&text, "polygon = [[1, 1]")));

    let e = parse_err(&BASE.replace("name = \"t\"", "name = \"t\"\ngrid = \"hex\""));
    assert_eq!((e.field.as_str(), e.line()), ("grid", Some(2)));

    let e = parse_err("robots = 2\n[area\npolygon = []\n");
    assert_eq!(e.line(), Some(2));
}

#[test]
fn negative_radius() {
    let text = format!(
        "{BASE}[[obstacles]]\ncircle = {{ center = [3, 6], radius = 1 }}\n[[obstacles]]\ncircle = {{ center = [7, 3], radius = -1 }}\n"
    );
    let e = parse_err(&text);
    let line = line_of(&text, "radius = -1");
    assert_eq!(e.to_string(), format!("bad.toml:{line}:38: obstacles[1].circle.radius: must be > 0, got -1"));
}

#[test]
fn bad_params() {
    let e = parse_err(&format!("{BASE}[params]\nr_safe = 0.2\n"));
    assert_eq!(e.field, "params.r_safe");
    assert!(e.message.contains("r_rob"), "{e}");
    let e = parse_err(&format!("{BASE}[params]\na = 0\n"));
    assert_eq!((e.field.as_str(), e.line()), ("params.a", Some(7)));
    let e = parse_err(&format!("{BASE}[params]\nr_st = -1.3\n"));
    assert_eq!(e.field, "params.r_st");
    let e = parse_err(&format!("{BASE}[params]\nr_safe = nan\n"));
    assert_eq!(e.field, "params.r_safe");
    let e = parse_err(&format!("{BASE}[lfp]\nbeta = 2.5\n"));
    assert_eq!(e.field, "lfp.beta");
}

#[test]
fn bad_area() {
    let bowtie = BASE.replace("[[0, 0], [10, 0], [10, 10], [0, 10]]", "[[0, 0], [10, 10], [10, 0], [0, 10]]");
    let e = parse_err(&bowtie);
    assert_eq!((e.field.as_str(), e.line()), ("area.polygon", Some(5)));
    assert!(e.message.contains("not simple"), "{e}");

    let e = parse_err(&BASE.replace("[[0, 0], [10, 0], [10, 10], [0, 10]]", "[[0, 0], [10, 0]]"));
    assert!(e.message.contains("at least 3"), "{e}");
    let e = parse_err(&BASE.replace("[[0, 0], [10, 0], [10, 10], [0, 10]]", "[[0, 0], [5, 5], [10, 10]]"));
    assert!(e.field.starts_with("area.polygon["), "{e}");
    assert!(e.message.contains("folds back"), "{e}");
    let e = parse_err(&BASE.replace("[[0, 0], [10, 0], [10, 10], [0, 10]]", "[[0, 0], [5, 0], [10, 0], [5, 0]]"));
    assert!(e.field.starts_with("area.polygon"), "{e}");
    let e = parse_err("robots = 1\n");
    assert!(e.message.contains("missing field `area`"), "{e}");
    assert_eq!((e.field.as_str(), e.line()), ("area", Some(1)));
    let text = format!("{BASE}[[obstacles]]\ncircle = {{ center = [5, 5] }}\n");
    let e = parse_err(&text);
    assert_eq!((e.field.as_str(), e.line()), ("obstacles[0].circle.radius", Some(7)));
}

#[test]
fn bad_obstacles() {
    let over = format!(
        "{BASE}[[obstacles]]\nrect = {{ min = [4, 4], max = [6, 6] }}\n[[obstacles]]\ncircle = {{ center = [6.5, 5], radius = 1 }}\n"
    );
    let e = parse_err(&over);
    // An error about a whole obstacle points at its table's header.
    assert_eq!((e.field.as_str(), e.line()), ("obstacles[1]", Some(line_of(&over, "circle") - 1)));
    assert!(e.message.contains("overlaps or touches obstacles[0]"), "{e}");

    let nested = format!("{BASE}[[obstacles]]\nrect = {{ min = [3, 3], max = [7, 7] }}\n[[obstacles]]\npolygon = [[4, 4], [5, 4], [5, 5]]\n");
    assert_eq!(parse_err(&nested).field, "obstacles[1]");

    let crossing = format!("{BASE}[[obstacles]]\nrect = {{ min = [8, 4], max = [12, 6] }}\n");
    let e = parse_err(&crossing);
    assert_eq!(e.field, "obstacles[0]");
    assert!(e.message.contains("inside the area"), "{e}");
    let outside = format!("{BASE}[[obstacles]]\ncircle = {{ center = [20, 5], radius = 1 }}\n");
    assert!(parse_err(&outside).message.contains("outside the area"));

    let both = format!(
        "{BASE}[[obstacles]]\ncircle = {{ center = [5, 5], radius = 1 }}\nrect = {{ min = [1, 1], max = [2, 2] }}\n"
    );
    assert!(parse_err(&both).message.contains("exactly one"));
    let flat = format!("{BASE}[[obstacles]]\nrect = {{ min = [4, 4], max = [6, 4] }}\n");
    assert_eq!(parse_err(&flat).field, "obstacles[0].rect.max");
}

#[test]
fn target_outside_ad() {
    let inside = format!("{BASE}[[obstacles]]\ncircle = {{ center = [8, 8.5], radius = 1 }}\n");
    let e = parse_err(&inside);
    assert_eq!((e.field.as_str(), e.line()), ("targets[1]", Some(3)));
    assert!(e.message.contains("inside obstacles[0]"), "{e}");
    let out = BASE.replace("[8, 8]]", "[8, 18]]");
    assert!(parse_err(&out).message.contains("outside the area"));
}

/// A laser reads where a target is, not which one it is: two targets
/// closer than its resolution would be one to the robots.
#[test]
fn two_targets_on_one_spot_are_refused() {
    let same = BASE.replace("[8, 8]]", "[8, 8], [8.0004, 8]]");
    let e = parse_err(&same);
    assert_eq!(e.field, "targets[2]");
    assert!(e.message.contains("where targets[1] is"), "{e}");
    let apart = BASE.replace("[8, 8]]", "[8, 8], [8.01, 8]]");
    let s = Scenario::parse(&apart, "ok.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.targets.len(), 3);
}

#[test]
fn bad_counts_and_starts() {
    let e = parse_err(&BASE.replace("name = \"t\"", "name = \"t\"\nsituation = 3"));
    assert_eq!((e.field.as_str(), e.line()), ("situation", Some(2)));
    assert!(e.message.contains("got 3"), "{e}");
    let e = parse_err(&BASE.replace("robots = 2", "robots = 0"));
    assert_eq!((e.field.as_str(), e.line()), ("robots", Some(2)));

    let few = format!("{BASE}[starts]\npoints = [[1, 1]]\n");
    let e = parse_err(&few);
    assert_eq!((e.field.as_str(), e.line()), ("starts.points", Some(line_of(&few, "points"))));
    assert!(e.message.contains("1 start points for robots = 2"), "{e}");

    let blocked = format!("{BASE}[starts]\npoints = [[1, 1], [0.1, 0.1]]\n");
    let e = parse_err(&blocked);
    assert_eq!(e.field, "starts.points[1]");
    assert!(e.message.contains("not accessible"), "{e}");

    let shared = format!("{BASE}[starts]\npoints = [[1.5, 0.9], [1.6, 0.8]]\n");
    let e = parse_err(&shared);
    assert_eq!(e.field, "starts.points[1]");
    assert!(e.message.contains("starts.points[0]"), "{e}");

    let both = format!("{BASE}[starts]\npoints = [[1, 1], [3, 1]]\nborder = {{ from = [0, 0] }}\n");
    assert_eq!(parse_err(&both).field, "starts");
}

#[test]
fn load_reports_missing_files_and_builtins() {
    let e = Scenario::load("/nonexistent/dir/x.toml").unwrap_err();
    let shown = e.to_string();
    assert!(shown.starts_with("/nonexistent/dir/x.toml: "), "{shown}");
    assert!(shown.contains("paper, open, cave, large"), "{shown}");

    let dir = std::env::temp_dir().join(format!("gridswarm-scenario-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("mine.toml");
    std::fs::write(&path, BASE.replace("robots = 2", "robots = -2")).unwrap();
    let e = Scenario::load(path.to_str().unwrap()).unwrap_err();
    assert_eq!((e.file.as_str(), e.field.as_str(), e.line()), (path.to_str().unwrap(), "robots", Some(2)));
    std::fs::write(&path, BASE).unwrap();
    assert_eq!(Scenario::load(path.to_str().unwrap()).unwrap().name, "t");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn failing_assumptions_are_reported_with_numbers() {
    // Ranges below their assumptions.
    let s = Scenario::parse(&format!("{BASE}[params]\nr_st = 1.0\nr_c = 1.5\n"), "t").unwrap();
    let (_, _, r) = report(&s, 2);
    assert!(!r.all_hold());
    let failed: Vec<&str> = r.failures().map(|c| c.id).collect();
    assert!(failed.contains(&"3.1.1") && failed.contains(&"2.5"), "{r}");
    assert!(r.to_string().contains("FAILS 3.1.1"), "{r}");
    assert!(r.get("3.1.1").unwrap().detail.contains("r_st = 1.00 < a + r_safe = 1.30"), "{r}");

    // Two obstacles 1 m apart: a passage narrower than W_pass.
    let narrow = format!(
        "{BASE}[[obstacles]]\nrect = {{ min = [3, 3], max = [4.5, 7] }}\n[[obstacles]]\nrect = {{ min = [5.5, 3], max = [7, 7] }}\n"
    );
    let s = Scenario::parse(&narrow, "t").unwrap();
    let (_, _, r) = report(&s, 2);
    let c = r.get("3.1.3").unwrap();
    assert!(!c.holds);
    assert!(
        c.detail.contains("obstacles[0] and obstacles[1]") && c.detail.contains("1.000 < W_pass = 1.600"),
        "{}",
        c.detail
    );

    // A target walled in by a C-shaped obstacle whose mouth is too narrow
    // for a robot: not detectable from Va.
    let walled = "robots = 2\ntargets = [[10, 10]]\n[area]\npolygon = [[0, 0], [20, 0], [20, 20], [0, 20]]\n\
        [[obstacles]]\npolygon = [[7, 7], [13, 7], [13, 9.8], [12.5, 9.8], [12.5, 7.5], [7.5, 7.5], [7.5, 12.5], \
        [12.5, 12.5], [12.5, 10.2], [13, 10.2], [13, 13], [7, 13]]\n";
    let s = Scenario::parse(walled, "t").unwrap();
    let (_, _, r) = report(&s, 2);
    for id in ["targets", "coverage", "3.1.3"] {
        assert!(!r.get(id).unwrap().holds, "{id} should fail:\n{r}");
    }
    assert!(r.get("targets").unwrap().detail.contains("targets[0] (10.00, 10.00)"), "{r}");
    assert!(r.get("3.1.3").unwrap().detail.contains("of obstacles[0]"), "{r}");
}

#[test]
fn tight_pocket_fails_3_1_2() {
    // A 30-degree spike of the area: no vertex comes near its apex.
    let text = "robots = 1\n[area]\npolygon = [[0, 0], [10, 0], [10, 10], [5, 10], [2.5, 19.33], [0, 10]]\n";
    let s = Scenario::parse(text, "t").unwrap();
    let (_, _, r) = report(&s, 1);
    let c = r.get("3.1.2").unwrap();
    assert!(!c.holds, "{r}");
    assert!(c.detail.contains("area corner 4 at (2.50, 19.33)"), "{}", c.detail);
    // A straight-walled rectangle has no pocket it cannot see.
    let s = Scenario::parse(BASE, "t").unwrap();
    assert!(report(&s, 2).2.all_hold());
}

#[test]
fn border_chain_falls_back_to_all_of_va() {
    // A 6 m x 5 m room: its border ring is shorter than Va.
    let text = "robots = 1\n[area]\npolygon = [[0, 0], [6, 0], [6, 5], [0, 5]]\n";
    let s = Scenario::parse(text, "t").unwrap();
    let w = s.world();
    let first = s.start_vertices(&w, 1).unwrap();
    let va = w.reachable_from(&first).iter().filter(|&&b| b).count();
    let all = s.start_vertices(&w, va).unwrap();
    for (k, &v) in all.iter().enumerate().skip(1) {
        assert!(!all[..k].contains(&v));
        assert!(all[..k].iter().any(|&u| w.can_move(u, v)), "robot {k} is not next to an earlier one");
    }
    let e = s.start_vertices(&w, va + 1).unwrap_err();
    assert_eq!(e.field, "starts.border");
    assert!(e.message.contains(&format!("only {va} vertices")), "{e}");
}

#[test]
fn other_lattices_place_robots_too() {
    for grid in ["square", "hexagonal"] {
        let mut s = Scenario::builtin("paper").unwrap();
        s.grid = grid.parse().unwrap();
        let w = s.world();
        let starts = s.start_vertices(&w, 13).unwrap();
        for (k, &v) in starts.iter().enumerate().skip(1) {
            assert!(starts[..k].iter().any(|&u| w.can_move(u, v)), "{grid}: robot {k}");
        }
        // The paper's point (Sec. 3): only the triangular grid sees every
        // corner with r_st = a + r_safe.
        let r = assumptions::check(&s, &w, &starts);
        assert!(!r.get("3.1.2").unwrap().holds && !r.get("coverage").unwrap().holds, "{grid}:\n{r}");
    }
}

/// docs/scenario-format.md's reference sets every field: it must parse
/// (every section denies unknown fields, so a misspelt key fails), and every
/// parameter the code knows must appear in it, so the reference cannot fall
/// behind the code.
#[test]
fn docs_scenario_reference_parses() {
    let doc = include_str!("../../docs/scenario-format.md");
    let start = doc.find("```toml\n").expect("a toml block") + "```toml\n".len();
    let text = &doc[start..start + doc[start..].find("```").expect("the block ends")];
    let s = Scenario::parse(text, "docs/scenario-format.md").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((s.name.as_str(), s.robots, s.targets.len(), s.obstacles.len()), ("reference", 4, 2, 3));
    let table: toml::Table = toml::from_str(text).unwrap();
    let keys = |section: &str| -> Vec<String> { table[section].as_table().unwrap().keys().cloned().collect() };
    let params = serde_json::to_value(s.params).unwrap();
    for k in params.as_object().unwrap().keys() {
        assert!(keys("params").contains(k), "[params] {k} is not in the reference");
    }
    let lfp = serde_json::to_value(gridswarm::lfp::LfpParams::default()).unwrap();
    for k in lfp.as_object().unwrap().keys() {
        assert!(keys("lfp").contains(k), "[lfp] {k} is not in the reference");
    }
}
