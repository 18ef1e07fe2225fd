//! Seeds of the Monte Carlo runs. Run `k` of (algorithm, robots) gets a seed
//! that depends only on the base seed and those three values, so results are
//! the same whatever the thread count or scheduling, and adding an algorithm
//! or a robot count to a sweep leaves the other cells' runs unchanged.

use gridswarm::policy::Policy;
use gridswarm::rng::derive;

/// FNV-1a of the algorithm's command-line name: the algorithm enters by its
/// name, not its enum position, so reordering the enum changes no result.
fn name_label(policy: Policy) -> u64 {
    policy.name().bytes().fold(0xCBF2_9CE4_8422_2325, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01B3))
}

/// The seed of run `k` of `policy` with `robots` robots in a sweep with base
/// seed `base`, derived with the shared crate's [`derive`] like every other
/// seed of the project.
pub fn run_seed(base: u64, policy: Policy, robots: usize, k: u64) -> u64 {
    derive(derive(derive(base, name_label(policy)), robots as u64), k)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn stable_and_distinct() {
        // Pinned: a change here silently changes every published sweep.
        assert_eq!(run_seed(1, Policy::Repulsive, 5, 0), 14_487_540_132_464_933_744);
        let mut seen = HashSet::new();
        for p in Policy::ALL {
            for r in 1..=13 {
                for k in 0..200 {
                    assert!(seen.insert(run_seed(7, p, r, k)));
                }
            }
        }
        assert_ne!(run_seed(1, Policy::Ru, 3, 4), run_seed(2, Policy::Ru, 3, 4));
    }
}
