//! Where robots were last heard, once failures are known: what a robot
//! needs to tell a silent body that no robot of the team can be any more
//! (one that thawed, or was heard again, and moved on) from one that
//! may still wall off what lies behind it (`Robot::phantoms`).
//!
//! A robot that knows of a failure writes its own sighting every slot; a
//! robot that does not (it has never heard of one) is written down by
//! those who hear it. Merged by latest round, like rejoins, so the order in
//! which maps arrive never changes what a robot knows. A failure-free run
//! never writes one: its maps and decisions are what they were.

use serde::{Deserialize, Serialize};

use crate::grid::VertexId;
use crate::map::thin::Thin;
use crate::map::RobotId;

/// Robot `robot` stood on `at` in `round`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Sighting {
    pub robot: RobotId,
    pub at: VertexId,
    pub round: u32,
}

impl Sighting {
    /// Of two sightings of one robot the later wins; on a tie (which one
    /// robot standing on one vertex a round never makes) the lower vertex,
    /// so merging stays independent of order.
    fn rank(&self) -> (u32, std::cmp::Reverse<VertexId>) {
        (self.round, std::cmp::Reverse(self.at))
    }
}

/// The latest sighting of each robot, sorted by robot.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Sightings(Thin<Sighting>);

impl Sightings {
    pub fn add(&mut self, s: Sighting) {
        match self.0.binary_search_by_key(&s.robot, |t| t.robot) {
            Ok(k) if s.rank() > self.0[k].rank() => self.0.vec_mut()[k] = s,
            Ok(_) => {}
            Err(k) => self.0.vec_mut().insert(k, s),
        }
    }

    pub fn merge(&mut self, other: &Sightings) {
        for &s in other.0.iter() {
            self.add(s);
        }
    }

    pub fn of(&self, robot: RobotId) -> Option<Sighting> {
        self.0.binary_search_by_key(&robot, |t| t.robot).ok().map(|k| self.0[k])
    }

    pub fn iter(&self) -> impl Iterator<Item = &Sighting> {
        self.0.iter()
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn clone_from_sightings(&mut self, source: &Sightings) {
        self.0.clone_from(&source.0);
    }

    /// Checks a list that came from elsewhere: sorted by robot, naming
    /// robots and vertices that exist.
    pub fn validate(&self, vertices: usize, robots: usize) -> Result<(), String> {
        if self.0.windows(2).any(|w| w[0].robot >= w[1].robot) {
            return Err("map sighting list not sorted by robot".into());
        }
        if self.0.iter().any(|s| s.robot as usize >= robots || s.at as usize >= vertices) {
            return Err("map sighting names a robot or vertex that does not exist".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seen(robot: RobotId, at: VertexId, round: u32) -> Sighting {
        Sighting { robot, at, round }
    }

    #[test]
    fn the_latest_sighting_wins_whatever_the_order() {
        let mut a = Sightings::default();
        a.add(seen(3, 10, 5));
        a.add(seen(1, 7, 2));
        a.add(seen(3, 11, 4));
        assert_eq!(a.of(3), Some(seen(3, 10, 5)), "an older sighting changes nothing");
        let mut b = Sightings::default();
        b.add(seen(3, 12, 5));
        b.add(seen(1, 8, 1));
        let mut ab = a.clone();
        ab.merge(&b);
        let mut ba = b.clone();
        ba.merge(&a);
        assert_eq!(ab, ba, "merging is independent of order");
        assert_eq!(ab.of(3), Some(seen(3, 10, 5)), "on a tie, the lower vertex");
        assert_eq!(ab.of(1), Some(seen(1, 7, 2)));
        assert_eq!(ab.validate(20, 4), Ok(()));
        assert!(ab.validate(20, 3).is_err(), "robot 3 of 3");
        assert!(ab.validate(10, 4).is_err(), "vertex 10 of 10");
    }
}
