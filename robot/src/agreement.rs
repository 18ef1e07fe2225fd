//! What every process of a distributed run agrees on before the first
//! slot (issue 23, point 1): the run key, the scenario (by its canonical
//! text's SHA3-256), the seed, the algorithm, the situation, the
//! parameters after the run's overrides, the team's size, the grid frame,
//! the number of targets a robot is told, and the protocol version. Every
//! robot-agent presents its [`Agreement`] in its hello; the world compares
//! it with its own and refuses an agent that differs, naming every field
//! that does on both sides (`seed: world 7, agent 8`), so that nothing is
//! recorded under the world's seed that was computed under another.
//!
//! Both sides derive it from a robot's setup ([`Agreement::of`]): the agent
//! from the setup it will run, the world from the one it would hand a
//! robot. Apart from the run key and the scenario's id, which no setup
//! holds, nothing in it is declared: an agent cannot present one thing
//! and run another (issue 36, point 9).
//!
//! The agreement knows no transport: it travels in the hello, whatever
//! carries the hello, and so holds whatever secures the link later.

use serde::{Deserialize, Serialize};
use sha3::{Digest, Sha3_256};

use crate::lattice::LatticeKind;
use crate::params::Params;
use crate::setup::RobotSetup;

/// The version of the world-agent messages ([`crate::wire`]). Version 1
/// was the hello of a robot number and a process id alone; version 2
/// added the agreement and the world's verdict; version 3 the slot rule in
/// the parameters and a map's stop in its header (the controller's
/// receiver reads it); version 4 the time a map's sender sensed; version 5
/// the `Wait` frame and the choice order in the parameters; version 6
/// targets as positions ([`crate::spot`]), not the world's ids; version 7
/// the survivor step's switch, how step 8 reaches every robot and rule
/// (2)'s choice among visited vertices in the parameters, and the team,
/// the grid frame and the targets told in the agreement, derived from the
/// agent's setup; version 8 frames the controller's base station relayed,
/// delivered from [`crate::protocol::CONTROLLER`]; version 9 `Wait` frames
/// at growing intervals, and receivers' patience with them growing alike
/// (issue 37: a robot of version 8 would give up on one of version 9). A hello starts with its
/// version, so that a later world can read it whatever follows.
pub const PROTOCOL_VERSION: u32 = 9;

/// A scenario as the processes of a run name it: its `name`, and the
/// SHA3-256 of its canonical text (`Scenario::to_toml`, before the run's
/// overrides), which two hosts compute alike from one file, a built-in name
/// or a `random:` spec.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ScenarioId {
    pub name: String,
    /// Lowercase hex, 64 digits.
    pub sha3_256: String,
}

/// What a scenario shows of itself to be named in an agreement. The robot
/// never holds a scenario: the world's crate implements this for its own.
pub trait Named {
    fn name(&self) -> &str;
    /// The canonical text two hosts write alike for one scenario.
    fn canonical(&self) -> String;
}

impl ScenarioId {
    pub fn of(scenario: &impl Named) -> Self {
        let digest = Sha3_256::digest(scenario.canonical().as_bytes());
        let sha3_256 = digest.iter().map(|b| format!("{b:02x}")).collect();
        ScenarioId { name: scenario.name().to_string(), sha3_256 }
    }

    /// `` `paper` (sha3 1a2b3c4d5e6f) ``: the name escaped, the hash's head.
    fn shown(&self) -> String {
        format!("`{}` (sha3 {})", shown(&self.name), shown(self.sha3_256.get(..12).unwrap_or(&self.sha3_256)))
    }
}

/// What one run is, as every process of it must hold it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Agreement {
    /// First, so that a hello of any version starts with its version.
    pub protocol: u32,
    /// The run key (zenoh: the root of its key expressions; iceoryx2: the
    /// run's prefix).
    pub key: String,
    pub scenario: ScenarioId,
    pub seed: u64,
    /// The grid algorithm, by name (a custom rule's too).
    pub algorithm: String,
    /// 1 or 2.
    pub situation: u8,
    /// The parameters after the run's overrides (`--retries`).
    pub params: Params,
    /// Robots in the team (the roster every robot holds).
    pub team: usize,
    /// The grid frame: its lattice, and the corners of the box it covers.
    pub lattice: LatticeKind,
    pub lo: [f64; 2],
    pub hi: [f64; 2],
    /// `|T|` as a robot is told it (0 in situation 2).
    pub targets_total: usize,
}

impl Agreement {
    /// The agreement of a run under `key` on `scenario` (its id taken
    /// before the run's overrides) whose robots run `setup` (its robot
    /// number aside: that is the hello's own): everything a robot runs
    /// with, read off the setup, never declared beside it.
    pub fn of(key: &str, scenario: ScenarioId, setup: &RobotSetup) -> Self {
        Agreement {
            protocol: PROTOCOL_VERSION,
            key: key.to_string(),
            scenario,
            seed: setup.seed,
            algorithm: setup.policy.name().to_string(),
            situation: setup.situation.number(),
            params: setup.params,
            team: setup.team,
            lattice: setup.lattice,
            lo: setup.lo,
            hi: setup.hi,
            targets_total: setup.targets_total,
        }
    }

    /// Every field in which `agent`'s agreement differs from this one (the
    /// world's), as `field: world X, agent Y`; empty when they agree. A
    /// different protocol version is said alone: the rest may mean
    /// something else to the other side.
    pub fn differences(&self, agent: &Agreement) -> Vec<String> {
        if self == agent {
            return Vec::new();
        }
        if self.protocol != agent.protocol {
            return vec![format!("protocol version: world {}, agent {}", self.protocol, agent.protocol)];
        }
        let mut d = Vec::new();
        let mut differ = |what: &str, world: String, agent: String| {
            if world != agent {
                d.push(format!("{what}: world {world}, agent {agent}"));
            }
        };
        differ("run key", format!("`{}`", shown(&self.key)), format!("`{}`", shown(&agent.key)));
        if self.scenario != agent.scenario {
            differ("scenario", self.scenario.shown(), agent.scenario.shown());
        }
        differ("seed", self.seed.to_string(), agent.seed.to_string());
        differ("algorithm", shown(&self.algorithm).into(), shown(&agent.algorithm).into());
        differ("situation", self.situation.to_string(), agent.situation.to_string());
        differ("team", self.team.to_string(), agent.team.to_string());
        differ("lattice", self.lattice.name().into(), agent.lattice.name().into());
        let frame = |a: &Agreement| format!("{:?} to {:?}", a.lo, a.hi);
        if (self.lo, self.hi) != (agent.lo, agent.hi) {
            differ("grid frame", frame(self), frame(agent));
        }
        differ("targets told", self.targets_total.to_string(), agent.targets_total.to_string());
        for (name, world, agent) in param_differences(&self.params, &agent.params) {
            differ(&format!("params.{name}"), world, agent);
        }
        d
    }
}

/// The parameters that differ, by name, with both values as TOML writes them.
fn param_differences(world: &Params, agent: &Params) -> Vec<(String, String, String)> {
    let table = |p: &Params| match toml::Value::try_from(p) {
        Ok(toml::Value::Table(t)) => t,
        _ => toml::map::Map::new(),
    };
    let (w, a) = (table(world), table(agent));
    let mut out: Vec<(String, String, String)> = w
        .iter()
        .filter(|(k, v)| a.get(*k) != Some(v))
        .map(|(k, v)| (k.clone(), v.to_string(), a.get(k).map_or_else(|| "none".into(), |x| x.to_string())))
        .collect();
    // NaN differs from itself yet shows alike: still a difference, and
    // said as one (the bits tell apart what the text cannot).
    if out.is_empty() && world != agent {
        out.push(("(some)".into(), format!("{world:?}"), format!("{agent:?}")));
    }
    out
}

/// `s` with its control characters escaped: text from another process
/// (a scenario's name, a host name) never reaches a terminal raw.
pub fn shown(s: &str) -> std::borrow::Cow<'_, str> {
    if !s.chars().any(char::is_control) {
        return s.into();
    }
    s.chars().map(|c| if c.is_control() { c.escape_default().to_string() } else { c.to_string() }).collect()
}

/// Robot numbers `0..n` as a bash user reads them: `0 to 12`, `only 0`.
pub fn robot_range(n: usize) -> String {
    match n {
        0 => "none".into(),
        1 => "only 0".into(),
        n => format!("0 to {}", n - 1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Situation;
    use crate::policy::Policy;

    /// A scenario by name and text alone (the world's crate tests its own).
    struct Text(&'static str, &'static str);

    impl Named for Text {
        fn name(&self) -> &str {
            self.0
        }
        fn canonical(&self) -> String {
            self.1.into()
        }
    }

    fn setup(seed: u64) -> RobotSetup {
        RobotSetup {
            id: 3,
            lattice: LatticeKind::Triangular,
            lo: [0.0, 0.0],
            hi: [40.0, 30.0],
            params: Params::default(),
            policy: Policy::Repulsive,
            situation: Situation::Two,
            targets_total: 0,
            seed,
            team: 9,
        }
    }

    fn paper(seed: u64) -> Agreement {
        Agreement::of("lab2", ScenarioId::of(&Text("paper", "[area]")), &setup(seed))
    }

    #[test]
    fn a_scenario_is_named_by_its_text() {
        assert!(paper(7).differences(&paper(7)).is_empty());
        let id = ScenarioId::of(&Text("paper", "[area]"));
        assert_eq!(id.sha3_256.len(), 64);
        assert_eq!(ScenarioId::of(&Text("copy", "[area]")).sha3_256, id.sha3_256);
        assert_ne!(ScenarioId::of(&Text("paper", "[area] ")).sha3_256, id.sha3_256);
    }

    #[test]
    fn every_difference_is_named_on_both_sides() {
        let world = paper(7);
        let mut agent = paper(8);
        assert_eq!(world.differences(&agent), ["seed: world 7, agent 8"]);
        agent.scenario = ScenarioId::of(&Text("open", "[area] open"));
        agent.params.retries = 2;
        agent.algorithm = "sequential".into();
        agent.key = "lab\u{1b}[2J".into();
        let d = world.differences(&agent).join("; ");
        for want in [
            "run key: world `lab2`, agent `lab\\u{1b}[2J`",
            "scenario: world `paper` (sha3 ",
            "agent `open` (sha3 ",
            "seed: world 7, agent 8",
            "algorithm: world repulsive, agent sequential",
            "params.retries: world 0, agent 2",
        ] {
            assert!(d.contains(want), "{want} in {d}");
        }
        agent.protocol = PROTOCOL_VERSION + 1;
        let want = format!("protocol version: world {PROTOCOL_VERSION}, agent {}", PROTOCOL_VERSION + 1);
        assert_eq!(world.differences(&agent), [want]);
    }

    /// An edited setup presents what it will run: each edit of issue 36's
    /// reproducer (and of the frame) is a difference the world names.
    #[test]
    fn the_agreement_is_what_the_setup_runs() {
        let world = paper(7);
        let mut other = Agreement::of("lab2", world.scenario.clone(), &RobotSetup { id: 0, ..setup(7) });
        assert!(world.differences(&other).is_empty(), "the robot number is the hello's, not the agreement's");
        let edits: [(&str, fn(&mut RobotSetup)); 8] = [
            ("seed: world 7, agent 8", |s| s.seed = 8),
            ("algorithm: world repulsive, agent sequential", |s| s.policy = Policy::Sequential),
            ("params.t_wait: world ", |s| s.params.t_wait += 1.0),
            ("team: world 9, agent 5", |s| s.team = 5),
            ("params.r_c: world ", |s| s.params.r_c = 30.0),
            ("situation: world 2, agent 1", |s| s.situation = Situation::One),
            ("lattice: world triangular, agent square", |s| s.lattice = LatticeKind::Square),
            ("grid frame: world [0.0, 0.0] to [40.0, 30.0], agent [0.0, 0.0] to [41.0, 30.0]", |s| s.hi[0] = 41.0),
        ];
        for (want, edit) in edits {
            let mut s = setup(7);
            edit(&mut s);
            other = Agreement::of("lab2", world.scenario.clone(), &s);
            let d = world.differences(&other);
            assert_eq!(d.len(), 1, "{want}: {d:?}");
            assert!(d[0].starts_with(want), "{want} in {d:?}");
        }
    }

    #[test]
    fn ranges_read_as_words() {
        assert_eq!(robot_range(13), "0 to 12");
        assert_eq!(robot_range(1), "only 0");
    }
}
