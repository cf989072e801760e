//! Anytime rounds: what the nester does with iterations beyond its base budget, so that more
//! time buys a better layout.
//!
//! The base search (`Model::run`) is built for a budget: its epochs, thresholds and final
//! compression are all scaled to it, and its stop rules end it once it stalls. Giving it more
//! iterations changes little (the compression stops on its own stall rules, however large its
//! budget). Rounds instead start again from the best layout so far, each on streams of its own:
//!
//! 1. a short ruin-and-recreate search per worker (`ROUND_ITERATIONS` over the workers), which
//!    may empty a sheet (fewer sheets first) or re-partition rows;
//! 2. the compression of the sheet whose used length counts, with its exploration (sparrow's two
//!    phases: shrink and separate by guided local search; at a ceiling the small steps cannot
//!    reach, a pool of overlapping layouts restored and disrupted), `ROUND_ITERATIONS`' worth
//!    of overlap evaluations, with fresh pair weights and a fresh pool.
//!
//! A round's layout replaces the best only if it scores better, so the best layout never gets
//! worse from one round to the next, and a budget of more rounds never ends worse than one of
//! fewer with the same seed. Rounds are counted, and a round that a [`SearchLimit`] cuts short is
//! thrown away whole, so the rounds completed, and with them the layout, are the same on any
//! machine. `ROUND_STALL` rounds in a row without a shorter layout end the rounds, so a layout
//! that cannot improve does not hold a time budget to its end.

use super::model::Model;
use super::random::worker_rng;
use super::score::Score;
use super::threads::parallel;
use crate::limit::{SearchEnd, SearchLimit};
use crate::placement::Sheets;
use crate::progress::NestProgress;

/// The base search's largest budget: a budget above it is the base search at this budget
/// followed by rounds. It is [`crate::NestSettings`]'s default, so a default run is the base
/// search alone.
pub(super) const BASE_ITERATIONS: usize = 1000;
/// Iterations a round counts for: its search's moves over all workers, and its compression's
/// budget (as `Model::compressed` counts it). Small enough that a round of a 300-part strip
/// takes well under a second, so a deadline wastes little on the round it cuts.
pub(super) const ROUND_ITERATIONS: usize = 100;
/// Rounds in a row without a shorter layout (fewer sheets, or a used length shorter by more
/// than the score's tolerance) after which the rounds end.
const ROUND_STALL: usize = 50;
/// Round `r` draws its streams from epochs `FIRST_ROUND_EPOCH + 2r` (search) and `+ 2r + 1`
/// (compression): far above the base search's epochs (at most `MAX_EPOCHS + 1`), so no round
/// shares a stream with the base search or with another round.
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
            let share =
                |w: usize| ROUND_ITERATIONS / workers + usize::from(w < ROUND_ITERATIONS % workers);
            let searched = parallel(workers, |w| {
                self.improve(&best.1, share(w), worker_rng(settings.seed, epoch, w))
            });
            // Ties to the lower worker, as between the base search's epochs.
            let mut pick = &searched[0];
            for s in &searched[1..] {
                if s.0.better_than(&pick.0) {
                    pick = s;
                }
            }
            let (sheets, stopped) =
                self.compressed(pick.1.clone(), epoch + 1, ROUND_ITERATIONS, &|| {
                    limit.reached()
                });
            // A round the limit cut short is dropped whole; one that finished counts, even if
            // the deadline passed as it finished.
            if stopped {
                return cut(best.1);
            }
            let score = self.score(&self.rebuild(&sheets));
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
}
