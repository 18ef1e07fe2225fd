//! `routes.svg`: the area, obstacles, accessible vertices, targets with
//! their sensing circles and each robot's route with arrows, like the
//! paper's Fig. 5. Written by hand: it is a few element kinds, and plain
//! SVG keeps every arrow exactly on its edge.

use std::fmt::Write as _;

use gridswarm::geometry::{Point, Polygon, Shape};
use gridswarm::outcome::Pose;
use gridswarm::world::World;
use serde_json::Value;

use crate::write::palette;

/// Robot `r`'s colour: the palette's, never the targets' red.
pub fn robot_colour(r: usize) -> String {
    palette::robot(r).to_string()
}

/// What happened to a robot, as its end mark on the map shows it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fate {
    /// Searching until the run ended: a dot.
    Running,
    /// Its record stops before the run's last round: a ring.
    Halted,
    /// Crashed (`--kill`, `--kill-random`): a black cross.
    Crashed,
    /// Frozen and never thawed (`--freeze`): a pause sign.
    Frozen,
}

/// An injected fault, marked where the robot was in that round.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FaultMark {
    pub robot: usize,
    pub round: usize,
    pub crash: bool,
    /// A freeze that ended before the run did.
    pub thawed: bool,
}

/// The words and fault marks of a route map, besides the routes.
#[derive(Clone, Debug, Default)]
pub struct Notes {
    pub title: String,
    /// The faults and radio settings ([`crate::figures::settings_line`]).
    pub settings: String,
    pub faults: Vec<FaultMark>,
}

impl Notes {
    /// From a run's `summary.json`: its settings and `failures` list.
    pub fn of(title: &str, summary: &Value) -> Self {
        let list = summary.get("failures").and_then(Value::as_array).map(Vec::as_slice).unwrap_or_default();
        let faults = list
            .iter()
            .filter_map(|f| {
                Some(FaultMark {
                    robot: f.get("robot")?.as_u64()? as usize,
                    round: f.get("round")?.as_u64()? as usize,
                    crash: f.get("kind")?.as_str()? == "crash",
                    thawed: f.get("thawed_s").is_some_and(|t| !t.is_null()),
                })
            })
            .collect();
        Notes { title: title.to_string(), settings: crate::figures::settings_line(summary), faults }
    }

    /// Robot `r`'s fate in a run whose longest record has `rounds` poses.
    pub fn fate(&self, r: usize, poses: usize, rounds: usize) -> Fate {
        let mine = || self.faults.iter().filter(move |f| f.robot == r);
        if mine().any(|f| f.crash) {
            Fate::Crashed
        } else if mine().any(|f| !f.crash && !f.thawed) {
            Fate::Frozen
        } else if poses < rounds {
            Fate::Halted
        } else {
            Fate::Running
        }
    }
}

/// Escapes text for XML content and attribute values.
pub fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c => out.push(c),
        }
    }
    out
}

/// Maps world coordinates (metres, y up) to SVG pixels (y down).
struct Frame {
    lo: Point,
    hi: Point,
    scale: f64,
    /// Left edge of the map, after the y axis's labels.
    margin: f64,
    top: f64,
}

impl Frame {
    fn x(&self, x: f64) -> f64 {
        self.margin + (x - self.lo.x) * self.scale
    }
    fn bottom(&self) -> f64 {
        self.y(self.lo.y)
    }
    fn y(&self, y: f64) -> f64 {
        self.top + (self.hi.y - y) * self.scale
    }
    fn pt(&self, p: Point) -> String {
        format!("{:.1},{:.1}", self.x(p.x), self.y(p.y))
    }
    fn len(&self, d: f64) -> f64 {
        d * self.scale
    }
}

fn polygon_points(f: &Frame, poly: &Polygon) -> String {
    poly.points.iter().map(|&p| f.pt(p)).collect::<Vec<_>>().join(" ")
}

/// Route of one robot: its positions with consecutive repeats (waiting)
/// removed, since a zero-length segment has no direction to draw, and the
/// middle points of straight runs merged, which keeps the file small on
/// large maps without changing the picture.
fn route(poses: &[Pose]) -> Vec<Point> {
    let mut out: Vec<Point> = Vec::new();
    for p in poses {
        let q = p.position;
        if out.last().is_some_and(|&l| (l - q).norm() <= 1e-9) {
            continue;
        }
        if let [.., a, b] = out[..] {
            let (u, v) = (b - a, q - b);
            // Same direction (not a reversal): b is inside a straight run.
            if (u.x * v.y - u.y * v.x).abs() <= 1e-9 * u.norm() * v.norm() && u.dot(&v) > 0.0 {
                out.pop();
            }
        }
        out.push(q);
    }
    out
}

/// At most this many arrowheads per robot: enough to read the direction,
/// few enough that a long route on a large map stays a small file.
const MAX_ARROWS: usize = 40;

/// The legend's layout: a swatch per robot in as many columns as the map's
/// height needs (200 robots fit), then what the marks mean.
struct Legend {
    robots: usize,
    rows: usize,
    columns: usize,
}

const LEGEND_ROW: f64 = 16.0;
const LEGEND_COLUMN: f64 = 92.0;
/// What the legend explains below the robots: a drawn sample, then words.
#[derive(Clone, Copy)]
enum Sample {
    Start,
    End(Fate),
    Thawed,
    Target,
    Text,
}

const MARKS: [(Sample, &str); 10] = [
    (Sample::Start, "start (robot number)"),
    (Sample::End(Fate::Running), "end, searching"),
    (Sample::End(Fate::Halted), "end, record stopped"),
    (Sample::End(Fate::Crashed), "crashed"),
    (Sample::End(Fate::Frozen), "frozen to the end"),
    (Sample::Thawed, "frozen, later thawed"),
    (Sample::Target, "target, r_st dashed"),
    (Sample::Text, "grey dots: accessible"),
    (Sample::Text, "dashed routes: robots"),
    (Sample::Text, "past the 24th colour"),
];
const MARK_ROW: f64 = 17.0;

/// The mark of a robot's end (or of a freeze it recovered from, `Thawed`)
/// at `(x, y)`, `rad` pixels across half.
fn end_mark(s: &mut String, fate: Option<Fate>, x: f64, y: f64, rad: f64, colour: &str, robot: Option<usize>) {
    let data = robot.map(|r| format!(r#" data-robot="{r}""#)).unwrap_or_default();
    let bars = |s: &mut String, fill: &str| {
        let (w, h) = (rad * 0.32, rad * 1.1);
        for dx in [-0.6 * w - w / 2.0, 0.6 * w + w / 2.0] {
            let _ = write!(
                s,
                r#"<rect x="{:.2}" y="{:.2}" width="{w:.2}" height="{h:.2}" fill="{fill}"/>"#,
                x + dx - w / 2.0,
                y - h / 2.0
            );
        }
    };
    match fate {
        Some(Fate::Running) => {
            let _ = writeln!(
                s,
                r#"<circle class="end running"{data} cx="{x:.2}" cy="{y:.2}" r="{:.2}" fill="{colour}"/>"#,
                rad * 0.8
            );
        }
        Some(Fate::Halted) => {
            let _ = writeln!(
                s,
                r##"<circle class="end halted"{data} cx="{x:.2}" cy="{y:.2}" r="{:.2}" fill="#ffffff" stroke="{colour}" stroke-width="{:.2}"/>"##,
                rad * 0.65,
                rad * 0.35
            );
        }
        Some(Fate::Crashed) => {
            let _ = writeln!(
                s,
                r##"<g class="end crashed"{data}><circle cx="{x:.2}" cy="{y:.2}" r="{:.2}" fill="{colour}"/><path d="M{:.2},{:.2}L{:.2},{:.2}M{:.2},{:.2}L{:.2},{:.2}" stroke="#000000" stroke-width="{:.2}" stroke-linecap="round"/></g>"##,
                rad * 0.7,
                x - rad,
                y - rad,
                x + rad,
                y + rad,
                x - rad,
                y + rad,
                x + rad,
                y - rad,
                (rad * 0.38).max(1.5)
            );
        }
        Some(Fate::Frozen) => {
            let _ = write!(
                s,
                r##"<g class="end frozen"{data}><circle cx="{x:.2}" cy="{y:.2}" r="{rad:.2}" fill="{colour}" stroke="#000000" stroke-width="1.2"/>"##
            );
            bars(s, "#ffffff");
            let _ = writeln!(s, "</g>");
        }
        None => {
            let _ = write!(
                s,
                r##"<g class="thawed"{data}><circle cx="{x:.2}" cy="{y:.2}" r="{rad:.2}" fill="#ffffff" stroke="{colour}" stroke-width="1.5"/>"##
            );
            bars(s, colour);
            let _ = writeln!(s, "</g>");
        }
    }
}

impl Legend {
    fn new(robots: usize, map_height: f64) -> Self {
        let rows = ((map_height - 90.0) / LEGEND_ROW).floor().max(10.0) as usize;
        Legend { robots, rows, columns: robots.div_ceil(rows).max(1) }
    }

    fn width(&self) -> f64 {
        (self.columns as f64 * LEGEND_COLUMN).max(140.0)
    }

    fn height(&self) -> f64 {
        self.robots.min(self.rows) as f64 * LEGEND_ROW + 8.0 + MARKS.len() as f64 * MARK_ROW + 10.0
    }

    fn write(&self, s: &mut String, x0: f64, y0: f64) {
        let _ = writeln!(s, r#"<g id="legend" font-size="12">"#);
        for r in 0..self.robots {
            let (lx, ly) =
                (x0 + (r / self.rows) as f64 * LEGEND_COLUMN, y0 + 10.0 + (r % self.rows) as f64 * LEGEND_ROW);
            let dash = palette::robot_dash(r).map(|d| format!(r#" stroke-dasharray="{d}""#)).unwrap_or_default();
            let _ = writeln!(
                s,
                r#"<line x1="{lx:.1}" y1="{ly:.1}" x2="{:.1}" y2="{ly:.1}" stroke="{}" stroke-width="3"{dash}/><text x="{:.1}" y="{:.1}">robot {r}</text>"#,
                lx + 22.0,
                robot_colour(r),
                lx + 28.0,
                ly + 4.0,
            );
        }
        let mut ly = y0 + 10.0 + self.robots.min(self.rows) as f64 * LEGEND_ROW + 8.0;
        let ink = "#444444";
        for (sample, words) in MARKS {
            let (gx, tx) = (x0 + 8.0, if matches!(sample, Sample::Text) { x0 } else { x0 + 20.0 });
            match sample {
                Sample::Start => {
                    let _ = writeln!(
                        s,
                        r##"<rect x="{:.1}" y="{:.1}" width="12" height="12" fill="#ffffff" stroke="{ink}" stroke-width="2"/>"##,
                        gx - 6.0,
                        ly - 6.0
                    );
                }
                Sample::End(fate) => end_mark(s, Some(fate), gx, ly, 6.0, ink, None),
                Sample::Thawed => end_mark(s, None, gx, ly, 6.0, ink, None),
                Sample::Target => {
                    let _ = writeln!(
                        s,
                        r#"<rect x="{:.1}" y="{:.1}" width="8" height="8" fill="{}" transform="rotate(45 {gx:.1} {ly:.1})"/>"#,
                        gx - 4.0,
                        ly - 4.0,
                        palette::TARGET
                    );
                }
                Sample::Text => {}
            }
            let _ = writeln!(s, r#"<text x="{tx:.1}" y="{:.1}" font-size="11">{words}</text>"#, ly + 4.0);
            ly += MARK_ROW;
        }
        let _ = writeln!(s, "</g>");
    }
}

/// A round step (1, 2 or 5 times a power of ten) giving about `n` ticks over `span`.
fn nice_step(span: f64, n: f64) -> f64 {
    let raw = (span / n).max(1e-9);
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0].into_iter().map(|m| m * p).find(|&s| s >= raw).unwrap_or(10.0 * p)
}

/// Axes in metres along the bottom and left of the map, and a scale bar.
fn axes(s: &mut String, f: &Frame, lo: Point, hi: Point) {
    let step = nice_step((hi.x - lo.x).max(hi.y - lo.y), 8.0);
    let (bottom, left) = (f.bottom(), f.x(lo.x));
    let _ = writeln!(s, r##"<g id="axes" font-size="12" fill="#444444" stroke="#444444" stroke-width="0.8">"##);
    let mut x = (lo.x / step).ceil() * step;
    while x <= hi.x + 1e-9 {
        let px = f.x(x);
        let _ = writeln!(
            s,
            r#"<line x1="{px:.1}" y1="{bottom:.1}" x2="{px:.1}" y2="{:.1}"/><text x="{px:.1}" y="{:.1}" text-anchor="middle" stroke="none">{}</text>"#,
            bottom + 4.0,
            bottom + 16.0,
            tick(x)
        );
        x += step;
    }
    let mut y = (lo.y / step).ceil() * step;
    while y <= hi.y + 1e-9 {
        let py = f.y(y);
        let _ = writeln!(
            s,
            r#"<line x1="{:.1}" y1="{py:.1}" x2="{left:.1}" y2="{py:.1}"/><text x="{:.1}" y="{:.1}" text-anchor="end" stroke="none">{}</text>"#,
            left - 4.0,
            left - 6.0,
            py + 3.5,
            tick(y)
        );
        y += step;
    }
    let (bx, by) = (left, bottom + 32.0);
    let _ = writeln!(
        s,
        r#"<g id="scale-bar"><line x1="{bx:.1}" y1="{by:.1}" x2="{:.1}" y2="{by:.1}" stroke-width="2"/><text x="{:.1}" y="{:.1}" stroke="none">{} m (axes in metres)</text></g>"#,
        bx + f.len(step),
        bx + f.len(step) + 6.0,
        by + 3.5,
        tick(step)
    );
    let _ = writeln!(s, "</g>");
}

/// A tick label without trailing zeros.
fn tick(v: f64) -> String {
    let t = format!("{v:.2}");
    let t = t.trim_end_matches('0').trim_end_matches('.');
    if t == "-0" {
        "0".into()
    } else {
        t.into()
    }
}

/// Where a map of `world` goes: about `side` px on the long side, but
/// never so small that vertices merge nor so large that a small map
/// becomes a poster. Returns the frame and the map's size in pixels.
fn frame_of(world: &World, side: f64) -> (Frame, f64, f64) {
    let (lo, hi) = world.area.bounding_box();
    let (w, h) = ((hi.x - lo.x).max(1e-6), (hi.y - lo.y).max(1e-6));
    let scale = (side / w.max(h)).clamp(8.0, 80.0);
    // Room above the map for a title and a line of settings.
    let frame = Frame { lo, hi, scale, margin: 44.0, top: 56.0 };
    let (pw, ph) = (frame.len(w), frame.len(h));
    (frame, pw, ph)
}

/// A map alone, `side` pixels on its long side, without text: the area,
/// obstacles and targets, for the thumbnails of a report over maps. `id`
/// names the `<svg>` element.
pub fn map_svg(world: &World, side: f64, id: &str) -> String {
    let (lo, hi) = world.area.bounding_box();
    let (w, h) = ((hi.x - lo.x).max(1e-6), (hi.y - lo.y).max(1e-6));
    let frame = Frame { lo, hi, scale: side / w.max(h), margin: 2.0, top: 2.0 };
    let (width, height) = (frame.len(w) + 4.0, frame.len(h) + 4.0);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg id="{}" xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.2} {height:.2}">"#,
        xml_escape(id)
    );
    area(&mut s, &frame, world);
    let star = (frame.len(world.params.a) * 0.5).clamp(3.0, 6.0);
    let _ = writeln!(s, r#"<g id="targets" fill="{}">"#, palette::TARGET);
    for t in &world.targets {
        let (x, y) = (frame.x(t.x), frame.y(t.y));
        let _ = writeln!(
            s,
            r#"<rect x="{:.1}" y="{:.1}" width="{star:.1}" height="{star:.1}" transform="rotate(45 {x:.1} {y:.1})"/>"#,
            x - star / 2.0,
            y - star / 2.0
        );
    }
    let _ = writeln!(s, "</g>\n</svg>");
    s
}

/// The document's start: size, title (and a line of settings under it,
/// if any), white background.
fn open_svg(s: &mut String, width: f64, height: f64, title: &str, settings: &str, frame: &Frame) {
    let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.2} {height:.2}" font-family="sans-serif">"#
    );
    let _ = writeln!(s, "<title>{}</title>", xml_escape(title));
    let _ = writeln!(s, r##"<rect x="0" y="0" width="{width:.2}" height="{height:.2}" fill="#ffffff"/>"##);
    let _ = writeln!(s, r##"<text x="{:.2}" y="22" font-size="14">{}</text>"##, frame.margin, xml_escape(title));
    if !settings.is_empty() {
        let _ = writeln!(
            s,
            r##"<text id="settings" x="{:.2}" y="40" font-size="12" fill="#444444">{}</text>"##,
            frame.margin,
            xml_escape(settings)
        );
    }
}

/// The area and its obstacles.
fn area(s: &mut String, frame: &Frame, world: &World) {
    let _ = writeln!(
        s,
        r##"<polygon id="area" points="{}" fill="#f4f4ef" stroke="#333333" stroke-width="1.5"/>"##,
        polygon_points(frame, &world.area)
    );
    let _ = writeln!(s, r##"<g id="obstacles" fill="#9a9a9a" stroke="#555555" stroke-width="1">"##);
    for o in &world.obstacles {
        match o {
            Shape::Polygon(p) => {
                let _ = writeln!(s, r#"<polygon points="{}"/>"#, polygon_points(frame, p));
            }
            Shape::Circle(c) => {
                let _ = writeln!(
                    s,
                    r#"<circle cx="{:.2}" cy="{:.2}" r="{:.2}"/>"#,
                    frame.x(c.center.x),
                    frame.y(c.center.y),
                    frame.len(c.radius)
                );
            }
        }
    }
    let _ = writeln!(s, "</g>");
}

/// Where a lattice leaves `Ad` undetected: the vertices of `Va` (grey) and
/// every raster sample no vertex of `Va` senses (`holes`, red), for
/// `experiment --grids`.
pub fn holes_svg(world: &World, va: &[Point], holes: &[Point], title: &str) -> String {
    // 880 px wide in all: a report shows it whole, its text unshrunk.
    let (frame, pw, ph) = frame_of(world, 816.0);
    let (lo, hi) = world.area.bounding_box();
    let (width, height) = (frame.margin + pw + 20.0, frame.top + ph + 48.0);
    let mut s = String::new();
    open_svg(&mut s, width, height, title, "", &frame);
    area(&mut s, &frame, world);
    let dot = (frame.len(world.params.a) * 0.05).clamp(0.8, 2.5);
    let _ = writeln!(s, r##"<g id="va" fill="#888888">"##);
    for p in va {
        let _ = writeln!(s, r#"<circle cx="{:.1}" cy="{:.1}" r="{dot:.1}"/>"#, frame.x(p.x), frame.y(p.y));
    }
    let _ = writeln!(s, "</g>");
    let cell = 2.5f64.max(dot * 1.5);
    let _ = writeln!(s, r#"<g id="holes" fill="{}">"#, palette::TARGET);
    for p in holes {
        let _ = writeln!(
            s,
            r#"<rect x="{:.1}" y="{:.1}" width="{cell:.1}" height="{cell:.1}"/>"#,
            frame.x(p.x) - cell / 2.0,
            frame.y(p.y) - cell / 2.0
        );
    }
    let _ = writeln!(s, "</g>");
    axes(&mut s, &frame, lo, hi);
    let _ = writeln!(s, "</svg>");
    s
}

/// Each robot's start square, the places it froze and thawed from, and
/// its end mark by [`Notes::fate`].
fn marks(s: &mut String, frame: &Frame, a: f64, trajectories: &[Vec<Pose>], notes: &Notes) {
    let rounds = trajectories.iter().map(Vec::len).max().unwrap_or(0);
    let _ = writeln!(s, r#"<g id="marks">"#);
    for (r, poses) in trajectories.iter().enumerate() {
        let colour = robot_colour(r);
        let pts = route(poses);
        if let Some(&start) = pts.first() {
            let (x, y) = (frame.x(start.x), frame.y(start.y));
            let rad = (frame.len(a) * 0.18).clamp(4.0, 10.0);
            let _ = writeln!(
                s,
                r##"<rect class="start" data-robot="{r}" x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="#ffffff" stroke="{colour}" stroke-width="2"/>"##,
                x - rad,
                y - rad,
                2.0 * rad,
                2.0 * rad
            );
            let _ = writeln!(
                s,
                r#"<text x="{x:.2}" y="{:.2}" font-size="{:.1}" text-anchor="middle" fill="{colour}">{r}</text>"#,
                y + rad * 0.45,
                rad * 1.2,
            );
        }
        let rad = (frame.len(a) * 0.14).clamp(4.0, 9.0);
        for f in notes.faults.iter().filter(|f| f.robot == r && !f.crash && f.thawed) {
            // Where it froze; its end mark is its fate at the end.
            let p = poses[f.round.min(poses.len().saturating_sub(1))].position;
            end_mark(s, None, frame.x(p.x), frame.y(p.y), rad, &colour, Some(r));
        }
        if let Some(end) = poses.last() {
            let fate = notes.fate(r, poses.len(), rounds);
            end_mark(s, Some(fate), frame.x(end.position.x), frame.y(end.position.y), rad, &colour, Some(r));
        }
    }
    let _ = writeln!(s, "</g>");
}

/// The route map of a run as an SVG document.
pub fn routes_svg(world: &World, trajectories: &[Vec<Pose>], notes: &Notes) -> String {
    let (lo, hi) = world.area.bounding_box();
    let a = world.params.a;
    let (frame, pw, ph) = frame_of(world, 900.0);
    let legend = Legend::new(trajectories.len(), ph);
    let width = frame.margin + pw + 20.0 + legend.width();
    let height = frame.top + ph.max(legend.height()) + 48.0;
    let mut s = String::new();
    open_svg(&mut s, width, height, &notes.title, &notes.settings, &frame);
    area(&mut s, &frame, world);

    let dot = (frame.len(a) * 0.04).clamp(0.6, 2.0);
    let _ = writeln!(s, r##"<g id="vertices" fill="#b0b0b0">"##);
    for v in world.accessible_vertices() {
        let p = world.grid.position(v);
        let _ = writeln!(s, r#"<circle cx="{:.1}" cy="{:.1}" r="{dot:.1}"/>"#, frame.x(p.x), frame.y(p.y));
    }
    let _ = writeln!(s, "</g>");

    let _ = writeln!(s, r##"<g id="targets">"##);
    let r_st = frame.len(world.params.r_st);
    let star = (frame.len(a) * 0.15).clamp(3.0, 8.0);
    for t in &world.targets {
        let (x, y) = (frame.x(t.x), frame.y(t.y));
        let red = palette::TARGET;
        let _ = writeln!(
            s,
            r#"<circle cx="{x:.2}" cy="{y:.2}" r="{r_st:.2}" fill="{red}" fill-opacity="0.06" stroke="{red}" stroke-width="0.8" stroke-dasharray="4 3"/>"#
        );
        let _ = writeln!(
            s,
            r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{red}" transform="rotate(45 {x:.2} {y:.2})"/>"#,
            x - star / 2.0,
            y - star / 2.0,
            star,
            star
        );
    }
    let _ = writeln!(s, "</g>");

    let stroke = (frame.len(a) * 0.05).clamp(1.0, 2.5);
    let head = (frame.len(a) * 0.22).clamp(4.0, 12.0);
    for (r, poses) in trajectories.iter().enumerate() {
        let colour = robot_colour(r);
        let pts = route(poses);
        let _ = writeln!(s, r#"<g id="robot-{r}" stroke="{colour}" fill="{colour}">"#);
        if pts.len() >= 2 {
            let dash = palette::robot_dash(r).map(|d| format!(r#" stroke-dasharray="{d}""#)).unwrap_or_default();
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke-width="{stroke:.2}" stroke-opacity="0.75" stroke-linejoin="round"{dash}/>"#,
                pts.iter().map(|&p| frame.pt(p)).collect::<Vec<_>>().join(" ")
            );
            // One arrowhead at the middle of every segment, pointing along it.
            let stride = (pts.len() - 1).div_ceil(MAX_ARROWS);
            for seg in pts.windows(2).step_by(stride) {
                let (p, q) = (seg[0], seg[1]);
                let (px, py, qx, qy) = (frame.x(p.x), frame.y(p.y), frame.x(q.x), frame.y(q.y));
                let (dx, dy) = (qx - px, qy - py);
                let len = (dx * dx + dy * dy).sqrt();
                if len < 1e-9 {
                    continue;
                }
                let (ux, uy) = (dx / len, dy / len);
                let (mx, my) = ((px + qx) / 2.0 + ux * head / 2.0, (py + qy) / 2.0 + uy * head / 2.0);
                let (bx, by) = (mx - ux * head, my - uy * head);
                let (nx, ny) = (-uy * head * 0.4, ux * head * 0.4);
                let _ = writeln!(
                    s,
                    r#"<polygon points="{mx:.2},{my:.2} {:.2},{:.2} {:.2},{:.2}" stroke="none"/>"#,
                    bx + nx,
                    by + ny,
                    bx - nx,
                    by - ny
                );
            }
        }
        let _ = writeln!(s, "</g>");
    }

    // Start, fault and end marks last, so that no later route hides them.
    marks(&mut s, &frame, a, trajectories, notes);
    axes(&mut s, &frame, lo, hi);
    legend.write(&mut s, frame.margin + pw + 20.0, frame.top);
    let _ = writeln!(s, "</svg>");
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridswarm::geometry::Circle;
    use gridswarm::lattice::LatticeKind;
    use gridswarm::params::Params;

    fn world() -> World {
        let area =
            Polygon::new(vec![Point::new(0.0, 0.0), Point::new(6.0, 0.0), Point::new(6.0, 4.0), Point::new(0.0, 4.0)]);
        let obstacle = Shape::Circle(Circle { center: Point::new(3.0, 2.0), radius: 0.5 });
        let square = Shape::Polygon(Polygon::new(vec![
            Point::new(4.5, 3.0),
            Point::new(5.0, 3.0),
            Point::new(5.0, 3.5),
            Point::new(4.5, 3.5),
        ]));
        World::new(area, vec![obstacle, square], vec![Point::new(5.0, 1.0)], Params::default(), LatticeKind::Triangular)
    }

    fn notes(title: &str) -> Notes {
        Notes { title: title.into(), ..Notes::default() }
    }

    fn poses(pts: &[(f64, f64)]) -> Vec<Pose> {
        pts.iter().map(|&(x, y)| Pose { vertex: None, position: Point::new(x, y) }).collect()
    }

    #[test]
    fn valid_xml_with_everything_drawn() {
        let w = world();
        let t = vec![poses(&[(1.0, 0.866), (2.0, 0.866), (2.0, 0.866), (2.5, 1.732)]), poses(&[(0.5, 2.598)])];
        let svg = routes_svg(&w, &t, &notes("paper <test> & co"));
        let doc = roxmltree::Document::parse(&svg).expect("valid XML");
        let root = doc.root_element();
        assert_eq!(root.tag_name().name(), "svg");
        let by_id =
            |id: &str| doc.descendants().find(|n| n.attribute("id") == Some(id)).unwrap_or_else(|| panic!("no {id}"));
        assert_eq!(by_id("obstacles").children().filter(|n| n.is_element()).count(), 2);
        assert_eq!(by_id("vertices").children().filter(|n| n.is_element()).count(), w.accessible_vertices().count());
        // Robot 0 (numbered as in the CLI and JSON): the wait is dropped,
        // so 2 segments and 2 arrowheads.
        let r1 = by_id("robot-0");
        assert_eq!(r1.children().filter(|n| n.has_tag_name("polygon")).count(), 2);
        let starts = |r: &str| {
            doc.descendants()
                .filter(|n| n.attribute("class") == Some("start") && n.attribute("data-robot") == Some(r))
                .count()
        };
        assert_eq!(starts("0"), 1);
        // Robot 1 never moved: a start mark but no route.
        let r2 = by_id("robot-1");
        assert_eq!(r2.children().filter(|n| n.has_tag_name("polyline")).count(), 0);
        assert_eq!(starts("1"), 1);
        assert!(svg.contains("paper &lt;test&gt; &amp; co"));
    }

    #[test]
    fn the_legend_of_200_robots_fits_inside_the_picture() {
        let w = world();
        let trajectories: Vec<Vec<Pose>> = (0..200).map(|_| poses(&[(1.0, 1.0), (2.0, 1.0)])).collect();
        let svg = routes_svg(&w, &trajectories, &notes("many"));
        let doc = roxmltree::Document::parse(&svg).expect("valid XML");
        let root = doc.root_element();
        let (width, height): (f64, f64) =
            (root.attribute("width").unwrap().parse().unwrap(), root.attribute("height").unwrap().parse().unwrap());
        let legend = doc.descendants().find(|n| n.attribute("id") == Some("legend")).unwrap();
        let labels: Vec<_> = legend
            .descendants()
            .filter(|n| n.has_tag_name("text") && n.text().is_some_and(|t| t.starts_with("robot ")))
            .collect();
        assert_eq!(labels.len(), 200);
        for t in labels {
            let (x, y): (f64, f64) =
                (t.attribute("x").unwrap().parse().unwrap(), t.attribute("y").unwrap().parse().unwrap());
            // "robot 199" is about 55 px wide at 12 px.
            assert!(x + 55.0 <= width && y <= height, "{} at ({x}, {y}) outside {width} x {height}", t.text().unwrap());
        }
        // Axes in metres and a scale bar.
        assert!(doc.descendants().any(|n| n.attribute("id") == Some("axes")));
        assert!(svg.contains("(axes in metres)"));
    }

    #[test]
    fn long_routes_keep_few_arrowheads() {
        let w = world();
        // A robot going back and forth 500 times.
        let pts: Vec<(f64, f64)> = (0..1000).map(|k| (1.0 + (k % 2) as f64, 1.0)).collect();
        let svg = routes_svg(&w, &[poses(&pts)], &notes("long"));
        let arrows = svg.matches("<polygon points=").count();
        assert!(arrows <= MAX_ARROWS + 2, "{arrows} arrowheads");
        // A straight run is one segment: its middle points are merged.
        assert_eq!(route(&poses(&[(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, 1.0)])).len(), 3);
    }

    #[test]
    fn fates_have_marks_of_their_own() {
        let w = world();
        let walk = poses(&[(1.0, 0.866), (2.0, 0.866), (2.5, 1.732)]);
        let t = vec![walk.clone(), walk.clone(), walk.clone(), walk[..2].to_vec(), walk];
        let summary = serde_json::json!({
            "failures": [
                { "robot": 1, "kind": "crash", "round": 1, "thawed_s": null },
                { "robot": 2, "kind": "freeze", "round": 1, "thawed_s": null },
                { "robot": 4, "kind": "freeze", "round": 1, "thawed_s": 9.5 },
            ],
            "faults": ["--kill 1@1", "--freeze 2@1", "--freeze 4@1:2"],
            "radio": { "loss": 0.2, "delay": 0, "jitter": 0, "dup": 0.0 },
            "retries": 1,
        });
        let svg = routes_svg(&w, &t, &Notes::of("fates", &summary));
        let doc = roxmltree::Document::parse(&svg).expect("valid XML");
        let end = |r: &str| {
            doc.descendants()
                .find(|n| {
                    n.attribute("data-robot") == Some(r) && n.attribute("class").is_some_and(|c| c.starts_with("end "))
                })
                .map(|n| {
                    (n.attribute("class").unwrap(), n.tag_name().name(), n.children().count(), n.attribute("fill"))
                })
                .unwrap_or_else(|| panic!("robot {r} has no end mark"))
        };
        let (running, crashed, frozen, halted, thawed) = (end("0"), end("1"), end("2"), end("3"), end("4"));
        assert_eq!(running.0, "end running");
        assert_eq!(crashed.0, "end crashed");
        assert_eq!(frozen.0, "end frozen");
        assert_eq!(halted.0, "end halted");
        // Thawed: it ends searching, and its freeze is marked where it happened.
        assert_eq!(thawed.0, "end running");
        assert!(doc
            .descendants()
            .any(|n| n.attribute("class") == Some("thawed") && n.attribute("data-robot") == Some("4")));
        // Four marks that differ in drawing, not only in name.
        let shapes: std::collections::HashSet<_> =
            [running, crashed, frozen, halted].iter().map(|m| (m.1, m.2, m.3)).collect();
        assert_eq!(shapes.len(), 4, "{svg}");
        let settings = doc.descendants().find(|n| n.attribute("id") == Some("settings")).unwrap().text().unwrap();
        assert!(
            settings.contains("--kill 1@1") && settings.contains("loss 0.2") && settings.contains("retries 1"),
            "{settings}"
        );
    }

    #[test]
    fn a_thumbnail_fits_its_side() {
        let svg = map_svg(&world(), 240.0, "map-0");
        let doc = roxmltree::Document::parse(&svg).expect("valid XML");
        let root = doc.root_element();
        assert_eq!(root.attribute("id"), Some("map-0"));
        let width: f64 = root.attribute("width").unwrap().parse().unwrap();
        assert!((width - 244.0).abs() < 1.0, "{width}");
        assert_eq!(doc.descendants().filter(|n| n.attribute("id") == Some("targets")).count(), 1);
        assert_eq!(
            doc.descendants()
                .find(|n| n.attribute("id") == Some("obstacles"))
                .unwrap()
                .children()
                .filter(|n| n.is_element())
                .count(),
            2
        );
    }

    #[test]
    fn no_robot_in_the_targets_red() {
        let w = world();
        let t: Vec<Vec<Pose>> = (0..30).map(|_| poses(&[(1.0, 1.0), (2.0, 1.0)])).collect();
        let svg = routes_svg(&w, &t, &notes("red"));
        let doc = roxmltree::Document::parse(&svg).expect("valid XML");
        for r in 0..30 {
            let g = doc.descendants().find(|n| n.attribute("id") == Some(format!("robot-{r}").as_str())).unwrap();
            assert_ne!(g.attribute("stroke"), Some(palette::TARGET), "robot {r}");
        }
        // Robots 0 and 12 (the `large` map's 13 robots) differ.
        assert_ne!(robot_colour(0), robot_colour(12));
    }

    #[test]
    fn colours_distinct_for_many_robots() {
        // A colour and a dash pattern per robot.
        let cs: std::collections::HashSet<_> = (0..60).map(|r| (robot_colour(r), palette::robot_dash(r))).collect();
        assert_eq!(cs.len(), 60);
    }
}
