//! The failure and radio flags of `simulate` and `run` (`--kill`,
//! `--freeze`, `--kill-random`, `--slow`, `--loss`, `--retries`, `--delay`,
//! `--dup`), and the run's other settings beyond its identity (`--slot`,
//! `--order`, `--starts`), defined once, and their one conversion into what an engine
//! runs with: the faults and radio of a [`RunConfig`] (in-process) or a
//! [`RunOptions`] (distributed). Times and shapes are parsed by
//! [`gridswarm::sim::schedule`]; what needs the run (robot ids, one failure
//! per robot, enough robots for `--kill-random`) is checked here, as a
//! usage error.

use gridswarm::outcome::RunConfig;
use gridswarm::params::{Order, Params, Situation, SlotRule};
use gridswarm::policy::Policy;
use gridswarm::scenario::StartRule;
use gridswarm::sim::{schedule, Fault, Radio, Time};

use crate::error::{Error, Result};
use crate::run::RunOptions;

/// A freeze and its thaw, as one `--freeze` gives them.
#[derive(Clone, Debug, PartialEq)]
pub struct Freeze(pub Vec<Fault>);

fn parse_freeze(s: &str) -> std::result::Result<Freeze, String> {
    schedule::parse_freeze(s).map(Freeze)
}

/// A probability: a number from 0 to 1.
pub fn parse_probability(s: &str) -> std::result::Result<f64, String> {
    let p: f64 = s.trim().parse().map_err(|_| format!("`{s}` is not a number"))?;
    if !(0.0..=1.0).contains(&p) {
        return Err(format!("`{s}` is not a probability (0 to 1)"));
    }
    Ok(p)
}

/// The flags, as clap reads them (`#[command(flatten)]`).
#[derive(clap::Args, Clone, Debug, Default, PartialEq)]
pub struct FaultFlags {
    /// Robot R crashes at T: ROUND, or ROUND+SECONDS into that round (repeatable).
    #[arg(long, value_name = "R@T", value_parser = schedule::parse_kill)]
    pub kill: Vec<Fault>,
    /// Robot R freezes at T, and thaws at T2 if given (repeatable).
    #[arg(long, value_name = "R@T[:T2]", value_parser = parse_freeze)]
    pub freeze: Vec<Freeze>,
    /// Crash K more distinct robots at random times inside rounds 1-20, drawn from the seed.
    #[arg(long, value_name = "K", default_value_t = 0)]
    pub kill_random: usize,
    /// From T on, robot R reacts MS milliseconds late (repeatable).
    #[arg(long, value_name = "R@T:MS", value_parser = schedule::parse_slow)]
    pub slow: Vec<Fault>,
    /// Probability that one transmission is lost on one link.
    #[arg(long, value_name = "P", default_value_t = 0.0, value_parser = parse_probability)]
    pub loss: f64,
    /// Extra copies of every frame [default: the scenario's params.retries].
    #[arg(long, value_name = "R", value_parser = clap::value_parser!(u32).range(0..=254))]
    pub retries: Option<u32>,
    /// Extra radio latency MS, plus a jitter drawn up to JITTER ms per delivery.
    #[arg(long, value_name = "MS[:JITTER]", value_parser = schedule::parse_delay)]
    pub delay: Option<(Time, Time)>,
    /// Probability that a delivery arrives twice.
    #[arg(long, value_name = "P", default_value_t = 0.0, value_parser = parse_probability)]
    pub dup: f64,
    /// What ends a slot: `adaptive` (the world, once every robot has
    /// commanded) or `fixed` (the robots' clocks) [default: the scenario's params.slot].
    #[arg(long, value_name = "RULE")]
    pub slot: Option<SlotRule>,
    /// Step 4's order, who waits for whose choice: `paper` (by position,
    /// chains grow with the team) or `local` (by vertex class, at most 7
    /// choices in a row; not the paper's) [default: the scenario's params.order].
    #[arg(long, value_name = "ORDER")]
    pub order: Option<Order>,
    /// Where the robots start: `fixed` (the scenario's [starts], as in Fig. 5) or `random`
    /// (distinct vertices drawn from the seed, on the border when the scenario starts there).
    #[arg(long, value_name = "RULE", default_value_t = StartRule::Fixed)]
    pub starts: StartRule,
}

/// What the flags ask for, independent of clap.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FaultPlan {
    /// Faults given explicitly, in the order given (a thaw after its freeze).
    pub faults: Vec<Fault>,
    /// Crash this many more robots at times drawn from the seed.
    pub kill_random: usize,
    pub radio: Radio,
    /// Overrides the scenario's `params.retries`.
    pub retries: Option<u32>,
    /// Overrides the scenario's `params.slot`.
    pub slot: Option<SlotRule>,
    /// Overrides the scenario's `params.order`.
    pub order: Option<Order>,
    /// Where the robots start; it applies to every algorithm, so
    /// [`FaultPlan::is_empty`] leaves it out.
    pub starts: StartRule,
}

impl FaultFlags {
    pub fn plan(&self) -> FaultPlan {
        let (delay, jitter) = self.delay.unwrap_or((0, 0));
        let mut faults = self.kill.clone();
        faults.extend(self.freeze.iter().flat_map(|f| f.0.iter().copied()));
        faults.extend(self.slow.iter().copied());
        FaultPlan {
            faults,
            kill_random: self.kill_random,
            radio: Radio { loss: self.loss, delay, jitter, dup: self.dup },
            retries: self.retries,
            slot: self.slot,
            order: self.order,
            starts: self.starts,
        }
    }
}

impl FaultPlan {
    /// Whether any fault or radio setting was asked for.
    pub fn is_empty(&self) -> bool {
        self.faults.is_empty()
            && self.kill_random == 0
            && self.radio.is_perfect()
            && self.retries.is_none()
            && self.slot.is_none()
            && self.order.is_none()
    }

    /// Checks the plan against a run of `policy` with `robots` robots.
    pub fn check(&self, policy: Policy, robots: usize) -> Result<()> {
        if !policy.on_grid() && !self.is_empty() {
            return Err(Error::Usage(format!(
                "`{policy}` moves off the grid without the radio protocol: \
                 --kill, --freeze, --kill-random, --slow, --loss, --retries, --delay, --dup, --slot and --order apply to grid policies only"
            )));
        }
        for (name, p) in [("--loss", self.radio.loss), ("--dup", self.radio.dup)] {
            if !(0.0..=1.0).contains(&p) {
                return Err(Error::Usage(format!("{name} {p}: a probability is between 0 and 1")));
            }
        }
        schedule::check(&self.faults, robots).map_err(Error::Usage)?;
        let taken = self.failing();
        let free = robots - taken.len().min(robots);
        if self.kill_random > free {
            return Err(Error::Usage(format!(
                "--kill-random {}: only {free} of the {robots} robots are left to kill",
                self.kill_random
            )));
        }
        Ok(())
    }

    /// Robots any explicit fault names (a slow one too): `--kill-random`
    /// draws among the others, in both engines.
    fn failing(&self) -> Vec<usize> {
        let mut v: Vec<usize> = self.faults.iter().map(|f| f.robot).collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// The retries override, applied to the scenario's parameters before its world is built.
    pub fn apply_params(&self, params: &mut Params) {
        if let Some(r) = self.retries {
            params.retries = r;
        }
        if let Some(s) = self.slot {
            params.slot = s;
        }
        if let Some(o) = self.order {
            params.order = o;
        }
    }

    /// Every fault of the run: the explicit ones, then the random kills
    /// drawn from `seed` exactly as `run --kill-random` draws them.
    pub fn schedule(&self, seed: u64, robots: usize) -> Result<Vec<Fault>> {
        let mut faults = self.faults.clone();
        let drawn = schedule::kill_random(seed, robots, self.kill_random, &self.failing()).map_err(Error::Usage)?;
        faults.extend(drawn);
        Ok(faults)
    }

    /// Sets the faults and the radio of an in-process run (checked first).
    pub fn configure(&self, cfg: &mut RunConfig, robots: usize) -> Result<()> {
        self.check(cfg.policy, robots)?;
        cfg.faults = self.schedule(cfg.seed, robots)?;
        cfg.radio = self.radio;
        Ok(())
    }

    /// Checks the plan for `run` (the robot count is the scenario's unless given).
    pub fn check_scenario(&self, base: &RunBase) -> Result<()> {
        let robots = match base.robots {
            Some(n) => n,
            None => crate::contract::load_scenario(&base.scenario)?.robots,
        };
        self.check(base.algorithm, robots)
    }

    /// The options of a distributed run with these faults.
    pub fn run_options(&self, base: RunBase) -> RunOptions {
        RunOptions {
            scenario: base.scenario,
            algorithm: base.algorithm,
            robots: base.robots,
            seed: base.seed,
            situation: base.situation,
            max_rounds: base.max_rounds,
            radio: self.radio,
            retries: self.retries,
            slot: self.slot,
            order: self.order,
            faults: self.faults.clone(),
            kill_random: self.kill_random,
            out: base.out,
            json: base.json,
            starts: self.starts,
            net: Default::default(),
            view: Default::default(),
        }
    }
}

/// What a run is besides its faults, for [`FaultPlan::run_options`].
#[derive(Clone, Debug)]
pub struct RunBase {
    pub scenario: String,
    pub algorithm: Policy,
    pub robots: Option<usize>,
    pub seed: u64,
    pub situation: Option<Situation>,
    pub max_rounds: u32,
    pub out: Option<std::path::PathBuf>,
    pub json: bool,
}

#[cfg(test)]
mod tests {
    use super::*;
    use gridswarm::sim::FaultKind;

    fn flags(kill: &[&str], freeze: &[&str]) -> FaultFlags {
        FaultFlags {
            kill: kill.iter().map(|s| schedule::parse_kill(s).unwrap()).collect(),
            freeze: freeze.iter().map(|s| parse_freeze(s).unwrap()).collect(),
            ..FaultFlags::default()
        }
    }

    #[test]
    fn probabilities() {
        assert_eq!(parse_probability("0.25"), Ok(0.25));
        assert!(parse_probability("1.5").is_err() && parse_probability("-0.1").is_err());
        assert!(parse_probability("NaN").is_err() && parse_probability("x").is_err());
    }

    #[test]
    fn plan_checks_robots_and_failures() {
        let p = flags(&["1@3+0.2"], &["2@4:6"]).plan();
        assert_eq!(p.faults.len(), 3);
        assert!(p.check(Policy::Repulsive, 3).is_ok());
        assert!(matches!(p.check(Policy::Repulsive, 2), Err(Error::Usage(_))));
        assert!(matches!(p.check(Policy::Lfp, 3), Err(Error::Usage(_))));
        assert!(FaultPlan::default().check(Policy::Lfp, 3).is_ok());
        let twice = flags(&["1@3"], &["1@4"]).plan();
        assert!(twice.check(Policy::Repulsive, 5).is_err());
        let mut random = flags(&["0@1"], &[]).plan();
        random.kill_random = 3;
        assert!(random.check(Policy::Repulsive, 3).is_err());
        random.kill_random = 2;
        assert!(random.check(Policy::Repulsive, 3).is_ok());
        let all = random.schedule(7, 3).unwrap();
        assert_eq!(all.iter().filter(|f| f.kind == FaultKind::Crash).count(), 3);
    }

    #[test]
    fn configure_sets_radio_and_faults() {
        let mut f = flags(&["0@2"], &[]);
        f.loss = 0.1;
        f.delay = Some((5000, 1000));
        let mut cfg = RunConfig::new(Policy::Repulsive, 1, Situation::One);
        f.plan().configure(&mut cfg, 4).unwrap();
        assert_eq!(cfg.faults.len(), 1);
        assert_eq!(cfg.radio, Radio { loss: 0.1, delay: 5000, jitter: 1000, dup: 0.0 });
    }
}
