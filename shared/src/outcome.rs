//! What one run asks for and what it returns, whichever engine ran it.

use serde::{Deserialize, Serialize};

use crate::geometry::Point;
use crate::lattice::Coord;
use crate::params::Situation;
use crate::policy::Policy;

/// One run's settings beyond the world and the start vertices.
#[derive(Clone, Debug)]
pub struct RunConfig {
    pub policy: Policy,
    pub seed: u64,
    pub situation: Situation,
    /// A run that has not stopped after this many rounds ends incomplete.
    pub max_rounds: u32,
    /// Measure the detected fraction of `Ad` at the end (costs a raster pass).
    pub measure_coverage: bool,
    /// Keep every robot's pose of every round.
    pub record_trajectories: bool,
}

impl RunConfig {
    pub fn new(policy: Policy, seed: u64, situation: Situation) -> Self {
        RunConfig { policy, seed, situation, max_rounds: 100_000, measure_coverage: true, record_trajectories: true }
    }
}

/// A robot's pose at the start of a round. `vertex` is `None` only for
/// policies that leave the grid (LFP).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    pub vertex: Option<Coord>,
    pub position: Point,
}

/// The outcome of one run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunResult {
    pub algorithm: Policy,
    pub robots: usize,
    pub seed: u64,
    pub situation: u8,
    /// Rounds played (moves made by the team).
    pub rounds: u32,
    /// Simulated search time (READING.md "Time"), not wall time.
    pub search_time_s: f64,
    pub targets_found: usize,
    pub targets_total: usize,
    /// Collisions counted by the ground-truth referee.
    pub collisions: u32,
    /// Detected fraction of `Ad` at the end, when measured.
    pub coverage: Option<f64>,
    /// Whether the stop rule was reached (all targets, or every vertex of `Va`).
    pub complete: bool,
    /// Robot-rounds: the sum over rounds of the robots still active.
    pub robot_rounds: u64,
    /// `trajectories[r][k]`: robot `r`'s pose at the start of round `k`
    /// (index `rounds` is where it ended). Empty unless recorded.
    #[serde(skip)]
    pub trajectories: Vec<Vec<Pose>>,
}
