//! Line plots side by side in one SVG, in the style of `fig7.svg`
//! ([`crate::plot`]): for the failure and scaling experiments, whose
//! figures show several quantities against one variable.

use plotters::element::DashedPathElement;
use plotters::prelude::*;

use crate::write::{palette, plot};

/// Panels side by side at most: a report shows the figure at its own
/// width (about 920 px), where 12-point text stays 12 px.
pub const COLUMNS: usize = 2;
const PANEL_W: u32 = 460;
const PANEL_H: u32 = 400;

/// Dash patterns `(dash, gap)` in pixels, by a series' `dash` index; 0 is solid.
const DASHES: [(u32, u32); 5] = [(0, 0), (9, 5), (3, 4), (16, 5), (6, 3)];

/// The palette's colour `k` for plotters.
pub fn colour(k: usize) -> RGBColor {
    let (r, g, b) = crate::write::palette::rgb(palette::COLOURS[k % palette::COLOURS.len()]);
    RGBColor(r, g, b)
}

/// One line: points `(x, y)` with an optional error half-width each.
#[derive(Clone, Debug)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64, f64)>,
    /// Palette index; the series' place in its panel when `None`.
    pub colour: Option<usize>,
    /// Dash pattern index (0: solid), e.g. a second variable of the experiment.
    pub dash: usize,
    /// The error drawn as a shaded band about the line, without marks at
    /// the points (a curve of many points), instead of bars.
    pub band: bool,
}

impl Series {
    pub fn new(label: impl Into<String>, points: impl IntoIterator<Item = (f64, Option<f64>)>) -> Self {
        Series::with_err(label, points.into_iter().map(|(x, y)| (x, y, None)))
    }

    /// Points without a value are left out.
    pub fn with_err(
        label: impl Into<String>,
        points: impl IntoIterator<Item = (f64, Option<f64>, Option<f64>)>,
    ) -> Self {
        Series {
            label: label.into(),
            points: points.into_iter().filter_map(|(x, y, e)| y.map(|y| (x, y, e.unwrap_or(0.0)))).collect(),
            colour: None,
            dash: 0,
            band: false,
        }
    }

    /// The same series in palette colour `colour` and dash pattern `dash`.
    pub fn styled(self, colour: usize, dash: usize) -> Self {
        Series { colour: Some(colour), dash, ..self }
    }

    /// The same series with its error as a band ([`Series::band`]).
    pub fn banded(self) -> Self {
        Series { band: true, ..self }
    }
}

/// One chart of the figure.
#[derive(Clone, Debug)]
pub struct Panel {
    pub title: String,
    pub x_desc: String,
    pub y_desc: String,
    pub series: Vec<Series>,
    /// Logarithmic y axis (decades labelled; values must be positive).
    pub log_y: bool,
    /// Fixed y range, e.g. `0..=1` for a rate; from the data when `None`.
    pub y_range: Option<(f64, f64)>,
    /// Whether the panel draws its legend: panels whose series are those
    /// of another panel leave it out, so that no key hides their lines.
    pub legend: bool,
    /// The x values this panel labels, when its axis is its own rather
    /// than the figure's (curves over time whose ends differ).
    pub xs: Option<Vec<f64>>,
}

impl Panel {
    pub fn new(title: &str, x_desc: &str, y_desc: &str, series: Vec<Series>) -> Self {
        Panel {
            title: title.into(),
            x_desc: x_desc.into(),
            y_desc: y_desc.into(),
            series,
            log_y: false,
            y_range: None,
            legend: true,
            xs: None,
        }
    }
}

fn nice(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if x.abs() >= 100.0 {
        format!("{x:.0}")
    } else if x.abs() >= 1.0 {
        let s = format!("{x:.1}");
        s.strip_suffix(".0").map(str::to_string).unwrap_or(s)
    } else {
        format!("{x:.2}")
    }
}

/// `10^e` as a tick label: `1000`, `1`, `0.01`, `1e-5`.
fn decade(e: i32) -> String {
    match e {
        0..=6 => format!("{}", 10u64.pow(e as u32)),
        -4..=-1 => format!("{:.*}", (-e) as usize, 10f64.powi(e)),
        _ => format!("1e{e}"),
    }
}

/// The x axis every panel shares: its range, tick count, and whether the
/// variable is whole (robot counts) or a fraction (a probability).
#[derive(Clone, Copy)]
struct XAxis {
    x0: f64,
    x1: f64,
    pad: f64,
    ticks: usize,
    whole: bool,
}

impl XAxis {
    fn of(xs: &[f64]) -> Self {
        let (mut x0, mut x1) =
            (xs.iter().copied().fold(f64::INFINITY, f64::min), xs.iter().copied().fold(f64::NEG_INFINITY, f64::max));
        if !x0.is_finite() {
            (x0, x1) = (0.0, 1.0);
        }
        // Whole-number variables (robot counts) get a tick per integer;
        // fractions (a probability) get plotters' own ticks.
        let whole = xs.iter().all(|x| (x - x.round()).abs() < 1e-9);
        let pad = if whole { ((x1 - x0) * 0.05).max(0.5) } else { ((x1 - x0) * 0.05).max(1e-3) };
        let ticks = if whole { ((x1 - x0).round() as usize).clamp(1, 10) + 1 } else { 8 };
        XAxis { x0, x1, pad, ticks, whole }
    }
}

/// Draws the panels under a common `title`, [`COLUMNS`] to a row; `xs`
/// are the x values every panel labels (the variable of the experiment).
pub fn panels_svg(title: &str, panels: &[Panel], xs: &[f64]) -> Result<String, String> {
    let n = panels.len().max(1);
    let (columns, rows) = (n.min(COLUMNS), n.div_ceil(COLUMNS));
    let (width, height) = (PANEL_W * columns as u32, PANEL_H * rows as u32 + 36);
    let x = XAxis::of(xs);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let root = root.titled(title, ("sans-serif", 20)).map_err(|e| e.to_string())?;
        let areas = root.split_evenly((rows, columns));
        for (panel, area) in panels.iter().zip(&areas) {
            draw_panel(panel, area, panel.xs.as_deref().map_or(x, XAxis::of))?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

/// The y range of a panel, in plotted units (decades on a log scale).
fn y_range(panel: &Panel, tf: impl Fn(f64) -> f64) -> (f64, f64) {
    let ys: Vec<f64> =
        panel.series.iter().flat_map(|s| s.points.iter().flat_map(|&(_, y, e)| [tf(y + e), tf(y - e)])).collect();
    let (mut y0, mut y1) = match panel.y_range {
        Some((a, b)) => (tf(a), tf(b)),
        None => {
            (ys.iter().copied().fold(f64::INFINITY, f64::min), ys.iter().copied().fold(f64::NEG_INFINITY, f64::max))
        }
    };
    if !y0.is_finite() {
        (y0, y1) = (0.0, 1.0);
    }
    // Room above the data for the legend in the upper left, so that
    // it covers no line: a decade on a log scale, a third otherwise.
    if panel.log_y {
        // Whole decades, so the labelled ticks are powers of ten.
        (y0, y1) = (y0.floor(), y1.ceil().max(y0.floor() + 1.0) + 1.0);
    } else if panel.y_range.is_none() {
        y0 = y0.min(0.0);
        y1 = if y1 > y0 { y1 + (y1 - y0) * 0.35 } else { y0 + 1.0 };
    }
    (y0, y1)
}

fn draw_panel<DB: DrawingBackend>(
    panel: &Panel,
    area: &DrawingArea<DB, plotters::coord::Shift>,
    x: XAxis,
) -> Result<(), String> {
    let log_y = panel.log_y;
    let tf = move |y: f64| if log_y { y.max(1e-9).log10() } else { y };
    let (y0, y1) = y_range(panel, tf);
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(42)
        .y_label_area_size(62)
        .build_cartesian_2d((x.x0 - x.pad)..(x.x1 + x.pad), y0..y1)
        .map_err(|e| e.to_string())?;
    let decades = (y1 - y0).round() as usize;
    chart
        .configure_mesh()
        .x_desc(&panel.x_desc)
        .y_desc(&panel.y_desc)
        .axis_desc_style(("sans-serif", 16))
        .label_style(("sans-serif", plot::TEXT))
        .x_labels(x.ticks)
        .x_label_formatter(&|v| {
            if !x.whole {
                format!("{}", (v * 1e4).round() / 1e4)
            } else if (v - v.round()).abs() < 1e-6 {
                format!("{}", v.round() as i64)
            } else {
                String::new()
            }
        })
        .y_labels(if log_y { decades + 1 } else { 8 })
        .y_label_formatter(&move |y| {
            if !log_y {
                nice(*y)
            } else if (y - y.round()).abs() < 1e-6 {
                decade(y.round() as i32)
            } else {
                String::new()
            }
        })
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(|e| e.to_string())?;
    for (k, s) in panel.series.iter().enumerate() {
        let c = colour(s.colour.unwrap_or(k));
        if s.band {
            let upper = s.points.iter().map(|&(x, y, e)| (x, tf(y + e)));
            let lower =
                s.points.iter().rev().map(|&(x, y, e)| (x, tf((y - e).max(if log_y { 1e-9 } else { f64::MIN }))));
            chart
                .draw_series([Polygon::new(upper.chain(lower).collect::<Vec<_>>(), c.mix(0.18).filled())])
                .map_err(|e| e.to_string())?;
        }
        let (dash, gap) = DASHES[s.dash % DASHES.len()];
        let line: Vec<(f64, f64)> = s.points.iter().map(|&(x, y, _)| (x, tf(y))).collect();
        let drawn = if dash == 0 {
            chart.draw_series(LineSeries::new(line, c.stroke_width(2)))
        } else {
            chart.draw_series(DashedLineSeries::new(line, dash, gap, c.stroke_width(2)))
        };
        drawn.map_err(|e| e.to_string())?.label(&s.label).legend(move |(x, y)| {
            let pts = vec![(x, y), (x + 24, y)];
            if dash == 0 {
                PathElement::new(pts, c.stroke_width(2)).into_dyn()
            } else {
                DashedPathElement::new(pts, dash, gap, c.stroke_width(2)).into_dyn()
            }
        });
        if s.band {
            continue;
        }
        chart
            .draw_series(s.points.iter().map(|&(x, y, _)| Circle::new((x, tf(y)), 3, c.filled())))
            .map_err(|e| e.to_string())?;
        chart
            .draw_series(s.points.iter().filter(|p| p.2 > 0.0).map(|&(x, y, e)| {
                PathElement::new(vec![(x, tf((y - e).max(1e-9))), (x, tf(y + e))], c.stroke_width(1))
            }))
            .map_err(|e| e.to_string())?;
    }
    if panel.legend && !panel.series.is_empty() {
        // A fixed range (a rate) has no headroom: its legend goes
        // low, where rates near 1 leave space.
        let pos =
            if panel.y_range.is_some() { SeriesLabelPosition::LowerRight } else { SeriesLabelPosition::UpperLeft };
        plot::legend(&mut chart, pos, plot::TEXT)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decades() {
        assert_eq!(decade(3), "1000");
        assert_eq!(decade(0), "1");
        assert_eq!(decade(-3), "0.001");
        assert_eq!(decade(-5), "1e-5");
        assert_eq!(decade(7), "1e7");
    }

    #[test]
    fn four_panels_two_to_a_row_with_type_of_12_px() {
        let p = |t: &str| Panel::new(t, "x", "y", vec![Series::new("s", [(0.0, Some(1.0)), (1.0, Some(2.0))])]);
        let svg = panels_svg("t", &[p("a"), p("b"), p("c"), p("d")], &[0.0, 1.0]).unwrap();
        let doc = roxmltree::Document::parse(&svg).expect("valid XML");
        let width: f64 = doc.root_element().attribute("width").unwrap().parse().unwrap();
        // Shown whole in a report's 884 px column, scaled by at most 0.96.
        assert!(width <= 920.0, "{width}");
        for t in doc.descendants().filter(|n| n.has_tag_name("text")) {
            let size: f64 = t.attribute("font-size").unwrap().parse().unwrap();
            assert!(size * 884.0 / width >= 11.0, "{:?} at {size} px", t.text());
        }
    }

    #[test]
    fn series_of_one_colour_differ_by_dash() {
        let s = |dash| Series::new("s", [(0.0, Some(1.0)), (1.0, Some(2.0))]).styled(3, dash);
        let one = |dash| panels_svg("t", &[Panel::new("a", "x", "y", vec![s(dash)])], &[0.0, 1.0]).unwrap();
        let (solid, dashed) = (one(0), one(1));
        let lines = |svg: &str| svg.matches("<polyline").count();
        // A dashed line is drawn as many short segments, a solid one as one.
        assert!(lines(&dashed) > lines(&solid) + 3, "{} vs {}", lines(&dashed), lines(&solid));
        // Plotters writes `#RRGGBB`.
        assert!(solid.contains(&palette::COLOURS[3].to_uppercase()), "{solid}");
    }

    #[test]
    fn draws_valid_svg_with_labels() {
        let mut log =
            Panel::new("wall", "robots", "ms", vec![Series::new("p50", [(13.0, Some(0.2)), (50.0, Some(3.0))])]);
        log.log_y = true;
        let lin = Panel::new(
            "time",
            "killed",
            "s",
            vec![Series::with_err("mean", [(0.0, Some(600.0), Some(40.0)), (1.0, None, None)])],
        );
        let empty = Panel::new("none", "x", "y", vec![]);
        let svg = panels_svg("title here", &[log, lin, empty], &[0.0, 1.0, 13.0, 50.0]).unwrap();
        let doc = roxmltree::Document::parse(&svg).expect("valid XML");
        let texts: Vec<&str> = doc.descendants().filter(|n| n.has_tag_name("text")).filter_map(|n| n.text()).collect();
        for t in ["title here", "wall", "p50", "mean", "killed", "robots"] {
            assert!(texts.iter().any(|x| x.contains(t)), "{t} missing from {texts:?}");
        }
    }
}
