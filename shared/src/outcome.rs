//! What one run asks for and what it returns, whichever engine ran it.

use serde::{Deserialize, Serialize};

use crate::geometry::Point;
use crate::lattice::Coord;
use crate::params::Situation;
use crate::policy::Policy;
use crate::setup::RobotSetup;
use crate::sim::{FaultKind, ProtocolStats, Radio};
use crate::world::World;

/// One run's settings beyond the world and the start vertices.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
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
    /// Radio impairments (grid policies).
    pub radio: Radio,
    /// Faults injected into robots (grid policies).
    pub faults: Vec<crate::sim::Fault>,
}

impl RunConfig {
    pub fn new(policy: Policy, seed: u64, situation: Situation) -> Self {
        RunConfig {
            policy,
            seed,
            situation,
            max_rounds: crate::scenario::limits::DEFAULT_MAX_ROUNDS,
            measure_coverage: true,
            record_trajectories: true,
            radio: Radio::default(),
            faults: Vec::new(),
        }
    }

    /// Whether the run has faults or an imperfect radio.
    pub fn is_faulty(&self) -> bool {
        !self.faults.is_empty() || !self.radio.is_perfect()
    }

    /// What robot `id` of a team of `team` on `world` holds before it
    /// starts: the world's frame and parameters, and in situation 1 the
    /// number of targets, nothing else of it.
    pub fn robot_setup(&self, world: &World, id: usize, team: usize) -> RobotSetup {
        let (lo, hi) = world.area.bounding_box();
        RobotSetup {
            id: id as crate::map::RobotId,
            lattice: world.grid.lattice.kind,
            lo: [lo.x, lo.y],
            hi: [hi.x, hi.y],
            params: world.params,
            policy: self.policy,
            situation: self.situation,
            targets_total: if self.situation == Situation::One { world.targets.len() } else { 0 },
            seed: self.seed,
            team,
        }
    }

    /// Robots the faults crash or freeze.
    pub fn failing_robots(&self) -> impl Iterator<Item = usize> + '_ {
        self.faults.iter().filter(|f| matches!(f.kind, FaultKind::Crash | FaultKind::Freeze)).map(|f| f.robot)
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
    /// Rounds played (slots in which the team moved), until every robot
    /// stopped or the round limit.
    pub rounds: u32,
    /// Simulated search time (docs/paper.md "Time"), not wall time: until the
    /// first stop that ends the search, or the end of the run without one.
    pub search_time_s: f64,
    pub targets_found: usize,
    pub targets_total: usize,
    /// Collisions counted by the ground-truth referee.
    pub collisions: u32,
    /// Detected fraction of `Ad` at the end, when measured.
    pub coverage: Option<f64>,
    /// Whether the stop rule was reached (all targets, or every vertex of `Va`).
    pub complete: bool,
    /// Ended `cut_off` while a running robot could still reach, around the
    /// bodies, a vertex nobody visited: what cut the team off was gone.
    /// In situation 2 the same as not `complete`; in situation 1, where
    /// `complete` means every target found, the only word on it. The
    /// simulation test's, never written out.
    #[serde(default)]
    pub cut_off_early: bool,
    /// Robot-rounds: the sum over rounds of the robots still active.
    pub robot_rounds: u64,
    /// `trajectories[r][k]`: robot `r`'s pose at the start of round `k`
    /// (index `rounds` is where it ended). Empty unless recorded.
    #[serde(skip)]
    pub trajectories: Vec<Vec<Pose>>,
    /// Simulated time at the end of every round (element `k` ends round `k`).
    #[serde(skip)]
    pub round_end_times_s: Vec<f64>,
    /// Collisions the referee counted in every round (element `k`: round
    /// `k`), also those that leave no trace in the trajectories (robots
    /// that back off end where they started).
    #[serde(default)]
    pub round_collisions: Vec<u32>,
    /// The protocol's and the radio's counts (grid policies).
    #[serde(default)]
    pub protocol: ProtocolStats,
    /// Coverage against time, times to each target, and each robot's
    /// distance, turns and radio traffic.
    #[serde(default)]
    pub metrics: RunMetrics,
}

/// What a run measured beyond its search time, for the sweeps' figures
/// (issue 22, item 4): a few numbers per robot and per target and a
/// hundred points of coverage, never a value per round. Every engine fills
/// it alike for the same run.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunMetrics {
    /// `coverage_s[i]`: the simulated time at which the detected fraction
    /// of `Ad` first reached `(i + 1) / LEVELS`
    /// ([`crate::world::coverage::LEVELS`]), for the levels reached; empty
    /// unless coverage was measured. Places count from the end of the
    /// round that brought a robot there (time 0 for the starts).
    pub coverage_s: Vec<f64>,
    /// The simulated time at which the `k`-th target (from 0) was first
    /// found: when a robot's laser first had it within `r_st`.
    pub targets_s: Vec<f64>,
    /// Per robot: the distance it drove (m) and the times it turned to a
    /// new direction.
    pub distance_m: Vec<f64>,
    pub rotations: Vec<u32>,
    /// Per robot: the frames it handed to the radio, retransmitted copies
    /// not counted, and their bytes as encoded on the wire. Empty for
    /// policies without a radio (LFP, the oracle).
    pub frames: Vec<u64>,
    pub bytes: Vec<u64>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::Scenario;

    #[test]
    fn the_robots_grid_is_the_worlds() {
        let sc = Scenario::builtin("paper").unwrap();
        let world = sc.world();
        let cfg = RunConfig::new(Policy::Repulsive, 3, Situation::Two);
        let s = cfg.robot_setup(&world, 2, 5);
        let g = s.grid();
        assert_eq!(g.len(), world.grid.len());
        for v in 0..g.len() as u32 {
            assert_eq!(g.coord(v), world.grid.coord(v));
        }
        assert_eq!(s.targets_total, 0, "situation 2: unknown");
        let back: RobotSetup = serde_json::from_str(&serde_json::to_string(&s).unwrap()).unwrap();
        assert_eq!(back, s);
    }
}
