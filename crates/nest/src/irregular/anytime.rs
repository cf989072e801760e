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
//! strikes), and each of their sweeps is the better of two tries (sparrow's two workers). A
//! round gives every chain `ROUND_EVALUATIONS` more overlap evaluations and resumes it where the
//! last round left it, in the middle of a separation if need be, so the pool, the weights and
//! each separation's own stall rules carry over from round to round; the lowest chain's layout,
//! its parts settled onto one another (`Model::settled`), replaces the sheet if it is lower. On
//! more than one sheet a round first runs a short ruin-and-recreate search per worker
//! (`ROUND_ITERATIONS` over the workers), which may empty a sheet (fewer sheets first); a better
//! layout from it restarts the chains on it.
//!
//! After each round, every chain whose layout is higher than the lowest chain's goes on as a copy
//! of the lowest one ([`Chain::fork`]: its layout, weights, pool and unfinished separation) on a
//! stream of its own. An exploration breaks through rarely and at random, one chain clearing a
//! lower ceiling while the other fails separation after separation from the layout it started
//! on. Following the chain that got through puts every worker on the ceilings below it, as
//! sparrow puts both of its workers on one separation, and chains that are level keep their own
//! pools, so the search still tries as many ways down as there are chains.
//!
//! Once the best layout has not got shorter for `COMPRESS_AFTER` rounds, a compression pass
//! (sparrow's compression phase) takes the rounds' place: fine chains ([`Pace::Fine`]), one per
//! worker and followed as the patient ones are, lower the best layout by steps under the
//! exploration's, for rounds that make `COMPRESS_SHARE_PERCENT` of those since the last pass (15
//! for every 85 explored) or until they end. Its chains are kept when it ends, and the next pass
//! goes on with them where they stopped (their step, weights and unfinished separation) rather
//! than from the largest fine step again, unless all of them have ended or a layout they did not
//! compress has become the best in between. Sparrow compresses once, in the last tenth to fifth
//! of its time. An anytime search does not know when its time ends, and a pass placed by the
//! end of the budget would make a longer budget a different search from a shorter one, no longer
//! sure to end at least as low; so the passes are spread through the rounds in the same share, and
//! every budget's rounds begin with a shorter budget's. After a pass, a patient chain exploring at
//! a ceiling that the compressed layout is already under starts again from that layout.
//!
//! A round's layout replaces the best only if it scores better, so the best layout never gets
//! worse from one round to the next, and a budget of more rounds never ends worse than one of
//! fewer with the same seed. Rounds are counted, and a round that a [`SearchLimit`] cuts short is
//! thrown away whole, so the rounds completed, and with them the layout, are the same on any
//! machine. Only the rounds' number or the limit ends them, never a stall: as sparrow's
//! exploration ends only on its time, a time budget is used to its end, since an exploration
//! may break through after thousands of rounds without a shorter layout.

use std::sync::Mutex;

use super::model::Model;
use super::random::worker_rng;
use super::score::Score;
use super::threads::{parallel, shared_out};
use crate::compress::{Chain, Pace, MAX_PARTS};
use crate::limit::{SearchEnd, SearchLimit};
use crate::placement::{Placement, Sheets};
use crate::progress::NestProgress;

/// The base search's largest budget: a budget above it is the base search at this budget
/// followed by rounds. It is [`crate::NestSettings`]'s default, so a default run is the base
/// search alone.
pub(super) const BASE_ITERATIONS: usize = 1000;
/// Iterations a round counts for (`--iterations` above the base budget buys rounds at this
/// rate), and its search's moves over all workers on more than one sheet.
pub(super) const ROUND_ITERATIONS: usize = 100;
/// Overlap evaluations each chain gets per round: a few separations, well under a second on a
/// strip of a few dozen parts, so a deadline wastes little on the round it cuts.
const ROUND_EVALUATIONS: usize = 50_000;
/// Rounds without a shorter layout after which a compression pass may begin (see the module
/// doc): about a second on a strip of two dozen parts, long enough that exploration has
/// stalled rather than paused between two successes.
const COMPRESS_AFTER: usize = 25;
/// The share of the rounds the compression passes take: 15 rounds of compression for every 85
/// of exploration, in the range of sparrow's split of its time (a tenth to a fifth).
const COMPRESS_SHARE_PERCENT: usize = 15;
/// Round `r` draws its search's streams from epoch `FIRST_ROUND_EPOCH + 2r`, and chains started
/// in it from `+ 2r + 1`: of `n` chains, chain `c` from stream `c`, a copy of the lowest chain put
/// in its place from stream `n + c`, a compression pass's chain from `3n + c` and a patient chain
/// restarted after a pass from `4n + c`. The first chains draw from `FIRST_ROUND_EPOCH - 1`. All
/// are far above the base search's epochs (at most `MAX_EPOCHS + 1`), so no two share a stream.
const FIRST_ROUND_EPOCH: usize = 1 << 16;

/// The compression passes (see the module doc): when they run, counted in rounds so that they
/// fall on the same rounds on any machine, and the fine chains they run.
#[derive(Default)]
struct Passes<'f> {
    /// Rounds of exploration since the last pass.
    explored: usize,
    /// Rounds left in the pass under way (0 between passes).
    left: usize,
    /// The chains of the pass under way, or of the last one while the best layout is still the
    /// one they compressed (none before the first pass or once another layout has replaced it).
    chains: Vec<Mutex<Chain<'f>>>,
}

impl<'f> Passes<'f> {
    /// True if a pass begins this round: none is under way, the best has not got shorter for
    /// `COMPRESS_AFTER` rounds, and the exploration since the last pass has earned a round of
    /// compression at least (`COMPRESS_SHARE_PERCENT`). It goes on with the last pass's chains if
    /// they are kept and one of them can go on, else with `fresh` ones.
    fn begins(
        &mut self,
        since_shorter: usize,
        fresh: impl FnOnce() -> Vec<Mutex<Chain<'f>>>,
    ) -> bool {
        if self.left > 0 || since_shorter < COMPRESS_AFTER {
            return false;
        }
        self.left = self.explored * COMPRESS_SHARE_PERCENT / (100 - COMPRESS_SHARE_PERCENT);
        if self.left == 0 {
            return false;
        }
        self.explored = 0;
        let resumable = self
            .chains
            .iter()
            .any(|c| !c.lock().expect("no thread panics").ended());
        if !resumable {
            self.chains = fresh();
        }
        true
    }

    /// The chains of the pass under way, or kept from the last one.
    fn chains(&self) -> &[Mutex<Chain<'f>>] {
        &self.chains
    }

    /// True while a pass is under way.
    fn compressing(&self) -> bool {
        self.left > 0
    }

    /// Counts a round that ran; true if it was the last of a pass (its rounds are spent, or
    /// `ended`: its chains can do no more). `lowered`: the round's chains lowered the best
    /// layout. Lowered by exploration, the best is no longer the layout the last pass
    /// compressed, so that pass's kept chains are dropped; lowered by a pass, they go on.
    fn count(&mut self, ended: bool, lowered: bool) -> bool {
        if self.left == 0 {
            self.explored += 1;
            if lowered {
                self.chains.clear();
            }
            return false;
        }
        self.left = if ended { 0 } else { self.left - 1 };
        self.left == 0
    }

    /// Drops the pass under way, and its chains: the layout they compressed has been replaced.
    fn cancel(&mut self) {
        self.left = 0;
        self.chains.clear();
    }
}

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
        let mut chains = self.chains(&best.1, FIRST_ROUND_EPOCH - 1, Pace::Patient, 0);
        let mut passes = Passes::default();
        let mut since_shorter = 0;
        // The lowest chain's layout last settled, and the settled layout.
        let mut settled: (Vec<Placement>, Vec<Placement>) = (Vec::new(), Vec::new());
        let ended_by_limit = || {
            if limit.interrupted() {
                SearchEnd::Interrupt
            } else {
                SearchEnd::Time
            }
        };
        let budget = done + rounds.saturating_mul(ROUND_ITERATIONS);
        for round in 0..rounds {
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
                let Some(pick) = self.round_search(&best.1, epoch, limit) else {
                    return cut(best.1);
                };
                if pick.0.better_than(&best.0) {
                    score = pick.0;
                    chains = self.chains(&pick.1, epoch + 1, Pace::Patient, 0);
                    passes.cancel();
                    best.1 = pick.1;
                }
            }
            let lowest = self.lowest_index(&best.1);
            if !chains.is_empty() {
                passes.begins(since_shorter, || {
                    self.chains(&best.1, epoch + 1, Pace::Fine, 3 * workers)
                });
            }
            let running = if passes.compressing() {
                passes.chains()
            } else {
                &chains
            };
            let stop = || limit.reached();
            let stopped = shared_out(workers, running.len(), |c| {
                let mut chain = running[c].lock().expect("no thread panics holding it");
                chain.advance(ROUND_EVALUATIONS, &|items| self.clear(items), &stop)
            });
            // A round the limit cut short is dropped whole; one that finished counts, even if
            // the deadline passed as it finished.
            if stopped.iter().any(|&s| s) {
                return cut(best.1);
            }
            let mut sheets = best.1.clone();
            // No chains where a part's shape has no footprint: the search above is all there is.
            if let Some(lowest_chain) = self.follow_lowest(running, epoch + 1) {
                let candidate = running[lowest_chain].lock().expect("no thread panics");
                // A chain's layout changes only when it clears a lower ceiling, so most rounds
                // find the one settled last round; settling costs a sweep of slides over the
                // sheet, which on a strip of 150 parts took a third of the rounds' time.
                if settled.0 != candidate.best() {
                    settled = (candidate.best().to_vec(), self.settled(candidate.best()));
                }
                let lowered = self.sheet_top(&settled.1) < self.sheet_top(&sheets[lowest]);
                if lowered {
                    sheets[lowest] = settled.1.clone();
                    score = self.score(&self.rebuild(&sheets));
                }
                let lowest_top = candidate.top();
                drop(candidate);
                let ended = running
                    .iter()
                    .all(|c| c.lock().expect("no thread panics").ended());
                if passes.count(ended, lowered) {
                    self.restart_under(&chains, lowest_top, &sheets[lowest], epoch + 1);
                }
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

    /// Each of `chains` exploring at a ceiling that `sheet`, the compressed layout whose top is
    /// `lowest_top`, is already under can find nothing lower: it starts again from that layout,
    /// on stream `4 n + c` of `epoch`.
    fn restart_under<'s>(
        &'s self,
        chains: &[Mutex<Chain<'s>>],
        lowest_top: f32,
        sheet: &[Placement],
        epoch: usize,
    ) {
        let n = chains.len();
        for (c, chain) in chains.iter().enumerate() {
            let mut chain = chain.lock().expect("no thread panics");
            if lowest_top <= chain.ceiling() {
                let fresh = self.chain(sheet, epoch, 4 * n + c, Pace::Patient);
                *chain =
                    fresh.expect("the chains' sheet has footprints and parts compression takes");
            }
        }
    }

    /// A round's short ruin-and-recreate search from `start`: `ROUND_ITERATIONS` shared out to
    /// the workers on streams of `epoch`, and the best worker's layout (ties to the lower
    /// worker, as between the base search's epochs); `None` if `limit` cut it.
    fn round_search(
        &self,
        start: &Sheets,
        epoch: usize,
        limit: &SearchLimit,
    ) -> Option<(Score, Sheets)> {
        let settings = &self.job.settings;
        let workers = settings.workers;
        let share =
            |w: usize| ROUND_ITERATIONS / workers + usize::from(w < ROUND_ITERATIONS % workers);
        let searched = parallel(workers, |w| {
            self.improve(start, share(w), worker_rng(settings.seed, epoch, w), limit)
        });
        if limit.reached() {
            return None;
        }
        let mut pick = 0;
        for (w, s) in searched.iter().enumerate().skip(1) {
            if s.0.better_than(&searched[pick].0) {
                pick = w;
            }
        }
        searched.into_iter().nth(pick)
    }

    /// The lowest of `chains` (ties to the lower one; `None` if there are none); every chain
    /// above it goes on from a copy of it (see the module doc) on stream `chains.len() + c` of
    /// `epoch`.
    fn follow_lowest(&self, chains: &[Mutex<Chain<'_>>], epoch: usize) -> Option<usize> {
        if chains.is_empty() {
            return None;
        }
        let tops: Vec<f32> = chains
            .iter()
            .map(|c| self.sheet_top(c.lock().expect("no thread panics").best()))
            .collect();
        let mut lowest = 0;
        for (c, t) in tops.iter().enumerate() {
            if *t < tops[lowest] {
                lowest = c;
            }
        }
        let follow = chains[lowest].lock().expect("no thread panics").clone();
        for (c, t) in tops.iter().enumerate() {
            if *t > tops[lowest] {
                let rng = worker_rng(self.job.settings.seed, epoch, chains.len() + c);
                *chains[c].lock().expect("no thread panics") = follow.fork(rng);
            }
        }
        Some(lowest)
    }

    /// Compression chains of `pace` (one per worker) on the sheet of `sheets` whose used length
    /// counts, on streams `first..` of `epoch`.
    fn chains(
        &self,
        sheets: &Sheets,
        epoch: usize,
        pace: Pace,
        first: usize,
    ) -> Vec<Mutex<Chain<'_>>> {
        if sheets.is_empty() {
            return Vec::new();
        }
        let sheet = &sheets[self.lowest_index(sheets)];
        (0..self.job.settings.workers)
            .map_while(|c| self.chain(sheet, epoch, first + c, pace).map(Mutex::new))
            .collect()
    }

    /// A compression chain of `pace` on `sheet`, on stream `stream` of `epoch`; `None` where a
    /// part's shape has no footprint or the sheet holds more parts than compression takes
    /// ([`crate::compress::MAX_PARTS`]).
    fn chain(
        &self,
        sheet: &[Placement],
        epoch: usize,
        stream: usize,
        pace: Pace,
    ) -> Option<Chain<'_>> {
        let footprints = self.footprints.as_ref()?;
        if sheet.len() > MAX_PARTS {
            return None;
        }
        let rng = worker_rng(self.job.settings.seed, epoch, stream);
        Some(Chain::new(footprints, sheet, rng, pace))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compress::{Footprint, Footprints};
    use std::cell::Cell;

    /// Counts `rounds` rounds that run, none of them ending a pass's chains; true for each that
    /// ended a pass.
    fn run(passes: &mut Passes, rounds: usize, since_shorter: &mut usize) -> Vec<bool> {
        (0..rounds)
            .map(|_| {
                passes.begins(*since_shorter, Vec::new);
                *since_shorter += 1;
                passes.count(false, false)
            })
            .collect()
    }

    #[test]
    fn a_pass_begins_after_a_stall_and_takes_its_share_of_the_rounds_explored() {
        let mut passes = Passes::default();
        // 85 rounds of exploration that keep getting shorter: no pass, however many rounds.
        for _ in 0..85 {
            assert!(!passes.begins(0, Vec::new));
            assert!(!passes.count(false, false));
        }
        // A stall one round short of `COMPRESS_AFTER`: still none.
        assert!(!passes.begins(COMPRESS_AFTER - 1, Vec::new));
        // At the stall, 15 rounds of compression for the 85 explored (85 x 15 / 85).
        assert!(passes.begins(COMPRESS_AFTER, Vec::new));
        assert!(passes.compressing());
        let mut since = COMPRESS_AFTER;
        let ends = run(&mut passes, 15, &mut since);
        assert_eq!(ends.iter().filter(|&&e| e).count(), 1);
        assert!(ends[14] && !passes.compressing());
        // The exploration's count starts again from the pass: 5 rounds earn none yet (5 x 15 / 85
        // rounds down to 0), 6 earn one.
        for _ in 0..5 {
            assert!(!passes.count(false, false));
        }
        assert!(!passes.begins(since, Vec::new));
        assert!(!passes.count(false, false));
        assert!(passes.begins(since, Vec::new));
        assert!(passes.count(false, false) && !passes.compressing());
    }

    /// Explores long enough to earn a pass, begins one with `fresh` chains unless it goes on
    /// with the last pass's, and ends it at once.
    fn pass<'f>(passes: &mut Passes<'f>, fresh: impl FnOnce() -> Vec<Mutex<Chain<'f>>>) {
        for _ in 0..170 {
            passes.count(false, false);
        }
        assert!(passes.begins(COMPRESS_AFTER, fresh));
        assert!(passes.count(true, false) && !passes.compressing());
    }

    /// A unit square's footprint, with room to move on a 10-by-10 sheet.
    fn squares() -> Footprints {
        Footprints::new(vec![vec![Footprint::rectangle(1.0, 1.0, 9.0, 9.0)]])
    }

    fn at(x: f32) -> Placement {
        Placement {
            part: 0,
            rot: 0,
            t: (x, 0.0),
        }
    }

    /// Two fine chains on `sheet`, counting them in `made`.
    fn fine_chains<'f>(
        squares: &'f Footprints,
        sheet: &[Placement],
        made: &Cell<usize>,
    ) -> Vec<Mutex<Chain<'f>>> {
        made.set(made.get() + 1);
        (0..2)
            .map(|c| Chain::new(squares, sheet, worker_rng(1, 0, c), Pace::Fine))
            .map(Mutex::new)
            .collect()
    }

    #[test]
    fn a_pass_goes_on_with_the_last_passs_chains_while_one_of_them_can() {
        let squares = squares();
        // Two parts: a chain has room to lower them. One part: it has ended from the start.
        let two = [at(0.0), at(2.0)];
        let one = [at(0.0)];
        let made = Cell::new(0);
        let fresh = |sheet: &[Placement]| fine_chains(&squares, sheet, &made);
        let mut passes = Passes::default();
        // The first pass starts chains; the next goes on with them, as they can go on.
        pass(&mut passes, || fresh(&two));
        pass(&mut passes, || fresh(&two));
        assert_eq!((made.get(), passes.chains().len()), (1, 2));
        // Once another layout has replaced the one they compressed, a pass starts new ones.
        passes.cancel();
        assert!(passes.chains().is_empty());
        pass(&mut passes, || fresh(&one));
        assert_eq!(made.get(), 2);
        // Chains that have all ended are replaced too.
        pass(&mut passes, || fresh(&two));
        assert_eq!(made.get(), 3);
        pass(&mut passes, || fresh(&two));
        assert_eq!(made.get(), 3);
    }

    #[test]
    fn a_round_that_explores_lower_drops_the_last_passs_chains_and_a_pass_that_does_keeps_them() {
        let squares = squares();
        let two = [at(0.0), at(2.0)];
        let made = Cell::new(0);
        let fresh = || fine_chains(&squares, &two, &made);
        let mut passes = Passes::default();
        pass(&mut passes, fresh);
        // Exploring rounds that do not lower the best layout leave the pass's chains kept.
        assert!(!passes.count(false, false));
        assert_eq!(passes.chains().len(), 2);
        // A pass's own round that lowers the best keeps them: that layout is theirs.
        for _ in 0..170 {
            passes.count(false, false);
        }
        assert!(passes.begins(COMPRESS_AFTER, fresh));
        assert_eq!(made.get(), 1, "the pass goes on with the kept chains");
        assert!(!passes.count(false, true));
        assert_eq!(passes.chains().len(), 2);
        while !passes.count(false, false) {}
        assert!(!passes.compressing());
        assert_eq!(passes.chains().len(), 2, "kept when the pass ends");
        // An exploring round that lowers the best drops them, and the next pass starts anew.
        assert!(!passes.count(false, true));
        assert!(passes.chains().is_empty());
        pass(&mut passes, fresh);
        assert_eq!((made.get(), passes.chains().len()), (2, 2));
    }

    #[test]
    fn a_pass_ends_early_when_its_chains_end_or_its_layout_is_replaced() {
        let mut passes = Passes::default();
        for _ in 0..170 {
            passes.count(false, false);
        }
        assert!(passes.begins(COMPRESS_AFTER, Vec::new));
        assert!(!passes.count(false, false));
        assert!(passes.count(true, false), "its chains can do no more");
        assert!(!passes.compressing());
        for _ in 0..170 {
            passes.count(false, false);
        }
        assert!(passes.begins(COMPRESS_AFTER, Vec::new));
        passes.cancel();
        assert!(!passes.compressing());
        assert!(
            !passes.count(false, false),
            "a round after a cancelled pass explores"
        );
    }
}
