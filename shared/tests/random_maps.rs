//! Random maps (`random:SEED[,options]`): the same text gives the same map,
//! maps pass every assumption check or break exactly the one asked for, and
//! a map written as TOML reads back to itself.

use std::time::Instant;

use gridswarm::assumptions;
use gridswarm::scenario::random::{self, Break, Spec};
use gridswarm::scenario::Scenario;

fn failing(s: &Scenario) -> Vec<&'static str> {
    let w = s.world();
    let starts = s.start_vertices(&w, s.robots).unwrap();
    let r = assumptions::check(s, &w, &starts);
    let mut f: Vec<&'static str> = r.failures().map(|c| c.id).collect();
    f.sort_unstable();
    f
}

#[test]
fn same_text_same_map_bytes() {
    let a = Scenario::load("random:5").unwrap().to_toml("");
    let b = Scenario::load("random:5").unwrap().to_toml("");
    assert_eq!(a, b);
    // Another spelling of the same options is the same map, named alike.
    let c = Scenario::load("random:5, density=0.15,size=20x16").unwrap();
    assert_eq!(c.to_toml(""), a);
    assert_eq!(c.name, "random:5");
    assert_ne!(Scenario::load("random:6").unwrap().to_toml(""), a);
    assert_ne!(Scenario::load("random:5,density=0.2").unwrap().to_toml(""), a);
}

#[test]
fn toml_reads_back_to_the_same_scenario() {
    for text in ["random:3", "random:4,size=30x20,density=0.25,targets=5,robots=7", "random:2,break=3.1.2"] {
        let s = Scenario::load(text).unwrap();
        let back = Scenario::parse(&s.to_toml("a generated map"), "x.toml").unwrap();
        assert_eq!(back, s, "{text}");
    }
    let builtin = Scenario::builtin("paper").unwrap();
    assert_eq!(Scenario::parse(&builtin.to_toml(""), "paper.toml").unwrap(), builtin);
}

#[test]
fn two_hundred_default_maps_pass_every_check() {
    let mut spent = 0.0;
    let mut attempts = 0;
    for seed in 0..200 {
        let started = Instant::now();
        let g = random::generate(&Spec::parse(&format!("random:{seed}")).unwrap()).unwrap();
        spent += started.elapsed().as_secs_f64();
        attempts += g.attempts;
        let s = &g.scenario;
        assert_eq!(failing(s), Vec::<&str>::new(), "random:{seed}");
        assert_eq!(s.targets.len(), 9);
        assert!(!s.obstacles.is_empty(), "random:{seed} has no obstacle");
        let density = random::obstacle_area(s) / s.area.signed_area().abs();
        assert!((0.15..0.3).contains(&density), "random:{seed}: density {density}");
    }
    let ms = spent * 1000.0 / 200.0;
    eprintln!("default maps: {ms:.2} ms per map, {:.2} attempts per map", attempts as f64 / 200.0);
}

#[test]
fn options_shape_the_map() {
    let s = Scenario::load("random:9,size=40x25,density=0.3,passage=2.5,targets=4,robots=6").unwrap();
    let (lo, hi) = s.area.bounding_box();
    assert!((hi.x - lo.x - 40.0).abs() <= 0.5 && (hi.y - lo.y - 25.0).abs() <= 1.0, "{lo} {hi}");
    assert_eq!((s.targets.len(), s.robots), (4, 6));
    let density = random::obstacle_area(&s) / s.area.signed_area().abs();
    assert!(density >= 0.3, "{density}");
    assert_eq!(failing(&s), Vec::<&str>::new());
    let w = s.world();
    let r = assumptions::check(&s, &w, &s.start_vertices(&w, 6).unwrap());
    // Every gap the check measures is at least the passage asked for.
    let detail = &r.get("3.1.3").unwrap().detail;
    if let Some(width) = detail.split(": ").nth(2).and_then(|x| x.split(' ').next()) {
        assert!(width.parse::<f64>().unwrap() >= 2.5, "{detail}");
    }
}

#[test]
fn break_breaks_exactly_that_assumption() {
    for b in Break::ALL {
        for seed in 0..20 {
            let text = format!("random:{seed},break={}", b.id());
            let s = Scenario::load(&text).unwrap_or_else(|e| panic!("{e}"));
            let mut want = b.failing().to_vec();
            want.sort_unstable();
            assert_eq!(failing(&s), want, "{text}");
        }
    }
}

#[test]
fn impossible_options_are_a_clear_error() {
    let e = Scenario::load("random:1,size=8x8,density=0.4,passage=5").unwrap_err().to_string();
    assert!(e.starts_with("random:1,size=8x8,density=0.4,passage=5: no map in 40 attempts"), "{e}");
    assert!(e.contains("with every cell used"), "{e}");
    let e = Scenario::load("random:1,passage=1.2").unwrap_err().to_string();
    assert!(e.contains("passage: 1.2 is below W_pass"), "{e}");
}
