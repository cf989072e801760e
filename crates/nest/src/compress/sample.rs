//! One part's move in a separation: weighted overlap at random spots on the sheet and near the
//! part, the best few kept apart, refined by coordinate descent in steps that are shares of the
//! part's size.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::separate::Separation;
use crate::overlap::bounds_meet;
use crate::placement::Placement;

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

impl Separation<'_> {
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
    pub(super) fn move_item(&mut self, i: usize, rng: &mut ChaCha8Rng) {
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
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::compress::separate::QUICK;
    use crate::compress::test_shapes::*;
    use crate::compress::{Footprint, Footprints};
    use crate::overlap::Pieces;

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
}
