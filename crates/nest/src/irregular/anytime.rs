//! Anytime rounds: what the nester does with iterations beyond its base budget, so that more
//! time buys a better layout.
//!
//! The base search (`Model::run`) is built for a budget: its epochs, thresholds and final
//! compression are all scaled to it, and its stop rules end it once it stalls. Giving it more
//! iterations changes little (the compression stops on its own stall rules, however large its
//! budget). The rounds instead run sparrow's exploration for as long as they are given
//! (Gardeyn & Wauters 2025): patient compression chains ([`Chain`]), one per worker (so each
//! has a thread to itself) on streams of their own, each started from the best layout's sheet
//! whose used length counts. A chain lowers the ceiling by the smallest step and separates by
//! guided local search; where a separation fails it keeps the failure in a pool of overlapping
//! layouts, restores one and disrupts it, and it never gives that ceiling up (the base search's
//! chains end after `EXPLORE_FAILURES`). Its separations take up to three stalls (sparrow's
//! strikes). A round gives every chain `ROUND_EVALUATIONS` more overlap evaluations and resumes
//! it where the last round left it, in the middle of a separation if need be, so the pool, the
//! weights and each separation's own stall rules carry over from round to round; the lowest
//! chain's layout replaces the sheet if it is lower. On more than one sheet a round first runs a
//! short ruin-and-recreate search per worker (`ROUND_ITERATIONS` over the workers), which may
//! empty a sheet (fewer sheets first); a better layout from it restarts the chains on it.
//!
//! After each round, every chain whose layout is higher than the lowest chain's goes on as a copy
//! of the lowest one ([`Chain::fork`]: its layout, weights, pool and unfinished separation) on a
//! stream of its own. An exploration breaks through rarely and at random, one chain clearing a
//! lower ceiling while the other fails separation after separation from the layout it started
//! on. Following the chain that got through puts every worker on the ceilings below it, as
//! sparrow puts both of its workers on one separation, and chains that are level keep their own
//! pools, so the search still tries as many ways down as there are chains.
//!
//! A round's layout replaces the best only if it scores better, so the best layout never gets
//! worse from one round to the next, and a budget of more rounds never ends worse than one of
//! fewer with the same seed. Rounds are counted, and a round that a [`SearchLimit`] cuts short is
//! thrown away whole, so the rounds completed, and with them the layout, are the same on any
//! machine. `ROUND_STALL` rounds in a row without a shorter layout end the rounds, so a layout
//! that cannot improve does not hold a time budget to its end.

use std::sync::Mutex;

use super::model::Model;
use super::random::worker_rng;
use super::score::Score;
use super::threads::{parallel, shared_out};
use crate::compress::Chain;
use crate::limit::{SearchEnd, SearchLimit};
use crate::placement::Sheets;
use crate::progress::NestProgress;

/// The base search's largest budget: a budget above it is the base search at this budget
/// followed by rounds. It is [`crate::NestSettings`]'s default, so a default run is the base
/// search alone.
pub(super) const BASE_ITERATIONS: usize = 1000;
/// Iterations a round counts for (`--iterations` above the base budget buys rounds at this
/// rate), and its search's moves over all workers on more than one sheet.
pub(super) const ROUND_ITERATIONS: usize = 100;
/// Rounds in a row without a shorter layout (fewer sheets, or a used length shorter by more
/// than the score's tolerance) after which the rounds end: 200 million evaluations per chain,
/// minutes of a time budget, so that an exploration that breaks through only after many
/// disruptions gets them (sparrow's exploration ends only on its time).
const ROUND_STALL: usize = 4000;
/// Overlap evaluations each chain gets per round: a few separations, well under a second on a
/// strip of a few dozen parts, so a deadline wastes little on the round it cuts.
const ROUND_EVALUATIONS: usize = 50_000;
/// Round `r` draws its search's streams from epoch `FIRST_ROUND_EPOCH + 2r`, and chains restarted
/// after it from `+ 2r + 1` (chain `c` of `n` from stream `c`, a copy of the lowest chain put in
/// its place from stream `n + c`); the first chains draw from `FIRST_ROUND_EPOCH - 1`. All are
/// far above the base search's epochs (at most `MAX_EPOCHS + 1`), so no two share a stream.
const FIRST_ROUND_EPOCH: usize = 1 << 16;

/// What the rounds came to.
pub(super) struct Rounds {
    pub(super) best: Sheets,
    pub(super) completed: usize,
    pub(super) ended: SearchEnd,
}

impl Model<'_> {
    /// Up to `rounds` rounds from `start` (see the module doc); `done` is the base search's
    /// iterations, for the reports to `observe` after each round.
    pub(super) fn rounds(
        &self,
        start: Sheets,
        rounds: usize,
        limit: &SearchLimit,
        observe: &dyn Fn(&NestProgress),
        done: usize,
    ) -> Rounds {
        let settings = &self.job.settings;
        let workers = settings.workers;
        let mut best: (Score, Sheets) = (self.score(&self.rebuild(&start)), start);
        let mut chains = self.chains(&best.1, FIRST_ROUND_EPOCH - 1);
        let mut since_shorter = 0;
        let ended_by_limit = || {
            if limit.interrupted() {
                SearchEnd::Interrupt
            } else {
                SearchEnd::Time
            }
        };
        let budget = done + rounds.saturating_mul(ROUND_ITERATIONS);
        for round in 0..rounds {
            if since_shorter >= ROUND_STALL {
                return Rounds {
                    best: best.1,
                    completed: round,
                    ended: SearchEnd::Budget,
                };
            }
            let cut = |best: Sheets| Rounds {
                best,
                completed: round,
                ended: ended_by_limit(),
            };
            if limit.reached() {
                return cut(best.1);
            }
            let epoch = FIRST_ROUND_EPOCH + 2 * round;
            let mut score = best.0;
            // On more than one sheet, a short ruin-and-recreate search may empty a sheet or
            // move parts between sheets, which compressing one sheet never does; and once
            // every chain has ended (no lower ceiling leaves room for the tallest part), it is
            // what may still find another structure. A better layout restarts the chains from
            // it. Otherwise one sheet (a strip) is the chains' alone.
            let exhausted = chains
                .iter()
                .all(|c| c.lock().expect("no thread panics").ended());
            if best.1.len() > 1 || exhausted {
                let share = |w: usize| {
                    ROUND_ITERATIONS / workers + usize::from(w < ROUND_ITERATIONS % workers)
                };
                let searched = parallel(workers, |w| {
                    self.improve(
                        &best.1,
                        share(w),
                        worker_rng(settings.seed, epoch, w),
                        limit,
                    )
                });
                if limit.reached() {
                    return cut(best.1);
                }
                // Ties to the lower worker, as between the base search's epochs.
                let mut pick = &searched[0];
                for s in &searched[1..] {
                    if s.0.better_than(&pick.0) {
                        pick = s;
                    }
                }
                if pick.0.better_than(&best.0) {
                    score = pick.0;
                    chains = self.chains(&pick.1, epoch + 1);
                    best.1 = pick.1.clone();
                }
            }
            let lowest = self.lowest_index(&best.1);
            let stop = || limit.reached();
            let stopped = shared_out(workers, chains.len(), |c| {
                let mut chain = chains[c].lock().expect("no thread panics holding it");
                chain.advance(ROUND_EVALUATIONS, &|items| self.clear(items), &stop)
            });
            // A round the limit cut short is dropped whole; one that finished counts, even if
            // the deadline passed as it finished.
            if stopped.iter().any(|&s| s) {
                return cut(best.1);
            }
            // The lowest chain (ties to the lower one) replaces the sheet if it is lower.
            let mut sheets = best.1.clone();
            let tops: Vec<f32> = chains
                .iter()
                .map(|c| self.sheet_top(c.lock().expect("no thread panics").best()))
                .collect();
            let mut lowest_chain = 0;
            for (c, t) in tops.iter().enumerate() {
                if *t < tops[lowest_chain] {
                    lowest_chain = c;
                }
            }
            // Chains above the lowest go on from a copy of it (see the module doc).
            let follow = chains[lowest_chain]
                .lock()
                .expect("no thread panics")
                .clone();
            for (c, t) in tops.iter().enumerate() {
                if *t > tops[lowest_chain] {
                    let rng = worker_rng(settings.seed, epoch + 1, chains.len() + c);
                    *chains[c].lock().expect("no thread panics") = follow.fork(rng);
                }
            }
            if tops[lowest_chain] < self.sheet_top(&sheets[lowest]) {
                sheets[lowest] = chains[lowest_chain]
                    .lock()
                    .expect("no thread panics")
                    .best()
                    .to_vec();
                score = self.score(&self.rebuild(&sheets));
            }
            since_shorter += 1;
            if score.shorter_than(&best.0) {
                since_shorter = 0;
            }
            if score.better_than(&best.0) {
                best = (score, sheets);
            }
            let done = done + (round + 1) * ROUND_ITERATIONS;
            observe(&self.progress(&best.0, done, budget, false));
        }
        Rounds {
            best: best.1,
            completed: rounds,
            ended: SearchEnd::Budget,
        }
    }

    /// Patient compression chains (one per worker) on the sheet of
    /// `sheets` whose used length counts, on the streams of `epoch`.
    fn chains(&self, sheets: &Sheets, epoch: usize) -> Vec<Mutex<Chain<'_>>> {
        let Some(footprints) = self.footprints.as_ref().filter(|_| !sheets.is_empty()) else {
            return Vec::new();
        };
        let sheet = &sheets[self.lowest_index(sheets)];
        let settings = &self.job.settings;
        (0..settings.workers)
            .map(|c| {
                let rng = worker_rng(settings.seed, epoch, c);
                Mutex::new(Chain::new(footprints, sheet, rng, true))
            })
            .collect()
    }
}
