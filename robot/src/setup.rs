//! What a robot holds before it starts, and nothing more (issue
//! "Decentralized for real", point 7): the grid frame (lattice, side `a`,
//! bounding box), its parameters, its identity, algorithm and seed, and the
//! number of targets in situation 1. Never obstacles, never target
//! positions. The in-process engine and the robot-agent both build their
//! robots from this, so both build the same robot; the world's crate
//! derives it from a run (`gridswarm::outcome::RunConfig::robot_setup`).

use serde::{Deserialize, Serialize};

use crate::agreement::{Agreement, ScenarioId};
use crate::geometry::Point;
use crate::grid::Grid;
use crate::lattice::{Lattice, LatticeKind};
use crate::map::RobotId;
use crate::params::{Params, Situation};
use crate::peer::PeerConfig;
use crate::policy::Policy;
use crate::robot::RobotConfig;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSetup {
    pub id: RobotId,
    pub lattice: LatticeKind,
    /// Corners of the bounding box the grid frame covers.
    pub lo: [f64; 2],
    pub hi: [f64; 2],
    pub params: Params,
    pub policy: Policy,
    pub situation: Situation,
    /// `|T|` in situation 1; 0 in situation 2, where no robot knows it.
    pub targets_total: usize,
    pub seed: u64,
    /// Robots in the team, this one included: the roster, known before
    /// the start like the robot's own id.
    pub team: usize,
}

/// What the orchestrator hands a robot-agent it starts (`--setup`): the
/// robot's setup, and the two things of the run's agreement no setup
/// holds, the run key and the scenario's id. The agreement the agent
/// presents is derived from the setup ([`SetupFile::agreement`]), never
/// declared beside it: an edited setup is presented as edited, and the
/// world refuses it unless it is the world's own (issue 36, point 9).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SetupFile {
    /// The run key (zenoh: the root of its key expressions; iceoryx2: the
    /// run's prefix): the run this setup was written for.
    pub key: String,
    /// The scenario the setup was derived from.
    pub scenario: ScenarioId,
    pub setup: RobotSetup,
}

impl SetupFile {
    /// The agreement this robot presents: the one its setup runs.
    pub fn agreement(&self) -> Agreement {
        Agreement::of(&self.key, self.scenario.clone(), &self.setup)
    }
}

impl RobotSetup {
    /// The grid frame, numbered as the world numbers it.
    pub fn grid(&self) -> Grid {
        Grid::new(
            Lattice::new(self.lattice, self.params.a),
            Point::new(self.lo[0], self.lo[1]),
            Point::new(self.hi[0], self.hi[1]),
        )
    }

    pub fn peer_config(&self) -> PeerConfig {
        let rc = RobotConfig {
            id: self.id,
            policy: self.policy,
            situation: self.situation,
            targets_total: self.targets_total,
            r_safe: self.params.r_safe,
            seed: self.seed,
            choices_update_maps: self.params.choices_update_maps,
            survivor_step: self.params.survivor_step,
            order: self.params.order,
            visited_choice: self.params.visited_choice,
            team: self.team,
        };
        PeerConfig::new(rc, &self.params)
    }
}
