//! Ranges and times of docs/paper.md's Table 1, and the situation being searched.

use serde::{Deserialize, Serialize};

/// Physical parameters of the robots and the grid. The defaults are the
/// project's reading of the lost Table 1 (docs/paper.md): `a`, `r_rob`,
/// `r_safe` and the move times are given, every range is the equality case
/// of its assumption.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Params {
    /// Grid side: one step (m).
    pub a: f64,
    /// Robot swing radius (m).
    pub r_rob: f64,
    /// Safety radius, all errors included (m).
    pub r_safe: f64,
    /// Obstacle sensing range, sonar (m).
    pub r_so: f64,
    /// Target sensing range, laser (m).
    pub r_st: f64,
    /// Communication range (m).
    pub r_c: f64,
    /// One rotation (s).
    pub t_rot: f64,
    /// One translation of length `a` (s).
    pub t_trans: f64,
    /// One robot's turn in step 5, compute and send (s). Not given by the
    /// paper; 0.1 s is the project's choice for a Wi-Fi round trip plus a
    /// small computation.
    pub t_choice: f64,
    /// The map exchange window at the start of every slot (s): robots
    /// broadcast their maps, and choose with the maps heard by its end.
    #[serde(default = "defaults::t_exchange")]
    pub t_exchange: f64,
    /// Radio latency of one frame, and the spacing of retransmissions (s).
    #[serde(default = "defaults::t_hop")]
    pub t_hop: f64,
    /// How long a robot waits for a neighbour's choice, and then for the
    /// choices that acknowledge its own, before it gives up on that
    /// neighbour for the round and (if unsure) stays (s).
    #[serde(default = "defaults::t_wait")]
    pub t_wait: f64,
    /// Extra copies of every frame a robot transmits (blind retransmission).
    #[serde(default)]
    pub retries: u32,
    /// Slots in a row a robot expected in radio range may stay silent before
    /// it is declared failed.
    #[serde(default = "defaults::suspect_rounds")]
    pub suspect_rounds: u32,
    /// Reading: a received choice marks its vertex visited in the
    /// receiver's map at once (the paper: "the receivers will update their
    /// maps"); false: only the next exchange's maps carry it.
    #[serde(default = "defaults::choices_update_maps")]
    pub choices_update_maps: bool,
    /// Reading "survivors": once a robot knows of a failure or a body, a
    /// robot of the paper's rules with every candidate visited steps
    /// towards the nearest unvisited vertex it can reach (escape's rule)
    /// instead of the paper's walk over visited vertices; false: the
    /// paper's rules as written, failures or not (docs/paper.md
    /// "Survivors"). Fault-free runs never take the step either way.
    #[serde(default = "defaults::survivor_step")]
    pub survivor_step: bool,
    /// How the world referees RU's collisions (the paper only says each
    /// costs a move time): see [`RuCollisions`].
    #[serde(default)]
    pub ru_collisions: RuCollisions,
    /// Rule (2)'s choice among visited candidates: see [`VisitedChoice`].
    #[serde(default)]
    pub visited_choice: VisitedChoice,
    /// What ends a slot: see [`SlotRule`].
    #[serde(default)]
    pub slot: SlotRule,
    /// Step 4's order, who waits for whose choice: see [`Order`].
    #[serde(default)]
    pub order: Order,
    /// How found targets and the stop reach every robot (step 8): see
    /// [`Broadcast`].
    #[serde(default)]
    pub broadcast: Broadcast,
}

/// How step 8's "broadcast target positions and the stop signal to all
/// robots and the human controller" reaches all robots (issue 36, item 1).
/// Robots flood what they find within `r_c` under both; the difference is
/// whether the human controller's base station, which hears the whole
/// area, passes it on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Broadcast {
    /// The paper's "to all robots": the controller relays every flood that
    /// tells it something new (a target, the stop) to every robot over its
    /// own long-range link, with the run's loss, delay and jitter. Every
    /// algorithm of a sweep, LFP included, then learns found targets the
    /// same way.
    #[default]
    Controller,
    /// Only the robots' own multi-hop flood within `r_c`: a robot learns a
    /// target once a chain of robots in range carries it (the project's
    /// reading before issue 36).
    Flood,
}

impl Broadcast {
    pub const NAMES: [&'static str; 2] = ["controller", "flood"];

    pub fn name(self) -> &'static str {
        match self {
            Broadcast::Controller => "controller",
            Broadcast::Flood => "flood",
        }
    }

    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "controller" => Some(Broadcast::Controller),
            "flood" => Some(Broadcast::Flood),
            _ => None,
        }
    }
}

/// Who waits for whose choice in step 4 (issue 21, point 5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Order {
    /// The paper's: a robot waits for every neighbour further east (then
    /// north). Chains of waits run across the team, so a slot's choices
    /// take longer the denser the team (docs/paper.md, "Choice order").
    #[default]
    Paper,
    /// A local order of bounded depth, not the paper's: vertices are
    /// coloured so that any two within `2a` differ
    /// ([`crate::lattice::Lattice::class`], 7 classes on the triangular
    /// lattice), and a robot waits only for neighbours of an earlier
    /// class. Robots of one class never conflict and choose at once, so
    /// a chain has at most one robot a class, whatever the team.
    Local,
}

impl Order {
    pub const NAMES: [&'static str; 2] = ["paper", "local"];

    pub fn name(self) -> &'static str {
        match self {
            Order::Paper => "paper",
            Order::Local => "local",
        }
    }

    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "paper" => Some(Order::Paper),
            "local" => Some(Order::Local),
            _ => None,
        }
    }
}

/// A command-line value (`--order`), one parser for every program.
impl std::str::FromStr for Order {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Order::from_name(s).ok_or_else(|| format!("`{s}`: one of {}", Order::NAMES.join(", ")))
    }
}

/// What ends a slot's decisions and starts its moves (issue 21, point 6).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SlotRule {
    /// The idealization: the world closes a slot as soon as every robot
    /// that is running and searching has given its motor command (or at a
    /// hard limit), so a slot lasts as long as its slowest decision. It
    /// needs a global view of who has commanded that real robots lack.
    #[default]
    Adaptive,
    /// Real robots with synchronized clocks: every slot lasts the same
    /// length, which each robot derives from its own parameters
    /// (`peer::Timing::decision_time`, then one move time); a command not
    /// given by the end of the decisions is no command, and the robot stays.
    Fixed,
}

impl SlotRule {
    pub const NAMES: [&'static str; 2] = ["adaptive", "fixed"];

    pub fn name(self) -> &'static str {
        match self {
            SlotRule::Adaptive => "adaptive",
            SlotRule::Fixed => "fixed",
        }
    }

    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "adaptive" => Some(SlotRule::Adaptive),
            "fixed" => Some(SlotRule::Fixed),
            _ => None,
        }
    }
}

/// A command-line value (`--slot`), one parser for every program.
impl std::str::FromStr for SlotRule {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        SlotRule::from_name(s).ok_or_else(|| format!("`{s}`: one of {}", SlotRule::NAMES.join(", ")))
    }
}

/// The reading of "one extra move time per collision" (issue 8, 1a; issue 22, 1; issue 36, 3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RuCollisions {
    /// Robots that collide back off to where they came from (or separate to
    /// a free adjacent vertex), and the round lasts one extra move time if
    /// any collision happened: the robots involved pay it together, in
    /// parallel, and a pair is never charged for standing still. The
    /// project's reading before issue 22; the text mentions no backing off.
    BackOff,
    /// Every colliding pair adds one move time to the whole team's round,
    /// and robots that end on one vertex stay there, charged again every
    /// round they start stacked. The default of issues 22 to 36.
    PerPair,
    /// Default, the paper's words ("an additional move time is added for
    /// each collision") read as events: a pair collides when its moves
    /// bring it within `2 r_safe`, or it ends on one vertex, having started
    /// the round apart; each such event adds one move time to the whole
    /// team's round. A pair that starts a round in contact (stacked on one
    /// vertex) has not moved apart since its collision: the same event,
    /// charged no more until it has been apart.
    #[default]
    PerEvent,
}

impl RuCollisions {
    pub const NAMES: [&'static str; 3] = ["per-event", "per-pair", "back-off"];

    pub fn name(self) -> &'static str {
        match self {
            RuCollisions::BackOff => "back-off",
            RuCollisions::PerPair => "per-pair",
            RuCollisions::PerEvent => "per-event",
        }
    }

    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "back-off" => Some(RuCollisions::BackOff),
            "per-pair" => Some(RuCollisions::PerPair),
            "per-event" => Some(RuCollisions::PerEvent),
            _ => None,
        }
    }
}

/// Rule (2)'s choice among visited candidates (issue 36, 5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum VisitedChoice {
    /// Default, as the text reads rule (2): the candidate farthest from
    /// `p_ave`, ties uniformly. Deterministic up to ties, so robots that
    /// stay in radio range can shuttle between two visited vertices for
    /// ever (docs/paper.md, "Theorem 4.1").
    #[default]
    Farthest,
    /// As Theorem 4.1's proof reads it ("robots will randomly choose
    /// accessible sensing neighbors"): uniformly over the visited
    /// candidates, with or without neighbours. Not the text's rule.
    Uniform,
    /// The proof's random choice with the repulsion as a bias: with
    /// probability 1/2 the farthest (ties uniformly), otherwise uniformly
    /// over every visited candidate, so each has probability at least
    /// `1 / (2 n)`. Not the text's rule.
    RandomBiased,
}

impl VisitedChoice {
    pub const NAMES: [&'static str; 3] = ["farthest", "uniform", "random-biased"];

    pub fn name(self) -> &'static str {
        match self {
            VisitedChoice::Farthest => "farthest",
            VisitedChoice::Uniform => "uniform",
            VisitedChoice::RandomBiased => "random-biased",
        }
    }

    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "farthest" => Some(VisitedChoice::Farthest),
            "uniform" => Some(VisitedChoice::Uniform),
            "random-biased" => Some(VisitedChoice::RandomBiased),
            _ => None,
        }
    }
}

/// Defaults of the protocol's timing, for files written before they existed.
mod defaults {
    pub fn t_exchange() -> f64 {
        0.05
    }
    pub fn t_hop() -> f64 {
        0.002
    }
    pub fn t_wait() -> f64 {
        3.0
    }
    pub fn suspect_rounds() -> u32 {
        1
    }
    pub fn choices_update_maps() -> bool {
        true
    }
    pub fn survivor_step() -> bool {
        true
    }
}

impl Params {
    /// Defaults for the given `a`, `r_rob`, `r_safe`: every range at the
    /// equality case of Assumptions 2.4, 2.5 and 3.1.1.
    pub fn derived(a: f64, r_rob: f64, r_safe: f64) -> Self {
        Params {
            a,
            r_rob,
            r_safe,
            r_so: a + r_safe,
            r_st: a + r_safe,
            r_c: 2.0 * a + r_safe - r_rob,
            t_rot: 1.25,
            t_trans: 4.5,
            t_choice: 0.1,
            t_exchange: defaults::t_exchange(),
            t_hop: defaults::t_hop(),
            t_wait: defaults::t_wait(),
            retries: 0,
            suspect_rounds: defaults::suspect_rounds(),
            choices_update_maps: defaults::choices_update_maps(),
            survivor_step: defaults::survivor_step(),
            ru_collisions: RuCollisions::default(),
            visited_choice: VisitedChoice::default(),
            slot: SlotRule::default(),
            order: Order::default(),
            broadcast: Broadcast::default(),
        }
    }

    /// One full move: a rotation and a translation (the RU penalty per collision).
    #[inline]
    pub fn move_time(&self) -> f64 {
        self.t_rot + self.t_trans
    }

    /// What `collisions` counted pairs add to a round (s), per
    /// [`Params::ru_collisions`]: once per round with any, or once per
    /// counted pair (the referee counts events or pairs accordingly).
    pub fn collision_penalty(&self, collisions: u32) -> f64 {
        match self.ru_collisions {
            RuCollisions::BackOff if collisions > 0 => self.move_time(),
            RuCollisions::BackOff => 0.0,
            RuCollisions::PerPair | RuCollisions::PerEvent => collisions as f64 * self.move_time(),
        }
    }
}

impl Default for Params {
    fn default() -> Self {
        Params::derived(1.0, 0.25, 0.30)
    }
}

/// Whether the number of targets is known (Sec. 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Situation {
    /// `|T|` known: stop when every target is found (rule 3).
    One,
    /// `|T|` unknown: stop when the map has no unvisited vertex (rule 4).
    Two,
}

impl Situation {
    pub fn number(self) -> u8 {
        match self {
            Situation::One => 1,
            Situation::Two => 2,
        }
    }

    pub fn from_number(n: u8) -> Option<Self> {
        match n {
            1 => Some(Situation::One),
            2 => Some(Situation::Two),
            _ => None,
        }
    }
}
