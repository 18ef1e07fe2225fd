//! The search algorithms compared in Sec. 5, by their command-line names.

use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Policy {
    /// The paper's (1),(2)&(3): sequential collision-free choice, rule (1)
    /// alone and rule (2) (repulsion) with neighbours.
    Repulsive,
    /// (1)&(3): the sequential collision-free choice with rule (1) only.
    Sequential,
    /// RU: random choice, unvisited first; simultaneous, no collision
    /// avoidance, one extra move time per collision.
    Ru,
    /// LFP: Levy flight with a potential field, continuous motion.
    Lfp,
    /// Repulsive, plus breadth-first search on the robot's own map to the
    /// nearest unvisited vertex when every adjacent vertex is visited.
    Escape,
    /// A centralized planner that knows the map (not the targets): a
    /// reference time, not a robot program; in-process only.
    Oracle,
}

impl Policy {
    pub const ALL: [Policy; 6] =
        [Policy::Repulsive, Policy::Sequential, Policy::Ru, Policy::Lfp, Policy::Escape, Policy::Oracle];

    pub fn name(self) -> &'static str {
        match self {
            Policy::Repulsive => "repulsive",
            Policy::Sequential => "sequential",
            Policy::Ru => "ru",
            Policy::Lfp => "lfp",
            Policy::Escape => "escape",
            Policy::Oracle => "oracle",
        }
    }

    /// The label the paper uses in Fig. 7.
    pub fn paper_label(self) -> &'static str {
        match self {
            Policy::Repulsive => "(1),(2)&(3)",
            Policy::Sequential => "(1)&(3)",
            Policy::Ru => "RU",
            Policy::Lfp => "LFP",
            Policy::Escape => "escape",
            Policy::Oracle => "oracle",
        }
    }

    /// Whether robots move on the grid and run the decision core (all but
    /// LFP and the oracle): what `run` can start as robot processes.
    pub fn on_grid(self) -> bool {
        !matches!(self, Policy::Lfp | Policy::Oracle)
    }

    /// Whether the policy promises no collisions.
    pub fn collision_free(self) -> bool {
        matches!(self, Policy::Repulsive | Policy::Sequential | Policy::Escape)
    }
}

impl std::fmt::Display for Policy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Policy {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Policy::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| format!("unknown algorithm `{s}` (expected one of repulsive, sequential, ru, lfp, escape, oracle)"))
    }
}
