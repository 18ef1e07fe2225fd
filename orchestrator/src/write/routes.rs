//! `routes.svg`: the area, obstacles, accessible vertices, targets with
//! their sensing circles and each robot's route with arrows, like the
//! paper's Fig. 5. Written by hand: it is a few element kinds, and plain
//! SVG keeps every arrow exactly on its edge.

use std::fmt::Write as _;

use gridswarm::geometry::{Point, Polygon, Shape};
use gridswarm::outcome::Pose;
use gridswarm::world::World;

/// Distinct colours for the first robots (Tableau 10), then golden-angle
/// hues, so any number of robots gets colours that differ from neighbours.
pub fn robot_colour(r: usize) -> String {
    const TAB10: [&str; 10] =
        ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"];
    match TAB10.get(r) {
        Some(c) => (*c).to_string(),
        None => format!("hsl({:.0},70%,40%)", (r as f64 * 137.507_764) % 360.0),
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
const MARKS: [&str; 5] = ["square: start", "dot: end", "diamond: target", "dashed: r_st", "grey dots: accessible"];

impl Legend {
    fn new(robots: usize, map_height: f64) -> Self {
        let rows = ((map_height - 90.0) / LEGEND_ROW).floor().max(10.0) as usize;
        Legend { robots, rows, columns: robots.div_ceil(rows).max(1) }
    }

    fn width(&self) -> f64 {
        (self.columns as f64 * LEGEND_COLUMN).max(130.0)
    }

    fn height(&self) -> f64 {
        self.robots.min(self.rows) as f64 * LEGEND_ROW + 8.0 + MARKS.len() as f64 * 13.0 + 10.0
    }

    fn write(&self, s: &mut String, x0: f64, y0: f64) {
        let _ = writeln!(s, r#"<g id="legend" font-size="12">"#);
        for r in 0..self.robots {
            let (lx, ly) =
                (x0 + (r / self.rows) as f64 * LEGEND_COLUMN, y0 + 10.0 + (r % self.rows) as f64 * LEGEND_ROW);
            let _ = writeln!(
                s,
                r#"<line x1="{lx:.1}" y1="{ly:.1}" x2="{:.1}" y2="{ly:.1}" stroke="{}" stroke-width="3"/><text x="{:.1}" y="{:.1}">robot {r}</text>"#,
                lx + 22.0,
                robot_colour(r),
                lx + 28.0,
                ly + 4.0,
            );
        }
        let mut ly = y0 + 10.0 + self.robots.min(self.rows) as f64 * LEGEND_ROW + 8.0;
        for line in MARKS {
            let _ = writeln!(s, r#"<text x="{x0:.1}" y="{ly:.1}" font-size="10">{line}</text>"#);
            ly += 13.0;
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
    let _ = writeln!(s, r##"<g id="axes" font-size="10" fill="#444444" stroke="#444444" stroke-width="0.8">"##);
    let mut x = (lo.x / step).ceil() * step;
    while x <= hi.x + 1e-9 {
        let px = f.x(x);
        let _ = writeln!(
            s,
            r#"<line x1="{px:.1}" y1="{bottom:.1}" x2="{px:.1}" y2="{:.1}"/><text x="{px:.1}" y="{:.1}" text-anchor="middle" stroke="none">{}</text>"#,
            bottom + 4.0,
            bottom + 15.0,
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

/// Where a map of `world` goes: about 900 px on the long side, but never
/// so small that vertices merge nor so large that a small map becomes a
/// poster. Returns the frame and the map's size in pixels.
fn frame_of(world: &World) -> (Frame, f64, f64) {
    let (lo, hi) = world.area.bounding_box();
    let (w, h) = ((hi.x - lo.x).max(1e-6), (hi.y - lo.y).max(1e-6));
    let scale = (900.0 / w.max(h)).clamp(8.0, 80.0);
    let frame = Frame { lo, hi, scale, margin: 44.0, top: 40.0 };
    let (pw, ph) = (frame.len(w), frame.len(h));
    (frame, pw, ph)
}

/// The document's start: size, title, white background.
fn open_svg(s: &mut String, width: f64, height: f64, title: &str, frame: &Frame) {
    let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.2} {height:.2}" font-family="sans-serif">"#
    );
    let _ = writeln!(s, "<title>{}</title>", xml_escape(title));
    let _ = writeln!(s, r##"<rect x="0" y="0" width="{width:.2}" height="{height:.2}" fill="#ffffff"/>"##);
    let _ = writeln!(s, r##"<text x="{:.2}" y="24" font-size="14">{}</text>"##, frame.margin, xml_escape(title));
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
    let (frame, pw, ph) = frame_of(world);
    let (lo, hi) = world.area.bounding_box();
    let (width, height) = (frame.margin + pw + 20.0, frame.top + ph + 48.0);
    let mut s = String::new();
    open_svg(&mut s, width, height, title, &frame);
    area(&mut s, &frame, world);
    let dot = (frame.len(world.params.a) * 0.05).clamp(0.8, 2.5);
    let _ = writeln!(s, r##"<g id="va" fill="#888888">"##);
    for p in va {
        let _ = writeln!(s, r#"<circle cx="{:.1}" cy="{:.1}" r="{dot:.1}"/>"#, frame.x(p.x), frame.y(p.y));
    }
    let _ = writeln!(s, "</g>");
    let cell = 2.5f64.max(dot * 1.5);
    let _ = writeln!(s, r##"<g id="holes" fill="#d62728">"##);
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

/// The route map of a run as an SVG document.
pub fn routes_svg(world: &World, trajectories: &[Vec<Pose>], title: &str) -> String {
    let (lo, hi) = world.area.bounding_box();
    let a = world.params.a;
    let (frame, pw, ph) = frame_of(world);
    let legend = Legend::new(trajectories.len(), ph);
    let width = frame.margin + pw + 20.0 + legend.width();
    let height = frame.top + ph.max(legend.height()) + 48.0;
    let mut s = String::new();
    open_svg(&mut s, width, height, title, &frame);
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
        let _ = writeln!(
            s,
            r##"<circle cx="{x:.2}" cy="{y:.2}" r="{r_st:.2}" fill="#d62728" fill-opacity="0.06" stroke="#d62728" stroke-width="0.8" stroke-dasharray="4 3"/>"##
        );
        let _ = writeln!(
            s,
            r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="#d62728" transform="rotate(45 {x:.2} {y:.2})"/>"##,
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
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke-width="{stroke:.2}" stroke-opacity="0.75" stroke-linejoin="round"/>"#,
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

    // Start and end marks last, so that no later route hides them.
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
        if let Some(&end) = pts.last() {
            let _ = writeln!(
                s,
                r#"<circle class="end" data-robot="{r}" cx="{:.2}" cy="{:.2}" r="{:.2}" fill="{colour}"/>"#,
                frame.x(end.x),
                frame.y(end.y),
                stroke * 2.0
            );
        }
    }
    let _ = writeln!(s, "</g>");

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

    fn poses(pts: &[(f64, f64)]) -> Vec<Pose> {
        pts.iter().map(|&(x, y)| Pose { vertex: None, position: Point::new(x, y) }).collect()
    }

    #[test]
    fn valid_xml_with_everything_drawn() {
        let w = world();
        let t = vec![poses(&[(1.0, 0.866), (2.0, 0.866), (2.0, 0.866), (2.5, 1.732)]), poses(&[(0.5, 2.598)])];
        let svg = routes_svg(&w, &t, "paper <test> & co");
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
        let svg = routes_svg(&w, &trajectories, "many");
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
        let svg = routes_svg(&w, &[poses(&pts)], "long");
        let arrows = svg.matches("<polygon points=").count();
        assert!(arrows <= MAX_ARROWS + 2, "{arrows} arrowheads");
        // A straight run is one segment: its middle points are merged.
        assert_eq!(route(&poses(&[(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, 1.0)])).len(), 3);
    }

    #[test]
    fn colours_distinct_for_many_robots() {
        let cs: std::collections::HashSet<String> = (0..40).map(robot_colour).collect();
        assert_eq!(cs.len(), 40);
    }
}
