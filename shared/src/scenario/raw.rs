//! The scenario file as written (serde types that mirror the TOML), and its
//! checked conversion into a [`Scenario`]. Every rejection names the field it
//! is about; [`Ctx`] turns that field's path into a file position.

use serde::Deserialize;

use super::limits::{self, Extent};
use super::locate::{line_col, Node};
use super::{gaps, Scenario, ScenarioError, Starts};
use crate::geometry::{Circle, Point, Polygon, Shape};
use crate::lattice::{Lattice, LatticeKind};
use crate::lfp::LfpParams;
use crate::params::{Broadcast, Order, Params, RuCollisions, Situation, SlotRule, VisitedChoice};
use crate::spot::{Spot, STEPS};

/// A point as written: `[x, y]`, exactly two numbers. A plain `[f64; 2]`
/// took the first two elements of any longer array (`[10, 0, "x"]`).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Xy([f64; 2]);

impl std::ops::Deref for Xy {
    type Target = [f64; 2];
    fn deref(&self) -> &[f64; 2] {
        &self.0
    }
}

impl<'de> Deserialize<'de> for Xy {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Xy, D::Error> {
        struct Visit;
        impl<'de> serde::de::Visitor<'de> for Visit {
            type Value = Xy;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a point [x, y] of exactly two numbers")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Xy, A::Error> {
                use serde::de::Error;
                let x = seq.next_element::<f64>()?.ok_or_else(|| A::Error::invalid_length(0, &self))?;
                let y = seq.next_element::<f64>()?.ok_or_else(|| A::Error::invalid_length(1, &self))?;
                let mut n = 2;
                while seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
                    n += 1;
                }
                if n > 2 {
                    return Err(A::Error::invalid_length(n, &self));
                }
                Ok(Xy([x, y]))
            }
        }
        d.deserialize_seq(Visit)
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawScenario {
    name: Option<String>,
    robots: Option<usize>,
    situation: Option<u8>,
    grid: Option<LatticeKind>,
    #[serde(default)]
    targets: Vec<Xy>,
    #[serde(default)]
    params: RawParams,
    area: RawArea,
    #[serde(default)]
    obstacles: Vec<RawObstacle>,
    starts: Option<RawStarts>,
    #[serde(default)]
    lfp: LfpParams,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawParams {
    a: Option<f64>,
    r_rob: Option<f64>,
    r_safe: Option<f64>,
    r_so: Option<f64>,
    r_st: Option<f64>,
    r_c: Option<f64>,
    t_rot: Option<f64>,
    t_trans: Option<f64>,
    t_choice: Option<f64>,
    t_exchange: Option<f64>,
    t_hop: Option<f64>,
    t_wait: Option<f64>,
    retries: Option<u32>,
    suspect_rounds: Option<u32>,
    choices_update_maps: Option<bool>,
    survivor_step: Option<bool>,
    ru_collisions: Option<String>,
    visited_choice: Option<String>,
    slot: Option<String>,
    order: Option<String>,
    broadcast: Option<String>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawArea {
    polygon: Vec<Xy>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawObstacle {
    polygon: Option<Vec<Xy>>,
    circle: Option<RawCircle>,
    rect: Option<RawRect>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCircle {
    center: Xy,
    radius: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRect {
    min: Xy,
    max: Xy,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawStarts {
    border: Option<RawBorder>,
    points: Option<Vec<Xy>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBorder {
    from: Xy,
}

/// A map's sidecar (`NAME.gridswarm.toml` beside `NAME.yaml`): a scenario
/// file without `[area]` and `[[obstacles]]`, which come from the map's
/// image, and with a `[map]` table of its own (`super::occupancy`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSidecar {
    name: Option<String>,
    robots: Option<usize>,
    situation: Option<u8>,
    grid: Option<LatticeKind>,
    #[serde(default)]
    targets: Vec<Xy>,
    #[serde(default)]
    params: RawParams,
    starts: Option<RawStarts>,
    #[serde(default)]
    lfp: LfpParams,
    #[serde(default)]
    pub map: RawMapOptions,
}

/// How a map's image is read (`[map]` in its sidecar).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMapOptions {
    /// Side of the cells the image is read in (m), rounded to whole pixels.
    pub cell: Option<f64>,
    /// How unknown pixels are read: "blocked" (default) or "free".
    pub unknown: Option<String>,
    /// Free parts narrower than this (m) are blocked (default 2 r_rob).
    pub sliver: Option<f64>,
}

impl RawSidecar {
    /// Reads a sidecar's text (`ctx.text`).
    pub fn parse(ctx: &Ctx) -> Result<RawSidecar, ScenarioError> {
        toml::from_str(ctx.text).map_err(|e| ctx.toml_error(&e))
    }

    /// The grid side, robot and safety radius it asks for, as written (unchecked).
    pub fn sizes(&self) -> (Option<f64>, Option<f64>, Option<f64>) {
        (self.params.a, self.params.r_rob, self.params.r_safe)
    }

    /// The scenario of this sidecar on the map's area and obstacles, named
    /// `name` unless the sidecar names it, checked as a scenario file is.
    pub fn into_scenario(
        self,
        ctx: &Ctx,
        name: &str,
        area: &[(f64, f64)],
        obstacles: &[Vec<(f64, f64)>],
    ) -> Result<Scenario, ScenarioError> {
        let xy = |pts: &[(f64, f64)]| -> Vec<Xy> { pts.iter().map(|&(x, y)| Xy([x, y])).collect() };
        let raw = RawScenario {
            name: Some(self.name.unwrap_or_else(|| name.to_string())),
            robots: self.robots,
            situation: self.situation,
            grid: self.grid,
            targets: self.targets,
            params: self.params,
            area: RawArea { polygon: xy(area) },
            obstacles: obstacles
                .iter()
                .map(|o| RawObstacle { polygon: Some(xy(o)), circle: None, rect: None })
                .collect(),
            starts: self.starts,
            lfp: self.lfp,
        };
        raw.into_scenario(ctx)
    }
}

/// The text being parsed, for turning field paths into positions.
pub(crate) struct Ctx<'a> {
    pub text: &'a str,
    pub file: &'a str,
    pub tree: Option<Node>,
}

impl Ctx<'_> {
    pub fn err(&self, field: impl Into<String>, message: impl AsRef<str>) -> ScenarioError {
        let field = field.into();
        let at = self.tree.as_ref().and_then(|t| t.span_of(&field)).map(|s| line_col(self.text, s.start));
        ScenarioError::new(self.file, at, field, message)
    }

    /// A toml error (syntax, unknown field, wrong type) located by its span.
    pub fn toml_error(&self, e: &toml::de::Error) -> ScenarioError {
        let span = e.span();
        let at = span.as_ref().map(|s| line_col(self.text, s.start));
        let missing = e.message().strip_prefix("missing field `").and_then(|m| m.split('`').next());
        let field = match (&self.tree, &span, missing) {
            // Reported at the table that lacks it; name the field itself.
            (Some(tree), Some(s), Some(name)) => match tree.path_with_span(s) {
                Some(table) if !table.is_empty() => format!("{table}.{name}"),
                _ => name.to_string(),
            },
            (Some(tree), Some(s), None) => tree.path_at(s.start).unwrap_or_default(),
            _ => String::new(),
        };
        ScenarioError::new(self.file, at, field, e.message())
    }
}

fn fmt_xy(p: Point) -> String {
    format!("({}, {})", p.x, p.y)
}

fn point(ctx: &Ctx, field: &str, xy: Xy) -> Result<Point, ScenarioError> {
    if !xy.iter().all(|v| v.is_finite()) {
        return Err(ctx.err(field, format!("coordinates must be finite numbers, got [{}, {}]", xy[0], xy[1])));
    }
    if let Some(v) = xy.iter().find(|v| v.abs() > limits::MAX_COORD) {
        let max = limits::MAX_COORD;
        let v = limits::show(*v);
        return Err(ctx.err(field, format!("coordinate {v} is beyond the limit MAX_COORD = {max} m in size")));
    }
    Ok(Point::new(xy[0], xy[1]))
}

/// A polygon the geometry code can trust: three or more distinct corners,
/// no edge folding back on the previous one, simple, with a non-zero area.
fn polygon(ctx: &Ctx, field: &str, raw: &[Xy]) -> Result<Polygon, ScenarioError> {
    if raw.len() < 3 {
        return Err(ctx.err(field, format!("a polygon needs at least 3 corners, got {}", raw.len())));
    }
    limits::count("corners", raw.len(), "MAX_CORNERS", limits::MAX_CORNERS).map_err(|m| ctx.err(field, m))?;
    let pts = raw
        .iter()
        .enumerate()
        .map(|(k, &xy)| point(ctx, &format!("{field}[{k}]"), xy))
        .collect::<Result<Vec<_>, _>>()?;
    let n = pts.len();
    for k in 0..n {
        let (prev, p, next) = (pts[(k + n - 1) % n], pts[k], pts[(k + 1) % n]);
        if p == next {
            return Err(ctx.err(format!("{field}[{}]", (k + 1) % n), format!("repeats corner {k} {}", fmt_xy(p))));
        }
        let (u, v) = (p - prev, next - p);
        if u.x * v.y - u.y * v.x == 0.0 && u.dot(&v) < 0.0 {
            return Err(ctx.err(format!("{field}[{k}]"), format!("the boundary folds back on itself at {}", fmt_xy(p))));
        }
    }
    let poly = Polygon::new(pts);
    if !poly.is_simple() {
        return Err(ctx.err(field, "the polygon is not simple: two of its edges cross or touch"));
    }
    if poly.signed_area().abs() < 1e-9 {
        return Err(ctx.err(field, "the polygon has zero area"));
    }
    Ok(poly)
}

fn positive(ctx: &Ctx, field: &str, v: f64) -> Result<f64, ScenarioError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(ctx.err(field, format!("must be > 0, got {v}")))
    }
}

fn non_negative(ctx: &Ctx, field: &str, v: f64) -> Result<f64, ScenarioError> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(ctx.err(field, format!("must be >= 0, got {v}")))
    }
}

/// The grid side `a`: positive and from [`limits::MIN_A`] to [`limits::MAX_A`].
fn grid_side(ctx: &Ctx, a: Option<f64>) -> Result<f64, ScenarioError> {
    let a = positive(ctx, "params.a", a.unwrap_or(Params::default().a))?;
    limits::within(a, limits::MIN_A, limits::MAX_A, "MIN_A to MAX_A").map_err(|m| ctx.err("params.a", m))
}

/// A robot-sized range: positive and at most [`limits::MAX_SENSING_SIDES`] grid sides.
fn sensing(ctx: &Ctx, field: &str, v: f64, a: f64) -> Result<f64, ScenarioError> {
    let v = positive(ctx, field, v)?;
    let sides = limits::MAX_SENSING_SIDES;
    limits::within(v, 0.0, sides * a, &format!("at most MAX_SENSING_SIDES = {sides} grid sides"))
        .map_err(|m| ctx.err(field, m))
}

/// More retransmissions than this buy nothing measurable and cost a slot's air time.
pub const MAX_RETRIES: u32 = 10;

impl RawParams {
    /// Ranges not given take the equality case of their assumption
    /// ([`Params::derived`]); the assumptions themselves are not enforced
    /// here, the checker reports them.
    fn into_params(self, ctx: &Ctx) -> Result<Params, ScenarioError> {
        let d = Params::default();
        let a = grid_side(ctx, self.a)?;
        let r_rob = sensing(ctx, "params.r_rob", self.r_rob.unwrap_or(d.r_rob), a)?;
        let r_safe = sensing(ctx, "params.r_safe", self.r_safe.unwrap_or(d.r_safe), a)?;
        if r_safe <= r_rob {
            return Err(
                ctx.err("params.r_safe", format!("must be > r_rob = {r_rob} (it includes every error), got {r_safe}"))
            );
        }
        let mut p = Params::derived(a, r_rob, r_safe);
        let opt = |field: &str, v: Option<f64>, check: fn(&Ctx, &str, f64) -> Result<f64, ScenarioError>, dflt: f64| {
            v.map_or(Ok(dflt), |v| check(ctx, field, v))
        };
        p.r_so = opt("params.r_so", self.r_so, positive, p.r_so)?;
        p.r_st = opt("params.r_st", self.r_st, positive, p.r_st)?;
        p.r_c = opt("params.r_c", self.r_c, positive, p.r_c)?;
        for (field, v) in [("params.r_so", p.r_so), ("params.r_st", p.r_st)] {
            sensing(ctx, field, v, a)?;
        }
        let radio = limits::MAX_RADIO_SIDES;
        limits::within(p.r_c, 0.0, radio * a, &format!("MAX_RADIO_SIDES = {radio} grid sides"))
            .map_err(|m| ctx.err("params.r_c", m))?;
        p.t_rot = opt("params.t_rot", self.t_rot, non_negative, p.t_rot)?;
        p.t_trans = opt("params.t_trans", self.t_trans, non_negative, p.t_trans)?;
        p.t_choice = opt("params.t_choice", self.t_choice, non_negative, p.t_choice)?;
        p.t_exchange = opt("params.t_exchange", self.t_exchange, positive, p.t_exchange)?;
        p.t_hop = opt("params.t_hop", self.t_hop, positive, p.t_hop)?;
        p.t_wait = opt("params.t_wait", self.t_wait, positive, p.t_wait)?;
        for (field, v, lo) in [
            ("params.t_rot", p.t_rot, 0.0),
            ("params.t_trans", p.t_trans, 0.0),
            ("params.t_choice", p.t_choice, 0.0),
            ("params.t_exchange", p.t_exchange, limits::MIN_TIME),
            ("params.t_hop", p.t_hop, limits::MIN_TIME),
            ("params.t_wait", p.t_wait, limits::MIN_TIME),
        ] {
            let why = if lo > 0.0 { "MIN_TIME to MAX_TIME" } else { "MAX_TIME" };
            limits::within(v, lo, limits::MAX_TIME, why).map_err(|m| ctx.err(field, m))?;
        }
        if p.t_hop >= p.t_exchange {
            return Err(ctx.err(
                "params.t_hop",
                format!(
                    "must be below t_exchange = {} (a map must be able to arrive within the exchange), got {}",
                    p.t_exchange, p.t_hop
                ),
            ));
        }
        if let Some(r) = self.retries {
            if r > MAX_RETRIES {
                return Err(ctx.err("params.retries", format!("must be at most {MAX_RETRIES}, got {r}")));
            }
            p.retries = r;
        }
        if let Some(k) = self.suspect_rounds {
            if k == 0 {
                return Err(ctx.err("params.suspect_rounds", "must be at least 1, got 0"));
            }
            p.suspect_rounds = k;
        }
        p.choices_update_maps = self.choices_update_maps.unwrap_or(p.choices_update_maps);
        p.survivor_step = self.survivor_step.unwrap_or(p.survivor_step);
        if let Some(name) = self.ru_collisions {
            p.ru_collisions = RuCollisions::from_name(&name).ok_or_else(|| {
                ctx.err(
                    "params.ru_collisions",
                    format!("must be one of {}, got `{name}`", RuCollisions::NAMES.join(", ")),
                )
            })?;
        }
        if let Some(name) = self.visited_choice {
            p.visited_choice = VisitedChoice::from_name(&name).ok_or_else(|| {
                ctx.err(
                    "params.visited_choice",
                    format!("must be one of {}, got `{name}`", VisitedChoice::NAMES.join(", ")),
                )
            })?;
        }
        if let Some(name) = self.slot {
            p.slot = SlotRule::from_name(&name).ok_or_else(|| {
                ctx.err("params.slot", format!("must be one of {}, got `{name}`", SlotRule::NAMES.join(", ")))
            })?;
        }
        if let Some(name) = self.order {
            p.order = Order::from_name(&name).ok_or_else(|| {
                ctx.err("params.order", format!("must be one of {}, got `{name}`", Order::NAMES.join(", ")))
            })?;
        }
        if let Some(name) = self.broadcast {
            p.broadcast = Broadcast::from_name(&name).ok_or_else(|| {
                ctx.err("params.broadcast", format!("must be one of {}, got `{name}`", Broadcast::NAMES.join(", ")))
            })?;
        }
        Ok(p)
    }
}

impl RawObstacle {
    fn into_shape(self, ctx: &Ctx, field: &str) -> Result<Shape, ScenarioError> {
        match (self.polygon, self.circle, self.rect) {
            (Some(p), None, None) => Ok(Shape::Polygon(polygon(ctx, &format!("{field}.polygon"), &p)?)),
            (None, Some(c), None) => {
                let center = point(ctx, &format!("{field}.circle.center"), c.center)?;
                let radius = positive(ctx, &format!("{field}.circle.radius"), c.radius)?;
                Ok(Shape::Circle(Circle { center, radius }))
            }
            (None, None, Some(r)) => {
                let lo = point(ctx, &format!("{field}.rect.min"), r.min)?;
                let hi = point(ctx, &format!("{field}.rect.max"), r.max)?;
                if !(hi.x > lo.x && hi.y > lo.y) {
                    return Err(ctx.err(
                        format!("{field}.rect.max"),
                        format!("must exceed min {} in x and y, got {}", fmt_xy(lo), fmt_xy(hi)),
                    ));
                }
                let pts = vec![lo, Point::new(hi.x, lo.y), hi, Point::new(lo.x, hi.y)];
                Ok(Shape::Polygon(Polygon::new(pts)))
            }
            _ => Err(ctx.err(field, "give exactly one of `polygon`, `circle` or `rect`")),
        }
    }
}

fn check_lfp(ctx: &Ctx, l: &LfpParams) -> Result<(), ScenarioError> {
    // Mantegna's method needs 0 < beta < 2 (its sigma vanishes at 2).
    if !(l.beta > 0.0 && l.beta < 2.0) {
        return Err(ctx.err("lfp.beta", format!("must be in (0, 2), got {}", l.beta)));
    }
    positive(ctx, "lfp.scale", l.scale)?;
    if !(l.max_step >= 1.0 && l.max_step.is_finite()) {
        return Err(ctx.err(
            "lfp.max_step",
            format!("must be >= 1 (steps are clamped to [a, max_step * a]), got {}", l.max_step),
        ));
    }
    if let crate::lfp::Turn::Sigma(sigma) = l.turn {
        non_negative(ctx, "lfp.turn", sigma)?;
    }
    non_negative(ctx, "lfp.k_robot", l.k_robot)?;
    non_negative(ctx, "lfp.k_obstacle", l.k_obstacle)?;
    check_lfp_limits(ctx, l)
}

/// The admission limits of `[lfp]`: finite gains, flights and loops.
fn check_lfp_limits(ctx: &Ctx, l: &LfpParams) -> Result<(), ScenarioError> {
    let sigma = match l.turn {
        crate::lfp::Turn::Sigma(s) => s,
        crate::lfp::Turn::Uniform => 0.0,
    };
    let checks = [
        ("lfp.scale", l.scale, 0.0, limits::MAX_LFP_GAIN, "MAX_LFP_GAIN"),
        ("lfp.k_robot", l.k_robot, 0.0, limits::MAX_LFP_GAIN, "MAX_LFP_GAIN"),
        ("lfp.k_obstacle", l.k_obstacle, 0.0, limits::MAX_LFP_GAIN, "MAX_LFP_GAIN"),
        ("lfp.max_step", l.max_step, 1.0, limits::MAX_FLIGHT_SIDES, "MAX_FLIGHT_SIDES"),
        ("lfp.turn", sigma, 0.0, limits::MAX_TURN_SIGMA, "MAX_TURN_SIGMA"),
        ("lfp.max_steer", l.max_steer, 0.0, std::f64::consts::PI, "an angle from 0 to pi"),
    ];
    for (field, v, lo, hi, why) in checks {
        limits::within(v, lo, hi, why).map_err(|m| ctx.err(field, m))?;
    }
    if !(1..=limits::MAX_MICRO_STEPS).contains(&l.micro_steps) {
        let max = limits::MAX_MICRO_STEPS;
        let got = l.micro_steps;
        return Err(ctx.err("lfp.micro_steps", format!("must be from 1 to MAX_MICRO_STEPS = {max}, got {got}")));
    }
    Ok(())
}

/// The project's default robot count: the three robots of Fig. 5.
const DEFAULT_ROBOTS: usize = 3;

impl RawScenario {
    pub fn into_scenario(mut self, ctx: &Ctx) -> Result<Scenario, ScenarioError> {
        let robots = self.robots.unwrap_or(DEFAULT_ROBOTS);
        if robots == 0 {
            return Err(ctx.err("robots", "must be >= 1, got 0"));
        }
        limits::count("robots", robots, "MAX_ROBOTS", limits::MAX_ROBOTS).map_err(|m| ctx.err("robots", m))?;
        let situation = self.situation.unwrap_or(1);
        let situation = Situation::from_number(situation).ok_or_else(|| {
            ctx.err("situation", format!("must be 1 (|T| known) or 2 (|T| unknown), got {situation}"))
        })?;
        let grid = self.grid.unwrap_or(LatticeKind::Triangular);
        // The area and the grid side first: together they decide the size
        // of everything else, and a grid far too fine is the error to report
        // even when the default ranges do not fit it either.
        let area = polygon(ctx, "area.polygon", &self.area.polygon)?;
        self.admit(ctx, &area, grid_side(ctx, self.params.a)?, grid, robots)?;
        let params = std::mem::take(&mut self.params).into_params(ctx)?;
        check_lfp(ctx, &self.lfp)?;
        let (obstacles, bad_shape) = shapes(ctx, self.obstacles);
        let near =
            limits::check_geometry(&area, &obstacles, params.a, params.r_safe).map_err(|m| ctx.err("obstacles", m))?;
        check_placement(ctx, &area, &obstacles, &near)?;
        // A shape that could not be read is reported after the ones before
        // it are placed, as when each was checked as it was read.
        if let Some(e) = bad_shape {
            return Err(e);
        }

        // Point tests look only at the obstacles whose boxes hold the point
        // (targets and start points times obstacles were up to 10^9 tests).
        let near = ObstacleBoxes::new(&area, &obstacles, params.r_safe.max(0.0) + params.a);
        let mut targets = Vec::with_capacity(self.targets.len());
        for (k, &xy) in self.targets.iter().enumerate() {
            let field = format!("targets[{k}]");
            let p = point(ctx, &field, xy)?;
            if !area.contains(p) {
                return Err(ctx.err(field, format!("{} is outside the area, so not in Ad", fmt_xy(p))));
            }
            if let Some(j) = near.at(p).find(|&j| obstacles[j].contains(p)) {
                return Err(ctx.err(field, format!("{} is inside obstacles[{j}], so not in Ad", fmt_xy(p))));
            }
            // Robots tell targets apart by where their lasers see them.
            if let Some(j) = targets.iter().position(|&q| Spot::at(q, params.a) == Spot::at(p, params.a)) {
                let m =
                    format!("{} is where targets[{j}] is, within a / {}: a laser reads them as one", fmt_xy(p), STEPS);
                return Err(ctx.err(field, m));
            }
            targets.push(p);
        }

        let starts = match self.starts {
            None => Starts::Border { from: area.points[0] },
            Some(RawStarts { border: Some(b), points: None }) => {
                Starts::Border { from: point(ctx, "starts.border.from", b.from)? }
            }
            Some(RawStarts { border: None, points: Some(pts) }) => {
                let pts = start_points(ctx, &pts, robots, &area, (&obstacles, &near), &params, grid)?;
                Starts::Points(pts)
            }
            Some(_) => return Err(ctx.err("starts", "give exactly one of `border` or `points`")),
        };

        let name = self.name.unwrap_or_else(|| file_stem(ctx.file));
        Ok(Scenario { name, area, obstacles, targets, starts, robots, params, grid, situation, lfp: self.lfp })
    }
}

impl RawScenario {
    /// The counts and sizes that decide how much the rest of the checks,
    /// the world and a run will cost, before any of them runs.
    fn admit(&self, ctx: &Ctx, area: &Polygon, a: f64, grid: LatticeKind, robots: usize) -> Result<(), ScenarioError> {
        let corners: usize = self.obstacles.iter().filter_map(|o| o.polygon.as_ref()).map(Vec::len).sum();
        let total = corners + area.points.len();
        let counts = [
            ("obstacles", "obstacles", self.obstacles.len(), "MAX_OBSTACLES", limits::MAX_OBSTACLES),
            ("obstacles", "polygon corners", total, "MAX_TOTAL_CORNERS", limits::MAX_TOTAL_CORNERS),
            ("targets", "targets", self.targets.len(), "MAX_TARGETS", limits::MAX_TARGETS),
        ];
        for (field, what, n, name, max) in counts {
            limits::count(what, n, name, max).map_err(|m| ctx.err(field, m))?;
        }
        if let Some(RawStarts { points: Some(pts), .. }) = &self.starts {
            limits::count("start points", pts.len(), "MAX_ROBOTS", limits::MAX_ROBOTS)
                .map_err(|m| ctx.err("starts.points", m))?;
        }
        let (lo, hi) = area.bounding_box();
        let extent = Extent { width: hi.x - lo.x, height: hi.y - lo.y, a, kind: grid };
        let pieces = limits::pieces(area.points.len(), self.obstacles.len(), self.targets.len());
        // Blame `a` when the file chose a finer grid than the default.
        let field = if a < Params::default().a { "params.a" } else { "area.polygon" };
        limits::check_size(&extent, pieces).map_err(|m| ctx.err(field, m))?;
        limits::check_robots(robots, extent.frame_vertices()).map_err(|m| ctx.err("robots", m))
    }
}

/// The obstacles as shapes, up to the first that cannot be read (and its error).
fn shapes(ctx: &Ctx, raw: Vec<RawObstacle>) -> (Vec<Shape>, Option<ScenarioError>) {
    let mut out = Vec::with_capacity(raw.len());
    for (k, raw) in raw.into_iter().enumerate() {
        match raw.into_shape(ctx, &format!("obstacles[{k}]")) {
            Ok(s) => out.push(s),
            Err(e) => return (out, Some(e)),
        }
    }
    (out, None)
}

/// Every obstacle inside the area, clear of its boundary, and clear of
/// every obstacle before it; the first that is not is the error. Only the
/// pieces `near` lists (boxes within `3a`) are measured: pieces whose
/// boxes are apart cannot meet.
fn check_placement(
    ctx: &Ctx,
    area: &Polygon,
    obstacles: &[Shape],
    near: &super::pairs::Near,
) -> Result<(), ScenarioError> {
    let edges: Vec<(Point, Point)> = area.edges().collect();
    let mut boundary = vec![Vec::new(); obstacles.len()];
    for &(i, e) in &near.boundary {
        boundary[i as usize].push(edges[e as usize]);
    }
    let mut earlier = vec![Vec::new(); obstacles.len()];
    for &(i, j) in &near.obstacles {
        earlier[j as usize].push(i as usize);
    }
    for (k, shape) in obstacles.iter().enumerate() {
        let field = format!("obstacles[{k}]");
        if !gaps::strictly_inside_near(area, boundary[k].iter().copied(), shape) {
            let g = gaps::boundary_gap(area, shape);
            let why = if g.width == 0.0 {
                format!("meets the area boundary near {}", fmt_xy(g.a))
            } else {
                "lies outside the area".to_string()
            };
            return Err(ctx.err(field, format!("must lie inside the area, clear of its boundary, but {why}")));
        }
        let bx = shape.bounding_box();
        // Boxes apart by any distance: the shapes cannot meet.
        for &j in &earlier[k] {
            if gaps::box_distance(&obstacles[j].bounding_box(), &bx) > 0.0 {
                continue;
            }
            let g = gaps::shape_gap(&obstacles[j], shape);
            if g.width == 0.0 {
                return Err(ctx.err(field, format!("overlaps or touches obstacles[{j}] near {}", fmt_xy(g.a))));
            }
        }
    }
    Ok(())
}

/// Obstacles by the cells their boxes, grown by a margin, cover: a point
/// farther than the margin from an obstacle's box is neither in it nor
/// within the margin of it.
struct ObstacleBoxes {
    cells: crate::world::buckets::Buckets,
}

impl ObstacleBoxes {
    fn new(area: &Polygon, obstacles: &[Shape], margin: f64) -> Self {
        let boxes: Vec<(Point, Point)> = obstacles.iter().map(Shape::bounding_box).collect();
        let (lo, hi) = area.bounding_box();
        let side = (2.0 * margin).max((hi.x - lo.x).max(hi.y - lo.y) / 1000.0).max(1e-9);
        ObstacleBoxes { cells: crate::world::buckets::Buckets::new(lo, hi, (side, side), &boxes, margin) }
    }

    /// Obstacles whose grown box may hold `p`, ascending (and maybe others).
    fn at(&self, p: Point) -> impl Iterator<Item = usize> + '_ {
        self.cells.near(p).iter().map(|&j| j as usize)
    }
}

/// Start points, each snapped to an accessible vertex of its own. The test
/// repeats the world's clearance rule for one vertex rather than building the
/// whole world.
fn start_points(
    ctx: &Ctx,
    raw: &[Xy],
    robots: usize,
    area: &Polygon,
    (obstacles, near): (&[Shape], &ObstacleBoxes),
    params: &Params,
    grid: LatticeKind,
) -> Result<Vec<Point>, ScenarioError> {
    if raw.len() < robots {
        return Err(ctx.err(
            "starts.points",
            format!("{} start points for robots = {robots}: give at least one point per robot", raw.len()),
        ));
    }
    let lattice = Lattice::new(grid, params.a);
    let mut seen = std::collections::HashMap::with_capacity(raw.len());
    let mut out = Vec::with_capacity(raw.len());
    for (k, &xy) in raw.iter().enumerate() {
        let field = format!("starts.points[{k}]");
        let p = point(ctx, &field, xy)?;
        let c = lattice.nearest(p);
        let q = lattice.position(c);
        let clear = area.contains(q)
            && area.boundary_distance(q) >= params.r_safe
            && near.at(q).all(|j| obstacles[j].distance(q) >= params.r_safe);
        if !clear {
            return Err(ctx.err(
                field,
                format!(
                    "the nearest vertex {} to {} is not accessible (in Ad, r_safe = {} clear)",
                    fmt_xy(q),
                    fmt_xy(p),
                    params.r_safe
                ),
            ));
        }
        if let Some(j) = seen.insert(c, k) {
            return Err(ctx.err(
                field,
                format!("snaps to vertex {} like starts.points[{j}]: two robots on one vertex", fmt_xy(q)),
            ));
        }
        out.push(p);
    }
    Ok(out)
}

fn file_stem(file: &str) -> String {
    std::path::Path::new(file).file_stem().and_then(|s| s.to_str()).unwrap_or(file).to_string()
}

#[cfg(test)]
mod tests {
    use crate::lfp::{RepelRange, Turn};
    use crate::params::{RuCollisions, VisitedChoice};
    use crate::scenario::Scenario;

    const AREA: &str = "[area]\npolygon = [[0, 0], [10, 0], [10, 10], [0, 10]]\n";

    fn parse(tables: &str) -> Result<Scenario, String> {
        Scenario::parse(&format!("{AREA}{tables}"), "t.toml").map_err(|e| e.to_string())
    }

    #[test]
    fn readings_default_to_the_papers_and_switch_by_name() {
        let s = parse("").unwrap();
        assert_eq!(s.params.ru_collisions, RuCollisions::PerEvent);
        assert_eq!(s.params.visited_choice, VisitedChoice::Farthest);
        let sigma = crate::lfp::DEFAULT_TURN_SIGMA;
        assert_eq!((s.lfp.turn, s.lfp.repel_range), (Turn::Sigma(sigma), RepelRange::Sonar));
        let s = parse("[params]\nru_collisions = \"back-off\"\n[lfp]\nturn = 0.5\nrepel_range = \"radio\"\n").unwrap();
        assert_eq!(s.params.ru_collisions, RuCollisions::BackOff);
        assert_eq!((s.lfp.turn, s.lfp.repel_range), (Turn::Sigma(0.5), RepelRange::Radio));
        let s = parse("[params]\nru_collisions = \"per-pair\"\nvisited_choice = \"random-biased\"\n").unwrap();
        assert_eq!(s.params.ru_collisions, RuCollisions::PerPair);
        assert_eq!(s.params.visited_choice, VisitedChoice::RandomBiased);
        assert_eq!(parse("[lfp]\nturn_sigma = 1\n").unwrap().lfp.turn, Turn::Sigma(1.0));
    }

    #[test]
    fn the_survivor_step_switches_and_is_written_only_when_off() {
        let on = parse("").unwrap();
        assert!(on.params.survivor_step);
        assert!(!on.to_toml("").contains("survivor_step"), "a scenario keeps its hash while the step is on");
        let off = parse("[params]\nsurvivor_step = false\n").unwrap();
        assert!(!off.params.survivor_step);
        let text = off.to_toml("");
        assert!(text.contains("survivor_step = false"), "{text}");
        assert!(!Scenario::parse(&text, "again.toml").unwrap().params.survivor_step);
        let e = parse("[params]\nsurvivor_step = \"no\"\n").unwrap_err();
        assert!(e.contains("survivor_step") && e.contains("bool"), "{e}");
    }

    #[test]
    fn bad_readings_are_named_errors() {
        let e = parse("[params]\nru_collisions = \"pairs\"\n").unwrap_err();
        assert!(
            e.contains("t.toml:4:17: params.ru_collisions: must be one of per-event, per-pair, back-off, got `pairs`"),
            "{e}"
        );
        let e = parse("[params]\nvisited_choice = \"random\"\n").unwrap_err();
        assert!(
            e.contains("params.visited_choice: must be one of farthest, uniform, random-biased, got `random`"),
            "{e}"
        );
        let e = parse("[lfp]\nturn = -0.5\n").unwrap_err();
        assert!(e.contains("lfp.turn: must be >= 0, got -0.5"), "{e}");
        let e = parse("[lfp]\nturn = \"normal\"\n").unwrap_err();
        assert!(e.contains("lfp.turn") && e.contains("\"uniform\" or a turn sigma"), "{e}");
        let e = parse("[lfp]\nrepel_range = \"wifi\"\n").unwrap_err();
        assert!(e.contains("lfp.repel_range") && e.contains("sonar"), "{e}");
    }
}
