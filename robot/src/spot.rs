//! What the laser reports (step 1): a target at a position, with no name.
//! A real laser sees a thing at a range and bearing, not a label the world
//! gave it, so robots tell targets apart by where they are: two readings of
//! the same target, by any robots, fall on the same [`Spot`], and the
//! robots' sets of found targets are sets of spots.

use serde::{Deserialize, Serialize};

use crate::geometry::Point;

/// Positions are read in steps of `a / STEPS` along each axis of the frame
/// robots share: fine enough that two targets the scenario keeps apart
/// (more than `a / 64`, `scenario` checks it) never share a spot.
pub const STEPS: f64 = 1024.0;

/// A target's position in the shared frame, in steps of `a / STEPS`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Spot {
    pub x: i32,
    pub y: i32,
}

impl Spot {
    /// The spot of a target sensed at `p`, with edge length `a`.
    pub fn at(p: Point, a: f64) -> Spot {
        let step = |v: f64| (v * STEPS / a).round().clamp(i32::MIN as f64, i32::MAX as f64) as i32;
        Spot { x: step(p.x), y: step(p.y) }
    }
}

/// The bytes postcard writes for `spots`: its length, then each
/// coordinate as a zigzag varint. Summed by hand, as every frame a robot
/// sends is counted.
pub fn wire_len(spots: &[Spot]) -> usize {
    crate::protocol::varint_len(spots.len() as u64) + spots.iter().map(|&s| coords_len(s)).sum::<usize>()
}

/// The bytes of a spot's two coordinates, zigzag varints.
fn coords_len(s: Spot) -> usize {
    let zigzag = |c: i32| crate::protocol::varint_len(((c << 1) ^ (c >> 31)) as u32 as u64);
    zigzag(s.x) + zigzag(s.y)
}

/// Targets known found, as a sorted set of spots. It grows as targets are
/// learnt: in situation 2 a robot does not know how many there are. On the
/// wire, a sequence of spots.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Spots(Vec<Spot>, Coords);

/// The bytes of a set's coordinates on the wire, kept as the set changes:
/// a robot's map counts them at every send ([`Spots::wire_len`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Coords(usize);

impl Serialize for Spots {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(s)
    }
}

impl<'de> Deserialize<'de> for Spots {
    /// As sent, sorted or not ([`Spots::is_canonical`] tells).
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let spots = Vec::<Spot>::deserialize(d)?;
        let coords = Coords(spots.iter().map(|&s| coords_len(s)).sum());
        Ok(Spots(spots, coords))
    }
}

impl Spots {
    pub fn count(&self) -> usize {
        self.0.len()
    }

    /// The bytes postcard writes for this set ([`wire_len`]).
    pub fn wire_len(&self) -> usize {
        crate::protocol::varint_len(self.0.len() as u64) + self.1 .0
    }

    pub fn contains(&self, s: Spot) -> bool {
        self.0.binary_search(&s).is_ok()
    }

    /// Adds `s`; whether it was new. The search inline, as it was before
    /// the set kept its length (merges mostly find what they bring).
    #[inline]
    pub fn insert(&mut self, s: Spot) -> bool {
        match self.0.binary_search(&s) {
            Ok(_) => false,
            Err(k) => {
                self.insert_at(k, s);
                true
            }
        }
    }

    #[inline(never)]
    fn insert_at(&mut self, k: usize, s: Spot) {
        self.0.insert(k, s);
        self.1 .0 += coords_len(s);
    }

    /// `self ∪= other`. Most merges bring nothing new (targets are few and
    /// found rarely), so an equal or empty set costs one comparison.
    pub fn union(&mut self, other: &Spots) {
        if other.0.is_empty() || other.0 == self.0 {
            return;
        }
        for &s in &other.0 {
            self.insert(s);
        }
    }

    pub fn iter(&self) -> impl Iterator<Item = Spot> + '_ {
        self.0.iter().copied()
    }

    /// Sorted and without repeats, as every set a robot builds is: a frame
    /// that says otherwise was not written by a robot.
    pub fn is_canonical(&self) -> bool {
        self.0.windows(2).all(|w| w[0] < w[1])
    }

    pub fn clone_from_spots(&mut self, other: &Spots) {
        self.0.clone_from(&other.0);
        self.1 = other.1;
    }
}

impl FromIterator<Spot> for Spots {
    fn from_iter<I: IntoIterator<Item = Spot>>(it: I) -> Self {
        let mut s = Spots::default();
        it.into_iter().for_each(|p| {
            s.insert(p);
        });
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_target_read_by_two_robots_is_one_spot() {
        let p = Point::new(10.123_456, -3.5);
        // The same point, as two robots' float arithmetic may give it.
        let q = Point::new(10.123_456 + 1e-12, -3.5 - 1e-12);
        assert_eq!(Spot::at(p, 2.0), Spot::at(q, 2.0));
        assert_eq!(Spot::at(Point::new(2.0, 0.0), 2.0), Spot { x: 1024, y: 0 });
        assert_ne!(Spot::at(p, 2.0), Spot::at(p + crate::geometry::Vector::new(2.0 / 64.0, 0.0), 2.0));
    }

    #[test]
    fn a_set_of_spots_is_a_set() {
        let s = |x| Spot { x, y: 0 };
        let mut a: Spots = [s(3), s(1), s(3)].into_iter().collect();
        assert_eq!(a.count(), 2);
        assert!(a.is_canonical());
        assert!(!a.insert(s(1)));
        let b: Spots = [s(2), s(1)].into_iter().collect();
        a.union(&b);
        assert_eq!(a.iter().map(|p| p.x).collect::<Vec<_>>(), [1, 2, 3]);
        assert!(a.contains(s(2)) && !a.contains(s(4)));
        assert!(!Spots(vec![s(2), s(1)], Coords(0)).is_canonical());
        assert!(!Spots(vec![s(1), s(1)], Coords(0)).is_canonical());
    }
}
