//! What a distributed run reports: the result in the in-process engine's
//! shape (trajectories rebuilt from the world's vertex ids), the
//! engine=distributed fields of `summary.json` (faults injected and how
//! the robots found out, wall time per round, start-up, memory, messages
//! and wake-ups per robot per round) and the terminal text.

use std::path::{Path, PathBuf};

use gridswarm::ipc::RunReport;
use gridswarm::outcome::{Pose, RunConfig, RunResult};
use gridswarm::scenario::Scenario;
use gridswarm::sim::{schedule, seconds, FaultKind};
use gridswarm::world::World;
use serde_json::{json, Value};

use gridswarm::transport::Guard;

use super::net::Launch;
use super::{Followed, Plan, RunOptions};

/// Nearest-rank percentile of unsorted samples.
pub fn percentile(samples: &[f64], p: f64) -> Option<f64> {
    if samples.is_empty() {
        return None;
    }
    let mut v = samples.to_vec();
    v.sort_by(f64::total_cmp);
    let rank = ((p / 100.0) * v.len() as f64).ceil().max(1.0) as usize;
    Some(v[rank.min(v.len()) - 1])
}

/// The kernel's result with its trajectories rebuilt.
pub fn result_of(world: &World, report: &RunReport) -> RunResult {
    let mut result = report.result.clone();
    let grid = &world.grid;
    result.trajectories = report
        .vertices
        .iter()
        .map(|vs| vs.iter().map(|&v| Pose { vertex: Some(grid.coord(v)), position: grid.position(v) }).collect())
        .collect();
    result.round_end_times_s = report.round_end_times_s.clone();
    result
}

fn injected(cfg: &RunConfig, applied: &[bool]) -> Vec<Value> {
    cfg.faults
        .iter()
        .zip(applied)
        .map(|(f, &a)| {
            json!({
                "robot": f.robot,
                "round": f.round,
                "offset_s": seconds(f.offset),
                "kind": f.kind.name(),
                "applied": a,
            })
        })
        .collect()
}

/// Failures some robot declared, as the kernel recorded them.
fn detected(result: &RunResult) -> Vec<Value> {
    result
        .protocol
        .failures
        .iter()
        .filter_map(|r| {
            let round = r.detected_round?;
            Some(json!({
                "robot": r.robot,
                "round": round,
                "kind": r.kind,
                "declared_by": r.declared_by,
                "injected_round": r.round,
                "delay_rounds": r.delay_rounds(),
                "delay_ms": r.delay_s().map(|s| s * 1e3),
            }))
        })
        .collect()
}

/// Per robot per round: `count / robot_rounds`.
fn per_robot_round(count: u64, result: &RunResult) -> Option<f64> {
    (result.robot_rounds > 0).then(|| count as f64 / result.robot_rounds as f64)
}

/// How the run's processes met: `transport` of the summary.
fn transport(opts: &RunOptions, launch: &Launch) -> Value {
    json!({
        "name": opts.net.transport.name(),
        "endpoints": launch.endpoints,
        "remote_agents": opts.net.remote_agents.is_some(),
        "security": security(launch.guard),
    })
}

/// How the links were protected: `security` of the summary's `transport`.
pub fn security(guard: Option<Guard>) -> Value {
    match guard {
        Some(Guard::Tls) => json!({"mode": "mutual-tls", "authenticated": true, "encrypted": true}),
        Some(Guard::Plain { .. }) => json!({"mode": "none", "authenticated": false, "encrypted": false}),
        // Shared memory or function calls: no network, files only the run's uid can open.
        None => json!({"mode": "local"}),
    }
}

/// The engine=distributed fields of the summary.
pub fn extra(
    prefix: &str,
    opts: &RunOptions,
    (plan, launch): (&Plan, &Launch),
    report: &RunReport,
    f: &Followed,
    killed_at_end: usize,
) -> Value {
    let r = &report.result;
    let wall = &report.round_wall_ms;
    let rss: Vec<f64> = report.agent_peak_rss_kib.iter().filter(|&&k| k > 0).map(|&k| k as f64).collect();
    json!({
        "engine": "distributed",
        "transport": transport(opts, launch),
        // What every robot-agent presented and the world accepted.
        "agreement": report.agreement,
        "ipc_prefix": prefix,
        "max_rounds": opts.max_rounds,
        "radio": plan.cfg.radio,
        "retries": plan.world.params.retries,
        "faults": schedule::to_args(&plan.cfg.faults),
        "start_rule": opts.starts,
        "failures_injected": injected(&plan.cfg, &f.applied),
        "failures_detected": detected(r),
        "refused_moves": r.protocol.refused,
        "protocol": r.protocol,
        "dropped_messages": { "total": report.dropped },
        "round_wall_ms": {
            "p50": percentile(wall, 50.0),
            "p99": percentile(wall, 99.0),
            "max": percentile(wall, 100.0),
        },
        "startup_ms": {
            "world_ready": f.ready_ms,
            "agents_spawned": f.spawned_ms,
            "all_hello": report.startup_ms,
        },
        "run_wall_ms": f.run_ms,
        "paused_ms": report.paused_ms,
        "world_fds": report.world_fds,
        "world_peak_rss_kib": report.world_peak_rss_kib,
        "agent_peak_rss_kib": { "p50": percentile(&rss, 50.0), "max": percentile(&rss, 100.0) },
        "agents_killed_at_end": killed_at_end,
        "world_cpu_ms_per_round": report.world_cpu_ms / f64::from(r.rounds.max(1)),
        // Agents on other hosts (`--remote-agents`) are not measured: unknown, not 0.
        "agent_cpu_ms_total": (!report.agent_cpu_ms.is_empty()).then(|| report.agent_cpu_ms.iter().sum::<f64>()),
        "messages_per_robot_round": per_robot_round(r.protocol.frames, r),
        "wakeups_per_robot_round": per_robot_round(r.protocol.wakes, r),
        "died": report.died,
        "liveness_checks": report.liveness_checks,
        "largest_wake_bytes": report.largest_wake_bytes,
        "round_trips_per_round": report.wake_batches as f64 / f64::from(r.rounds.max(1)),
        "ended_by": r.protocol.ended_by,
    })
}

/// A warning about agents that did not end cleanly (faulted robots aside).
pub fn agent_warning(cfg: &RunConfig, applied: &[bool], status: &[Option<i32>], log: &Path) -> Option<String> {
    let faulted = |r: usize| {
        cfg.faults
            .iter()
            .zip(applied)
            .any(|(f, &a)| a && f.robot == r && matches!(f.kind, FaultKind::Crash | FaultKind::Freeze))
    };
    let bad: Vec<usize> = (0..status.len()).filter(|&r| !faulted(r) && status[r] != Some(0)).collect();
    if bad.is_empty() {
        return None;
    }
    let log = std::fs::read_to_string(log).unwrap_or_default();
    let first = log.lines().next().map(|l| format!(": {l}")).unwrap_or_default();
    Some(format!("warning: robot-agent(s) {bad:?} did not end cleanly{first}"))
}

/// The terminal text of a run.
pub fn text(
    scenario: &Scenario,
    result: &RunResult,
    report: &RunReport,
    summary: &Value,
    written: &[PathBuf],
) -> String {
    let p = &result.protocol;
    let mut text =
        crate::output::headline(scenario, result, ": one process per robot", &format!("refused moves {}; ", p.refused));
    let ms = |v: &Value| v.as_f64().map(|x| format!("{x:.3}")).unwrap_or_else(|| "-".into());
    text += &format!(
        "wall time per round: p50 {} ms, p99 {} ms, max {} ms; start-up {:.0} ms; \
         {} messages and {} wake-ups per robot per round\n",
        ms(&summary["round_wall_ms"]["p50"]),
        ms(&summary["round_wall_ms"]["p99"]),
        ms(&summary["round_wall_ms"]["max"]),
        report.startup_ms,
        ms(&summary["messages_per_robot_round"]),
        ms(&summary["wakeups_per_robot_round"]),
    );
    for i in summary["failures_injected"].as_array().into_iter().flatten() {
        let done = if i["applied"] == true { "" } else { " (not applied: the search ended first)" };
        text += &format!(
            "injected: {} robot {} at round {} + {} s{done}\n",
            i["kind"].as_str().unwrap_or("?"),
            i["robot"],
            i["round"],
            i["offset_s"]
        );
    }
    for r in &p.failures {
        match r.detected_round {
            Some(k) => {
                text += &format!("declared: robot {} ({}) in round {k} by {:?}\n", r.robot, r.kind, r.declared_by)
            }
            None => text += &format!("never declared: robot {} ({})\n", r.robot, r.kind),
        }
    }
    for w in written {
        text += &format!("wrote {}\n", w.display());
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles() {
        assert_eq!(percentile(&[], 50.0), None);
        assert_eq!(percentile(&[3.0, 1.0, 2.0], 50.0), Some(2.0));
        assert_eq!(percentile(&[3.0, 1.0, 2.0], 99.0), Some(3.0));
        assert_eq!(percentile(&[5.0], 99.0), Some(5.0));
    }
}
