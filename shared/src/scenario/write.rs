//! A scenario written back as a scenario file, so a generated map can be
//! kept, read, edited and run like a hand-made one. Numbers are written in
//! Rust's shortest form that reads back to the same `f64`, so
//! `Scenario::parse(&s.to_toml())` gives `s` again.

use std::fmt::Write as _;

use super::{Scenario, Starts};
use crate::geometry::{Point, Shape};
use crate::lfp::LfpParams;

fn xy(p: &Point) -> String {
    format!("[{}, {}]", p.x, p.y)
}

fn list(points: &[Point]) -> String {
    points.iter().map(xy).collect::<Vec<_>>().join(", ")
}

/// TOML's basic string: quotes and backslashes escaped.
fn quoted(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

impl Scenario {
    /// This scenario as a scenario file; `header` lines become comments on top.
    pub fn to_toml(&self, header: &str) -> String {
        self.write_toml(header, true)
    }

    /// This scenario as a map's sidecar: the scenario file without its
    /// area and obstacles, which the map's image holds.
    pub fn to_sidecar(&self, header: &str) -> String {
        self.write_toml(header, false)
    }

    fn write_toml(&self, header: &str, geometry: bool) -> String {
        let mut s = String::new();
        for line in header.lines() {
            let _ = writeln!(s, "# {line}");
        }
        let _ = writeln!(s, "name = {}", quoted(&self.name));
        let _ = writeln!(s, "robots = {}", self.robots);
        let _ = writeln!(s, "situation = {}", self.situation.number());
        let _ = writeln!(s, "grid = {}", quoted(self.grid.name()));
        let _ = writeln!(s, "targets = [{}]", list(&self.targets));
        let p = &self.params;
        let _ = writeln!(s, "\n[params]");
        for (k, v) in [
            ("a", p.a),
            ("r_rob", p.r_rob),
            ("r_safe", p.r_safe),
            ("r_so", p.r_so),
            ("r_st", p.r_st),
            ("r_c", p.r_c),
            ("t_rot", p.t_rot),
            ("t_trans", p.t_trans),
            ("t_choice", p.t_choice),
            ("t_exchange", p.t_exchange),
            ("t_hop", p.t_hop),
            ("t_wait", p.t_wait),
        ] {
            let _ = writeln!(s, "{k} = {v:?}");
        }
        let _ = writeln!(s, "retries = {}\nsuspect_rounds = {}", p.retries, p.suspect_rounds);
        // The readings too: a scenario written back must run the same.
        let _ = writeln!(s, "choices_update_maps = {}", p.choices_update_maps);
        let _ = writeln!(s, "ru_collisions = {}", quoted(p.ru_collisions.name()));
        // Only when not the default, so that every scenario of the adaptive
        // rule keeps the hash it had before there was a rule to choose.
        if p.slot != crate::params::SlotRule::Adaptive {
            let _ = writeln!(s, "slot = {}", quoted(p.slot.name()));
        }
        if p.order != crate::params::Order::Paper {
            let _ = writeln!(s, "order = {}", quoted(p.order.name()));
        }
        if p.broadcast != crate::params::Broadcast::Controller {
            let _ = writeln!(s, "broadcast = {}", quoted(p.broadcast.name()));
        }
        // Likewise: every scenario keeps its hash while the step is on.
        if !p.survivor_step {
            let _ = writeln!(s, "survivor_step = false");
        }
        if p.visited_choice != crate::params::VisitedChoice::Farthest {
            let _ = writeln!(s, "visited_choice = {}", quoted(p.visited_choice.name()));
        }
        if geometry {
            self.write_geometry(&mut s);
        }
        let _ = match &self.starts {
            Starts::Border { from } => {
                writeln!(s, "\n[starts]\nborder = {{ from = {} }}", xy(from))
            }
            Starts::Points(pts) => writeln!(s, "\n[starts]\npoints = [{}]", list(pts)),
        };
        if self.lfp != LfpParams::default() {
            let table = toml::to_string(&self.lfp).expect("LfpParams is a flat table of numbers");
            let _ = write!(s, "\n[lfp]\n{table}");
        }
        s
    }

    fn write_geometry(&self, s: &mut String) {
        let _ = writeln!(s, "\n[area]\npolygon = [{}]", list(&self.area.points));
        for o in &self.obstacles {
            let _ = writeln!(s, "\n[[obstacles]]");
            let _ = match o {
                Shape::Polygon(poly) => writeln!(s, "polygon = [{}]", list(&poly.points)),
                Shape::Circle(c) => writeln!(s, "circle = {{ center = {}, radius = {:?} }}", xy(&c.center), c.radius),
            };
        }
    }
}

/// A run's agreement names a scenario by its canonical text
/// (`agreement::ScenarioId::of`).
impl crate::agreement::Named for Scenario {
    fn name(&self) -> &str {
        &self.name
    }

    fn canonical(&self) -> String {
        self.to_toml("")
    }
}

#[cfg(test)]
mod tests {
    use crate::agreement::ScenarioId;
    use crate::scenario::Scenario;

    #[test]
    fn a_scenario_hashes_alike_when_reread() {
        let sc = Scenario::builtin("paper").unwrap();
        let again = Scenario::parse(&sc.to_toml("a comment"), "copy.toml").unwrap();
        assert_eq!(ScenarioId::of(&again), ScenarioId::of(&sc), "comments and file name aside");
        assert_eq!(ScenarioId::of(&sc).sha3_256.len(), 64);
        assert_ne!(ScenarioId::of(&Scenario::builtin("open").unwrap()).sha3_256, ScenarioId::of(&sc).sha3_256);
    }
}
