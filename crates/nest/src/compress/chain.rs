//! A compression chain: the lowest clear layout so far, the ceiling step it lowers the sheet
//! by, and what it does when a step fails (halve it, explore, or end), resumable slice after
//! slice of budget.

use rand_chacha::ChaCha8Rng;

use super::explore::{Exploration, EXPLORE_FAILURES};
use super::separate::{Effort, Outcome, Separation, FINE, PATIENT, QUICK};
use super::{all_under_ceiling, Footprints};
use crate::placement::Placement;

/// First ceiling step, as a share of the sheet's used length; halved after each failure down to
/// `SHRINK_LAST`.
const SHRINK_FIRST: f32 = 0.01;
const SHRINK_LAST: f32 = 0.001;
/// A fine chain's first and smallest step, as shares of the used length (sparrow's compression
/// phase, Gardeyn & Wauters 2025, its default configuration: 0.05 % to 0.001 %). It halves the
/// step on each failure (sparrow's failure-based decay), where sparrow lowers it with the time
/// left, which an anytime search does not know.
const FINE_FIRST: f32 = 0.0005;
const FINE_LAST: f32 = 0.00001;
/// Failed attempts in a row at a fine chain's smallest step after which it ends: its
/// separations are the most patient of all, and a pass of them takes time from exploration.
const FINE_ATTEMPTS: usize = 3;
/// Failed attempts in a row at the smallest step after which compression stops: the layout is
/// taken as one it can no longer improve (counted in attempts, so the stop is deterministic).
/// The compression gets the job's whole budget however early the search stopped, and this rule
/// keeps it from spending that budget on a sheet it cannot lower.
const STALL_ATTEMPTS: usize = 10;

/// One compression chain: the lowest clear layout so far and where the search stands (the
/// ceiling step, the pair weights, the exploration's pool), so that it can be resumed
/// ([`Chain::advance`]) as often as there is budget. Its [`Pace`] says how it steps. A quick
/// chain halves its step from 1 % down to the smallest, explores once the smallest has failed
/// `STALL_ATTEMPTS` times and ends by the stall rules ([`compress`]). A patient one is
/// sparrow's exploration (Gardeyn & Wauters 2025): it shrinks by the smallest step alone,
/// explores from the first failure (which goes into the pool) and never leaves an exploration
/// it has begun, keeping its pool at a ceiling for as long as its time lasts: the anytime
/// rounds give it that time in counted slices. A 1 % step is what a budget-bound compression
/// needs to get down fast; a patient chain starts from a layout already compressed, where a
/// step of 1 % fails, and each failure costs it millions of evaluations. A fine one is
/// sparrow's compression phase: steps under the patient one's, which take the room left below
/// a layout that exploration could not lower by a whole step.
#[derive(Clone)]
pub(crate) struct Chain<'f> {
    footprints: &'f Footprints,
    pub(super) best: Vec<Placement>,
    best_top: f32,
    /// The used length of the start, which the ceiling steps are shares of.
    length: f32,
    step: f32,
    failed_at_last: usize,
    /// The small steps' pair weights, carried from one attempt to the next (see
    /// `Separation::weights`).
    weights: Vec<f32>,
    exploring: Option<Exploration>,
    /// A patient chain's separation that its last slice ended in the middle of, and whether it
    /// is an exploration's: the next slice resumes it, so a separation is judged by its own
    /// stall and strike rules, never by where a slice happened to end.
    paused: Option<(Separation<'f>, bool)>,
    spent: usize,
    pace: Pace,
    ended: bool,
    pub(super) rng: ChaCha8Rng,
}

/// How a [`Chain`] lowers its ceiling and what it does when a step fails.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Pace {
    /// The budget-bound compression of [`compress`]: steps from 1 % down to 0.1 %, exploration
    /// once the smallest keeps failing, an end by the stall rules.
    Quick,
    /// Sparrow's exploration: steps of 0.1 %, exploration from the first failure, no end.
    Patient,
    /// Sparrow's compression phase: steps from 0.05 % down to 0.001 %, no exploration, an end
    /// after `FINE_ATTEMPTS` failures at the smallest.
    Fine,
}

impl Pace {
    /// The first and the smallest ceiling step, as shares of the used length.
    fn steps(self) -> (f32, f32) {
        match self {
            Pace::Quick => (SHRINK_FIRST, SHRINK_LAST),
            Pace::Patient => (SHRINK_LAST, SHRINK_LAST),
            Pace::Fine => (FINE_FIRST, FINE_LAST),
        }
    }

    /// How hard its separations try.
    fn effort(self) -> Effort {
        match self {
            Pace::Quick => QUICK,
            Pace::Patient => PATIENT,
            Pace::Fine => FINE,
        }
    }
}

impl<'f> Chain<'f> {
    pub(crate) fn new(
        footprints: &'f Footprints,
        sheet: &[Placement],
        rng: ChaCha8Rng,
        pace: Pace,
    ) -> Self {
        let best = sheet.to_vec();
        let best_top = top(footprints, &best);
        let bottom = best
            .iter()
            .map(|s| {
                let f = &footprints[s.part][s.rot];
                f.y.0 + f.pieces.bounds[1]
            })
            .fold(f32::MAX, f32::min);
        let length = best_top - bottom;
        Chain {
            footprints,
            weights: vec![1.0; best.len() * best.len()],
            ended: best.len() < 2,
            best,
            best_top,
            length,
            step: pace.steps().0 * length,
            failed_at_last: 0,
            exploring: None,
            paused: None,
            spent: 0,
            pace,
            rng,
        }
    }

    /// The smallest ceiling step.
    fn last_step(&self) -> f32 {
        self.pace.steps().1 * self.length
    }

    /// True once the chain can do no more (too few parts, or no lower ceiling leaves room for
    /// the tallest part, or, if not patient, its stall rules).
    pub(crate) fn ended(&self) -> bool {
        self.ended
    }

    /// A copy of this chain (its layouts, ceiling step, weights, exploration pool and paused
    /// separation) that goes on drawing from `rng`.
    pub(crate) fn fork(&self, rng: ChaCha8Rng) -> Self {
        Chain {
            rng,
            ..self.clone()
        }
    }

    /// The ceiling the chain is working under: its exploration's, else one step below its best.
    pub(crate) fn ceiling(&self) -> f32 {
        match &self.exploring {
            Some(exploration) => exploration.ceiling,
            None => self.best_top - self.step,
        }
    }

    /// The top of the lowest clear layout so far.
    pub(crate) fn top(&self) -> f32 {
        self.best_top
    }

    /// The lowest clear layout so far.
    pub(crate) fn best(&self) -> &[Placement] {
        &self.best
    }

    /// Runs the chain for `budget` more overlap evaluations (the last separation may run past
    /// them by its own count), or until its stall rules end it; true if `stop` ended it first.
    pub(crate) fn advance(
        &mut self,
        budget: usize,
        clear: &impl Fn(&[Placement]) -> bool,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> bool {
        let target = self.spent.saturating_add(budget);
        while !self.ended && self.spent < target {
            if stop() {
                return true;
            }
            let Some((mut separation, explores, fresh)) = self.next_separation() else {
                continue;
            };
            // Setting up counts as one evaluation per part, so that attempts which need no moves
            // (and a judge that rejects them) still spend the budget.
            if fresh {
                self.spent += separation.n();
            }
            let before = separation.evaluations;
            let outcome = separation.run(
                &mut self.rng,
                before + target.saturating_sub(self.spent),
                stop,
            );
            self.spent += separation.evaluations - before;
            if outcome == Outcome::Paused && self.pace != Pace::Quick {
                // Out of slice (or stopped): resume it in the next slice.
                self.paused = Some((separation, explores));
                continue;
            }
            let separated = outcome == Outcome::Clear && clear(&separation.items);
            self.settle(separation, separated, explores);
        }
        false
    }

    /// The separation to run next, whether it is an exploration's and whether it is new (not a
    /// paused one resumed); `None` where the chain only changed its state (began an exploration,
    /// halved its step, or ended), for the caller to ask again.
    fn next_separation(&mut self) -> Option<(Separation<'f>, bool, bool)> {
        let footprints = self.footprints;
        let last = self.last_step();
        let effort = self.pace.effort();
        if let Some((paused, explores)) = self.paused.take() {
            return Some((paused, explores, false));
        }
        if let Some(exploration) = self.exploring.as_mut() {
            if self.pace == Pace::Quick && exploration.failures >= EXPLORE_FAILURES {
                self.ended = true;
                return None;
            }
            return Some((exploration.start(footprints, effort), true, true));
        }
        if self.pace == Pace::Fine && self.failed_at_last >= FINE_ATTEMPTS {
            // A fine chain's smallest step keeps failing: what is left takes exploration.
            self.ended = true;
            return None;
        }
        if self.failed_at_last >= STALL_ATTEMPTS {
            // The smallest step keeps failing: explore at it, and go back to small steps from
            // whatever clear layout exploration finds.
            self.exploring = Exploration::new(footprints, &self.best, self.best_top - last);
            self.ended = self.exploring.is_none();
            return None;
        }
        let ceiling = self.best_top - self.step;
        let Some(trial) = all_under_ceiling(footprints, &self.best, ceiling) else {
            // A part is taller than the room under this ceiling: no lower ceiling will do.
            if self.step <= last {
                self.ended = true;
            }
            self.step = (self.step * 0.5).max(last);
            return None;
        };
        let weights = std::mem::take(&mut self.weights);
        Some((
            Separation::new(footprints, trial, ceiling, weights, effort),
            false,
            true,
        ))
    }

    /// Takes the end of a separation that ran to its rules: an exploration's goes to the
    /// exploration (a clear layout ends it), a small step's keeps its weights and either lowers
    /// the best layout or halves the step.
    fn settle(&mut self, mut separation: Separation<'f>, separated: bool, explores: bool) {
        let footprints = self.footprints;
        if explores {
            let exploration = self.exploring.as_mut().expect("an exploration separates");
            if let Some(found) =
                exploration.finish(footprints, separation, separated, &mut self.rng)
            {
                self.best_top = top(footprints, &found);
                self.best = found;
                self.failed_at_last = 0;
                self.exploring = None;
            }
            return;
        }
        self.weights = std::mem::take(&mut separation.weights);
        let last = self.last_step();
        if separated {
            self.best = separation.items;
            self.best_top = top(footprints, &self.best);
        } else if self.pace == Pace::Patient && self.step <= last {
            self.exploring = Some(Exploration::after(footprints, separation, &mut self.rng));
        } else {
            if self.step <= last {
                self.failed_at_last += 1;
            }
            self.step = (self.step * 0.5).max(last);
        }
    }
}

/// The top of a layout: its highest shape's top edge.
fn top(footprints: &Footprints, items: &[Placement]) -> f32 {
    items
        .iter()
        .map(|s| footprints[s.part][s.rot].pieces.bounds[3] + s.t.1)
        .fold(f32::MIN, f32::max)
}

#[cfg(test)]
mod tests {
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::compress::test_shapes::*;

    #[test]
    fn a_patient_chain_keeps_exploring_where_compression_gives_up_and_resumes_where_it_stopped() {
        // Four bars of height 1 in rows of at most two: top 2 is the least, so every ceiling
        // below fails. Compression ends by its stall rules well within an endless budget; a
        // patient chain spends every slice it is given, a slice starts where the last one
        // ended, and its layout stays clear, between the start and top 2.
        let start = two_rows_of_bars();
        let footprints = bars();
        let mut impatient = chain_from(&footprints, &start, Pace::Quick);
        assert!(!impatient.advance(usize::MAX / 2, &bars_clear, &never));
        assert!(impatient.ended && impatient.spent < usize::MAX / 2);
        let mut patient = chain_from(&footprints, &start, Pace::Patient);
        let slice = 2 * impatient.spent;
        for k in 1..=3 {
            assert!(!patient.advance(slice, &bars_clear, &never));
            assert!(!patient.ended);
            assert!(
                patient.spent >= k * slice,
                "slice {k}: {} spent",
                patient.spent
            );
        }
        assert!(patient.exploring.is_some());
        let top = |items: &[Placement]| items.iter().map(|s| s.t.1 + 1.0).fold(0.0, f32::max);
        let best = patient.best();
        assert!(bars_clear(best));
        assert!(
            top(best) >= 2.0 && top(best) <= top(&start),
            "top {}",
            top(best)
        );
    }

    #[test]
    fn a_patient_chain_shrinks_by_the_smallest_step_and_explores_from_its_first_failure() {
        // Two rows of bars 0.01 apart: steps of 0.1 % of the used length close the gap, and the
        // first ceiling under top 2 fails. The patient chain never takes a larger step, and
        // that first failure starts an exploration whose pool holds it, with a disrupted copy
        // to separate next. The impatient chain halves its step on a failure instead.
        let start = two_rows_of_bars();
        let footprints = bars();
        let mut patient = chain_from(&footprints, &start, Pace::Patient);
        let smallest = SHRINK_LAST * patient.length;
        let mut slices = 0;
        while patient.exploring.is_none() && slices < 1000 {
            assert_eq!(patient.step, smallest);
            patient.advance(200, &bars_clear, &never);
            slices += 1;
        }
        let exploration = patient
            .exploring
            .as_ref()
            .expect("a failure starts an exploration");
        assert_eq!((exploration.failures, exploration.pool.len()), (1, 1));
        assert!(exploration.pool[0].0 > 0.0);
        assert_ne!(exploration.current, exploration.pool[0].1);
        let top = |items: &[Placement]| items.iter().map(|s| s.t.1 + 1.0).fold(0.0, f32::max);
        assert!(top(patient.best()) < top(&start) && top(patient.best()) >= 2.0);
        assert!(exploration.ceiling < top(patient.best()));

        let mut impatient = chain_from(&footprints, &start, Pace::Quick);
        let first = impatient.step;
        impatient.advance(2000, &bars_clear, &never);
        assert!(impatient.exploring.is_none());
        assert!(first > smallest && impatient.step < first);
    }

    #[test]
    fn a_fine_chain_takes_a_gap_under_the_patient_step_and_ends_without_exploring() {
        // Two rows of bars 0.0015 further apart than the overlap measure's clearance, which
        // makes 2 + clearance the least top: the patient chain's step (0.1 % of the used
        // length, about 0.002) is larger than that room, so no patient step can lower the top.
        // A fine chain steps by at most 0.05 % (about 0.001), halving on each failure, never
        // explores, takes some of the room and ends after its failures at its smallest step.
        let room = 0.0015;
        let row = 1.0 + crate::overlap::CLEARANCE_MM + room;
        let start = vec![
            at(0, 0.0, 0.0),
            at(1, 6.1, 0.0),
            at(0, 0.0, row),
            at(1, 6.1, row),
        ];
        let footprints = bars();
        let mut fine = chain_from(&footprints, &start, Pace::Fine);
        assert!(SHRINK_LAST * fine.length > room);
        let (first, smallest) = (FINE_FIRST * fine.length, FINE_LAST * fine.length);
        let mut slices = 0;
        while !fine.ended && slices < 100_000 {
            assert!(fine.step <= first && fine.step >= smallest);
            assert!(fine.exploring.is_none());
            fine.advance(1000, &bars_clear, &never);
            slices += 1;
        }
        assert!(fine.ended, "ends by its own rule");
        assert_eq!((fine.step, fine.failed_at_last), (smallest, FINE_ATTEMPTS));
        assert!(bars_clear(fine.best()));
        let least = 2.0 + crate::overlap::CLEARANCE_MM;
        assert!(
            fine.top() >= least - 1e-6 && fine.top() < row + 1.0 - first / 2.0,
            "top {}",
            fine.top()
        );
    }

    #[test]
    fn a_fork_carries_on_from_the_chain_it_copies_and_draws_from_its_own_stream() {
        // Four bars exploring at a ceiling they cannot clear (top 2 is the least): after a
        // slice the chain holds a pool. A fork on the chain's own stream goes on exactly as the
        // chain does; a fork on another stream starts from the same layout and pool and goes
        // another way.
        let start = two_rows_of_bars();
        let footprints = bars();
        let mut chain = chain_from(&footprints, &start, Pace::Patient);
        assert!(!chain.advance(20_000_000, &bars_clear, &never));
        let pool = |c: &Chain| c.exploring.as_ref().map(|e| e.pool.len());
        assert!(pool(&chain).is_some_and(|n| n > 0));
        let mut same = chain.fork(chain.rng.clone());
        let mut other = chain.fork(ChaCha8Rng::seed_from_u64(6));
        assert_eq!(other.best(), chain.best());
        assert_eq!(pool(&other), pool(&chain));
        assert_eq!(other.spent, chain.spent);
        for c in [&mut chain, &mut same, &mut other] {
            assert!(!c.advance(500_000, &bars_clear, &never));
        }
        assert_eq!(same.best(), chain.best());
        assert_eq!(same.spent, chain.spent);
        // Where each stands: the separation it paused in, else the exploration's next start.
        let current = |c: &Chain| match &c.paused {
            Some((separation, _)) => separation.items.clone(),
            None => c
                .exploring
                .as_ref()
                .map_or_else(Vec::new, |e| e.current.clone()),
        };
        assert_eq!(current(&same), current(&chain));
        assert_ne!(current(&other), current(&chain));
    }
}
