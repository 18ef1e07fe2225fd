//! Where a robot stood, round by round, as it sensed it: its own trail,
//! which no other robot holds. A body others found where it stood silent
//! (frozen, or unheard) was itself; only it can tell, and only from this.

use crate::grid::VertexId;

/// Stays, oldest first: a vertex and the first round the robot stood on it.
/// A stay lasts until the next one's first round, the last one until the
/// latest round sensed.
#[derive(Clone, Debug, Default)]
pub struct Trail {
    stays: Vec<(VertexId, u32)>,
    last: u32,
}

impl Trail {
    /// The robot sensed round `round` on `at`. Rounds skipped (it was
    /// frozen) went to where it stands now: a frozen robot does not move,
    /// and the one move it may have commanded before it froze ended in the
    /// round it froze in, so it has stood on `at` since the round after
    /// the last it sensed.
    pub fn record(&mut self, round: u32, at: VertexId) {
        match self.stays.last() {
            Some(&(v, _)) if v == at => {}
            Some(_) => self.stays.push((at, self.last + 1)),
            None => self.stays.push((at, round)),
        }
        self.last = round;
    }

    /// If the robot stood on `v` in round `t`, the last round of that stay.
    pub fn stood(&self, v: VertexId, t: u32) -> Option<u32> {
        let k = self.stays.partition_point(|s| s.1 <= t).checked_sub(1)?;
        if self.stays[k].0 != v || t > self.last {
            return None;
        }
        Some(self.stays.get(k + 1).map_or(self.last, |s| s.1 - 1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stay_covers_the_rounds_until_the_next_and_frozen_rounds_go_to_where_it_woke() {
        let mut t = Trail::default();
        t.record(3, 10);
        t.record(4, 10);
        t.record(5, 11);
        // Frozen in rounds 6-8 (its move of round 5 done), woken on 12.
        t.record(9, 12);
        assert_eq!(t.stood(10, 2), None, "before its first round");
        assert_eq!(t.stood(10, 3), Some(4));
        assert_eq!(t.stood(10, 4), Some(4));
        assert_eq!(t.stood(10, 5), None);
        assert_eq!(t.stood(11, 5), Some(5));
        assert_eq!(t.stood(12, 6), Some(9));
        assert_eq!(t.stood(12, 9), Some(9));
        assert_eq!(t.stood(12, 10), None, "not sensed yet");
        t.record(10, 12);
        assert_eq!(t.stood(12, 10), Some(10));
    }
}
