//! What the failure and radio experiments keep of one run, whichever
//! engine ran it (read from the run's summary fields, so both engines go
//! through one reader), and the statistics of a group of such runs.

use gridswarm::outcome::RunResult;
use gridswarm::sim::ENDINGS;
use serde::Serialize;
use serde_json::Value;

use crate::figures;
use crate::stats::{mean, sample_std};

/// One run, as the experiments keep it.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ProtoRun {
    pub seed: u64,
    pub complete: bool,
    pub ended_by: String,
    pub search_time_s: f64,
    pub rounds: u64,
    pub collisions: u64,
    pub moves: u64,
    pub transmissions: u64,
    pub retransmissions: u64,
    pub lost: u64,
    pub timeouts: u64,
    pub unsure: u64,
    pub declarations: u64,
    pub false_suspicions: u64,
    pub rejoins: u64,
    pub forced_slots: u64,
    /// Crashes and freezes that happened before the run ended.
    pub injected: usize,
    /// Of those, the ones some robot declared.
    pub detected: usize,
    /// Robots that waited on a failed robot, kept searching long enough to
    /// declare it, and never did (summed over the failures): should be 0.
    pub unaware: usize,
    /// Detection delays of the detected ones: rounds, and simulated seconds.
    pub delay_rounds: Vec<f64>,
    pub delay_s: Vec<f64>,
}

impl ProtoRun {
    /// An in-process run.
    pub fn of(result: &RunResult) -> Self {
        let mut v = figures::summary_fields(result);
        v["complete"] = result.complete.into();
        v["search_time_s"] = result.search_time_s.into();
        v["rounds"] = result.rounds.into();
        v["collisions"] = result.collisions.into();
        ProtoRun::from_summary(result.seed, &v)
    }

    /// A run's `summary.json` (the object `run --json` prints).
    pub fn from_summary(seed: u64, v: &Value) -> Self {
        let u = |k: &str| v[k].as_u64().unwrap_or(0);
        let failures = v["failures"].as_array().map(Vec::as_slice).unwrap_or_default();
        let detected: Vec<&Value> = failures.iter().filter(|f| !f["detected_round"].is_null()).collect();
        ProtoRun {
            seed,
            complete: v["complete"].as_bool().unwrap_or(false),
            ended_by: v["ended_by"].as_str().unwrap_or("").to_string(),
            search_time_s: v["search_time_s"].as_f64().unwrap_or(f64::NAN),
            rounds: u("rounds"),
            collisions: u("collisions"),
            moves: u("moves"),
            transmissions: u("transmissions"),
            retransmissions: u("retransmissions"),
            lost: u("lost"),
            timeouts: u("timeouts"),
            unsure: u("unsure"),
            declarations: u("declarations"),
            false_suspicions: u("false_suspicions"),
            rejoins: u("rejoins"),
            forced_slots: u("forced_slots"),
            injected: failures.len(),
            detected: detected.len(),
            unaware: failures.iter().map(|f| f["unaware"].as_array().map_or(0, Vec::len)).sum(),
            delay_rounds: detected.iter().filter_map(|f| f["detection_delay_rounds"].as_f64()).collect(),
            delay_s: detected.iter().filter_map(|f| f["detection_delay_s"].as_f64()).collect(),
        }
    }
}

/// Statistics of a group of runs. Search time and rounds are over the
/// completed runs; counts are means per run over all runs; collisions per
/// 10^6 moves pool every run's collisions and moves; detection delays are
/// over every detected failure.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ProtoStats {
    pub runs: usize,
    pub completed_runs: usize,
    pub completion_rate: f64,
    pub mean_search_time_s: Option<f64>,
    pub std_search_time_s: Option<f64>,
    /// Half-width of the normal 95% confidence interval of the mean.
    pub ci95_search_time_s: Option<f64>,
    pub mean_rounds: Option<f64>,
    pub collisions: u64,
    pub moves: u64,
    pub collisions_per_million_moves: f64,
    pub mean_transmissions: f64,
    pub mean_retransmissions: f64,
    pub mean_lost: f64,
    pub mean_timeouts: f64,
    pub mean_unsure: f64,
    pub mean_false_suspicions: f64,
    pub mean_rejoins: f64,
    pub mean_forced_slots: f64,
    pub injected: usize,
    pub detected: usize,
    pub unaware: usize,
    pub mean_delay_rounds: Option<f64>,
    pub mean_delay_s: Option<f64>,
    /// Runs per `ended_by` label, in [`ENDINGS`]' order.
    pub ended_by: [usize; ENDINGS.len()],
}

impl ProtoStats {
    pub fn of(runs: &[ProtoRun]) -> Self {
        let done: Vec<&ProtoRun> = runs.iter().filter(|r| r.complete).collect();
        let times: Vec<f64> = done.iter().map(|r| r.search_time_s).collect();
        let per_run =
            |f: &dyn Fn(&ProtoRun) -> u64| mean(&runs.iter().map(|r| f(r) as f64).collect::<Vec<_>>()).unwrap_or(0.0);
        let std = sample_std(&times);
        let (collisions, moves) = runs.iter().fold((0, 0), |a, r| (a.0 + r.collisions, a.1 + r.moves));
        let mut ended_by = [0; ENDINGS.len()];
        for r in runs {
            if let Some(k) = ENDINGS.iter().position(|e| *e == r.ended_by) {
                ended_by[k] += 1;
            }
        }
        ProtoStats {
            runs: runs.len(),
            completed_runs: done.len(),
            completion_rate: if runs.is_empty() { 0.0 } else { done.len() as f64 / runs.len() as f64 },
            mean_search_time_s: mean(&times),
            std_search_time_s: std,
            ci95_search_time_s: std.map(|s| 1.96 * s / (times.len() as f64).sqrt()),
            mean_rounds: mean(&done.iter().map(|r| r.rounds as f64).collect::<Vec<_>>()),
            collisions,
            moves,
            collisions_per_million_moves: if moves == 0 { 0.0 } else { collisions as f64 * 1e6 / moves as f64 },
            mean_transmissions: per_run(&|r| r.transmissions),
            mean_retransmissions: per_run(&|r| r.retransmissions),
            mean_lost: per_run(&|r| r.lost),
            mean_timeouts: per_run(&|r| r.timeouts),
            mean_unsure: per_run(&|r| r.unsure),
            mean_false_suspicions: per_run(&|r| r.false_suspicions),
            mean_rejoins: per_run(&|r| r.rejoins),
            mean_forced_slots: per_run(&|r| r.forced_slots),
            injected: runs.iter().map(|r| r.injected).sum(),
            detected: runs.iter().map(|r| r.detected).sum(),
            unaware: runs.iter().map(|r| r.unaware).sum(),
            mean_delay_rounds: mean(&runs.iter().flat_map(|r| r.delay_rounds.iter().copied()).collect::<Vec<_>>()),
            mean_delay_s: mean(&runs.iter().flat_map(|r| r.delay_s.iter().copied()).collect::<Vec<_>>()),
            ended_by,
        }
    }

    /// `stop 9, cut_off 1`: the labels that occurred.
    pub fn endings(&self) -> String {
        let parts: Vec<String> =
            ENDINGS.iter().zip(self.ended_by).filter(|(_, n)| *n > 0).map(|(e, n)| format!("{e} {n}")).collect();
        parts.join(", ")
    }

    /// `123.4 ± 5.6` (mean ± 95% CI half-width), or `-` without completed runs.
    pub fn time_text(&self) -> String {
        match (self.mean_search_time_s, self.ci95_search_time_s) {
            (Some(m), Some(c)) => format!("{m:.1} ± {c:.1}"),
            (Some(m), None) => format!("{m:.1}"),
            _ => "-".into(),
        }
    }
}

/// The statistics' columns of a CSV row, after the experiment's own keys.
pub const CSV_COLUMNS: &str = "runs,completed_runs,completion_rate,mean_search_time_s,std_search_time_s,\
    ci95_search_time_s,mean_rounds,collisions,moves,collisions_per_million_moves,mean_transmissions,\
    mean_retransmissions,mean_lost,mean_timeouts,mean_unsure,mean_false_suspicions,mean_rejoins,\
    mean_forced_slots,failures_injected,failures_detected,unaware,mean_detection_delay_rounds,\
    mean_detection_delay_s,ended_stop,ended_exhausted,ended_false_stop,ended_cut_off,ended_no_robots,\
    ended_max_rounds,ended_past_bound";

/// The statistics as CSV cells, in [`CSV_COLUMNS`]' order.
pub fn csv_cells(s: &ProtoStats) -> String {
    let n = crate::output::csv_num;
    format!(
        "{},{},{:.6},{},{},{},{},{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{},{},{},{},{},{}",
        s.runs,
        s.completed_runs,
        s.completion_rate,
        n(s.mean_search_time_s),
        n(s.std_search_time_s),
        n(s.ci95_search_time_s),
        n(s.mean_rounds),
        s.collisions,
        s.moves,
        s.collisions_per_million_moves,
        s.mean_transmissions,
        s.mean_retransmissions,
        s.mean_lost,
        s.mean_timeouts,
        s.mean_unsure,
        s.mean_false_suspicions,
        s.mean_rejoins,
        s.mean_forced_slots,
        s.injected,
        s.detected,
        s.unaware,
        n(s.mean_delay_rounds),
        n(s.mean_delay_s),
        s.ended_by.map(|n| n.to_string()).join(",")
    )
}

/// The columns of every run in a runs CSV, after the experiment's own keys.
pub const RUN_CSV_COLUMNS: &str = "seed,complete,ended_by,search_time_s,rounds,collisions,moves,transmissions,\
    retransmissions,lost,timeouts,unsure,declarations,false_suspicions,rejoins,forced_slots,failures_injected,\
    failures_detected,unaware,mean_detection_delay_rounds,mean_detection_delay_s";

pub fn run_csv_cells(r: &ProtoRun) -> String {
    let n = crate::output::csv_num;
    format!(
        "{},{},{},{:.6},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
        r.seed,
        r.complete,
        r.ended_by,
        r.search_time_s,
        r.rounds,
        r.collisions,
        r.moves,
        r.transmissions,
        r.retransmissions,
        r.lost,
        r.timeouts,
        r.unsure,
        r.declarations,
        r.false_suspicions,
        r.rejoins,
        r.forced_slots,
        r.injected,
        r.detected,
        r.unaware,
        n(mean(&r.delay_rounds)),
        n(mean(&r.delay_s))
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn runs_from_summaries_and_their_statistics() {
        let v = json!({
            "complete": true, "ended_by": "stop", "search_time_s": 100.0, "rounds": 10, "collisions": 1,
            "moves": 250_000, "retransmissions": 4, "unsure": 2,
            "failures": [
                {"detected_round": 5, "detection_delay_rounds": 2, "detection_delay_s": 9.5},
                {"detected_round": null, "detection_delay_rounds": null, "detection_delay_s": null},
            ],
        });
        let a = ProtoRun::from_summary(9, &v);
        assert_eq!((a.injected, a.detected, a.delay_rounds.clone()), (2, 1, vec![2.0]));
        let mut b = a.clone();
        b.complete = false;
        b.ended_by = "max_rounds".into();
        b.collisions = 0;
        let mut c = b.clone();
        c.ended_by = "past_bound".into();
        c.moves = 0;
        let s = ProtoStats::of(&[a, b, c]);
        assert_eq!(s.completion_rate, 1.0 / 3.0);
        assert_eq!(s.collisions_per_million_moves, 2.0);
        assert_eq!(s.mean_search_time_s, Some(100.0));
        assert_eq!(s.ci95_search_time_s, None);
        assert_eq!(s.endings(), "stop 1, max_rounds 1, past_bound 1");
        assert!(csv_cells(&s).ends_with(",1,0,0,0,0,1,1") && CSV_COLUMNS.ends_with(",ended_past_bound"));
        assert_eq!(s.mean_retransmissions, 4.0);
        assert_eq!(csv_cells(&s).split(',').count(), CSV_COLUMNS.split(',').count());
        assert_eq!(run_csv_cells(&ProtoRun::default()).split(',').count(), RUN_CSV_COLUMNS.split(',').count());
    }
}
