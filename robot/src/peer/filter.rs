//! A robot's receive filter while it chooses: which frames may wait in its
//! radio's buffer until its next wake-up, because reading them on arrival
//! would not have changed anything it did.

use super::Peer;
use crate::io::Listen;
use crate::protocol::{KIND_ACK, KIND_COMMIT, KIND_WAIT};
use crate::robot::Robot;

impl Peer<'_> {
    /// Which frames should wake it while it chooses and waits for answers.
    ///
    /// Held, of this round: acks, unless addressed to it after it chose
    /// (an ack changes nothing but whether the sender acked or refused
    /// this robot, which it reads only once it chose); commits, unless,
    /// after it chose, from a robot it heard on the vertex it chose, or
    /// from one after it in step 4's order (whose staying it waits for in
    /// a conflict, `Peer::acks`): the only commits it reads; waits (what it reads of one is its arrival time, and only at its
    /// deadline).
    /// Reading a held frame later, before the frames that came after it,
    /// leaves it as reading it on arrival would have: the radio hands them
    /// over, in order, with whatever wakes it next. And a wake-up with
    /// nothing new to read could not have made it act either: its choice
    /// depends on maps and choices only, and every time it compares `now`
    /// with is one of its alarms. Maps, choices and frames of another
    /// round, and floods, always wake it.
    pub(super) fn filter(&self) -> Listen {
        let (mut except, mut tags) = ([0; 8], [0; 8]);
        if let Some(c) = self.robot.as_ref().and_then(Robot::choice) {
            tags[KIND_ACK as usize] = Listen::bit(self.id());
            let robot = self.robot.as_ref().expect("chose");
            for h in self.heard.iter().filter(|h| !h.halted && (h.at == c || robot.precedes(h.id))) {
                except[KIND_COMMIT as usize] |= Listen::bit(h.id);
            }
        }
        // Floods always wake it: their targets are positions, and a header
        // cannot say whether they are ones it knows. They are rare.
        let hold = 1 << KIND_ACK | 1 << KIND_COMMIT | 1 << KIND_WAIT;
        Listen { on: true, round: self.round, hold, except, tags }
    }
}
