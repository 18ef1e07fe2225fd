//! What robots note for the reports ([`Note`]): declarations, time-outs,
//! rejoins, stops, stale and malformed frames. The kernel counts them and
//! ties them to the failure in force; it never acts on them.

use super::{Body, Kernel};
use crate::map::RobotId;
use crate::sim::{seconds, Framed, Note};

impl<'w, P: Clone + Framed> Kernel<'w, P> {
    pub(super) fn note(&mut self, r: usize, note: Note) {
        let st = &mut self.stats;
        match note {
            Note::Declared { robot } => {
                st.declarations += 1;
                let j = robot as usize;
                if self.bots.get(j).is_some_and(|b| b.body == Body::Running) {
                    self.stats.false_suspicions += 1;
                }
                if let Some(i) = self.record_of(j) {
                    let (round, now) = (self.round, seconds(self.now));
                    let rec = &mut self.stats.failures[i];
                    if rec.detected_round.is_none() {
                        rec.detected_round = Some(round);
                        rec.detected_s = Some(now);
                    }
                    if !rec.declared_by.contains(&(r as RobotId)) {
                        rec.declared_by.push(r as RobotId);
                    }
                }
            }
            Note::Rejoined { .. } => st.rejoins += 1,
            Note::TimedOut { robot } => {
                st.timeouts += 1;
                if let Some(i) = self.record_of(robot as usize) {
                    self.waiters.push((i, r as RobotId, self.round));
                }
            }
            // Counted at the round's end, once a robot-round.
            Note::Unsure => self.bots[r].unsure = true,
            // For the record only: the search ends when the controller
            // hears the stop (`Kernel::to_controller`), not on this note.
            Note::Stopped { ends_search, relayed, exhausted } => {
                if ends_search && !relayed && st.stop_round.is_none() {
                    st.stop_round = Some(self.round);
                    st.stop_s = Some(seconds(self.now));
                    self.stop_exhausted = exhausted;
                }
            }
            Note::Stale => st.stale += 1,
            Note::Malformed => st.malformed += 1,
        }
    }
}
