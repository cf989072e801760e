//! The workers: a portfolio of greedy starts built in parallel, epochs of local search that share
//! the best layout, and the final compression of the sheet whose used length counts. Work is cut
//! by iteration count and every worker has its own random stream, so thread timing never enters
//! a decision.

use super::model::Model;
use super::random::worker_rng;
use super::score::Score;
use crate::compress::compress;
use crate::placement::{Placement, Sheets};
use crate::problem::NestError;

/// Overlap evaluations of the final compression per iteration of the budget, per worker.
const COMPRESSION_EVALUATIONS: usize = 3000;
/// Epochs split the budget so workers share progress; each epoch gives a worker at least this
/// many iterations, and there are at most this many epochs.
const MIN_EPOCH_ITERATIONS: usize = 25;
const MAX_EPOCHS: usize = 16;
/// Share of the epochs in which workers keep to their own starts (see `Model::run`).
const INDEPENDENT_EPOCHS: f64 = 0.5;

impl Model<'_> {
    /// Greedy fill per worker, then epochs of local search; returns the best layout found. In
    /// the first `INDEPENDENT_EPOCHS` share of the epochs each worker improves its own start,
    /// so the basins of different starts are all explored; after that, every epoch starts all
    /// workers from the best layout so far.
    pub(super) fn run(&self) -> Result<Sheets, NestError> {
        let settings = &self.job.settings;
        let workers = settings.workers;
        let mut own: Vec<(Score, Sheets)> = parallel(workers, |w| self.construct(w))
            .into_iter()
            .collect::<Result<_, _>>()?;
        let mut best = own[0].clone();
        let iterations = self.job.iteration_budget();
        let epochs = (iterations / (workers * MIN_EPOCH_ITERATIONS)).clamp(1, MAX_EPOCHS);
        let independent = (epochs as f64 * INDEPENDENT_EPOCHS) as usize;
        let slots = epochs * workers;
        for epoch in 0..=epochs {
            for start in &own {
                if start.0.better_than(&best.0) {
                    best = start.clone();
                }
            }
            if epoch == epochs {
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
            own = parallel(workers, |w| {
                let slot = epoch * workers + w;
                let budget = iterations / slots + usize::from(slot < iterations % slots);
                self.improve(
                    incumbents[w],
                    budget,
                    worker_rng(settings.seed, epoch + 1, w),
                )
            });
        }
        Ok(self.compressed(best.1, epochs + 1))
    }

    /// The layout with its lowest-topped sheet (the one whose used length counts) compressed
    /// through overlap ([`crate::compress`]), each worker on its own random stream with
    /// `COMPRESSION_EVALUATIONS` per iteration of the budget; the lowest top wins (ties to the
    /// lower worker).
    pub(super) fn compressed(&self, mut sheets: Sheets, epoch: usize) -> Sheets {
        let Some(footprints) = self.footprints.as_ref().filter(|_| !sheets.is_empty()) else {
            return sheets;
        };
        let top = |sheet: &[Placement]| {
            sheet
                .iter()
                .map(|s| self.shapes[s.part][s.rot].plain.bbox().y_max + s.t.1)
                .fold(self.usable.y_min, f32::max)
        };
        // The sheet whose used length counts, found as the score finds it: `sheets` lists the
        // sheets in key order and `rebuild` keeps that order.
        let problem = self.rebuild(&sheets);
        debug_assert!(problem
            .layouts()
            .values()
            .zip(&sheets)
            .all(|(layout, sheet)| layout.placed_items().len() == sheet.len()));
        let (key, _) = self.lowest_sheet(&problem);
        let lowest = problem
            .layouts()
            .keys()
            .position(|k| k == key)
            .expect("the lowest sheet is one of them");
        let settings = &self.job.settings;
        let budget = self.job.iteration_budget() * COMPRESSION_EVALUATIONS;
        let candidates = parallel(settings.workers, |w| {
            let mut rng = worker_rng(settings.seed, epoch, w);
            compress(footprints, &sheets[lowest], budget, &mut rng, |items| {
                self.clear(items)
            })
        });
        let best = candidates
            .into_iter()
            .min_by(|a, b| top(a).total_cmp(&top(b)))
            .expect("at least one worker");
        if top(&best) < top(&sheets[lowest]) {
            sheets[lowest] = best;
        }
        sheets
    }
}

/// Runs `job(w)` for `w in 0..workers` on that many threads; results in worker order.
fn parallel<T: Send>(workers: usize, job: impl Fn(usize) -> T + Sync) -> Vec<T> {
    if workers == 1 {
        return vec![job(0)];
    }
    std::thread::scope(|scope| {
        let handles: Vec<_> = (1..workers)
            .map(|w| {
                let job = &job;
                scope.spawn(move || job(w))
            })
            .collect();
        let mut results = vec![job(0)];
        results.extend(
            handles
                .into_iter()
                .map(|h| h.join().expect("nesting worker panicked")),
        );
        results
    })
}
