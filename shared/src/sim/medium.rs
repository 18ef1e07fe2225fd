//! The radio medium: who hears whom, and what happens to each transmission
//! on each link. Range is physics (`r_c` between the bodies); loss, delay,
//! jitter (which reorders frames) and duplication are the run's radio
//! settings. Every draw is a hash of the seed and the transmission's
//! identity (sender, its transmission count, receiver, copy), never of the
//! order things happen in, so two engines draw the same fates.

use serde::{Deserialize, Serialize};

use super::Time;
use crate::geometry::Point;
use crate::near::Cells;
use crate::rng::mix;

/// Radio impairments of a run, per transmission and per link.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Radio {
    /// Probability that one transmission is lost on one link.
    pub loss: f64,
    /// Extra latency of every delivery.
    pub delay: Time,
    /// Extra latency drawn uniformly in `[0, jitter]` per delivery (reorders frames).
    pub jitter: Time,
    /// Probability that a delivery arrives twice (the copy after a further draw of jitter + latency).
    pub dup: f64,
}

impl Radio {
    pub fn is_perfect(&self) -> bool {
        self.loss == 0.0 && self.delay == 0 && self.jitter == 0 && self.dup == 0.0
    }
}

/// The fate of one frame on one link.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Fate {
    /// When it arrives, if any copy survives.
    pub arrival: Option<Time>,
    /// When a duplicate arrives too.
    pub duplicate: Option<Time>,
    /// Copies lost on the way.
    pub lost: u32,
}

/// Who is in range of whom in the current slot, and the fates of frames.
#[derive(Clone, Debug)]
pub struct Medium {
    seed: u64,
    radio: Radio,
    hop: Time,
    r_c2: f64,
    /// `links[k]`: robots within `r_c` of robot `k`, ascending.
    links: Vec<Vec<u32>>,
    cells: Cells,
}

/// A uniform number in `[0, 1)` from a hash.
fn unit(h: u64) -> f64 {
    (h >> 11) as f64 / (1u64 << 53) as f64
}

impl Medium {
    pub fn new(seed: u64, radio: Radio, hop: Time, r_c: f64, robots: usize) -> Self {
        Medium {
            seed: mix(seed ^ 0x7261_6469_6f00),
            radio,
            hop,
            r_c2: r_c * r_c,
            links: vec![Vec::new(); robots],
            cells: Cells::new(r_c),
        }
    }

    pub fn radio(&self) -> &Radio {
        &self.radio
    }

    /// Recomputes the links from the bodies' positions (once a slot: bodies
    /// move only between slots). Cells of side `r_c` keep it near linear.
    pub fn relink(&mut self, positions: &[Point]) {
        if positions.len() <= 64 {
            // Few robots: every pair, no sorting.
            for (k, l) in self.links.iter_mut().enumerate() {
                l.clear();
                let p = positions[k];
                for (j, q) in positions.iter().enumerate() {
                    if j != k && (q - p).norm_squared() <= self.r_c2 {
                        l.push(j as u32);
                    }
                }
            }
            return;
        }
        self.cells.fill(positions);
        for (k, &p) in positions.iter().enumerate() {
            let l = &mut self.links[k];
            l.clear();
            let r_c2 = self.r_c2;
            self.cells.around(p, |j| {
                if j as usize != k && (positions[j as usize] - p).norm_squared() <= r_c2 {
                    l.push(j);
                }
            });
            l.sort_unstable();
        }
    }

    /// Robots within radio range of `k` this slot.
    pub fn links(&self, k: usize) -> &[u32] {
        &self.links[k]
    }

    /// The fate of transmission number `seq` of `from` on the link to `to`:
    /// the first copy that survives arrives one hop after it was sent.
    pub fn fate(&self, from: usize, seq: u64, to: usize, ready: Time, copies: u8) -> Fate {
        let r = &self.radio;
        let base = mix(self.seed ^ mix((from as u64) << 32 ^ seq) ^ (to as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let mut lost = 0;
        let mut first = None;
        for c in 0..copies.max(1) as u64 {
            if r.loss > 0.0 && unit(mix(base ^ (c + 1))) < r.loss {
                lost += 1;
                continue;
            }
            first = Some(c);
            break;
        }
        let Some(c) = first else {
            return Fate { arrival: None, duplicate: None, lost };
        };
        let jitter = |salt: u64| if r.jitter == 0 { 0 } else { mix(base ^ salt) % (r.jitter + 1) };
        let arrival = ready + self.hop * (c + 1) + r.delay + jitter(0x6a69);
        let duplicate =
            (r.dup > 0.0 && unit(mix(base ^ 0x0064_7570)) < r.dup).then(|| arrival + self.hop + jitter(0x6475_7032));
        Fate { arrival: Some(arrival), duplicate, lost }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn links_are_the_robots_within_range() {
        let pts: Vec<Point> = [(0.0, 0.0), (2.0, 0.0), (2.06, 0.0), (-1.0, -1.0), (10.0, 10.0)]
            .iter()
            .map(|&(x, y)| Point::new(x, y))
            .collect();
        let mut m = Medium::new(1, Radio::default(), 1000, 2.05, pts.len());
        m.relink(&pts);
        for k in 0..pts.len() {
            let want: Vec<u32> =
                (0..pts.len()).filter(|&j| j != k && (pts[j] - pts[k]).norm() <= 2.05).map(|j| j as u32).collect();
            assert_eq!(m.links(k), &want[..], "robot {k}");
        }
    }

    #[test]
    fn fates_depend_on_identity_only_and_loss_has_its_rate() {
        let radio = Radio { loss: 0.3, delay: 5, jitter: 100, dup: 0.1 };
        let m = Medium::new(7, radio, 1000, 2.0, 4);
        assert_eq!(m.fate(1, 9, 2, 50, 1), m.fate(1, 9, 2, 50, 1));
        let n = 20_000;
        let lost = (0..n).filter(|&s| m.fate(0, s, 1, 0, 1).arrival.is_none()).count();
        assert!((lost as f64 / n as f64 - 0.3).abs() < 0.02, "{lost}");
        // Two copies: both must be lost.
        let lost2 = (0..n).filter(|&s| m.fate(0, s, 1, 0, 2).arrival.is_none()).count();
        assert!((lost2 as f64 / n as f64 - 0.09).abs() < 0.015, "{lost2}");
        for s in 0..1000 {
            if let Some(a) = m.fate(0, s, 1, 0, 3).arrival {
                assert!((1005..=3105).contains(&a), "{a}");
            }
        }
        let perfect = Medium::new(7, Radio::default(), 1000, 2.0, 4);
        assert_eq!(perfect.fate(0, 3, 1, 10, 1), Fate { arrival: Some(1010), duplicate: None, lost: 0 });
    }
}
