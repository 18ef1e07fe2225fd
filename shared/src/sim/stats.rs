//! What a run measured about the protocol and the radio, for reports: the
//! world's own counts (moves, transmissions, losses, wake-ups) and what the
//! robots noted (declarations, rejoins, time-outs), compared with the ground
//! truth of the faults injected.

use serde::{Deserialize, Serialize};

use crate::map::RobotId;

/// One injected crash or freeze, and how the team found out.
/// Every way a run can end, as `ended_by` says it. Only `stop` is a
/// complete search: `exhausted` is a stop by a robot that knew targets were
/// unfound (situation 1, nothing left to visit), `false_stop` a stop on an
/// incomplete search (a fault of the protocol, which the simulation test
/// looks for), `cut_off` every live robot halted behind failed ones,
/// `no_robots` none left searching, `max_rounds` the round limit,
/// `past_bound` a run past a stated bound in which no robot moved for
/// [`crate::bounds::STALL_ROUNDS`] rounds ([`ProtocolStats::past_bound`] says which).
pub const ENDINGS: [&str; 7] = ["stop", "exhausted", "false_stop", "cut_off", "no_robots", "max_rounds", "past_bound"];

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FailureRecord {
    pub robot: RobotId,
    /// `crash` or `freeze`.
    pub kind: String,
    /// Round and simulated time of the fault.
    pub round: u32,
    pub at_s: f64,
    /// Simulated time of the thaw, for a freeze that ended.
    pub thawed_s: Option<f64>,
    /// When a robot first declared it failed (after the fault).
    pub detected_round: Option<u32>,
    pub detected_s: Option<f64>,
    /// Every robot that declared it, in order.
    pub declared_by: Vec<RobotId>,
    /// Robots that timed out waiting on it and never declared it although
    /// they kept running for `suspect_rounds + 1` more rounds: should be none.
    pub unaware: Vec<RobotId>,
}

impl FailureRecord {
    /// Rounds from the fault to its first declaration.
    pub fn delay_rounds(&self) -> Option<u32> {
        self.detected_round.map(|r| r.saturating_sub(self.round))
    }

    /// Simulated seconds from the fault to its first declaration.
    pub fn delay_s(&self) -> Option<f64> {
        self.detected_s.map(|t| t - self.at_s)
    }
}

/// Counts of one run of the protocol.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ProtocolStats {
    /// Moves executed (a robot translating along an edge).
    pub moves: u64,
    /// Moves refused by the world (not along a traversable edge).
    pub refused: u64,
    /// Frames robots handed to the radio.
    pub frames: u64,
    /// Transmissions, retransmitted copies included.
    pub transmissions: u64,
    pub retransmissions: u64,
    /// Frames that reached a robot (per link), and copies lost per link.
    pub deliveries: u64,
    pub lost: u64,
    pub duplicated: u64,
    /// Times a robot was woken.
    pub wakes: u64,
    /// Declarations of a robot that was running at the time.
    pub false_suspicions: u64,
    /// Declarations in all.
    pub declarations: u64,
    pub rejoins: u64,
    /// Times a robot gave up waiting for a neighbour's choice.
    pub timeouts: u64,
    /// Times a robot stayed for want of acknowledgements.
    pub unsure: u64,
    /// Frames robots dropped as stale or malformed.
    pub stale: u64,
    pub malformed: u64,
    /// Slots the clock had to close at their limit, robots without a motor
    /// command staying.
    pub forced_slots: u64,
    /// Under the fixed slot rule, moves commanded for a time past the
    /// slot's end, which the robot did not make: the protocol never gives
    /// one (`crate::peer`), so a count here is a fault of the protocol.
    #[serde(default)]
    pub late_motors: u64,
    /// Floods the human controller relayed to every robot
    /// ([`crate::params::Broadcast::Controller`]).
    #[serde(default)]
    pub relays: u64,
    /// How the run ended: one of [`ENDINGS`].
    pub ended_by: String,
    /// For a run that ended `past_bound`, or at its round limit past a
    /// stated bound: which bound, and which robots
    /// ([`crate::bounds::Bounds::past`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub past_bound: Option<String>,
    /// Round and simulated time of the first stop that ends the search.
    pub stop_round: Option<u32>,
    pub stop_s: Option<f64>,
    pub failures: Vec<FailureRecord>,
}

impl ProtocolStats {
    /// Collisions per million moves.
    pub fn collisions_per_million_moves(&self, collisions: u32) -> f64 {
        if self.moves == 0 {
            0.0
        } else {
            collisions as f64 * 1e6 / self.moves as f64
        }
    }
}
