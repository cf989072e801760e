//! One separation: the guided local search that moves overlapping parts under a fixed ceiling
//! until none overlap, with pair weights that grow while a pair keeps colliding, stalls and
//! strikes that end it, and pauses that let a chain resume it.

use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

use super::Footprints;
use crate::overlap::{bounds_meet, loss, overlap, overlap_reaching, shifted, Box32, Pieces};
use crate::placement::Placement;

/// Sweeps over the overlapping parts without a 1 % fall of the total overlap before an attempt
/// gives up (12 gave up on attempts that 40 resolve: bench strip density +1.0 on one batch).
const STALL_SWEEPS: usize = 40;
/// Weight of an overlapping pair grows by up to this factor per sweep (the most overlapping pair
/// by all of it); a clear pair's weight decays back towards 1. Growth 1.3 let the same pairs trade
/// overlap back and forth; 2.0 resolved more attempts (strip density +1.0 on the bench's first
/// batch) and 3.0 fewer.
const WEIGHT_GROWTH: f32 = 2.0;
/// Every overlapping pair's weight grows by at least this factor (sparrow's 1.2), so that pairs
/// much shallower than the worst still get heavier while they keep colliding.
const WEIGHT_LEAST_GROWTH: f32 = 1.2;
const WEIGHT_DECAY: f32 = 0.95;
/// The least fall of the least overlap in a stall that does not count as a strike (under 2 %
/// is a strike: sparrow's 0.98).
const STRIKE_GAIN: f32 = 0.98;

/// How hard a separation tries: the stalls in a row it takes before it gives up.
#[derive(Debug, Clone, Copy)]
pub(super) struct Effort {
    strikes: usize,
    /// Sweeps without a 1 % fall of the total overlap that make a stall.
    stall: usize,
    /// Samples of a move refined by a coarse descent (see `COARSE_DESCENT`).
    pub(super) descents: usize,
    /// Whether a sweep is the better of two tries from the same layout
    /// ([`Separation::sweep`]): sparrow's separator with two workers, as the benchmarks run it
    /// (Gardeyn & Wauters 2025, Algorithm 10). On strips of parts of whole-number sizes, where
    /// a layout gets shorter only once exploration finds another arrangement, the better of two
    /// tries cleared ceilings that as many evaluations in single sweeps did not.
    best_of_two: bool,
}

/// The compression within a budget, where evaluations are the cost: one stall of
/// `STALL_SWEEPS` ends a separation, and a move refines its best sample alone (refining three,
/// the 60-actuator batch took a quarter more CPU for its evaluations, 6.4 s against 5.2 s, and the
/// lab's measuring strips came out no denser).
pub(super) const QUICK: Effort = Effort {
    strikes: 1,
    stall: STALL_SWEEPS,
    descents: 1,
    best_of_two: false,
};
/// The patient chains of the anytime rounds, which have time to spend: sparrow's exploration
/// separator (Gardeyn & Wauters 2025, its default configuration), with 200 sweeps to a stall,
/// three strikes, three samples refined per move and the better of two tries a sweep.
pub(super) const PATIENT: Effort = Effort {
    strikes: 3,
    stall: 200,
    descents: 3,
    best_of_two: true,
};
/// Fine chains: sparrow's compression separator (its default configuration), with 100 sweeps
/// to a stall, five strikes, three samples refined per move and the better of two tries a
/// sweep.
pub(super) const FINE: Effort = Effort {
    strikes: 5,
    stall: 100,
    descents: 3,
    best_of_two: true,
};

/// The guided local search of one compression attempt: parts under a fixed ceiling, with their
/// pairwise overlaps and weights.
#[derive(Clone)]
pub(super) struct Separation<'a> {
    pub(super) footprints: &'a Footprints,
    pub(super) items: Vec<Placement>,
    pub(super) ceiling: f32,
    /// Shape bounds of each item where it is.
    pub(super) bounds: Vec<Box32>,
    /// `n x n`, symmetric: unweighted loss of each pair ([`loss`]).
    overlaps: Vec<f32>,
    /// Kept from one small step to the next (where sparrow starts each strip width from unit
    /// weights): a pair that kept colliding under the last ceiling will likely collide under
    /// the next, and starting it heavy separates it sooner, which leaves more of the budget for
    /// lowering the ceiling (denser layouts on most strips than unit weights at every step).
    /// Exploration starts from unit weights: it is there to leave the structure the small steps
    /// are stuck in.
    pub(super) weights: Vec<f32>,
    pub(super) effort: Effort,
    pub(super) evaluations: usize,
    /// Where the sweeps stand, so that a paused separation resumes where it stopped: the least
    /// total overlap so far, sweeps since it last fell by 1 %, stalls in a row that each
    /// lowered it by under `STRIKE_GAIN`, the least at the start of this strike, and (with
    /// strikes) the layout it was reached at.
    least: f32,
    stalled: usize,
    struck: usize,
    strike_start: f32,
    least_layout: Option<Layout>,
}

/// Items, their bounds and their pairwise overlaps: a layout a separation can go back to.
type Layout = (Vec<Placement>, Vec<Box32>, Vec<f32>);

/// How a call of [`Separation::run`] ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Outcome {
    /// Nothing overlaps.
    Clear,
    /// The stall and strike rules gave up.
    GaveUp,
    /// The evaluations allowed ran out, or `stop` said so, with the rules still going: the
    /// separation can be resumed.
    Paused,
}

impl<'a> Separation<'a> {
    /// `weights`: `n x n`, the chain's (see `weights`); `effort`: how hard it tries.
    pub(super) fn new(
        footprints: &'a Footprints,
        items: Vec<Placement>,
        ceiling: f32,
        weights: Vec<f32>,
        effort: Effort,
    ) -> Self {
        let n = items.len();
        debug_assert_eq!(weights.len(), n * n, "one weight per ordered pair of parts");
        let mut separation = Separation {
            footprints,
            bounds: Vec::with_capacity(n),
            overlaps: vec![0.0; n * n],
            weights,
            items,
            ceiling,
            effort,
            evaluations: 0,
            least: 0.0,
            stalled: 0,
            struck: 0,
            strike_start: 0.0,
            least_layout: None,
        };
        for i in 0..n {
            separation
                .bounds
                .push(separation.bounds_of(separation.items[i]));
        }
        for i in 0..n {
            separation.refresh(i);
        }
        separation.least = separation.total();
        separation.strike_start = separation.least;
        if effort.strikes > 1 {
            separation.least_layout = Some(separation.layout());
        }
        separation
    }

    fn layout(&self) -> Layout {
        (
            self.items.clone(),
            self.bounds.clone(),
            self.overlaps.clone(),
        )
    }

    pub(super) fn n(&self) -> usize {
        self.items.len()
    }

    pub(super) fn pieces(&self, s: Placement) -> &'a Pieces {
        &self.footprints[s.part][s.rot].pieces
    }

    pub(super) fn bounds_of(&self, s: Placement) -> Box32 {
        shifted(self.pieces(s).bounds, [s.t.0, s.t.1])
    }

    /// The collision loss of shape `a` at `t` against item `j` where it is, or some loss of at
    /// least `enough` once it is known to reach that (`f32::MAX` for the exact loss).
    pub(super) fn loss_against(&self, a: &Pieces, t: (f32, f32), j: usize, enough: f32) -> f32 {
        let b = self.items[j];
        let pb = self.pieces(b);
        let o = overlap(
            a,
            [t.0, t.1],
            pb,
            [b.t.0, b.t.1],
            self.footprints.table.as_ref(),
            overlap_reaching(enough, a, pb),
        );
        loss(o, a, pb)
    }

    /// Recomputes item `i`'s losses against every other item.
    pub(super) fn refresh(&mut self, i: usize) {
        let n = self.n();
        let (a, ta) = (self.pieces(self.items[i]), self.items[i].t);
        for j in 0..n {
            let o = if j == i || !bounds_meet(self.bounds[i], self.bounds[j]) {
                0.0
            } else {
                self.loss_against(a, ta, j, f32::MAX)
            };
            self.overlaps[i * n + j] = o;
            self.overlaps[j * n + i] = o;
        }
    }

    pub(super) fn total(&self) -> f32 {
        self.overlaps.iter().sum::<f32>() / 2.0
    }

    fn colliding(&self, i: usize) -> bool {
        let n = self.n();
        self.overlaps[i * n..(i + 1) * n].iter().any(|&o| o > 0.0)
    }

    /// Moves parts until nothing overlaps ([`Outcome::Clear`]) or the total overlap stalls
    /// ([`Outcome::GaveUp`]); pauses once its evaluations reach `limit` or `stop` says so. With
    /// `Effort::strikes` above 1 a stall is a strike, as in sparrow's separator (Gardeyn &
    /// Wauters 2025, Algorithm 9): the parts go back to the least overlapping layout of the
    /// separation, keeping their weights, and the sweeps go on, until that many stalls in a row
    /// have each lowered the least overlap by under `STRIKE_GAIN`; the parts are then left at
    /// that least overlapping layout.
    pub(super) fn run(
        &mut self,
        rng: &mut ChaCha8Rng,
        limit: usize,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Outcome {
        let strikes = self.effort.strikes;
        loop {
            if self.least == 0.0 {
                return Outcome::Clear;
            }
            if self.stalled >= self.effort.stall && strikes > 1 {
                self.struck = if self.least > STRIKE_GAIN * self.strike_start {
                    self.struck + 1
                } else {
                    0
                };
                if let Some(layout) = self.least_layout.take() {
                    self.restore(&layout);
                    self.least_layout = Some(layout);
                }
                if self.struck < strikes {
                    self.stalled = 0;
                    self.strike_start = self.least;
                }
            }
            if self.stalled >= self.effort.stall {
                return Outcome::GaveUp;
            }
            if self.evaluations >= limit || stop() {
                return Outcome::Paused;
            }
            self.sweep(rng);
            let total = self.total();
            if total < 0.99 * self.least {
                self.stalled = 0;
            } else {
                self.stalled += 1;
            }
            if total < self.least && strikes > 1 {
                self.least_layout = Some(self.layout());
            }
            self.least = self.least.min(total);
            if total == 0.0 {
                return Outcome::Clear;
            }
            self.reweigh();
        }
    }

    /// One sweep of the separation: every colliding part moved once, in a random order. With
    /// [`Effort::best_of_two`], two tries from the same layout, each in an order of its own, of
    /// which the one that ends with the less weighted overlap is kept (a tie to the second), as
    /// sparrow's separator gives every worker the same layout, lets each move the parts in its
    /// own order and keeps the best (Gardeyn & Wauters 2025, Algorithm 10). Its workers run side
    /// by side; here the tries run one after the other on the chain's own thread, so the sweep
    /// costs twice the evaluations. That is still the better use of them where a separation has
    /// to get out of a deep collision: a try that makes the weighted overlap worse is thrown away
    /// instead of being the next sweep's start.
    ///
    /// Layouts change hands rather than being copied: the first try's layout is swapped out for
    /// the start, so the sweep copies the layout once.
    fn sweep(&mut self, rng: &mut ChaCha8Rng) {
        if !self.effort.best_of_two {
            self.move_colliding(rng);
            return;
        }
        let start = self.layout();
        self.move_colliding(rng);
        let first = self.weighted();
        let first_layout = self.replace(start);
        self.move_colliding(rng);
        if first < self.weighted() {
            self.replace(first_layout);
        }
    }

    /// Moves every colliding part once, in a random order (a part that an earlier move has
    /// cleared stays where it is).
    fn move_colliding(&mut self, rng: &mut ChaCha8Rng) {
        let mut order: Vec<usize> = (0..self.n()).filter(|&i| self.colliding(i)).collect();
        order.shuffle(rng);
        for i in order {
            if self.colliding(i) {
                self.move_item(i, rng);
            }
        }
    }

    /// The weighted overlap summed over ordered pairs (so each pair twice): what a sweep's tries
    /// are compared by.
    fn weighted(&self) -> f32 {
        self.overlaps
            .iter()
            .zip(&self.weights)
            .map(|(o, w)| o * w)
            .sum()
    }

    /// Puts the parts where `layout` has them, and hands back the layout they leave.
    fn replace(&mut self, layout: Layout) -> Layout {
        (
            std::mem::replace(&mut self.items, layout.0),
            std::mem::replace(&mut self.bounds, layout.1),
            std::mem::replace(&mut self.overlaps, layout.2),
        )
    }

    /// Puts the parts back where `layout` has them.
    fn restore(&mut self, layout: &Layout) {
        self.items.clone_from(&layout.0);
        self.bounds.clone_from(&layout.1);
        self.overlaps.clone_from(&layout.2);
    }

    /// Heavier weights on the pairs that still overlap (most on the worst), lighter on the rest.
    fn reweigh(&mut self) {
        let worst = self.overlaps.iter().copied().fold(0.0, f32::max);
        for (w, &o) in self.weights.iter_mut().zip(&self.overlaps) {
            *w = if o > 0.0 {
                *w * (WEIGHT_LEAST_GROWTH + (WEIGHT_GROWTH - WEIGHT_LEAST_GROWTH) * o / worst)
            } else {
                (*w * WEIGHT_DECAY).max(1.0)
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::compress::test_shapes::*;

    #[test]
    fn a_separation_starts_from_the_weights_it_is_given() {
        // Two squares overlapping by half: their pair starts at the weight the chain carried
        // over (3, not 1), and a sweep that leaves them overlapping doubles it (the most
        // overlapping pair grows by all of `WEIGHT_GROWTH`), for the next attempt to start from.
        let footprints = squares();
        let items = vec![at(0, 0.0, 0.0), at(0, 0.5, 0.0)];
        let carried = vec![1.0, 3.0, 3.0, 1.0];
        let mut separation = Separation::new(&footprints, items, 10.0, carried, QUICK);
        assert_eq!(separation.weights, [1.0, 3.0, 3.0, 1.0]);
        assert!(separation.total() > 0.0);
        separation.reweigh();
        assert_eq!(separation.weights, [1.0, 6.0, 6.0, 1.0]);
    }

    #[test]
    fn a_sweep_of_two_tries_keeps_the_one_with_the_least_weighted_overlap() {
        // Three unit squares under a ceiling of 1 on a sheet 2.1 wide: one row holds two, so
        // every try leaves some overlap, and two tries from the same layout end differently.
        let footprints = squares();
        let start = vec![at(0, 0.0, 0.0), at(0, 0.5, 0.0), at(0, 1.1, 0.0)];
        let single = Effort {
            best_of_two: false,
            ..PATIENT
        };
        const { assert!(PATIENT.best_of_two) };
        let mut differed = 0;
        for seed in 0..10 {
            let fresh =
                |effort| Separation::new(&footprints, start.clone(), 1.0, vec![1.0; 9], effort);
            // The two tries replayed one after the other on one stream, each from the start.
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let mut first = fresh(single);
            first.sweep(&mut rng);
            let mut second = fresh(single);
            second.sweep(&mut rng);
            let mut two = fresh(PATIENT);
            two.sweep(&mut ChaCha8Rng::seed_from_u64(seed));
            let kept = if first.weighted() < second.weighted() {
                &first
            } else {
                &second
            };
            assert_eq!(two.items, kept.items, "seed {seed}");
            assert_eq!(two.weighted(), first.weighted().min(second.weighted()));
            assert_eq!(two.evaluations, first.evaluations + second.evaluations);
            differed += usize::from(first.weighted() != second.weighted());
        }
        assert!(
            differed > 0,
            "the tries always ended alike: nothing was chosen"
        );
    }

    #[test]
    fn a_separation_with_strikes_ends_at_the_least_overlap_it_reached() {
        // Three unit squares under a ceiling of 1 on a sheet 2.1 wide: one row holds two, so
        // overlap never reaches zero. With strikes, the parts end where the total overlap was
        // least, which is never above where they started.
        let footprints = squares();
        let start = vec![at(0, 0.0, 0.0), at(0, 0.5, 0.0), at(0, 1.1, 0.0)];
        for seed in 0..5 {
            let mut separation =
                Separation::new(&footprints, start.clone(), 1.0, vec![1.0; 9], PATIENT);
            let before = separation.total();
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            assert_eq!(
                separation.run(&mut rng, usize::MAX, &never),
                Outcome::GaveUp
            );
            assert!(separation.total() > 0.0);
            assert!(separation.total() <= before, "seed {seed}");
            // The overlaps kept are those of the parts where they are.
            let total = separation.total();
            for i in 0..3 {
                separation.refresh(i);
            }
            assert_eq!(separation.total(), total);
        }
    }

    #[test]
    fn a_separation_paused_slice_by_slice_ends_as_one_run_through() {
        // Five squares pushed under a ceiling of 3.1 on a sheet 2.1 wide (three rows of two hold
        // them): one call with no limit, and calls of 100 evaluations each resumed on the same
        // stream, make the same sweeps, so they end alike, at the same layout.
        let footprints = squares();
        let start = vec![
            at(0, 0.0, 0.0),
            at(0, 0.3, 0.2),
            at(0, 0.6, 0.4),
            at(0, 0.9, 0.6),
            at(0, 1.1, 0.8),
        ];
        let fresh = || Separation::new(&footprints, start.clone(), 3.1, vec![1.0; 25], PATIENT);
        let mut whole = fresh();
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let outcome = whole.run(&mut rng, usize::MAX, &never);
        assert_eq!(outcome, Outcome::Clear);
        let mut sliced = fresh();
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let mut pauses = 0;
        let last = loop {
            let limit = sliced.evaluations + 100;
            match sliced.run(&mut rng, limit, &never) {
                Outcome::Paused => pauses += 1,
                other => break other,
            }
        };
        assert!(pauses > 0, "the slices are shorter than the separation");
        assert_eq!(last, outcome);
        assert_eq!(sliced.items, whole.items);
        assert_eq!(sliced.evaluations, whole.evaluations);
    }
}
