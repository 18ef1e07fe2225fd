//! How much a sweep over several maps depends on the map: for every
//! algorithm and robot count, the least, median and greatest of the per-map
//! mean search times, as a figure (median line, min-max bars), a table and
//! one line for the terminal; and the maps themselves.

use gridswarm::policy::Policy;
use plotters::prelude::*;

use crate::maps::{Map, MapRow, Spread};
use crate::report::{Block, Section, Table};

fn f1(x: Option<f64>) -> String {
    x.map(|v| format!("{v:.1}")).unwrap_or_else(|| "-".into())
}

fn idx(x: Option<usize>) -> String {
    x.map(|v| v.to_string()).unwrap_or_else(|| "-".into())
}

/// `(max - min) / median` in percent: the map's share of the variation.
fn range_pct(s: &Spread) -> Option<f64> {
    match (s.min_s, s.median_s, s.max_s) {
        (Some(lo), Some(med), Some(hi)) if med > 0.0 => Some(100.0 * (hi - lo) / med),
        _ => None,
    }
}

pub fn table(spreads: &[Spread]) -> Table {
    Table {
        header: [
            "algorithm",
            "robots",
            "maps",
            "min (s)",
            "median (s)",
            "max (s)",
            "range / median",
            "min map",
            "max map",
        ]
        .map(String::from)
        .to_vec(),
        rows: spreads
            .iter()
            .map(|s| {
                vec![
                    s.algorithm.name().to_string(),
                    s.robots.to_string(),
                    s.maps.to_string(),
                    f1(s.min_s),
                    f1(s.median_s),
                    f1(s.max_s),
                    range_pct(s).map(|p| format!("{p:.0}%")).unwrap_or_else(|| "-".into()),
                    idx(s.min_map),
                    idx(s.max_map),
                ]
            })
            .collect(),
    }
}

fn maps_table(rows: &[MapRow]) -> Table {
    Table {
        header: ["map", "scenario", "draws", "made in (ms)", "obstacles", "obstacle share", "accessible vertices"]
            .map(String::from)
            .to_vec(),
        rows: rows
            .iter()
            .map(|r| {
                vec![
                    r.map.to_string(),
                    r.scenario.clone(),
                    r.attempts.to_string(),
                    format!("{:.2}", r.make_ms),
                    r.obstacles.to_string(),
                    format!("{:.1}%", 100.0 * r.obstacle_share),
                    r.accessible_vertices.to_string(),
                ]
            })
            .collect(),
    }
}

/// Each map as a thumbnail, named as it can be rerun alone.
fn thumbnails(maps: &[Map]) -> Block {
    Block::Gallery(
        maps.iter()
            .enumerate()
            .map(|(k, m)| {
                let svg = crate::routes::map_svg(&m.scenario.world(), 240.0, &format!("map-{k}"));
                (svg, format!("map {k}: {}", crate::output::shown(&m.scenario.name)))
            })
            .collect(),
    )
}

/// The report's sections for a sweep over maps.
pub fn sections(maps: &[Map], rows: &[MapRow], spreads: &[Spread]) -> Vec<Section> {
    let mut blocks = vec![Block::Text(format!(
        "Each map's mean search time per algorithm and robot count, over its own runs; below, the least, \
         median and greatest of those means over the {} maps, and on which map each extreme fell. A wide \
         range means the map matters as much as the algorithm: compare algorithms map by map (results.csv \
         has every map's cells) before trusting a pooled difference.",
        rows.len()
    ))];
    match svg(spreads) {
        Ok(svg) => blocks.push(Block::Figure {
            svg,
            caption: "Median over maps of the per-map mean search time (line), with bars from the least to the \
                      greatest per-map mean."
                .into(),
        }),
        Err(e) => blocks.push(Block::Text(format!("(figure not drawn: {e})"))),
    }
    blocks.push(Block::Table(table(spreads)));
    vec![
        Section::new("Per-map spread", blocks),
        Section::new("Maps", vec![thumbnails(maps), Block::Table(maps_table(rows))]),
    ]
}

/// One line for the terminal: the widest spread and where it is.
pub fn one_line(spreads: &[Spread]) -> String {
    let widest = spreads.iter().filter_map(|s| range_pct(s).map(|p| (p, s))).max_by(|a, b| a.0.total_cmp(&b.0));
    match widest {
        None => "per-map spread: no cell completed on two maps".into(),
        Some((p, s)) => format!(
            "per-map spread of mean search time: widest {} with {} robots, {} .. {} s over maps ({p:.0}% of the \
             median); every cell in report.html, every map's cells in results.csv",
            s.algorithm.name(),
            s.robots,
            f1(s.min_s),
            f1(s.max_s)
        ),
    }
}

/// Median per-map mean against robots, one line per algorithm, min-max bars.
pub fn svg(spreads: &[Spread]) -> Result<String, String> {
    let mut algorithms: Vec<Policy> = Vec::new();
    for s in spreads {
        if !algorithms.contains(&s.algorithm) {
            algorithms.push(s.algorithm);
        }
    }
    let done: Vec<(Policy, f64, f64, f64, f64)> =
        spreads.iter().filter_map(|s| Some((s.algorithm, s.robots as f64, s.min_s?, s.median_s?, s.max_s?))).collect();
    let x0 = done.iter().map(|d| d.1).fold(f64::INFINITY, f64::min);
    let x1 = done.iter().map(|d| d.1).fold(f64::NEG_INFINITY, f64::max);
    let (x0, x1) = if x0.is_finite() { (x0, x1) } else { (1.0, 2.0) };
    let y1 = done.iter().map(|d| d.4).fold(1.0, f64::max) * 1.08;
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (900, 500)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let mut chart = ChartBuilder::on(&root)
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d((x0 - 0.5)..(x1 + 0.5), 0.0..y1)
            .map_err(|e| e.to_string())?;
        crate::plot::robots_axes(&mut chart, x0, x1, "per-map mean search time (s)")?;
        let n = algorithms.len().max(1) as f64;
        for (k, &p) in algorithms.iter().enumerate() {
            let c = crate::plot::colour(p);
            // Bars of different algorithms side by side, not on top of each other.
            let dx = (k as f64 - (n - 1.0) / 2.0) * 0.08;
            let mine: Vec<_> = done.iter().filter(|d| d.0 == p).collect();
            chart
                .draw_series(LineSeries::new(
                    mine.iter().map(|d| (d.1 + dx, d.3)),
                    ShapeStyle::from(&c).stroke_width(2),
                ))
                .map_err(|e| e.to_string())?
                .label(p.paper_label())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], ShapeStyle::from(&c).stroke_width(2))
                });
            chart
                .draw_series(mine.iter().map(|d| {
                    PathElement::new(vec![(d.1 + dx, d.2), (d.1 + dx, d.4)], ShapeStyle::from(&c).stroke_width(2))
                }))
                .map_err(|e| e.to_string())?;
        }
        crate::plot::legend(&mut chart, SeriesLabelPosition::UpperRight, 15)?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spread(p: Policy, r: usize, v: Option<(f64, f64, f64)>) -> Spread {
        Spread {
            algorithm: p,
            robots: r,
            maps: if v.is_some() { 3 } else { 0 },
            min_s: v.map(|x| x.0),
            median_s: v.map(|x| x.1),
            max_s: v.map(|x| x.2),
            min_map: v.map(|_| 2),
            max_map: v.map(|_| 0),
        }
    }

    #[test]
    fn widest_spread_and_table() {
        let s = [spread(Policy::Ru, 1, Some((90.0, 100.0, 150.0))), spread(Policy::Ru, 2, Some((50.0, 60.0, 66.0)))];
        assert!(one_line(&s).contains("widest ru with 1 robots, 90.0 .. 150.0 s over maps (60% of the median)"));
        let t = table(&s);
        assert_eq!(t.rows[1][3..7], ["50.0", "60.0", "66.0", "27%"].map(String::from));
        assert!(one_line(&[spread(Policy::Ru, 1, None)]).contains("no cell completed"));
        let svg = svg(&s).unwrap();
        assert!(svg.contains("<svg") && svg.contains("RU"), "{svg}");
    }
}
