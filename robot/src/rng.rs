//! Seeding: every random choice of a run flows from the run seed. A robot's
//! stream depends on (run seed, robot id) and nothing else, so it is the same
//! whichever engine or process runs the robot.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// SplitMix64 finaliser: spreads nearby inputs over the whole range.
#[inline]
pub fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The random stream of robot `id` in a run with seed `seed`.
pub fn robot_rng(seed: u64, id: u16) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(mix(mix(seed) ^ (id as u64 + 1).wrapping_mul(0xD6E8_FEB8_6659_FD93)))
}

/// A seed derived from a parent seed and a label, e.g. run `k` of a sweep.
#[inline]
pub fn derive(seed: u64, label: u64) -> u64 {
    mix(mix(seed) ^ mix(label.wrapping_add(0xA076_1D64_78BD_642F)))
}
