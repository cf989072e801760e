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

/// The random stream of one worker in one epoch (epoch 0 is the greedy fill, where `worker` is
/// the start's recipe): stream `epoch << 32 | worker` of the ChaCha8 generator keyed by `seed`.
/// ChaCha's streams of one key are independent by construction, so no two workers or epochs
/// share random numbers and none depends on thread timing.
pub(super) fn worker_rng(seed: u64, epoch: usize, worker: usize) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(((epoch as u64) << 32) | worker as u64);
    rng
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_worker_and_epoch_has_its_own_reproducible_stream() {
        let draw = |epoch, worker| {
            let mut rng = worker_rng(7, epoch, worker);
            (0..4).map(|_| rng.gen::<u64>()).collect::<Vec<_>>()
        };
        assert_eq!(draw(3, 1), draw(3, 1));
        let streams = [draw(0, 0), draw(0, 1), draw(1, 0), draw(1, 1)];
        for (i, a) in streams.iter().enumerate() {
            for b in &streams[i + 1..] {
                assert_ne!(a, b);
            }
        }
        let mut other_seed = worker_rng(8, 0, 0);
        assert_ne!(draw(0, 0)[0], other_seed.gen::<u64>());
    }
}
