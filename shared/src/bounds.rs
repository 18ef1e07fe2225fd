//! The bounds the design states (ARCHITECTURE.md, "Bounds"), as numbers
//! from the robots' own timing ([`Timing`]) and predicates on a run's
//! radio and faults. (Not to be confused with [`crate::bound`], a lower
//! bound on search time.) Inside every bound the robots promise to keep
//! searching; past one they may stand still for good, and the world's
//! record of such a run ends `past_bound` ([`STALL_ROUNDS`]) instead of
//! running on silently to its round limit. The world decides nothing for
//! the robots with these: it knows the faults it injected, as it knows its
//! round limit.

use crate::outcome::RunConfig;
use crate::params::{Params, SlotRule};
use crate::peer::{Timing, MAX_WIDEN};
use crate::sim::{FaultKind, Radio, Time};

/// Slots in a row, past a bound, in which robots searched and none moved,
/// after which the world ends the run's record `past_bound`: five times the
/// longest robots stand still on purpose and then go on (`TOO_SLOW_SLOTS`,
/// 10 slots after a map later than the widest window), so that a run past a
/// bound that still moves now and then is not ended.
pub const STALL_ROUNDS: u32 = 50;

/// Slots in a row, past a bound, in which robots searched and no vertex
/// was visited for the first time, after which the world ends the run's
/// record `past_bound`: robots that move for ever between vertices they
/// know (a slow robot past half a `t_wait` standing beside `frontier-sensed`
/// robots, issue 37). A fifth of the simulation test's round limit: a
/// rule's own walk over visited vertices may take a few hundred rounds
/// between first visits (docs/paper.md), so a run past a bound that
/// still finds new ground now and then is not ended.
pub const AIMLESS_ROUNDS: u32 = 400;

/// The stated bounds of one world's parameters.
#[derive(Clone, Copy, Debug)]
pub struct Bounds {
    timing: Timing,
    slot: SlotRule,
}

impl Bounds {
    pub fn of(params: &Params) -> Self {
        Bounds { timing: Timing::from_params(params), slot: params.slot }
    }

    /// The most delay plus jitter (µs) whose maps a robot still takes in
    /// its widest window: a frame arrives a hop after it is sent plus the
    /// delay, and a robot widens its window to a measured latency plus a
    /// hop (`Peer::widen_for`).
    pub fn latency(&self) -> Time {
        self.timing.widest().saturating_sub(2 * self.timing.hop)
    }

    /// The most jitter (µs) a robot's wait for its choice covers
    /// (`Peer::listen_until`): the choice time.
    pub fn jitter(&self) -> Time {
        self.timing.choice
    }

    /// The most one robot may be slow (µs) under this slot rule, on
    /// `radio`. A late robot reacts twice in a slot, to sense and to decide
    /// after listening one window of its own. Under the fixed rule both
    /// and the choice fit the slot's decisions; under the adaptive rule the
    /// world's slot limit leaves room for two reactions of `4 t_wait`.
    pub fn slow(&self, radio: &Radio) -> Time {
        let t = &self.timing;
        match (self.slot, t.decision) {
            (SlotRule::Fixed, Some(d)) => {
                let widen = (radio.delay + radio.jitter + 2 * t.hop).saturating_sub(t.exchange);
                let window = t.exchange + widen.min(MAX_WIDEN * t.exchange);
                d.saturating_sub(window + t.choice) / 2
            }
            _ => 4 * t.wait,
        }
    }

    /// The most one robot may be slow (µs) while other robots run: half a
    /// `t_wait`, within which it senses early enough to choose with them
    /// (`Peer::sits_out`); later, it sits out every slot it is behind a
    /// searching robot, and never moves while one is within its range.
    /// Never more than [`Bounds::slow`].
    pub fn slow_among(&self, radio: &Radio) -> Time {
        self.slow(radio).min(self.timing.wait / 2)
    }

    /// The most several robots may be slow at once (µs): as much as the
    /// radio may be late ([`Bounds::latency`]), since to each other they
    /// are a radio that late.
    pub fn slow_together(&self) -> Time {
        self.latency()
    }

    /// Whether the safety claim covers `cfg` (ARCHITECTURE.md, "Safety"):
    /// no loss, every map within the widest window, jitter within the
    /// choice time, robots that avoid each other (RU's are particles).
    pub fn safe(&self, cfg: &RunConfig) -> bool {
        let r = &cfg.radio;
        r.loss == 0.0
            && r.delay + r.jitter <= self.latency()
            && r.jitter <= self.jitter()
            && cfg.policy.collision_free()
    }

    /// The first liveness bound the run is past, given its `radio`, the
    /// slowness of each running robot (`(robot, µs)`) and how many robots
    /// run, as a sentence naming the bound and the robots; `None` inside
    /// every bound.
    pub fn past(&self, radio: &Radio, slow: &[(usize, Time)], running: usize) -> Option<String> {
        let ms = |t: Time| t as f64 / 1000.0;
        let s = |t: Time| t as f64 / 1e6;
        let late = radio.delay + radio.jitter;
        if late > self.latency() {
            return Some(format!(
                "radio delay plus jitter {} ms, past the bound of {} ms (the widest window less two hops)",
                ms(late),
                ms(self.latency())
            ));
        }
        let together: Vec<(usize, Time)> = slow.iter().copied().filter(|&(_, t)| t > self.slow_together()).collect();
        if together.len() > 1 {
            let names: Vec<String> = together.iter().map(|(k, _)| k.to_string()).collect();
            let least = together.iter().map(|&(_, t)| t).min().unwrap_or(0);
            return Some(format!(
                "robots {} slow by {} s or more at once, past the bound of {} s for more than one slow robot",
                names.join(", "),
                s(least),
                s(self.slow_together())
            ));
        }
        let rule = if self.slot == SlotRule::Fixed { "fixed" } else { "adaptive" };
        let (bound, of) = match running {
            0 | 1 => (self.slow(radio), format!("the {rule} slot's bound")),
            _ => (self.slow_among(radio), "the bound for a slow robot among running ones".to_string()),
        };
        if let Some(&(k, t)) = slow.iter().find(|&&(_, t)| t > bound) {
            return Some(format!("robot {k} slow by {} s, past {of} of {} s", s(t), s(bound)));
        }
        None
    }

    /// [`Bounds::past`] at round `round` of `cfg` with `robots` robots,
    /// from its fault schedule: the faults of rounds up to `round` in
    /// force, crashed and frozen robots not counted.
    pub fn past_at(&self, cfg: &RunConfig, robots: usize, round: u32) -> Option<String> {
        let (slow, running) = slowness_at(cfg, robots, round);
        self.past(&cfg.radio, &slow, running)
    }

    /// Whether `cfg` is past a liveness bound at any round.
    pub fn past_ever(&self, cfg: &RunConfig, robots: usize) -> bool {
        let rounds = std::iter::once(0).chain(cfg.faults.iter().map(|f| f.round));
        rounds.into_iter().any(|r| self.past_at(cfg, robots, r).is_some())
    }
}

/// The running robots that are slow at round `round` of `cfg`'s fault
/// schedule, and by how much (µs); and how many robots run.
pub fn slowness_at(cfg: &RunConfig, robots: usize, round: u32) -> (Vec<(usize, Time)>, usize) {
    let mut faults: Vec<_> = cfg.faults.iter().filter(|f| f.round <= round && f.robot < robots).collect();
    faults.sort_by_key(|f| (f.round, f.offset));
    let mut slow = vec![0; robots];
    let mut running = vec![true; robots];
    for f in faults {
        match f.kind {
            FaultKind::Crash | FaultKind::Freeze => running[f.robot] = false,
            FaultKind::Thaw => running[f.robot] = true,
            FaultKind::Slow(t) => slow[f.robot] = t,
        }
    }
    let slowed = (0..robots).filter(|&k| running[k] && slow[k] > 0).map(|k| (k, slow[k])).collect();
    (slowed, running.iter().filter(|&&r| r).count())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bounds_of_the_default_timing() {
        let mut p = Params::default();
        let b = Bounds::of(&p);
        let radio = Radio::default();
        assert_eq!(b.latency(), 1_046_000);
        assert_eq!(b.jitter(), 100_000);
        assert_eq!(b.slow(&radio), 12_000_000);
        p.slot = SlotRule::Fixed;
        let f = Bounds::of(&p);
        // The decisions (7.154 s) less the window and the choice, halved.
        assert_eq!(f.slow(&radio), 3_502_000);
        // A radio 500 ms late widens the late robot's window by as much.
        let late = Radio { delay: 500_000, ..Radio::default() };
        assert_eq!(f.slow(&late), 3_502_000 - 227_000);
    }

    #[test]
    fn past_names_the_bound_and_the_robot() {
        let p = Params { slot: SlotRule::Fixed, ..Params::default() };
        let b = Bounds::of(&p);
        let radio = Radio::default();
        assert_eq!(b.past(&radio, &[(1, 3_502_000)], 1), None);
        let why = b.past(&radio, &[(0, 4_000_000)], 1).expect("past");
        assert_eq!(why, "robot 0 slow by 4 s, past the fixed slot's bound of 3.502 s");
        let late = Radio { delay: 1_047_000, ..Radio::default() };
        assert!(b.past(&late, &[], 3).expect("past").contains("1047 ms, past the bound of 1046 ms"));
        let a = Bounds::of(&Params::default());
        assert_eq!(a.past(&radio, &[(2, 1_046_000), (3, 1_046_000)], 5), None);
        assert_eq!(a.past(&radio, &[(2, 1_400_000)], 5), None);
        // Among running robots one may be late by half a t_wait, alone by the slot rule's bound.
        assert_eq!(a.slow_among(&radio), 1_500_000);
        let why = a.past(&radio, &[(2, 1_600_000)], 5).expect("past");
        assert_eq!(why, "robot 2 slow by 1.6 s, past the bound for a slow robot among running ones of 1.5 s");
        assert_eq!(a.past(&radio, &[(2, 1_600_000)], 1), None);
        let why = a.past(&radio, &[(2, 1_400_000), (3, 1_500_000)], 5).expect("past");
        assert!(why.starts_with("robots 2, 3 slow by 1.4 s or more at once"), "{why}");
    }
}
