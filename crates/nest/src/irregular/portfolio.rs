//! The workers: a portfolio of greedy starts built in parallel, epochs of local search that share
//! the best layout, and the final compression of the sheet whose used length counts. Work is cut
//! by iteration count and every worker has its own random stream, so thread timing never enters
//! a decision.

use super::model::Model;
use super::random::worker_rng;
use super::score::Score;
use super::threads::{parallel, shared_out};
use crate::compress::{compress, MAX_PARTS};
use crate::limit::SearchLimit;
use crate::placement::{Placement, Sheets};
use crate::problem::NestError;
use crate::progress::NestProgress;
use std::time::Instant;

/// Overlap evaluations of the final compression per iteration of the budget, per worker.
const COMPRESSION_EVALUATIONS: usize = 3000;
/// Compression chains per worker. Each chain compresses the sheet on its own stream with an
/// equal share of the evaluations, and the chains go to whichever thread is free: a thread
/// whose chain stopped early (by `compress`'s stall rule) takes the next instead of idling
/// while the other finishes, and the best of more independent chains depends less on luck
/// (where compression decides the density, one chain's result varied by 3 points with its
/// stream).
pub(super) const COMPRESSION_CHAINS_PER_WORKER: usize = 2;
/// The compression's budget, in iterations' worth: the settings' full budget, not the share a
/// small job's search gets, times `COMPRESSION_BOOST_COPIES` over the copies, between 1 and
/// `MAX_COMPRESSION_BOOST` (twice on jobs of up to 60 copies, the plain budget from 120 on).
/// Compressing a small sheet is cheap, and on small strips the chains are still lowering the
/// top when the plain budget ends: the boost buys density there for under a second of wall time.
const COMPRESSION_BOOST_COPIES: usize = 120;
const MAX_COMPRESSION_BOOST: usize = 2;
/// Epochs split the budget so workers share progress; each epoch gives a worker at least this
/// many iterations, and there are at most this many epochs.
const MIN_EPOCH_ITERATIONS: usize = 25;
const MAX_EPOCHS: usize = 16;
/// Share of the epochs in which workers keep to their own starts (see `Model::run`).
const INDEPENDENT_EPOCHS: f64 = 0.5;
/// Stop rule, part 1: the search ends once this many iterations (over all workers, counted at
/// epoch ends) have passed without a better layout, neither the best nor any worker's own,
/// where better means fewer sheets or a used length shorter by more than the score's
/// tolerance (`Score::shorter_than`): the score's lower terms (fills, heights) keep changing
/// while the length stands still, and counting them kept every job running to its budget.
/// 50 (one or two epochs): where the search stalls, what it would still find is little beside
/// what the final compression does. On the 60-actuator batch's sheet layers the search never
/// shortened the greedy layout (two rows of standing parts, which interleave only through the
/// compression's overlap), and a wait of 200 iterations spent a third of the batch's CPU
/// there; on strips the longer wait bought about a tenth of a point of mean density.
const STALL_ITERATIONS: usize = 50;
/// Stop rule, part 2: the search ends once the layout uses the fewest sheets the part area
/// allows and its used length is within this share of the shortest possible (the part area over
/// the sheet width, i.e. a density of 1 / (1 + share)).
const LENGTH_TOLERANCE: f64 = 0.05;
/// Share of a deadline's time the greedy fill and the search epochs may use before the
/// compression takes the rest: where the deadline comes before the base search would end, the
/// compression, which lowers the top the most per second, still gets most of the time (on the
/// tuning instances albano, jakobs1 and swim at 20 s, 0.1 gave a mean 79.46 % against 79.09 % with
/// 0.3: albano's fill alone can take seconds).
const SEARCH_TIME_SHARE: f64 = 0.1;

impl Model<'_> {
    /// Greedy fill per worker, then epochs of local search; returns the best layout found. In
    /// the first `INDEPENDENT_EPOCHS` share of the epochs each worker improves its own start,
    /// so the basins of different starts are all explored; after that, every epoch starts all
    /// workers from the best layout so far. The search stops early by the stop rule
    /// (`STALL_ITERATIONS`, `LENGTH_TOLERANCE`), checked between epochs, so the stop is the
    /// same on any machine. `observe` gets a report after the fill and after every epoch.
    ///
    /// The instant returned is when the greedy fill ended: the first feasible layout, which no
    /// limit cuts short. `limit` is checked inside the compression, and in the greedy fill and between epochs
    /// against `SEARCH_TIME_SHARE` of its time: once reached, the epochs end and the compression starts
    /// (or ends) with the best layout so far, and the returned flag says the budget did not
    /// decide where (the layout is then not reproducible by any budget).
    pub(super) fn run(
        &self,
        observe: &dyn Fn(&NestProgress),
        limit: &SearchLimit,
    ) -> Result<(Sheets, usize, bool, Instant), NestError> {
        let settings = &self.job.settings;
        let workers = settings.workers;
        let search_limit = limit.share_of(Instant::now(), SEARCH_TIME_SHARE);
        let (mut own, mut cut) = self.construct_all(&search_limit)?;
        let first_layout = Instant::now();
        let mut best = own[0].clone();
        let iterations = self.job.iteration_budget();
        let epochs = (iterations / (workers * MIN_EPOCH_ITERATIONS)).clamp(1, MAX_EPOCHS);
        let independent = (epochs as f64 * INDEPENDENT_EPOCHS) as usize;
        let slots = epochs * workers;
        let mut done = 0;
        let mut since_better = 0;
        let mut previous: Vec<Score> = own.iter().map(|o| o.0).collect();
        for epoch in 0..=epochs {
            let mut improved = false;
            for (w, start) in own.iter().enumerate() {
                if start.0.better_than(&best.0) {
                    improved |= start.0.shorter_than(&best.0);
                    best = start.clone();
                }
                if start.0.shorter_than(&previous[w]) {
                    improved = true;
                    previous[w] = start.0;
                }
            }
            if improved {
                since_better = 0;
            }
            observe(&self.progress(&best.0, done, iterations, false));
            if epoch == epochs || since_better >= STALL_ITERATIONS || self.close_enough(&best.0) {
                break;
            }
            if search_limit.reached() {
                cut = true;
                break;
            }
            let incumbents: Vec<&Sheets> = (0..workers)
                .map(|w| {
                    if epoch < independent {
                        &own[w].1
                    } else {
                        &best.1
                    }
                })
                .collect();
            let budgets: Vec<usize> = (0..workers)
                .map(|w| {
                    let slot = epoch * workers + w;
                    iterations / slots + usize::from(slot < iterations % slots)
                })
                .collect();
            own = parallel(workers, |w| {
                self.improve(
                    incumbents[w],
                    budgets[w],
                    worker_rng(settings.seed, epoch + 1, w),
                    &search_limit,
                )
            });
            // An epoch the limit may have cut short is not that of any budget.
            cut |= search_limit.reached();
            let spent: usize = budgets.iter().sum();
            done += spent;
            since_better += spent;
        }
        // The used length is decided on the sheet with the lowest top, so that is where the
        // rest of the budget goes: the compression gets the whole budget's worth of
        // evaluations, however early the search stopped, and stops by its own rule when it
        // can no longer lower the top (`compress`, `STALL_ATTEMPTS`, `EXPLORE_FAILURES`).
        // Its budget never shrinks with the job as the search's does (`Job::iteration_budget`),
        // and small jobs get more (`compression_iterations`).
        let (sheets, stopped) =
            self.compressed(best.1, epochs + 1, self.compression_iterations(), &|| {
                limit.reached()
            });
        Ok((sheets, done, cut || stopped, first_layout))
    }

    /// Iterations' worth of compression for this job (`COMPRESSION_BOOST_COPIES`); none when
    /// the budget is only the greedy fill.
    fn compression_iterations(&self) -> usize {
        let counted = self.job.copies().clamp(
            COMPRESSION_BOOST_COPIES / MAX_COMPRESSION_BOOST,
            COMPRESSION_BOOST_COPIES,
        );
        self.job
            .settings
            .iterations
            .saturating_mul(COMPRESSION_BOOST_COPIES)
            / counted
    }

    /// Fewest sheets the part area allows.
    pub(super) fn sheets_lower_bound(&self) -> usize {
        let bin = &self.job.bin;
        let area = self.job.part_area();
        ((area / (bin.width_mm * bin.height_mm)) - 1e-9)
            .ceil()
            .max(1.0) as usize
    }

    /// Stop rule, part 2 (see `LENGTH_TOLERANCE`).
    fn close_enough(&self, score: &Score) -> bool {
        let area = self.job.part_area();
        score.sheets <= self.sheets_lower_bound()
            && self.used_length(score) <= area / self.job.bin.width_mm * (1.0 + LENGTH_TOLERANCE)
    }

    /// Used length of a scored layout in sheet terms: the score's length is measured from the
    /// usable bottom to the top of the inflated shapes, which both sit half the model's
    /// separation inside the part's; the cut along the top keeps the full separation.
    fn used_length(&self, score: &Score) -> f64 {
        score.length + self.job.settings.separation_mm
    }

    pub(super) fn progress(
        &self,
        score: &Score,
        done: usize,
        budget: usize,
        finished: bool,
    ) -> NestProgress {
        let bin = &self.job.bin;
        let area = self.job.part_area();
        let length = self.used_length(score);
        NestProgress {
            iterations_done: done,
            iterations_budget: budget,
            sheets: score.sheets,
            sheets_lower_bound: self.sheets_lower_bound(),
            best_density: if length > 0.0 {
                (area / (bin.width_mm * length)).min(1.0)
            } else {
                0.0
            },
            finished,
        }
    }

    /// Top of a sheet's parts (the usable bottom if it has none).
    pub(super) fn sheet_top(&self, sheet: &[Placement]) -> f32 {
        sheet
            .iter()
            .map(|s| self.shapes[s.part][s.rot].plain.bbox().y_max + s.t.1)
            .fold(self.usable.y_min, f32::max)
    }

    /// Index in `sheets` of the sheet whose used length counts, found as the score finds it:
    /// `sheets` lists the sheets in key order and `rebuild` keeps that order.
    pub(super) fn lowest_index(&self, sheets: &Sheets) -> usize {
        let problem = self.rebuild(sheets);
        debug_assert!(problem
            .layouts()
            .values()
            .zip(sheets)
            .all(|(layout, sheet)| layout.placed_items().len() == sheet.len()));
        let (key, _) = self.lowest_sheet(&problem);
        problem
            .layouts()
            .keys()
            .position(|k| k == key)
            .expect("the lowest sheet is one of them")
    }

    /// The layout with its lowest-topped sheet (the one whose used length counts) compressed
    /// through overlap ([`crate::compress`]) by `COMPRESSION_CHAINS_PER_WORKER` chains per
    /// worker, each on its own random stream with its share of `COMPRESSION_EVALUATIONS` per
    /// worker and iteration of `iterations`; the lowest top wins (ties to the lower chain).
    /// Chains end early once `stop` says so, and the flag returned says whether any did. A
    /// sheet of more than [`MAX_PARTS`] parts is left as it is.
    pub(super) fn compressed(
        &self,
        mut sheets: Sheets,
        epoch: usize,
        iterations: usize,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> (Sheets, bool) {
        let Some(footprints) = self.footprints.as_ref().filter(|_| !sheets.is_empty()) else {
            return (sheets, false);
        };
        let top = |sheet: &[Placement]| self.sheet_top(sheet);
        let lowest = self.lowest_index(&sheets);
        if sheets[lowest].len() > MAX_PARTS {
            return (sheets, false);
        }
        let settings = &self.job.settings;
        let chains = settings.workers * COMPRESSION_CHAINS_PER_WORKER;
        let budget = iterations * COMPRESSION_EVALUATIONS / COMPRESSION_CHAINS_PER_WORKER;
        let candidates = shared_out(settings.workers, chains, |chain| {
            let mut rng = worker_rng(settings.seed, epoch, chain);
            compress(
                footprints,
                &sheets[lowest],
                budget,
                &mut rng,
                |items| self.clear(items),
                stop,
            )
        });
        let stopped = candidates.iter().any(|c| c.stopped);
        let best = candidates
            .into_iter()
            .map(|c| c.items)
            .min_by(|a, b| top(a).total_cmp(&top(b)))
            .expect("at least one worker");
        if top(&best) < top(&sheets[lowest]) {
            sheets[lowest] = best;
        }
        (sheets, stopped)
    }
}

#[cfg(test)]
mod tests {
    use crate::job::Job;
    use crate::problem::NestSettings;
    use crate::test_support::squares_job;

    use super::Model;

    #[test]
    fn small_jobs_get_up_to_twice_the_compression_budget_and_never_less_than_the_full_one() {
        let compression = |copies: usize, iterations: usize| {
            let (items, bin) = squares_job(copies, 10);
            let settings = NestSettings {
                iterations,
                ..NestSettings::default()
            };
            let job = Job::new(&items, &bin, &settings).unwrap();
            Model::new(&job).unwrap().compression_iterations()
        };
        // Up to 60 copies: twice the full budget, however little of it the search gets
        // (`Job::iteration_budget` gives 12 copies 200 of 1000).
        assert_eq!(compression(12, 1000), 2000);
        assert_eq!(compression(60, 1000), 2000);
        // Between: 120 / copies of it, 90 copies -> 4/3.
        assert_eq!(compression(90, 900), 1200);
        // 120 copies and up: the full budget.
        assert_eq!(compression(120, 1000), 1000);
        assert_eq!(compression(300, 1000), 1000);
        // A greedy-only budget compresses nothing.
        assert_eq!(compression(12, 0), 0);
    }
}
