//! The search algorithms by their command-line names: the four compared in
//! Sec. 5, the project's `escape` and `frontier`, and rules registered by a
//! program ([`crate::choice::register`]). On the wire and in files a policy
//! is its name.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::choice::registry::{self, RuleName};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
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
    /// Repulsive, plus a shortest path on the robot's own map to a nearest
    /// unvisited vertex when every adjacent vertex is visited.
    Escape,
    /// Nearest-frontier exploration (Yamauchi 1998), decentralized: the
    /// paper's robots with a shortest-path choice rule and no repulsion.
    Frontier,
    /// A centralized planner that knows the map (not the targets): a
    /// reference time, not a robot program; in-process only.
    Oracle,
    /// A choice rule a program registered by name; it runs like the
    /// sequential collision-free policies.
    Custom(RuleName),
}

impl Policy {
    /// The built-in algorithms.
    pub const ALL: [Policy; 7] = [
        Policy::Repulsive,
        Policy::Sequential,
        Policy::Ru,
        Policy::Lfp,
        Policy::Escape,
        Policy::Frontier,
        Policy::Oracle,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Policy::Repulsive => "repulsive",
            Policy::Sequential => "sequential",
            Policy::Ru => "ru",
            Policy::Lfp => "lfp",
            Policy::Escape => "escape",
            Policy::Frontier => "frontier",
            Policy::Oracle => "oracle",
            Policy::Custom(n) => n.as_str(),
        }
    }

    /// The label the paper uses in Fig. 7 (the name for the others).
    pub fn paper_label(self) -> &'static str {
        match self {
            Policy::Repulsive => "(1),(2)&(3)",
            Policy::Sequential => "(1)&(3)",
            Policy::Ru => "RU",
            Policy::Lfp => "LFP",
            p => p.name(),
        }
    }

    /// Whether robots move on the grid and run the decision core (all but
    /// LFP and the oracle): what `run` can start as robot processes.
    pub fn on_grid(self) -> bool {
        !matches!(self, Policy::Lfp | Policy::Oracle)
    }

    /// Whether robots choose one after another in priority order, avoiding
    /// earlier choices (all grid policies but RU, whose robots are particles).
    pub fn sequential(self) -> bool {
        !matches!(self, Policy::Ru | Policy::Lfp | Policy::Oracle)
    }

    /// Whether the policy promises no collisions.
    pub fn collision_free(self) -> bool {
        self.sequential()
    }
}

impl std::fmt::Display for Policy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Policy {
    type Err = String;
    /// A built-in name or one registered (or announced) in this process.
    fn from_str(s: &str) -> Result<Self, String> {
        if let Some(p) = Policy::ALL.into_iter().find(|p| p.name() == s) {
            return Ok(p);
        }
        registry::lookup(s).ok_or_else(|| {
            let mut names: Vec<&str> = Policy::ALL.iter().map(|p| p.name()).collect();
            names.extend(registry::custom_names());
            format!("unknown algorithm `{s}` (expected one of {})", names.join(", "))
        })
    }
}

impl Serialize for Policy {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Policy {
    /// Any well-formed name: a process may pass on a policy it cannot run;
    /// the one that builds robots checks ([`crate::choice::registry::runnable`]).
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = <std::borrow::Cow<'de, str>>::deserialize(d)?;
        if let Some(p) = Policy::ALL.into_iter().find(|p| p.name() == s) {
            return Ok(p);
        }
        registry::intern(&s).map(Policy::Custom).map_err(serde::de::Error::custom)
    }
}
