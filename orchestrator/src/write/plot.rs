//! `fig7.svg`: mean search time against the number of robots, one line per
//! algorithm with its 95% interval, labelled as in the paper's Fig. 7.

use gridswarm::policy::Policy;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use crate::stats::CellStats;

/// Line colours by algorithm, fixed so that one algorithm looks the same in
/// every figure the project makes.
pub(crate) fn colour(p: Policy) -> RGBColor {
    match p {
        Policy::Lfp => RGBColor(0x8c, 0x56, 0x4b),
        Policy::Ru => RGBColor(0xff, 0x7f, 0x0e),
        Policy::Sequential => RGBColor(0x2c, 0xa0, 0x2c),
        Policy::Repulsive => RGBColor(0x1f, 0x77, 0xb4),
        Policy::Escape => RGBColor(0x94, 0x67, 0xbd),
        Policy::Frontier => RGBColor(0x17, 0xbe, 0xcf),
        Policy::Oracle => RGBColor(0x7f, 0x7f, 0x7f),
        _ => RGBColor(0xbc, 0xbd, 0x22),
    }
}

/// The smallest type of any figure, in plotters' points: plotters writes
/// an SVG font size of points / 1.24, so 15 is 12.1 px, and still 11 px
/// or more when a report shows a 920 px figure in 880 px.
pub(crate) const TEXT: u32 = 15;

/// One plotted point: robots, mean search time, half-width of its 95% interval.
type Mark = (f64, f64, f64);

/// The legend of every figure: the series' labels in a white box with a
/// black border at `pos`, in `size`-point type.
pub(crate) fn legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    pos: SeriesLabelPosition,
    size: u32,
) -> Result<(), String> {
    chart
        .configure_series_labels()
        .position(pos)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font(("sans-serif", size))
        .draw()
        .map_err(|e| e.to_string())
}

/// The axes of every figure of seconds against robot counts `x0..=x1`:
/// whole counts only on x (at most 21 labels), whole seconds on y.
pub(crate) fn robots_axes<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    x0: f64,
    x1: f64,
    y_desc: &str,
) -> Result<(), String> {
    chart
        .configure_mesh()
        .x_desc("number of robots")
        .y_desc(y_desc)
        .axis_desc_style(("sans-serif", 16))
        .label_style(("sans-serif", TEXT))
        .x_labels(((x1 - x0).round() as usize).clamp(1, 20) + 1)
        .x_label_formatter(&|x| {
            if (x - x.round()).abs() < 1e-6 {
                format!("{}", x.round() as i64)
            } else {
                String::new()
            }
        })
        .y_label_formatter(&|y| format!("{y:.0}"))
        .light_line_style(WHITE.mix(0.0))
        .draw()
        .map_err(|e| e.to_string())
}

/// Draws the figure into an SVG string. `title` goes in the caption (the
/// scenario and the number of runs, so a figure alone says what it shows).
pub fn fig7_svg(cells: &[CellStats], algorithms: &[Policy], title: &str) -> Result<String, String> {
    let points: Vec<(Policy, Vec<Mark>)> = algorithms
        .iter()
        .map(|&p| {
            let mut v: Vec<(f64, f64, f64)> = cells
                .iter()
                .filter(|c| c.algorithm == p)
                .filter_map(|c| c.mean_search_time_s.map(|m| (c.robots as f64, m, c.ci95_s.unwrap_or(0.0))))
                .collect();
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
            (p, v)
        })
        .collect();
    let all = points.iter().flat_map(|(_, v)| v.iter());
    let (mut x0, mut x1, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for &(x, m, ci) in all {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y1 = y1.max(m + ci);
    }
    if !x0.is_finite() {
        // No completed run anywhere: an empty frame still says so.
        (x0, x1, y1) = (1.0, 2.0, 1.0);
    }
    let y1 = if y1 > 0.0 { y1 * 1.08 } else { 1.0 };

    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (900, 600)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 20))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d((x0 - 0.5)..(x1 + 0.5), 0.0..y1)
            .map_err(|e| e.to_string())?;
        robots_axes(&mut chart, x0, x1, "average search time (s); bars: 95% CI of the mean")?;
        let cap = 0.12;
        for (p, v) in &points {
            let c = colour(*p);
            let style = ShapeStyle::from(&c).stroke_width(2);
            chart
                .draw_series(LineSeries::new(v.iter().map(|&(x, m, _)| (x, m)), style))
                .map_err(|e| e.to_string())?
                .label(p.paper_label())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], ShapeStyle::from(&c).stroke_width(2))
                });
            chart
                .draw_series(v.iter().map(|&(x, m, _)| Circle::new((x, m), 3, c.filled())))
                .map_err(|e| e.to_string())?;
            // Interval bars with caps.
            chart
                .draw_series(v.iter().filter(|&&(_, _, ci)| ci > 0.0).flat_map(|&(x, m, ci)| {
                    [
                        PathElement::new(vec![(x, m - ci), (x, m + ci)], ShapeStyle::from(&c).stroke_width(1)),
                        PathElement::new(
                            vec![(x - cap, m - ci), (x + cap, m - ci)],
                            ShapeStyle::from(&c).stroke_width(1),
                        ),
                        PathElement::new(
                            vec![(x - cap, m + ci), (x + cap, m + ci)],
                            ShapeStyle::from(&c).stroke_width(1),
                        ),
                    ]
                }))
                .map_err(|e| e.to_string())?;
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight, 15)?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(p: Policy, r: usize, m: Option<f64>) -> CellStats {
        CellStats {
            algorithm: p,
            robots: r,
            runs: 5,
            completed_runs: if m.is_some() { 5 } else { 0 },
            mean_search_time_s: m,
            std_search_time_s: m.map(|x| x / 10.0),
            ci95_s: m.map(|x| x / 20.0),
            mean_rounds: m,
            mean_collisions: Some(0.0),
            median_search_time_s: m,
            mean_targets_found: 9.0,
            metrics: Default::default(),
        }
    }

    #[test]
    fn labels_and_valid_xml() {
        let algs = [Policy::Lfp, Policy::Ru, Policy::Sequential, Policy::Repulsive];
        let mut cells = Vec::new();
        for (k, &p) in algs.iter().enumerate() {
            for r in 1..=13 {
                cells.push(cell(p, r, Some(1000.0 / r as f64 + 100.0 * k as f64)));
            }
        }
        cells.push(cell(Policy::Ru, 14, None));
        let svg = fig7_svg(&cells, &algs, "paper: 5 runs").unwrap();
        let doc = roxmltree::Document::parse(&svg).expect("valid XML");
        let texts: Vec<&str> = doc.descendants().filter(|n| n.has_tag_name("text")).filter_map(|n| n.text()).collect();
        for label in
            ["LFP", "RU", "(1)&(3)", "(1),(2)&(3)", "number of robots", "average search time (s)", "paper: 5 runs"]
        {
            assert!(texts.iter().any(|t| t.contains(label)), "{label} missing from {texts:?}");
        }
    }

    #[test]
    fn empty_table_still_draws() {
        let svg = fig7_svg(&[cell(Policy::Ru, 1, None)], &[Policy::Ru], "none").unwrap();
        roxmltree::Document::parse(&svg).expect("valid XML");
    }
}
