//! The files of a distributed run that speak of the world: what the
//! orchestrator hands the world-server (`--run FILE`) and the report the
//! world-server writes back. Only the world's programs read them; a
//! robot-agent never does (its setup is a `SetupFile` of the robot's
//! crate), so they live here and not in the transport crate.

use serde::{Deserialize, Serialize};

use crate::outcome::{RunConfig, RunResult};

/// What the orchestrator hands the world-server (`--run FILE`).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunFile {
    /// Built-in scenario name or TOML path.
    pub scenario: String,
    pub robots: usize,
    /// Overrides the scenario's `params.retries`.
    #[serde(default)]
    pub retries: Option<u32>,
    /// Overrides the scenario's `params.slot`.
    #[serde(default)]
    pub slot: Option<crate::params::SlotRule>,
    /// Overrides the scenario's `params.order`.
    #[serde(default)]
    pub order: Option<crate::params::Order>,
    /// How the world places the robots (drawn from `config.seed` when random).
    #[serde(default)]
    pub starts: crate::scenario::StartRule,
    pub config: RunConfig,
}

/// What the world-server writes at the end of a run, for the orchestrator.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunReport {
    /// The kernel's result (its trajectories and round times are below).
    pub result: RunResult,
    /// Simulated time at the end of each round (element `k` ends round `k`).
    pub round_end_times_s: Vec<f64>,
    /// `vertices[r][k]`: the vertex id robot `r` stood on at the start of round `k`.
    pub vertices: Vec<Vec<u32>>,
    /// Wall time of every round played, in milliseconds, pauses for
    /// fault injection left out.
    pub round_wall_ms: Vec<f64>,
    /// From the world's start until every robot had said hello, in milliseconds.
    pub startup_ms: f64,
    /// Wall time spent paused at faults, in milliseconds.
    pub paused_ms: f64,
    pub world_fds: usize,
    pub world_peak_rss_kib: u64,
    /// CPU time the world spent after every hello, ms.
    pub world_cpu_ms: f64,
    /// Peak RSS of each robot-agent still running at the end (0 if unknown), KiB.
    pub agent_peak_rss_kib: Vec<u64>,
    /// CPU time each robot-agent still running at the end had used, ms.
    pub agent_cpu_ms: Vec<f64>,
    /// Robots whose process vanished outside the fault schedule.
    pub died: Vec<usize>,
    /// Wire messages the world dropped (stale or malformed chunks).
    pub dropped: u64,
    /// Times the world checked whether robots it waited on still exist.
    #[serde(default)]
    pub liveness_checks: u64,
    /// Round trips: wake-ups of the robots due at one simulated instant.
    #[serde(default)]
    pub wake_batches: u64,
    /// Bytes of the largest wake-up (more than `ipc::CHUNK_BYTES`: it went in chunks).
    #[serde(default)]
    pub largest_wake_bytes: usize,
    /// What every robot-agent of the run agreed on (the world's own).
    pub agreement: crate::agreement::Agreement,
}
