//! Faults on robots' bodies (crash, freeze, thaw, slowness) at the
//! instants the run's plan gives, and the failure records they open.

use super::{Body, Ev, Kernel};
use crate::map::RobotId;
use crate::sim::stats::FailureRecord;
use crate::sim::{seconds, Fault, FaultKind, Framed};

impl<'w, P: Clone + Framed> Kernel<'w, P> {
    pub(super) fn apply_fault(&mut self, f: &Fault) {
        self.may_close = true;
        if self.trace {
            eprintln!("{:>10} r{} fault {f:?}", self.now, self.round);
        }
        let r = f.robot;
        if r >= self.bots.len() {
            return;
        }
        let now = self.now;
        let body = self.bots[r].body;
        match f.kind {
            FaultKind::Crash if body != Body::Dead => {
                let b = &mut self.bots[r];
                b.body = Body::Dead;
                b.pending.clear();
                self.open_record(r, "crash");
            }
            FaultKind::Freeze if body == Body::Running => {
                self.bots[r].body = Body::Frozen;
                self.open_record(r, "freeze");
            }
            FaultKind::Thaw if body == Body::Frozen => {
                self.bots[r].body = Body::Running;
                // Its sensors are read afresh: it must know the slot it is
                // in. Between slots, the next slot's start wakes it.
                if self.slot_open {
                    self.bots[r].tick_due = true;
                    self.mark(r);
                }
                if let Some(rec) =
                    self.stats.failures.iter_mut().rev().find(|x| x.robot as usize == r && x.kind == "freeze")
                {
                    rec.thawed_s.get_or_insert(seconds(now));
                }
            }
            FaultKind::Slow(s) => self.bots[r].slow = s,
            _ => {}
        }
    }

    pub(super) fn open_record(&mut self, r: usize, kind: &str) {
        // Between a slot's close and the next slot's start the robots are
        // still moving: that belongs to the slot that closed.
        let round = if self.slot_open { self.round } else { self.round.saturating_sub(1) };
        self.stats.failures.push(FailureRecord {
            robot: r as RobotId,
            kind: kind.to_string(),
            round,
            at_s: seconds(self.now),
            ..Default::default()
        });
    }

    /// The failure record of robot `j` that is in force now, if any.
    pub(super) fn record_of(&self, j: usize) -> Option<usize> {
        let b = self.bots.get(j)?;
        if b.body == Body::Running {
            return None;
        }
        self.stats.failures.iter().rposition(|x| x.robot as usize == j && x.thawed_s.is_none())
    }

    /// Whether a frozen robot is due to thaw later.
    pub(super) fn thaw_ahead(&self) -> bool {
        self.cfg.faults.iter().any(|f| {
            f.kind == FaultKind::Thaw
                && self.bots.get(f.robot).is_some_and(|b| b.body == Body::Frozen)
                && f.round >= self.round
        }) || self.queue.events().any(|e| matches!(e, Ev::Fault(i) if self.cfg.faults[*i].kind == FaultKind::Thaw))
    }
}
