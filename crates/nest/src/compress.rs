//! Compression of one sheet through overlap: the last stage of the irregular nester.
//!
//! Ruin and recreate only puts parts where they are clear, so the parts under the top of a
//! sheet rarely get past one another. Strip packers of the sparrow kind (Gardeyn & Wauters 2025,
//! after Egeblad et al. 2007 and Umetani et al. 2009) do better by letting them overlap: lower
//! the ceiling a little, push every part that reaches above it down into its neighbours, and
//! move parts one at a time to where they overlap the others least (a guided local search on
//! the collision loss of [`super::overlap`]) until no overlap is left. A move samples spots on
//! the sheet and near the part and refines the best by coordinate descent in steps that are
//! shares of the part's size (`Separation::descend`). Pairs that keep overlapping get
//! heavier weights, so the search stops trading the same collision back and forth; the weights
//! carry over from one ceiling step to the next (sparrow starts each width afresh). If the
//! overlap does not reach zero within a few rounds the attempt fails and the ceiling is lowered
//! by less next time; a layout that comes out clear is checked by jagua-rs before it is kept.
//!
//! Where the smallest step keeps failing (`STALL_ATTEMPTS` in a row), the layout's structure is
//! what holds it: which parts share a row across the sheet. Small steps never change that, so
//! compression turns to sparrow's exploration ([`Exploration`]): it stays at the ceiling it failed
//! at, keeps the failed layouts in a pool ordered by their overlap, takes one back (the better
//! ones more often), swaps two large parts of different shapes in it (the parts a swapped part
//! now covers go to the room it left) and separates again. A swap moves a part into another
//! row, which is how rows whose lengths do not add up to the sheet width get re-partitioned. A
//! clear layout sends compression back to its small steps; `EXPLORE_FAILURES` failures in a
//! row, or the budget, end it. A [`Chain`] holds all of this state, so that the anytime rounds
//! can resume a *patient* chain, slice after slice of budget, down to a separation a slice
//! ended in the middle of ([`Outcome::Paused`]): a separation cut short would count as failed
//! however near it was to clear. A patient chain is sparrow's exploration alone: it shrinks by
//! the smallest step, explores from its first failure and never gives an exploration up. A
//! *fine* chain is sparrow's compression phase: steps of 0.05 % down to 0.001 % and no
//! exploration, for the rounds' compression passes.
//!
//! Work is counted in overlap evaluations, never time, and the random stream is the caller's,
//! so the same input gives the same layout on any machine.

use rand::seq::SliceRandom;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::overlap::{
    bounds_meet, loss, overlap, overlap_reaching, shifted, Bounds, Pieces, Projections,
};
use crate::placement::Placement;

/// A part at one of its rotations, as compression sees it.
pub(crate) struct Footprint {
    /// The collision shape (inflated by half the separation) at the origin.
    pub(crate) pieces: Pieces,
    /// Translations that keep the shape inside the usable sheet.
    pub(crate) x: (f32, f32),
    pub(crate) y: (f32, f32),
}

impl Footprint {
    /// An axis-aligned `width` x `height` rectangle's footprint, free to move from the origin to
    /// `x_max` across and `y_max` up: the shape the unit tests of the compression and of the
    /// rounds nest.
    #[cfg(test)]
    pub(crate) fn rectangle(width: f32, height: f32, x_max: f32, y_max: f32) -> Footprint {
        Footprint {
            pieces: Pieces::new(&[[0., 0.], [width, 0.], [width, height], [0., height]])
                .expect("a rectangle is a convex piece"),
            x: (0.0, x_max),
            y: (0.0, y_max),
        }
    }

    /// Translations (x range, y range) that keep the shape inside the usable sheet and its top
    /// at most `ceiling`; `None` if there are none.
    fn range_under(&self, ceiling: f32) -> Option<((f32, f32), (f32, f32))> {
        let y_max = self.y.1.min(ceiling - self.pieces.bounds[3]);
        (self.x.0 <= self.x.1 && self.y.0 <= y_max).then_some((self.x, (self.y.0, y_max)))
    }
}

/// Every part at every rotation (`[part][rotation]`), with the table of their pieces'
/// projections ([`Projections`]) that makes the overlap queries cheap. Reads as the slice of
/// footprints.
pub(crate) struct Footprints {
    shapes: Vec<Vec<Footprint>>,
    table: Option<Projections>,
}

impl Footprints {
    pub(crate) fn new(mut shapes: Vec<Vec<Footprint>>) -> Footprints {
        let mut pieces: Vec<&mut Pieces> = shapes
            .iter_mut()
            .flat_map(|rotations| rotations.iter_mut().map(|f| &mut f.pieces))
            .collect();
        let table = Projections::new(&mut pieces);
        Footprints { shapes, table }
    }
}

impl std::ops::Deref for Footprints {
    type Target = [Vec<Footprint>];

    fn deref(&self) -> &Self::Target {
        &self.shapes
    }
}

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
/// Failed separations in a row after which exploration gives up on a ceiling (and compression
/// ends): counted, like everything here, so the stop is deterministic. On strips of a dozen
/// large parts a limit of 400 found nothing that 50 did not; the budget binds first.
const EXPLORE_FAILURES: usize = 50;
/// Parts count as large, and are the ones exploration swaps, from the largest down until they
/// make up this share of the parts' area (sparrow's percentile, Gardeyn & Wauters 2025).
const LARGE_AREA_SHARE: f32 = 0.75;
/// Exploration takes back the failed layout at rank `|N(0, POOL_SPREAD)|` of the pool's length
/// (clipped below 1): mostly the least overlapping ones, now and then a worse one (sparrow's
/// setting).
const POOL_SPREAD: f32 = 0.25;
/// The most failed layouts an exploration's pool keeps: past it the most overlapping goes. A
/// rank drawn from `|N(0, POOL_SPREAD)|` falls past three quarters of the pool once in 370, so
/// the worst of a long exploration's failures are all but never taken back, and without a bound
/// a chain exploring one ceiling for an hour would hold every failure it met (each a copy of the
/// layout), and copy them all each round it is followed ([`Chain::fork`]).
const POOL_ROOM: usize = 1024;
/// Random positions anywhere on the sheet, and near the part, tried per move: sparrow's 50 in the
/// container and 25 focussed on the item (Gardeyn & Wauters 2025, its default configuration).
/// For the same evaluations that is fewer moves, each to a better spot: where parts of a few
/// whole-number sizes fill rows exactly, a move must find the one gap that takes a part.
const GLOBAL_SAMPLES: usize = 50;
const LOCAL_SAMPLES: usize = 25;
/// Local samples fall within this share of the part's larger side of where it is.
const LOCAL_RADIUS_SHARE: f32 = 0.25;
/// A sample: weighted overlap, rotation, translation.
type Sample = (f32, usize, (f32, f32));

/// First and last step of a coordinate descent, as shares of the part's shorter side.
#[derive(Clone, Copy)]
struct Descent {
    first: f32,
    last: f32,
}

/// The samples' refinement (sparrow's, Gardeyn & Wauters 2025, its default configuration): a
/// coarse descent from each of the `Effort::descents` best samples that lie apart by more than
/// `UNIQUE_SHARE` of the part's shorter side, then a fine one from the best of them.
const COARSE_DESCENT: Descent = Descent {
    first: 0.25,
    last: 0.02,
};
const FINE_DESCENT: Descent = Descent {
    first: 0.01,
    last: 0.001,
};
const UNIQUE_SHARE: f32 = 0.05;
/// A step that found a better spot grows by this factor (sparrow's 1.1); one that did not halves.
const DESCENT_GROWTH: f32 = 1.1;
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
pub(crate) struct Effort {
    strikes: usize,
    /// Sweeps without a 1 % fall of the total overlap that make a stall.
    stall: usize,
    /// Samples of a move refined by a coarse descent (see `COARSE_DESCENT`).
    descents: usize,
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
const QUICK: Effort = Effort {
    strikes: 1,
    stall: STALL_SWEEPS,
    descents: 1,
    best_of_two: false,
};
/// The patient chains of the anytime rounds, which have time to spend: sparrow's exploration
/// separator (Gardeyn & Wauters 2025, its default configuration), with 200 sweeps to a stall,
/// three strikes, three samples refined per move and the better of two tries a sweep.
const PATIENT: Effort = Effort {
    strikes: 3,
    stall: 200,
    descents: 3,
    best_of_two: true,
};
/// Fine chains: sparrow's compression separator (its default configuration), with 100 sweeps
/// to a stall, five strikes, three samples refined per move and the better of two tries a
/// sweep.
const FINE: Effort = Effort {
    strikes: 5,
    stall: 100,
    descents: 3,
    best_of_two: true,
};

/// The lowest-topped clear layout of `sheet`'s parts that compression finds within `budget`
/// overlap evaluations (the input itself if none is lower). `clear` is the final judge of a
/// layout (jagua-rs's collision test). `stop` is asked before every separation and every
/// sweep of one: once it says yes, compression returns the best layout so far, and
/// `Compressed::stopped` tells the caller that the budget did not decide where it ended.
pub(crate) fn compress(
    footprints: &Footprints,
    sheet: &[Placement],
    budget: usize,
    rng: &mut ChaCha8Rng,
    clear: impl Fn(&[Placement]) -> bool,
    stop: &(dyn Fn() -> bool + Sync),
) -> Compressed {
    let mut chain = Chain::new(footprints, sheet, rng.clone(), Pace::Quick);
    let stopped = chain.advance(budget, &clear, stop);
    *rng = chain.rng;
    Compressed {
        items: chain.best,
        stopped,
    }
}

/// What [`compress`] returns.
pub(crate) struct Compressed {
    /// The lowest clear layout found.
    pub(crate) items: Vec<Placement>,
    /// True if `stop` ended compression before its budget or its stall rules did.
    pub(crate) stopped: bool,
}

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
    best: Vec<Placement>,
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
    rng: ChaCha8Rng,
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

/// Sparrow's exploration (Gardeyn & Wauters 2025, "exploration phase") at a fixed `ceiling`
/// below the top of the chain's best layout: separate; on a failure put the failed layout in a
/// pool ordered by its remaining overlap, take one back (`POOL_SPREAD`), disrupt it
/// ([`disrupt`]) and separate again.
#[derive(Clone)]
struct Exploration {
    ceiling: f32,
    current: Vec<Placement>,
    large: Vec<usize>,
    pool: Vec<(f32, Vec<Placement>)>,
    failures: usize,
}

impl Exploration {
    /// Exploration at `ceiling` from `best` pushed under it; `None` if a part fits under
    /// `ceiling` at no rotation.
    fn new(footprints: &Footprints, best: &[Placement], ceiling: f32) -> Option<Self> {
        let current = all_under_ceiling(footprints, best, ceiling)?;
        let mut exploration = Exploration::empty(footprints, &current, ceiling);
        exploration.current = current;
        Some(exploration)
    }

    /// Exploration at the ceiling of `failed`, a separation that gave up, with its layout as
    /// the pool's first failure (the next separation is of that layout disrupted), as sparrow's
    /// exploration takes every failed shrink.
    fn after(footprints: &Footprints, failed: Separation, rng: &mut ChaCha8Rng) -> Self {
        let mut exploration = Exploration::empty(footprints, &failed.items, failed.ceiling);
        exploration.finish(footprints, failed, false, rng);
        exploration
    }

    /// Exploration at `ceiling` of the parts of `items`, with no layout to separate yet.
    fn empty(footprints: &Footprints, items: &[Placement], ceiling: f32) -> Self {
        Exploration {
            ceiling,
            large: large_parts(footprints, items),
            current: Vec::new(),
            pool: Vec::new(),
            failures: 0,
        }
    }

    /// A separation of the current layout, with unit weights (exploration is there to leave
    /// the structure the small steps are stuck in).
    fn start<'f>(&mut self, footprints: &'f Footprints, effort: Effort) -> Separation<'f> {
        let current = std::mem::take(&mut self.current);
        let parts = current.len();
        Separation::new(
            footprints,
            current,
            self.ceiling,
            vec![1.0; parts * parts],
            effort,
        )
    }

    /// The end of a separation [`Exploration::start`] began: its layout if `separated`, else
    /// none (the failure goes to the pool, and the next current layout is drawn from it and
    /// disrupted).
    fn finish(
        &mut self,
        footprints: &Footprints,
        separation: Separation,
        separated: bool,
        rng: &mut ChaCha8Rng,
    ) -> Option<Vec<Placement>> {
        if separated {
            return Some(separation.items);
        }
        self.failures += 1;
        let overlap = separation.total();
        let at = self.pool.partition_point(|(o, _)| *o <= overlap);
        self.pool.insert(at, (overlap, separation.items));
        self.pool.truncate(POOL_ROOM);
        let rank = (POOL_SPREAD * standard_normal(rng)).abs().min(0.999);
        self.current = self.pool[(rank * self.pool.len() as f32) as usize]
            .1
            .clone();
        disrupt(
            footprints,
            &mut self.current,
            &self.large,
            self.ceiling,
            rng,
        );
        None
    }
}

/// Indices of the large parts of a sheet (`LARGE_AREA_SHARE`), by the area of their shapes'
/// convex hulls, as sparrow ranks them.
fn large_parts(footprints: &[Vec<Footprint>], items: &[Placement]) -> Vec<usize> {
    let area = |s: &Placement| footprints[s.part][s.rot].pieces.hull_area();
    let mut areas: Vec<f32> = items.iter().map(area).collect();
    areas.sort_by(|a, b| b.total_cmp(a));
    let total: f32 = areas.iter().sum();
    let mut sum = 0.0;
    let mut cutoff = 0.0;
    for a in areas {
        sum += a;
        cutoff = a;
        if sum >= LARGE_AREA_SHARE * total {
            break;
        }
    }
    (0..items.len())
        .filter(|&i| area(&items[i]) >= cutoff)
        .collect()
}

/// Swaps the places of a random large part and a large part of another shape
/// ([`Pieces::unlike`]: two copies of one shape listed as two designs swap to no effect), or
/// any other part if all large ones are alike, each kept at its own rotation and clamped to
/// where it fits under `ceiling`; then moves the parts whose inner point a swapped part now
/// covers by the way back to where that part was (the disruption of sparrow's exploration,
/// Gardeyn & Wauters 2025).
fn disrupt(
    footprints: &[Vec<Footprint>],
    items: &mut [Placement],
    large: &[usize],
    ceiling: f32,
    rng: &mut ChaCha8Rng,
) {
    let n = items.len();
    if n < 2 || large.is_empty() {
        return;
    }
    let i = large[rng.gen_range(0..large.len())];
    let others: Vec<usize> = large
        .iter()
        .copied()
        .filter(|&j| {
            let shape = |k: usize| &footprints[items[k].part][items[k].rot].pieces;
            shape(j).unlike(shape(i))
        })
        .collect();
    let j = if others.is_empty() {
        let j = rng.gen_range(0..n - 1);
        j + usize::from(j >= i)
    } else {
        others[rng.gen_range(0..others.len())]
    };
    let (ti, tj) = (items[i].t, items[j].t);
    let shifted_under =
        |s: Placement, t: (f32, f32)| match footprints[s.part][s.rot].range_under(ceiling) {
            Some((x, y)) => (t.0.clamp(x.0, x.1), t.1.clamp(y.0, y.1)),
            None => s.t,
        };
    for (k, t) in [(i, tj), (j, ti)] {
        items[k].t = shifted_under(items[k], t);
    }
    // The parts a swapped part now covers go to the room it left, where they keep their places
    // relative to it, as in sparrow's disruption: swapping a large part with a smaller one would
    // otherwise bury the small one's neighbours under the large one.
    for (k, old) in [(i, ti), (j, tj)] {
        let at = items[k];
        let shape = &footprints[at.part][at.rot].pieces;
        let back = (old.0 - at.t.0, old.1 - at.t.1);
        for (c, s) in items.iter_mut().enumerate() {
            if c == i || c == j {
                continue;
            }
            let inner = footprints[s.part][s.rot].pieces.inner_point();
            let p = [inner[0] + s.t.0 - at.t.0, inner[1] + s.t.1 - at.t.1];
            if shape.contains(p) {
                s.t = shifted_under(*s, (s.t.0 + back.0, s.t.1 + back.1));
            }
        }
    }
}

/// A draw of the standard normal distribution (Box-Muller).
fn standard_normal(rng: &mut ChaCha8Rng) -> f32 {
    let u: f32 = rng.gen_range(f32::EPSILON..1.0);
    let v: f32 = rng.gen();
    (-2.0 * u.ln()).sqrt() * (std::f32::consts::TAU * v).cos()
}

/// The parts of `items` that reach above `ceiling` pushed down into their neighbours (turned to
/// a rotation that fits under it if theirs does not), or `None` if a part fits under it at no
/// rotation.
fn all_under_ceiling(
    footprints: &[Vec<Footprint>],
    items: &[Placement],
    ceiling: f32,
) -> Option<Vec<Placement>> {
    items
        .iter()
        .map(|&s| under_ceiling(footprints, s, ceiling))
        .collect()
}

/// `s` moved down (or turned) so that it stays under `ceiling`, or `None` if no rotation of the
/// part fits under it.
fn under_ceiling(footprints: &[Vec<Footprint>], s: Placement, ceiling: f32) -> Option<Placement> {
    if let Some((_, y)) = footprints[s.part][s.rot].range_under(ceiling) {
        return Some(Placement {
            t: (s.t.0, s.t.1.min(y.1)),
            ..s
        });
    }
    footprints[s.part].iter().enumerate().find_map(|(rot, f)| {
        let (x, y) = f.range_under(ceiling)?;
        Some(Placement {
            part: s.part,
            rot,
            t: (s.t.0.clamp(x.0, x.1), s.t.1.clamp(y.0, y.1)),
        })
    })
}

/// The best few samples of a move, kept apart: a sample within `apart` (in x and y) of a kept
/// one of the same rotation replaces it if better and is dropped if not.
struct Starts {
    kept: Vec<Sample>,
    room: usize,
    apart: f32,
}

impl Starts {
    fn new(room: usize, apart: f32) -> Self {
        Starts {
            kept: Vec::with_capacity(room + 1),
            room,
            apart,
        }
    }

    fn offer(&mut self, s: Sample) {
        let near = |k: &Sample| {
            k.1 == s.1
                && (k.2 .0 - s.2 .0).abs() < self.apart
                && (k.2 .1 - s.2 .1).abs() < self.apart
        };
        if let Some(at) = self.kept.iter().position(near) {
            if s.0 < self.kept[at].0 {
                self.kept.remove(at);
            } else {
                return;
            }
        }
        let at = self.kept.partition_point(|k| k.0 <= s.0);
        if at < self.room {
            self.kept.insert(at, s);
            self.kept.truncate(self.room);
        }
    }

    /// What a sample must beat to be kept (the early stop of `Separation::cost`).
    fn bound(&self) -> f32 {
        if self.kept.len() < self.room {
            f32::MAX
        } else {
            self.kept[self.room - 1].0
        }
    }

    fn kept(&self) -> &[Sample] {
        &self.kept
    }

    fn best(&self) -> Sample {
        self.kept[0]
    }
}

/// The guided local search of one compression attempt: parts under a fixed ceiling, with their
/// pairwise overlaps and weights.
#[derive(Clone)]
struct Separation<'a> {
    footprints: &'a Footprints,
    items: Vec<Placement>,
    ceiling: f32,
    /// Shape bounds of each item where it is.
    bounds: Vec<Bounds>,
    /// `n x n`, symmetric: unweighted loss of each pair ([`loss`]).
    overlaps: Vec<f32>,
    /// Kept from one small step to the next (where sparrow starts each strip width from unit
    /// weights): a pair that kept colliding under the last ceiling will likely collide under
    /// the next, and starting it heavy separates it sooner, which leaves more of the budget for
    /// lowering the ceiling (denser layouts on most strips than unit weights at every step).
    /// Exploration starts from unit weights: it is there to leave the structure the small steps
    /// are stuck in.
    weights: Vec<f32>,
    effort: Effort,
    evaluations: usize,
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
type Layout = (Vec<Placement>, Vec<Bounds>, Vec<f32>);

/// How a call of [`Separation::run`] ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Outcome {
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
    fn new(
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

    fn n(&self) -> usize {
        self.items.len()
    }

    fn pieces(&self, s: Placement) -> &'a Pieces {
        &self.footprints[s.part][s.rot].pieces
    }

    fn bounds_of(&self, s: Placement) -> Bounds {
        shifted(self.pieces(s).bounds, [s.t.0, s.t.1])
    }

    /// The collision loss of shape `a` at `t` against item `j` where it is, or some loss of at
    /// least `enough` once it is known to reach that (`f32::MAX` for the exact loss).
    fn loss_against(&self, a: &Pieces, t: (f32, f32), j: usize, enough: f32) -> f32 {
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
    fn refresh(&mut self, i: usize) {
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

    fn total(&self) -> f32 {
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
    fn run(
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

    /// Translations of item `i` at rotation `rot` inside the sheet and under the ceiling.
    fn range(&self, i: usize, rot: usize) -> Option<((f32, f32), (f32, f32))> {
        self.footprints[self.items[i].part][rot].range_under(self.ceiling)
    }

    /// Weighted overlap of item `i` put at `rot`, `t` with every other item; stops adding once it
    /// reaches `cutoff` (the caller only wants to know whether it beats that).
    fn cost(&mut self, i: usize, rot: usize, t: (f32, f32), cutoff: f32) -> f32 {
        self.evaluations += 1;
        let n = self.n();
        let s = Placement {
            part: self.items[i].part,
            rot,
            t,
        };
        let (a, bounds) = (self.pieces(s), self.bounds_of(s));
        let mut sum = 0.0;
        for j in 0..n {
            if j == i || !bounds_meet(bounds, self.bounds[j]) {
                continue;
            }
            let w = self.weights[i * n + j];
            sum += w * self.loss_against(a, t, j, (cutoff - sum) / w);
            if sum >= cutoff {
                break;
            }
        }
        sum
    }

    /// Coordinate descent of item `i` from `start` (cost, rotation, translation), as sparrow
    /// refines its samples (Gardeyn & Wauters 2025, §4.3): two candidates a step either way
    /// along a random axis (across, along, or one of the diagonals); a candidate no worse is
    /// taken, a better one grows that axis's step by `DESCENT_GROWTH`, anything else halves it
    /// and draws another axis, until both steps are under the schedule's last. Steps are shares
    /// of the part's shorter side, so the descent is the same on a strip in mm and on one in
    /// hundreds of units.
    fn descend(
        &mut self,
        i: usize,
        start: Sample,
        schedule: Descent,
        min_side: f32,
        rng: &mut ChaCha8Rng,
    ) -> Sample {
        let Some((x, y)) = self.range(i, start.1) else {
            return start;
        };
        let mut at = start;
        let last = schedule.last * min_side;
        let mut steps = (schedule.first * min_side, schedule.first * min_side);
        let mut axis = rng.gen_range(0..4);
        while (steps.0 >= last || steps.1 >= last) && at.0 > 0.0 {
            let (dx, dy) = match axis {
                0 => (steps.0, 0.0),
                1 => (0.0, steps.1),
                2 => (steps.0, steps.1),
                _ => (-steps.0, steps.1),
            };
            let mut candidate = |sign: f32| {
                let t = (
                    (at.2 .0 + sign * dx).clamp(x.0, x.1),
                    (at.2 .1 + sign * dy).clamp(y.0, y.1),
                );
                (self.cost(i, at.1, t, at.0), at.1, t)
            };
            let (ahead, back) = (candidate(1.0), candidate(-1.0));
            let pick = if back.0 < ahead.0 { back } else { ahead };
            let better = pick.0 < at.0;
            if pick.0 <= at.0 {
                at = pick;
            }
            let m = if better { DESCENT_GROWTH } else { 0.5 };
            match axis {
                0 => steps.0 *= m,
                1 => steps.1 *= m,
                _ => {
                    steps.0 *= m.sqrt();
                    steps.1 *= m.sqrt();
                }
            }
            if !better {
                axis = rng.gen_range(0..4);
            }
        }
        at
    }

    /// Puts item `i` where its weighted overlap is least among random positions on the sheet
    /// and near where it is, refined by a coordinate descent.
    fn move_item(&mut self, i: usize, rng: &mut ChaCha8Rng) {
        let now = self.items[i];
        let rotations = self.footprints[now.part].len();
        let b = self.pieces(now).bounds;
        let mut starts = Starts::new(
            self.effort.descents,
            UNIQUE_SHARE * (b[2] - b[0]).min(b[3] - b[1]),
        );
        starts.offer((self.cost(i, now.rot, now.t, f32::MAX), now.rot, now.t));
        let radius = LOCAL_RADIUS_SHARE * (b[2] - b[0]).max(b[3] - b[1]);
        for k in 0..GLOBAL_SAMPLES + LOCAL_SAMPLES {
            let local = k >= GLOBAL_SAMPLES;
            let rot = if local && rng.gen_bool(0.8) {
                now.rot
            } else {
                rng.gen_range(0..rotations)
            };
            let Some((x, y)) = self.range(i, rot) else {
                continue;
            };
            let t = if local {
                (
                    (now.t.0 + rng.gen_range(-radius..=radius)).clamp(x.0, x.1),
                    (now.t.1 + rng.gen_range(-radius..=radius)).clamp(y.0, y.1),
                )
            } else {
                (rng.gen_range(x.0..=x.1), rng.gen_range(y.0..=y.1))
            };
            let c = self.cost(i, rot, t, starts.bound());
            starts.offer((c, rot, t));
        }
        // A coarse descent from each kept sample, a fine one from the best that comes of them.
        let min_side = (b[2] - b[0]).min(b[3] - b[1]);
        let mut best = starts.best();
        for &start in starts.kept() {
            let refined = self.descend(i, start, COARSE_DESCENT, min_side, rng);
            if refined.0 < best.0 {
                best = refined;
            }
        }
        let best = self.descend(i, best, FINE_DESCENT, min_side, rng);
        let moved = Placement {
            part: now.part,
            rot: best.1,
            t: best.2,
        };
        self.items[i] = moved;
        self.bounds[i] = self.bounds_of(moved);
        self.refresh(i);
    }
}

#[cfg(test)]
mod tests {
    use rand::SeedableRng;

    use super::*;

    /// Unit squares on a sheet 2.1 wide: left edges in `[0, 1.1]`, bottoms in `[0, 10]`.
    fn squares() -> Footprints {
        Footprints::new(vec![square_footprints()])
    }

    fn square_footprints() -> Vec<Footprint> {
        vec![Footprint::rectangle(1.0, 1.0, 1.1, 10.0)]
    }

    /// Independent of the overlap measure: axis-aligned unit squares are clear iff their boxes
    /// do not overlap.
    fn boxes_clear(items: &[Placement]) -> bool {
        items.iter().enumerate().all(|(i, a)| {
            items[i + 1..]
                .iter()
                .all(|b| (a.t.0 - b.t.0).abs() >= 1.0 || (a.t.1 - b.t.1).abs() >= 1.0)
        })
    }

    fn column(n: usize) -> Vec<Placement> {
        (0..n)
            .map(|k| Placement {
                part: 0,
                rot: 0,
                t: (0.0, 1.01 * k as f32),
            })
            .collect()
    }

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
    fn a_cost_under_its_cutoff_is_exact_and_one_over_it_is_at_least_the_cutoff() {
        // Ells of two pieces each, crowded onto a small sheet: a cut-off sum (and an overlap
        // stopped inside a pair of pieces) may only ever say "no better than the cutoff".
        let ell = || Pieces::new(&[[0., 0.], [3., 0.], [3., 1.], [1., 1.], [1., 3.], [0., 3.]]);
        let footprints = Footprints::new(vec![vec![Footprint {
            pieces: ell().unwrap(),
            x: (0.0, 4.0),
            y: (0.0, 4.0),
        }]]);
        let items: Vec<Placement> = (0..4).map(|k| at(0, k as f32, 0.7 * k as f32)).collect();
        let mut separation = Separation::new(&footprints, items, 7.0, vec![1.5; 16], QUICK);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let (mut under, mut over) = (0, 0);
        for _ in 0..200 {
            let t = (rng.gen_range(0.0..4.0), rng.gen_range(0.0..4.0));
            let exact = separation.cost(0, 0, t, f32::MAX);
            for cutoff in [0.3 * exact, 0.9 * exact, 1.1 * exact, 3.0 * exact] {
                let cut = separation.cost(0, 0, t, cutoff);
                if exact < cutoff {
                    assert_eq!(cut.to_bits(), exact.to_bits(), "{t:?} under {cutoff}");
                    under += 1;
                } else {
                    assert!(cut >= cutoff && cut <= exact, "{t:?}: {cut} of {exact}");
                    over += 1;
                }
            }
        }
        assert!(under > 100 && over > 100, "{under} under, {over} over");
    }

    #[test]
    fn a_descent_in_steps_of_the_part_clears_a_part_as_well_in_hundreds_of_units_as_in_ones() {
        // Two squares of side `side` on a sheet three sides wide, the second pushed 0.3 of a
        // side into the first. The coarse descent starts at a quarter of the side, so it clears
        // the pair in as few evaluations at side 100 as at side 1 (a descent in fixed mm steps
        // would need a hundred times as many at side 100).
        let spent = |side: f32| {
            let footprints = Footprints::new(vec![vec![Footprint::rectangle(
                side,
                side,
                2.0 * side,
                2.0 * side,
            )]]);
            let items = vec![at(0, 0.0, 0.0), at(0, 0.7 * side, 0.0)];
            let mut separation =
                Separation::new(&footprints, items, 3.0 * side, vec![1.0; 4], QUICK);
            let start = (
                separation.cost(1, 0, (0.7 * side, 0.0), f32::MAX),
                0,
                (0.7 * side, 0.0),
            );
            assert!(start.0 > 0.0);
            let mut rng = ChaCha8Rng::seed_from_u64(4);
            let before = separation.evaluations;
            let end = separation.descend(1, start, COARSE_DESCENT, side, &mut rng);
            assert_eq!(end.0, 0.0, "side {side}: {end:?}");
            separation.evaluations - before
        };
        let (small, large) = (spent(1.0), spent(100.0));
        assert!(
            small <= 40 && large <= 40,
            "{small} and {large} evaluations"
        );
    }

    #[test]
    fn the_kept_samples_are_the_best_few_apart_from_one_another() {
        // Room for two, apart by more than 0.5: a better sample near a kept one replaces it, a
        // worse one near it is dropped, and one far away takes its rank.
        let mut starts = Starts::new(2, 0.5);
        assert_eq!(starts.bound(), f32::MAX);
        starts.offer((5.0, 0, (0.0, 0.0)));
        starts.offer((4.0, 0, (0.2, 0.0)));
        assert_eq!(starts.kept(), [(4.0, 0, (0.2, 0.0))]);
        starts.offer((6.0, 0, (0.1, 0.1)));
        assert_eq!(starts.kept(), [(4.0, 0, (0.2, 0.0))]);
        // Near in place but at another rotation: apart.
        starts.offer((7.0, 1, (0.2, 0.0)));
        starts.offer((3.0, 0, (2.0, 2.0)));
        assert_eq!(starts.kept(), [(3.0, 0, (2.0, 2.0)), (4.0, 0, (0.2, 0.0))]);
        assert_eq!(starts.bound(), 4.0);
        assert_eq!(starts.best(), (3.0, 0, (2.0, 2.0)));
    }

    #[test]
    fn a_column_of_four_squares_compresses_into_two_rows() {
        // Closed form: four unit squares on a 2.1 wide sheet need two rows, top 2 (plus the
        // clearance); stacked in one column their top is 4.03.
        let start = column(4);
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let packed = compress(&squares(), &start, 2_000_000, &mut rng, boxes_clear, &never).items;
        assert!(boxes_clear(&packed));
        let top = packed.iter().map(|s| s.t.1 + 1.0).fold(0.0, f32::max);
        assert!(top < 2.1, "top {top}, two rows reach 2");
        assert!(packed
            .iter()
            .all(|s| (0.0..=1.1).contains(&s.t.0) && s.t.1 >= 0.0));
    }

    #[test]
    fn stops_when_the_tallest_part_sets_the_top_even_with_an_endless_budget() {
        // A 1 x 3 bar beside two squares: no layout is lower than the bar, so every lower
        // ceiling fails at once and compression must stop on its own, not on the budget.
        let footprints = Footprints::new(vec![
            square_footprints(),
            vec![Footprint::rectangle(1.0, 3.0, 1.1, 10.0)],
        ]);
        let start = vec![
            Placement {
                part: 1,
                rot: 0,
                t: (0.0, 0.0),
            },
            Placement {
                part: 0,
                rot: 0,
                t: (1.05, 0.0),
            },
            Placement {
                part: 0,
                rot: 0,
                t: (1.05, 1.01),
            },
        ];
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let kept = compress(&footprints, &start, usize::MAX, &mut rng, |_| true, &never).items;
        assert_eq!(kept, start);
    }

    /// Bars 6 x 1 (design 0) and 4 x 1 (design 1) on a sheet 10.2 wide.
    fn bars() -> Footprints {
        Footprints::new(vec![bar(6.0), bar(4.0)])
    }

    /// A bar `length` x 1 on a sheet 10.2 wide.
    fn bar(length: f32) -> Vec<Footprint> {
        vec![Footprint::rectangle(length, 1.0, 10.2 - length, 10.0)]
    }

    /// Independent of the overlap measure: axis-aligned bars are clear iff their boxes do not
    /// overlap.
    fn bars_clear(items: &[Placement]) -> bool {
        let length = |s: &Placement| if s.part == 0 { 6.0 } else { 4.0 };
        items.iter().enumerate().all(|(i, a)| {
            items[i + 1..].iter().all(|b| {
                a.t.0 + length(a) <= b.t.0
                    || b.t.0 + length(b) <= a.t.0
                    || (a.t.1 - b.t.1).abs() >= 1.0
            })
        })
    }

    fn at(part: usize, x: f32, y: f32) -> Placement {
        Placement {
            part,
            rot: 0,
            t: (x, y),
        }
    }

    /// An [`Exploration`] driven as a quick [`Chain`] drives it: the first clear layout under
    /// `ceiling` (or none, after `EXPLORE_FAILURES` failures in a row or when `budget` overlap
    /// evaluations are spent) and the evaluations spent. The chain itself only explores after
    /// its small steps stall, which would hide the exploration's own behaviour behind theirs.
    fn explore(
        footprints: &Footprints,
        best: &[Placement],
        ceiling: f32,
        budget: usize,
        rng: &mut ChaCha8Rng,
        clear: &impl Fn(&[Placement]) -> bool,
    ) -> (Option<Vec<Placement>>, usize) {
        let Some(mut exploration) = Exploration::new(footprints, best, ceiling) else {
            return (None, 0);
        };
        let mut spent = 0;
        while exploration.failures < EXPLORE_FAILURES && spent < budget {
            let mut separation = exploration.start(footprints, QUICK);
            let outcome = separation.run(rng, budget - spent, &never);
            spent += separation.evaluations + separation.n();
            let separated = outcome == Outcome::Clear && clear(&separation.items);
            let found = exploration.finish(footprints, separation, separated, rng);
            if found.is_some() {
                return (found, spent);
            }
        }
        (None, spent)
    }

    #[test]
    fn exploration_repartitions_rows_whose_lengths_do_not_add_up() {
        // Closed form: two long bars (6) cannot share a row of 10.2, nor can a long bar and
        // two short ones (14); so rows {6, 4} + {6, 4} are the only two-row layout, top 2.
        // The start has the long bars in rows of their own and the short ones together: top 3.
        let start = vec![
            at(0, 0.0, 0.0),
            at(0, 0.0, 1.01),
            at(1, 0.0, 2.02),
            at(1, 5.0, 2.02),
        ];
        let run = |seed| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            explore(&bars(), &start, 2.05, 5_000_000, &mut rng, &bars_clear)
        };
        let (found, spent) = run(11);
        let found = found.expect("a two-row layout exists");
        assert!(bars_clear(&found));
        let top = found.iter().map(|s| s.t.1 + 1.0).fold(0.0, f32::max);
        assert!(top <= 2.05, "top {top}");
        assert!(spent > 0 && spent <= 5_000_000);
        // The same stream gives the same layout.
        assert_eq!(run(11).0, Some(found));
    }

    #[test]
    fn an_exploration_pool_keeps_the_least_overlapping_failures_up_to_its_room() {
        // Two long bars, one on the other, overlap by as much as the upper one's height makes
        // them: failures of as many overlaps as there are heights, more than the pool holds,
        // handed to the exploration out of order. It counts them all and keeps the least
        // overlapping.
        let footprints = bars();
        let stack = |y: f32| vec![at(0, 0.0, 0.0), at(0, 0.0, y)];
        let mut exploration = Exploration::new(&footprints, &stack(1.5), 3.0).expect("fits");
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let failures = POOL_ROOM + 200;
        let mut overlaps = Vec::new();
        for k in 0..failures {
            // 7919 is prime, so k -> 7919 k mod failures visits every height once.
            let y = 0.9 * ((k * 7919) % failures) as f32 / failures as f32;
            let separation = Separation::new(&footprints, stack(y), 3.0, vec![1.0; 4], PATIENT);
            overlaps.push(separation.total());
            assert!(exploration
                .finish(&footprints, separation, false, &mut rng)
                .is_none());
        }
        assert_eq!(exploration.failures, failures);
        overlaps.sort_by(f32::total_cmp);
        assert!(overlaps[0] > 0.0 && overlaps[POOL_ROOM] > overlaps[0]);
        let kept: Vec<f32> = exploration.pool.iter().map(|(o, _)| *o).collect();
        assert_eq!(kept, overlaps[..POOL_ROOM]);
    }

    /// A long and a short bar in each of two rows: a top of 2 (plus the gap), the least four
    /// bars of height 1 in rows of at most two can have.
    fn two_rows_of_bars() -> Vec<Placement> {
        vec![
            at(0, 0.0, 0.0),
            at(1, 6.1, 0.0),
            at(0, 0.0, 1.01),
            at(1, 6.1, 1.01),
        ]
    }

    #[test]
    fn exploration_gives_up_when_nothing_fits_under_the_ceiling() {
        // Four bars of height 1 in rows of at most two need a top of 2: under 1.5 nothing is
        // clear, so exploration stops after its failures, well within an endless budget.
        let start = two_rows_of_bars();
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let (found, spent) = explore(&bars(), &start, 1.5, usize::MAX, &mut rng, &bars_clear);
        assert!(found.is_none());
        assert!(spent > 0 && spent < usize::MAX);
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

    #[test]
    fn a_disruption_never_swaps_two_copies_of_one_shape_listed_as_two_designs() {
        // Designs 0 and 1 are the same long bar, design 2 a short one: a swap of the two long
        // bars would leave the layout as it was, so every swap takes a short bar.
        let footprints = Footprints::new(vec![bar(6.0), bar(6.0), bar(4.0)]);
        let before = vec![
            at(0, 0.0, 0.0),
            at(1, 0.0, 2.0),
            at(2, 6.1, 0.0),
            at(2, 6.1, 2.0),
        ];
        for (seed, _, moved) in swaps(&footprints, &before, 40) {
            assert!(
                moved.iter().any(|&k| before[k].part == 2),
                "seed {seed}: {moved:?}"
            );
        }
    }

    /// `before` disrupted on streams `0..seeds` under a ceiling of 10: the seed, the layout after
    /// and the two parts it moved (it must move two).
    fn swaps(
        footprints: &Footprints,
        before: &[Placement],
        seeds: u64,
    ) -> Vec<(u64, Vec<Placement>, Vec<usize>)> {
        let large = large_parts(footprints, before);
        (0..seeds)
            .map(|seed| {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                let mut after = before.to_vec();
                disrupt(footprints, &mut after, &large, 10.0, &mut rng);
                let moved: Vec<usize> = (0..before.len())
                    .filter(|&k| after[k] != before[k])
                    .collect();
                assert_eq!(moved.len(), 2, "seed {seed}: {after:?}");
                (seed, after, moved)
            })
            .collect()
    }

    #[test]
    fn a_disruption_swaps_two_large_parts_of_different_shapes() {
        let footprints = bars();
        let before = vec![
            at(0, 0.0, 0.0),
            at(0, 0.0, 2.0),
            at(1, 6.1, 0.0),
            at(1, 6.1, 2.0),
        ];
        // By hull area the long bars make up 0.6 of the total: the third part (a short bar)
        // takes it past 3/4, and every part at least as large as that one counts as large.
        assert_eq!(large_parts(&footprints, &before), vec![0, 1, 2, 3]);
        for (_, after, moved) in swaps(&footprints, &before, 20) {
            let (i, j) = (moved[0], moved[1]);
            assert_ne!(before[i].part, before[j].part);
            // Each takes the other's place, clamped to its own x range (a long bar cannot
            // start at x = 6.1 on a 10.2 sheet: it goes to 4.2).
            let clamp = |k: usize, t: (f32, f32)| {
                (
                    t.0.min(10.2 - if before[k].part == 0 { 6.0 } else { 4.0 }),
                    t.1,
                )
            };
            assert_eq!(after[i].t, clamp(i, before[j].t));
            assert_eq!(after[j].t, clamp(j, before[i].t));
        }
    }

    #[test]
    fn a_disruption_moves_the_parts_a_swapped_part_now_covers_to_the_room_it_left() {
        // A 4 x 4 square at the origin swaps with a unit square at (6, 0) whose neighbours sit
        // at (7, 0) and (6, 1). The big square now covers them: they keep their places relative
        // to it and go where it was, (1, 0) and (0, 1). A part far off stays put.
        let square = |side: f32| vec![Footprint::rectangle(side, side, 12.0 - side, 10.0)];
        let footprints = Footprints::new(vec![square(4.0), square(1.0)]);
        let before = vec![
            at(0, 0.0, 0.0),
            at(1, 6.0, 0.0),
            at(1, 7.0, 0.0),
            at(1, 6.0, 1.0),
            at(1, 11.0, 5.0),
        ];
        for seed in 0..10 {
            let mut after = before.clone();
            disrupt(
                &footprints,
                &mut after,
                &[0, 1],
                10.0,
                &mut ChaCha8Rng::seed_from_u64(seed),
            );
            let places: Vec<(f32, f32)> = after.iter().map(|s| s.t).collect();
            assert_eq!(
                places,
                [(6.0, 0.0), (0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (11.0, 5.0)],
                "seed {seed}"
            );
        }
        // The inner point lies inside the shape, and `contains` is the closed form of a square.
        let ell =
            Pieces::new(&[[0., 0.], [3., 0.], [3., 1.], [1., 1.], [1., 3.], [0., 3.]]).unwrap();
        assert!(ell.contains(ell.inner_point()));
        let unit = &footprints[1][0].pieces;
        assert!(unit.contains([0.5, 0.99]) && !unit.contains([0.5, 1.01]));
        assert!(!unit.contains([-0.01, 0.5]) && !ell.contains([2.0, 2.0]));
    }

    /// A chain of `pace` from `start` on stream 5, the stream every chain test draws from.
    fn chain_from<'f>(footprints: &'f Footprints, start: &[Placement], pace: Pace) -> Chain<'f> {
        Chain::new(footprints, start, ChaCha8Rng::seed_from_u64(5), pace)
    }

    /// The `stop` of a compression that only its budget and stall rules end.
    fn never() -> bool {
        false
    }

    #[test]
    fn a_stop_ends_compression_with_the_start_it_was_given_and_says_so() {
        let run = |stop: &(dyn Fn() -> bool + Sync)| {
            let mut rng = ChaCha8Rng::seed_from_u64(3);
            compress(&squares(), &column(5), 300_000, &mut rng, boxes_clear, stop)
        };
        let stopped = run(&|| true);
        assert!(stopped.stopped);
        assert_eq!(stopped.items, column(5));
        let ran = run(&never);
        assert!(!ran.stopped);
        assert_ne!(ran.items, column(5), "five stacked squares compress");
    }

    #[test]
    fn the_same_stream_gives_the_same_layout_and_a_rejected_layout_is_never_kept() {
        let run = |seed| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            compress(
                &squares(),
                &column(5),
                300_000,
                &mut rng,
                boxes_clear,
                &never,
            )
            .items
        };
        assert_eq!(run(3), run(3));
        // A judge that refuses everything leaves the start as it was.
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let kept = compress(&squares(), &column(5), 300_000, &mut rng, |_| false, &never).items;
        assert_eq!(kept, column(5));
    }
}
