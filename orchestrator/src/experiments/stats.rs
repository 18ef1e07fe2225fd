//! Per-cell statistics of a sweep: one cell is one (algorithm, robot count)
//! with its Monte Carlo runs.

use gridswarm::outcome::RunResult;
use gridswarm::policy::Policy;
use gridswarm::world::coverage::LEVELS;
use serde::Serialize;

/// What the sweep keeps of one run: enough for the statistics, small enough
/// to hold every run of a large sweep in memory (a kilobyte at most with
/// its coverage curve).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RunRecord {
    pub seed: u64,
    pub search_time_s: f64,
    pub rounds: u32,
    pub collisions: u32,
    pub targets_found: usize,
    pub complete: bool,
    /// When the last of the world's targets was found; `None` unless every
    /// one was. The search ends (`search_time_s`) once a robot knows it,
    /// which under the controller's relay is within a slot's exchange.
    pub last_target_s: Option<f64>,
    /// What the run measured beyond its time (issue 22, item 4).
    pub measured: Measured,
}

impl RunRecord {
    /// The run as measured by its last find instead of its end: the same
    /// run, its time the last target's, complete only where every target
    /// was found. The claims are judged under both (docs/paper.md,
    /// "Comparing algorithms fairly").
    pub fn at_last_find(&self) -> RunRecord {
        RunRecord {
            seed: self.seed,
            search_time_s: self.last_target_s.unwrap_or(f64::NAN),
            rounds: self.rounds,
            collisions: self.collisions,
            targets_found: self.targets_found,
            complete: self.complete && self.last_target_s.is_some(),
            last_target_s: self.last_target_s,
            measured: Measured::default(),
        }
    }
}

/// A run's metrics as the sweep keeps them: per robot, means over the team.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Measured {
    /// The detected fraction of `Ad` at the end, and the times it first
    /// reached each hundredth ([`gridswarm::outcome::RunMetrics::coverage_s`]).
    pub coverage: Option<f64>,
    pub coverage_s: Vec<f64>,
    /// When the k-th target was first found.
    pub targets_s: Vec<f64>,
    /// Per robot: metres driven, turns, frames sent and their bytes (the
    /// last two `None` for policies without a radio).
    pub distance_m: f64,
    pub rotations: f64,
    pub frames: Option<f64>,
    pub bytes: Option<f64>,
}

impl Measured {
    /// The run's metrics, its curve and targets' times moved, not copied.
    pub fn of(r: RunResult) -> Self {
        let mut m = r.metrics;
        // Every run's curve is kept to the end of the sweep: no spare room.
        m.coverage_s.shrink_to_fit();
        let per_robot = |sum: f64| sum / r.robots.max(1) as f64;
        let radio = |xs: &[u64]| (!xs.is_empty()).then(|| per_robot(xs.iter().sum::<u64>() as f64));
        Measured {
            coverage: r.coverage,
            coverage_s: m.coverage_s,
            targets_s: m.targets_s,
            distance_m: per_robot(m.distance_m.iter().sum()),
            rotations: per_robot(m.rotations.iter().map(|&t| f64::from(t)).sum()),
            frames: radio(&m.frames),
            bytes: radio(&m.bytes),
        }
    }

    /// The time the detected fraction first reached one half.
    pub fn half_coverage_s(&self) -> Option<f64> {
        self.coverage_s.get(LEVELS / 2 - 1).copied()
    }

    /// The detected fraction at time `t` of a run that ended at `end`: the
    /// levels reached by then, and the run's final fraction from its end on.
    pub fn coverage_at(&self, t: f64, end: f64) -> Option<f64> {
        let last = self.coverage?;
        if t >= end {
            return Some(last);
        }
        let reached = self.coverage_s.partition_point(|&s| s <= t);
        Some((reached as f64 / LEVELS as f64).min(last))
    }
}

/// Statistics of one (algorithm, robot count) cell. Times, rounds and
/// collisions are over the completed runs only: an incomplete run stopped at
/// the round limit, and its time would measure the limit, not the search.
/// `None` where there are too few completed runs to say.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CellStats {
    pub algorithm: Policy,
    pub robots: usize,
    pub runs: usize,
    pub completed_runs: usize,
    pub mean_search_time_s: Option<f64>,
    /// Sample standard deviation (n - 1).
    pub std_search_time_s: Option<f64>,
    /// Half-width of the normal 95% confidence interval of the mean: 1.96 std / sqrt(n).
    pub ci95_s: Option<f64>,
    pub mean_rounds: Option<f64>,
    pub mean_collisions: Option<f64>,
    pub median_search_time_s: Option<f64>,
    /// Mean over all runs, complete or not.
    pub mean_targets_found: f64,
    /// Issue 22's metrics, over the completed runs.
    pub metrics: CellMetrics,
}

/// A cell's means of the runs' metrics, each with the half-width of its
/// 95% interval, over the completed runs (the time to half coverage over
/// those that reached it, the k-th target's time over those that found k).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct CellMetrics {
    pub collisions: Estimate,
    pub coverage: Estimate,
    pub half_coverage_s: Estimate,
    pub distance_m: Estimate,
    pub rotations: Estimate,
    pub frames: Estimate,
    pub bytes: Estimate,
    /// Element k: the (k + 1)-th target.
    pub targets_s: Vec<Estimate>,
    /// The last target's time, over the completed runs that found every target.
    pub last_target_s: Estimate,
}

/// A mean and the half-width of its normal 95% interval (`None` where
/// there are too few values).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Estimate {
    pub mean: Option<f64>,
    pub ci95: Option<f64>,
}

impl Estimate {
    pub fn of(xs: &[f64]) -> Self {
        Estimate { mean: mean(xs), ci95: ci95(xs) }
    }
}

/// Half-width of the normal 95% interval of the mean: 1.96 std / sqrt(n).
pub fn ci95(xs: &[f64]) -> Option<f64> {
    sample_std(xs).map(|s| 1.96 * s / (xs.len() as f64).sqrt())
}

impl CellMetrics {
    fn of(done: &[&RunRecord]) -> Self {
        let est =
            |f: &dyn Fn(&RunRecord) -> Option<f64>| Estimate::of(&done.iter().filter_map(|r| f(r)).collect::<Vec<_>>());
        let most = done.iter().map(|r| r.measured.targets_s.len()).max().unwrap_or(0);
        CellMetrics {
            collisions: est(&|r| Some(f64::from(r.collisions))),
            coverage: est(&|r| r.measured.coverage),
            half_coverage_s: est(&|r| r.measured.half_coverage_s()),
            distance_m: est(&|r| Some(r.measured.distance_m)),
            rotations: est(&|r| Some(r.measured.rotations)),
            frames: est(&|r| r.measured.frames),
            bytes: est(&|r| r.measured.bytes),
            targets_s: (0..most).map(|k| est(&|r| r.measured.targets_s.get(k).copied())).collect(),
            last_target_s: est(&|r| r.last_target_s),
        }
    }
}

pub fn mean(xs: &[f64]) -> Option<f64> {
    (!xs.is_empty()).then(|| xs.iter().sum::<f64>() / xs.len() as f64)
}

/// Sample standard deviation; needs two values.
pub fn sample_std(xs: &[f64]) -> Option<f64> {
    if xs.len() < 2 {
        return None;
    }
    let m = mean(xs)?;
    let ss: f64 = xs.iter().map(|x| (x - m) * (x - m)).sum();
    Some((ss / (xs.len() - 1) as f64).sqrt())
}

pub fn median(xs: &[f64]) -> Option<f64> {
    if xs.is_empty() {
        return None;
    }
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 { v[n / 2] } else { (v[n / 2 - 1] + v[n / 2]) / 2.0 })
}

impl CellStats {
    /// Statistics of `records`, in the order given (sums are order-dependent
    /// in floating point; the sweep always passes runs in run order).
    pub fn of(algorithm: Policy, robots: usize, records: &[RunRecord]) -> Self {
        let done: Vec<&RunRecord> = records.iter().filter(|r| r.complete).collect();
        let times: Vec<f64> = done.iter().map(|r| r.search_time_s).collect();
        let rounds: Vec<f64> = done.iter().map(|r| f64::from(r.rounds)).collect();
        let collisions: Vec<f64> = done.iter().map(|r| f64::from(r.collisions)).collect();
        let std = sample_std(&times);
        let found: Vec<f64> = records.iter().map(|r| r.targets_found as f64).collect();
        CellStats {
            algorithm,
            robots,
            runs: records.len(),
            completed_runs: done.len(),
            mean_search_time_s: mean(&times),
            std_search_time_s: std,
            ci95_s: std.map(|s| 1.96 * s / (times.len() as f64).sqrt()),
            mean_rounds: mean(&rounds),
            mean_collisions: mean(&collisions),
            median_search_time_s: median(&times),
            mean_targets_found: mean(&found).unwrap_or(0.0),
            metrics: CellMetrics::of(&done),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rec(t: f64, complete: bool) -> RunRecord {
        RunRecord {
            seed: 0,
            search_time_s: t,
            rounds: t as u32,
            collisions: 1,
            targets_found: 9,
            complete,
            ..Default::default()
        }
    }

    #[test]
    fn known_values() {
        let rs = [
            rec(2.0, true),
            rec(4.0, true),
            rec(4.0, true),
            rec(4.0, true),
            rec(5.0, true),
            rec(5.0, true),
            rec(7.0, true),
            rec(9.0, true),
            rec(1e9, false),
        ];
        let c = CellStats::of(Policy::Ru, 3, &rs);
        assert_eq!(c.runs, 9);
        assert_eq!(c.completed_runs, 8);
        assert_eq!(c.mean_search_time_s, Some(5.0));
        // Sum of squares 32, n - 1 = 7.
        let std = (32.0f64 / 7.0).sqrt();
        assert!((c.std_search_time_s.unwrap() - std).abs() < 1e-12);
        assert!((c.ci95_s.unwrap() - 1.96 * std / 8f64.sqrt()).abs() < 1e-12);
        assert_eq!(c.median_search_time_s, Some(4.5));
        assert_eq!(c.mean_rounds, Some(5.0));
    }

    #[test]
    fn too_few_runs() {
        let c = CellStats::of(Policy::Lfp, 1, &[rec(3.0, true)]);
        assert_eq!(c.mean_search_time_s, Some(3.0));
        assert_eq!(c.std_search_time_s, None);
        assert_eq!(c.ci95_s, None);
        let none = CellStats::of(Policy::Lfp, 1, &[rec(3.0, false)]);
        assert_eq!(none.completed_runs, 0);
        assert_eq!(none.mean_search_time_s, None);
    }
}
