//! Coverage against time for a sweep's cells (issue 22, item 4): each
//! completed run's detected fraction read at common times, and per cell
//! the mean and the half-width of its 95% interval at each. The times of a
//! robot count are shared by its algorithms, so their curves compare on
//! one axis; they run to the 90th percentile of the slowest cell's search
//! times at that count (later, most runs have ended and the curves are
//! flat).

use std::fmt::Write as _;

use gridswarm::policy::Policy;
use serde::Serialize;

use crate::output::csv_num;
use crate::stats::{Estimate, RunRecord};

/// Times on a robot count's axis, from 0.
pub const POINTS: usize = 61;

/// One cell's coverage against time.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Curve {
    pub algorithm: Policy,
    pub robots: usize,
    /// The completed runs it averages.
    pub runs: usize,
    /// `(time, mean detected fraction and its interval)`.
    pub points: Vec<(f64, Estimate)>,
}

/// The curve of each cell, `cells[k]` with its runs `runs[k]` (in run order).
pub fn curves(cells: &[(Policy, usize)], runs: &[&[RunRecord]]) -> Vec<Curve> {
    cells
        .iter()
        .zip(runs)
        .map(|(&(algorithm, robots), cell)| {
            let axis = axis(robots, cells, runs);
            let done: Vec<&RunRecord> = cell.iter().filter(|r| r.complete).collect();
            let points = axis
                .iter()
                .map(|&t| {
                    let at: Vec<f64> = done.iter().filter_map(|r| r.measured.coverage_at(t, r.search_time_s)).collect();
                    (t, Estimate::of(&at))
                })
                .collect();
            Curve { algorithm, robots, runs: done.len(), points }
        })
        .collect()
}

/// The times of robot count `robots`: [`POINTS`] from 0 to the largest
/// 90th percentile of its cells' completed search times.
fn axis(robots: usize, cells: &[(Policy, usize)], runs: &[&[RunRecord]]) -> Vec<f64> {
    let end = cells
        .iter()
        .zip(runs)
        .filter(|(c, _)| c.1 == robots)
        .filter_map(|(_, cell)| {
            let mut t: Vec<f64> = cell.iter().filter(|r| r.complete).map(|r| r.search_time_s).collect();
            t.sort_by(f64::total_cmp);
            t.get(((t.len() as f64 * 0.9).ceil() as usize).saturating_sub(1)).copied()
        })
        .fold(0.0f64, f64::max);
    let end = if end > 0.0 { end } else { 1.0 };
    (0..POINTS).map(|k| end * k as f64 / (POINTS - 1) as f64).collect()
}

/// `coverage.csv`: every cell's curve, a row per time.
pub fn csv(curves: &[Curve]) -> String {
    let mut s = String::from("algorithm,robots,time_s,runs,mean_coverage,ci95_coverage\n");
    for c in curves {
        for (t, e) in &c.points {
            let _ = writeln!(
                s,
                "{},{},{t:.6},{},{},{}",
                c.algorithm.name(),
                c.robots,
                c.runs,
                csv_num(e.mean),
                csv_num(e.ci95)
            );
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::Measured;

    fn run(end: f64, levels: &[f64], coverage: f64) -> RunRecord {
        RunRecord {
            search_time_s: end,
            complete: true,
            measured: Measured { coverage: Some(coverage), coverage_s: levels.to_vec(), ..Default::default() },
            ..Default::default()
        }
    }

    #[test]
    fn the_mean_of_runs_read_at_common_times() {
        // Two runs of one cell: 1% at 0 s, 2% at 5 s, ended at 10 s with 2.5%;
        // and 1% at 0 s, ended at 20 s with 1.5%.
        let a = run(10.0, &[0.0, 5.0], 0.025);
        let b = run(20.0, &[0.0], 0.015);
        let c = curves(&[(Policy::Ru, 2)], &[&[a, b][..]]);
        assert_eq!((c[0].runs, c[0].points.len()), (2, POINTS));
        let at = |t: f64| c[0].points.iter().find(|p| (p.0 - t).abs() < 1e-9).map(|p| p.1.mean.unwrap());
        // The 90th percentile of 10 and 20 is 20: a point every 1/3 s.
        assert_eq!(c[0].points.last().unwrap().0, 20.0);
        assert_eq!(at(0.0), Some(0.01));
        assert!((at(6.0).unwrap() - 0.015).abs() < 1e-12);
        assert!((at(20.0).unwrap() - 0.02).abs() < 1e-12, "both ended: their final fractions");
        assert!(c[0].points.windows(2).all(|w| w[0].1.mean <= w[1].1.mean));
        let text = csv(&c);
        assert_eq!(text.lines().count(), 1 + POINTS);
        assert!(text.starts_with(
            "algorithm,robots,time_s,runs,mean_coverage,ci95_coverage\nru,2,0.000000,2,0.010000,0.000000\n"
        ));
    }
}
