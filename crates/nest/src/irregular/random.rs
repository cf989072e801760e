//! The random streams of the workers and the perturbation of size orders.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Swaps each element with the next one with probability 1/8: a small perturbation of a
/// size order that keeps it mostly large-first.
pub(super) fn blink_shuffle<T>(order: &mut [T], rng: &mut ChaCha8Rng) {
    for i in 1..order.len() {
        if rng.gen_ratio(1, 8) {
            order.swap(i - 1, i);
        }
    }
}

/// The random stream of one worker in one epoch (epoch 0 is the greedy fill): SplitMix64 of the
/// seed, epoch and worker, so streams differ and do not depend on thread timing.
pub(super) fn worker_rng(seed: u64, epoch: usize, worker: usize) -> ChaCha8Rng {
    let mut z = seed
        ^ (epoch as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (worker as u64).wrapping_mul(0xD1B5_4A32_D192_ED03);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ChaCha8Rng::seed_from_u64(z ^ (z >> 31))
}
