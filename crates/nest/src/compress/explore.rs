//! Sparrow's exploration at a fixed ceiling: a pool of failed layouts, one taken back and
//! disrupted (two large parts of different shapes swapped), separated again.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::separate::{Effort, Separation};
use super::{all_under_ceiling, Footprint, Footprints};
use crate::placement::Placement;

/// Failed separations in a row after which exploration gives up on a ceiling (and compression
/// ends): counted, like everything here, so the stop is deterministic. On strips of a dozen
/// large parts a limit of 400 found nothing that 50 did not; the budget binds first.
pub(super) const EXPLORE_FAILURES: usize = 50;
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

/// Sparrow's exploration (Gardeyn & Wauters 2025, "exploration phase") at a fixed `ceiling`
/// below the top of the chain's best layout: separate; on a failure put the failed layout in a
/// pool ordered by its remaining overlap, take one back (`POOL_SPREAD`), disrupt it
/// ([`disrupt`]) and separate again.
#[derive(Clone)]
pub(super) struct Exploration {
    pub(super) ceiling: f32,
    pub(super) current: Vec<Placement>,
    large: Vec<usize>,
    pub(super) pool: Vec<(f32, Vec<Placement>)>,
    pub(super) failures: usize,
}

impl Exploration {
    /// Exploration at `ceiling` from `best` pushed under it; `None` if a part fits under
    /// `ceiling` at no rotation.
    pub(super) fn new(footprints: &Footprints, best: &[Placement], ceiling: f32) -> Option<Self> {
        let current = all_under_ceiling(footprints, best, ceiling)?;
        let mut exploration = Exploration::empty(footprints, &current, ceiling);
        exploration.current = current;
        Some(exploration)
    }

    /// Exploration at the ceiling of `failed`, a separation that gave up, with its layout as
    /// the pool's first failure (the next separation is of that layout disrupted), as sparrow's
    /// exploration takes every failed shrink.
    pub(super) fn after(footprints: &Footprints, failed: Separation, rng: &mut ChaCha8Rng) -> Self {
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
    pub(super) fn start<'f>(
        &mut self,
        footprints: &'f Footprints,
        effort: Effort,
    ) -> Separation<'f> {
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
    pub(super) fn finish(
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

#[cfg(test)]
mod tests {
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::compress::separate::{Outcome, PATIENT, QUICK};
    use crate::compress::test_shapes::*;
    use crate::overlap::Pieces;

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
}
