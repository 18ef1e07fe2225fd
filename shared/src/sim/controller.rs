//! The human controller's base station (step 8), a node of the radio
//! medium at [`super::CONTROLLER`]: it hears the whole area, each frame on
//! its own link with the run's loss, delay and jitter. It reads of a frame
//! only whether it carries the stop (which ends the search's record) and,
//! under [`Broadcast::Controller`], a flood's targets and stop: a flood
//! that tells it something new it relays, as it was sent, to every robot
//! over its long-range link. So step 8's "to all robots and the human
//! controller" reaches every robot whoever is in radio range, as LFP's
//! "broadcast to all" does. It decides nothing for a robot: a robot learns
//! a target from the flood, as from any other.

use std::collections::HashSet;

use crate::params::Broadcast;
use crate::spot::Spot;

/// What the controller has heard, and its own transmissions' count.
#[derive(Debug, Default)]
pub struct Controller {
    relays: bool,
    targets: HashSet<Spot>,
    stop: bool,
    seq: u64,
}

impl Controller {
    pub fn new(broadcast: Broadcast) -> Self {
        Controller { relays: broadcast == Broadcast::Controller, ..Controller::default() }
    }

    /// Whether it relays floods at all.
    pub fn relays(&self) -> bool {
        self.relays
    }

    /// Takes in a flood heard; whether it told something new (a target, or
    /// the stop), and so is to be relayed.
    pub fn news(&mut self, targets: &[Spot], stop: bool) -> bool {
        let mut new = stop && !self.stop;
        self.stop |= stop;
        for &t in targets {
            new |= self.targets.insert(t);
        }
        new
    }

    /// The number of its next transmission (the medium's draws are keyed by it).
    pub fn next_seq(&mut self) -> u64 {
        self.seq += 1;
        self.seq - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_news_is_relayed() {
        let mut c = Controller::new(Broadcast::Controller);
        let (a, b) = (Spot { x: 1, y: 2 }, Spot { x: 3, y: 4 });
        assert!(c.relays());
        assert!(c.news(&[a], false));
        assert!(!c.news(&[a], false), "a target heard again is no news");
        assert!(c.news(&[a, b], false), "one new target among old ones is");
        assert!(!c.news(&[], false));
        assert!(c.news(&[], true));
        assert!(!c.news(&[b], true), "the stop is news once");
        assert_eq!((c.next_seq(), c.next_seq()), (0, 1));
        assert!(!Controller::new(Broadcast::Flood).relays());
    }
}
