//! The Fig. 7 sweep's figures of its runs' metrics (issue 22, item 4), in
//! the style of the experiments' panels ([`crate::panels`]): coverage
//! against time, a panel per robot count; the time to each target, a panel
//! per algorithm; and per robot the distance, turns, frames and bytes, with
//! the collisions, against the robot count. Each algorithm keeps its colour
//! of `fig7.svg` ([`crate::plot::colour`]). It draws what it is given.

use gridswarm::policy::Policy;

use crate::curves::Curve;
use crate::panels::{panels_svg, Panel, Series};
use crate::stats::{CellStats, Estimate};
use crate::write::palette;

/// The palette index of the algorithm's colour in `fig7.svg`, when the
/// palette has it (the oracle's grey it has not).
fn colour_of(p: Policy) -> Option<usize> {
    let c = crate::plot::colour(p);
    let hex = format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2);
    palette::COLOURS.iter().position(|&k| k == hex)
}

/// A series of one algorithm.
fn series(p: Policy, points: impl IntoIterator<Item = (f64, Option<f64>, Option<f64>)>, k: usize) -> Series {
    let s = Series::with_err(p.paper_label(), points);
    s.styled(colour_of(p).unwrap_or(k), 0)
}

/// Coverage against time: a panel per robot count, each algorithm's mean
/// detected fraction with its 95% interval as a band.
pub fn coverage_svg(curves: &[Curve], algorithms: &[Policy], robots: &[usize], title: &str) -> Result<String, String> {
    let panels: Vec<Panel> = robots
        .iter()
        .enumerate()
        .map(|(n, &r)| {
            let mine: Vec<&Curve> = curves.iter().filter(|c| c.robots == r).collect();
            let lines = algorithms
                .iter()
                .enumerate()
                .filter_map(|(k, &p)| {
                    let c = mine.iter().find(|c| c.algorithm == p)?;
                    Some(series(p, c.points.iter().map(|(t, e)| (*t, e.mean, e.ci95)), k).banded())
                })
                .collect();
            let mut panel = Panel::new(
                &format!("{r} robot{}", if r == 1 { "" } else { "s" }),
                "simulated time (s)",
                "detected fraction of Ad",
                lines,
            );
            panel.y_range = Some((0.0, 1.0));
            panel.xs = Some(mine.first().map(|c| c.points.iter().map(|p| p.0).collect()).unwrap_or_default());
            panel.legend = n == 0;
            panel
        })
        .collect();
    panels_svg(title, &panels, &[])
}

/// Per robot and per run against the robot count: distance, turns,
/// frames, kilobytes and collisions, each a mean with its 95% interval.
pub fn effort_svg(cells: &[CellStats], algorithms: &[Policy], title: &str) -> Result<String, String> {
    let panel = |name: &str, y: &str, pick: &dyn Fn(&CellStats) -> Estimate, scale: f64, radio: bool| {
        let lines = algorithms
            .iter()
            .enumerate()
            .filter(|(_, p)| !radio || p.on_grid())
            .map(|(k, &p)| {
                let points = cells.iter().filter(|c| c.algorithm == p).map(|c| {
                    let e = pick(c);
                    (c.robots as f64, e.mean.map(|m| m / scale), e.ci95.map(|m| m / scale))
                });
                series(p, points, k)
            })
            .collect();
        let mut panel = Panel::new(name, "number of robots", y, lines);
        panel.legend = name.starts_with("distance");
        panel
    };
    let panels = [
        panel("distance per robot", "m", &|c| c.metrics.distance_m, 1.0, false),
        panel("turns per robot", "turns", &|c| c.metrics.rotations, 1.0, false),
        panel("frames sent per robot", "frames", &|c| c.metrics.frames, 1.0, true),
        panel("bytes sent per robot", "kB", &|c| c.metrics.bytes, 1e3, true),
        panel("collisions per run", "collisions", &|c| c.metrics.collisions, 1.0, false),
        panel("time to half coverage", "s", &|c| c.metrics.half_coverage_s, 1.0, false),
    ];
    let xs: Vec<f64> = cells.iter().map(|c| c.robots as f64).collect();
    panels_svg(title, &panels, &xs)
}

/// The mean time to the k-th target against the robot count, a panel per
/// algorithm and a line per k (at most ten of them, spread over k).
pub fn targets_svg(cells: &[CellStats], algorithms: &[Policy], title: &str) -> Result<String, String> {
    let most = cells.iter().map(|c| c.metrics.targets_s.len()).max().unwrap_or(0);
    let ks: Vec<usize> = if most <= 10 { (0..most).collect() } else { (0..10).map(|i| i * (most - 1) / 9).collect() };
    let panels: Vec<Panel> = algorithms
        .iter()
        .enumerate()
        .map(|(n, &p)| {
            let lines = ks
                .iter()
                .enumerate()
                .map(|(i, &k)| {
                    let points = cells.iter().filter(|c| c.algorithm == p).map(|c| {
                        let e = c.metrics.targets_s.get(k).copied().unwrap_or_default();
                        (c.robots as f64, e.mean, e.ci95)
                    });
                    Series::with_err(format!("target {}", k + 1), points).styled(i, 0)
                })
                .collect();
            let mut panel = Panel::new(p.paper_label(), "number of robots", "time to find it (s)", lines);
            panel.legend = n == 0;
            panel
        })
        .collect();
    let xs: Vec<f64> = cells.iter().map(|c| c.robots as f64).collect();
    panels_svg(title, &panels, &xs)
}
