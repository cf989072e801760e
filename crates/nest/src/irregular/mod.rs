//! Irregular nesting on jagua-rs's bin-packing model, with an optimiser of our own.
//!
//! jagua-rs (`probs::bpp`) keeps one layout per open sheet and answers "does this polygon collide
//! with anything placed, or leave the sheet?" Parts are inflated and the sheet deflated by half
//! the separation, so a collision-free layout keeps the full separation between parts and to the
//! sheet edge. Everything else is ours:
//!
//! * **Placement** (`Model::find_spot`): start positions at the sheet corner, next to and above
//!   placed parts, where parts of the same design sat before a ruin, and at random; each is
//!   pushed down and left in halving steps (a bottom-left slide) while it stays collision-free,
//!   and the end position with the lowest `top + λ·right` wins. Candidates stop at 1/8 mm steps
//!   and only the winner slides on to 0.01 mm: the fine steps, where a part nearly touches its
//!   neighbours, cost the most collision tests. The slide drops a part turned by
//!   180° into the slanted gap its neighbour leaves, which is where trapezoids gain over their
//!   bounding boxes.
//! * **Greedy fills** (`Model::construct`): each worker builds two starts (on jobs of
//!   up to 150 copies, else one) and keeps the better. Even recipes place copies in decreasing
//!   size (area or length with two workers; box area, then shuffled, with more), each on the first sheet
//!   that takes it. Odd recipes fill *best fit*: each step finds a spot for every design still
//!   to place and takes the lowest (ties within a recipe's width: the largest part), so low
//!   gaps get whatever fits them and rows mix designs whose lengths add up to the sheet width,
//!   where a size order leaves every row of one design short of the right edge. The search
//!   below rarely leaves the basin of its start (five times the iterations gained 0.6 points),
//!   so a portfolio of starts buys more than iterations do. The collision shapes come from
//!   jagua-rs's separation offset, simplified outwards (a superset, so the gap holds) to keep
//!   queries cheap. On jobs of more than 300 copies each insertion gets a share of the effort
//!   (300 over the copies) and takes its anchors from the parts placed last, and the
//!   collision engine's quadtree grows deeper with the parts a sheet holds, so that a fill of
//!   thousands of small parts takes seconds, not minutes; compression leaves a sheet of more
//!   than 1,000 parts to the search (its pair tables grow with the square of the parts).
//! * **Local search** (`Model::improve`): ruin and recreate. Either remove the parts nearest a
//!   random point of a sheet and pull up to three parts from the emptiest sheet, or pull one part
//!   and put it at a random spot of a sheet, removing what is in its way. Pulled parts go in
//!   first, then the removed ones: the ruined sheet first, then fuller sheets, the emptiest last.
//!   A few moves instead repack a sheet and the emptiest one from scratch in a perturbed order.
//!   A share of the moves (half of them on a single sheet) *shrink*, as strip packers shrink
//!   the strip: put a ceiling a little below the top of the sheet with the lowest top, remove
//!   the parts above it and either a band just under the ceiling or up to 16 parts around a
//!   random point, and reinsert them on the other sheets or under the ceiling, or fail. On a
//!   single sheet the other moves *recombine*: ruin a band across the sheet or around a point
//!   and reinsert without a ceiling. Shrink and recombine moves reinsert in a size or random
//!   order, or best fit as the greedy fill does.
//!   The objective is lexicographic: fewer sheets, a shorter *used length* (all sheets but the
//!   one with the lowest top counted whole, plus that top: what
//!   [`NestSolution::used_length_mm`](crate::NestSolution::used_length_mm) measures), a higher
//!   sum of squared fills (it rises as parts move into fuller sheets, i.e. as the last sheet
//!   empties), then lower parts. Moves are accepted by thresholds on the length, the fills and,
//!   when neither changes, the area-weighted mean top (so such moves pack parts down instead of
//!   drifting), all shrinking to zero over the budget; the best layout is kept.
//! * **Compression** (`Model::compressed`, module `compress`): the moves above only place parts
//!   where they are clear, so the parts under a sheet's top seldom get past one another. Last,
//!   the sheet with the lowest top is compressed through overlap as sparrow does: lower its
//!   ceiling, push the parts above it into their neighbours, and move parts to where they
//!   overlap least until none do (guided local search on the overlap area of convex pieces,
//!   charged as sparrow charges a collision, module `overlap`, whose pair weights carry over
//!   from one ceiling step to the next);
//!   jagua-rs checks every layout it keeps. Where the smallest step keeps
//!   failing, a chain explores as sparrow does: it stays at that ceiling, keeps the failed
//!   layouts in a pool, and separates again from one of them with two large parts of
//!   different shapes swapped, which re-partitions rows the small steps cannot. Two chains
//!   per worker compress on their own streams, shared out to the threads as they come free,
//!   each with half of `COMPRESSION_EVALUATIONS` overlap evaluations per worker and iteration
//!   of the settings' full budget, not the smaller share a small job's search gets, and twice
//!   that up to 60 copies (the sheet with the lowest top decides the used length, so it gets
//!   the budget the search did not use); a chain stops early after `EXPLORE_FAILURES` failed
//!   explorations in a row, and the lowest top wins.
//! * **Anytime rounds** (`anytime`): iterations above the base budget of 1000 go to rounds of
//!   100, in which patient compression chains (one per worker) carry on sparrow's exploration
//!   from the best layout so far, resumed round after round with their pools, weights and
//!   unfinished separations, the chains above the
//!   lowest going on from a copy of it (on more than one sheet, after a short ruin-and-recreate
//!   search); once the rounds stall, compression passes with finer steps (sparrow's compression
//!   phase) take 15 % of them; the best is kept, so more rounds never end worse. A
//!   [`SearchLimit`] (deadline, interrupt) is checked in the greedy fill,
//!   between search moves and inside the compression, and drops a round it cuts, so the layout
//!   is that of the iterations reached. The greedy fill cannot stop: every part must be placed,
//!   so past the limit it places the rest at the repair effort, and a search whose first layout
//!   came after the deadline says so with its time ([`Reached::over_budget`]).
//! * **Determinism**: a fixed number of workers, each with its own ChaCha8 stream of the
//!   seed (one stream per worker and epoch); work is cut into epochs by iteration count. In the first half of the epochs each
//!   worker improves its own start; after each later epoch the best layout (ties to the lower
//!   worker index) seeds all workers. Thread timing never enters a decision.
//! * **Stop rule** (`portfolio`): between epochs the search ends once `STALL_ITERATIONS` (50)
//!   iterations over all workers have brought no shorter layout (fewer sheets or a used length
//!   shorter by more than 1 µm, neither the best nor any worker's own; the score's lower terms
//!   do not count), or once the best uses the fewest sheets the part area allows with a used
//!   length within `LENGTH_TOLERANCE` (5 %) of the part area over the sheet width. Both are
//!   counted in iterations, so the stop is the same on any machine. Progress goes to the
//!   caller's observer ([`nest_observed`], [`crate::NestProgress`]) at the same points.
//! * **Threads**: the greedy starts are shared out to the threads as they come free (a best-fit
//!   start costs several times a size-order one), and each start is a function of its recipe
//!   alone, so the starts do not depend on which thread built them.
//! * **Where it stands** (docs/benchmarks.md): on the lab's strips of actuators ahead of
//!   sparrow, the state-of-the-art strip packer, given 5 s, 30 s and 120 s; on the twelve
//!   public ESICUP instances ahead of it in the mean of three seeds at 5 s (by 1.5 points), 30 s
//!   (by 0.75) and 120 s (by 0.6), on 10 to 12 of the 12; jakobs2 turns on whether either
//!   engine's exploration gets below one ceiling.
//!
//! The code follows these concerns: `model` is the jagua-rs adapter (instance, collision
//! shapes, collision queries, the slide, conversions), `score` the objective, `construct` the
//! spot search and the greedy fills, `moves` ruin and recreate with its acceptance loop,
//! `portfolio` the workers, epochs and final compression, `anytime` the rounds after it,
//! `random` the streams.

mod anytime;
mod construct;
mod model;
mod moves;
mod portfolio;
mod random;
mod score;
mod settle;
mod threads;

use crate::job::Job;
use crate::limit::{Reached, SearchEnd, SearchLimit};
use crate::problem::{NestBin, NestError, NestItem, NestSettings, NestSolution, SheetShape};
use crate::progress::{ignore, NestProgress};
use anytime::{BASE_ITERATIONS, ROUND_ITERATIONS};
use model::Model;
use std::time::Instant;

/// Nests the items on as few sheets as the budget finds, keeping `separation_mm` between parts
/// and to the sheet edges and cutting each part only at its allowed rotations.
pub fn nest(
    items: &[NestItem],
    bin: &NestBin,
    settings: &NestSettings,
) -> Result<NestSolution, NestError> {
    nest_observed(items, bin, settings, &ignore)
}

/// [`nest`] that reports its progress to `observe` (after the greedy fill, after every epoch of
/// the search, and once finished with the final layout's figures); see [`NestProgress`]. The
/// layout is the same as [`nest`]'s.
pub fn nest_observed(
    items: &[NestItem],
    bin: &NestBin,
    settings: &NestSettings,
    observe: &dyn Fn(&NestProgress),
) -> Result<NestSolution, NestError> {
    nest_until(items, bin, settings, &SearchLimit::default(), observe).map(|(layout, _)| layout)
}

/// [`nest_observed`] that also ends at `limit`'s deadline or interrupt, with the best layout so
/// far, and says how far it got ([`Reached`]). Up to `BASE_ITERATIONS` (1000, the default) the
/// budget is the base search's; above it, the base search at 1000 is followed by anytime rounds
/// of `ROUND_ITERATIONS` (100) each (see "Anytime rounds" above). With no limit, or a limit
/// that struck only in the rounds, the layout is that of `nest` at the iterations reached.
pub fn nest_until(
    items: &[NestItem],
    bin: &NestBin,
    settings: &NestSettings,
    limit: &SearchLimit,
    observe: &dyn Fn(&NestProgress),
) -> Result<(NestSolution, Reached), NestError> {
    nest_shaped_until(items, bin, &SheetShape::default(), settings, limit, observe)
}

/// [`nest_until`] on sheets of `shape` (a remnant, a sheet with flaws): every sheet of `bin` cut
/// down to the shape's outline, less its keep-outs, which the parts keep the separation from.
pub fn nest_shaped_until(
    items: &[NestItem],
    bin: &NestBin,
    shape: &SheetShape,
    settings: &NestSettings,
    limit: &SearchLimit,
    observe: &dyn Fn(&NestProgress),
) -> Result<(NestSolution, Reached), NestError> {
    let base = NestSettings {
        iterations: settings.iterations.min(BASE_ITERATIONS),
        ..*settings
    };
    let rounds = (settings.iterations - base.iterations) / ROUND_ITERATIONS;
    let job = Job::new(items, bin, &base)?.with_shape(shape)?;
    let started = Instant::now();
    let mut reached = Reached {
        iterations: base.iterations,
        replayable: true,
        ended: SearchEnd::Budget,
        over_budget: None,
    };
    if job.parts.is_empty() {
        return Ok((job.solution(Vec::new())?, reached));
    }
    let model = Model::new(&job)?;
    let (mut best, mut done, cut, first_layout) = model.run(observe, limit)?;
    // A base search the limit cut short cannot be replayed; if the limit has time left (the
    // search epochs stopped at their share of it), the rounds still use that time.
    reached.replayable = !cut;
    if cut && limit.reached() {
        reached.ended = if limit.interrupted() {
            SearchEnd::Interrupt
        } else {
            SearchEnd::Time
        };
    } else if rounds > 0 {
        let after = model.rounds(best, rounds, limit, observe, done);
        best = after.best;
        done += after.completed * ROUND_ITERATIONS;
        reached.iterations += after.completed * ROUND_ITERATIONS;
        reached.ended = after.ended;
    }
    let problem = model.rebuild(&best);
    let score = model.score(&problem);
    let budget = job.iteration_budget() + rounds * ROUND_ITERATIONS;
    observe(&model.progress(&score, done, budget, true));
    // Every part must be placed, so the first layout ends whatever the deadline; a search
    // whose first layout came after it says how long it took in all.
    if limit.deadline.is_some_and(|d| first_layout > d) {
        reached.over_budget = Some(started.elapsed());
    }
    Ok((job.solution(model.export(&best))?, reached))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{square, squares_job};
    use crate::verify::{verify, verify_shape};
    use crate::NestViolation;

    fn settings() -> NestSettings {
        NestSettings {
            separation_mm: 0.5,
            seed: 3,
            iterations: 100,
            workers: 2,
        }
    }

    /// Nests `demand` 10 mm squares on 100 mm sheets of `shape` and checks the layout with the
    /// verifiers, the shape's among them; the layout.
    fn nested_on(shape: &SheetShape, demand: usize) -> NestSolution {
        let (items, bin) = squares_job(demand, 5);
        let (layout, _) = nest_shaped_until(
            &items,
            &bin,
            shape,
            &settings(),
            &SearchLimit::default(),
            &ignore,
        )
        .unwrap();
        verify(&items, &bin, &settings(), &layout, 1e-9).unwrap();
        for (b, sheet) in layout.bins.iter().enumerate() {
            verify_shape(shape, 0.5, b, &sheet.parts, 1e-9).unwrap();
        }
        layout
    }

    #[test]
    fn parts_keep_clear_of_a_flaw_over_the_corner_the_fill_starts_from() {
        // A 60 mm square flaw over the corner: 6,400 mm² left in an L 40 mm wide, room for 20
        // squares of 10.5 mm pitch (3 across each arm's width).
        let flaw = SheetShape {
            outline: Vec::new(),
            keep_outs: vec![square(60.0)],
        };
        let layout = nested_on(&flaw, 20);
        assert_eq!(layout.bins_used(), 1);
        assert_eq!(layout.parts_placed(), 20);
    }

    #[test]
    fn a_remnant_outline_takes_parts_only_inside_it() {
        // The L of a sheet whose 60 x 60 mm top right was cut before; keep-outs inside it too.
        let remnant = SheetShape {
            outline: vec![
                [0.0, 0.0],
                [100.0, 0.0],
                [100.0, 40.0],
                [40.0, 40.0],
                [40.0, 100.0],
                [0.0, 100.0],
            ],
            keep_outs: vec![place_ring_at(&square(5.0), [10.0, 10.0])],
        };
        // At 10.5 mm pitch the L holds 9 x 3 squares along its foot and 3 x 6 up its leg, 45 at
        // most: 60 squares take two sheets of it, where one whole sheet takes 81.
        let layout = nested_on(&remnant, 60);
        assert_eq!(layout.bins_used(), 2);
    }

    fn place_ring_at(ring: &[[f64; 2]], at: [f64; 2]) -> Vec<[f64; 2]> {
        ring.iter().map(|q| [q[0] + at[0], q[1] + at[1]]).collect()
    }

    #[test]
    fn the_shape_check_finds_a_part_on_a_keep_out_or_outside_the_outline() {
        let part = |x: f64, y: f64| crate::PlacedPart {
            item: 0,
            copy: 0,
            rotation_deg: 0.0,
            translation: [x, y],
            outline: place_ring_at(&square(10.0), [x, y]),
        };
        let flaw = SheetShape {
            outline: Vec::new(),
            keep_outs: vec![place_ring_at(&square(5.0), [50.0, 50.0])],
        };
        assert_eq!(
            verify_shape(&flaw, 0.5, 0, &[part(20.0, 20.0)], 1e-9),
            Ok(())
        );
        // 0.4 mm short of the flaw, and over it.
        assert!(matches!(
            verify_shape(&flaw, 0.5, 0, &[part(39.6, 50.0)], 1e-9),
            Err(NestViolation::NearKeepOut { keep_out: 0, .. })
        ));
        assert!(matches!(
            verify_shape(&flaw, 0.5, 0, &[part(48.0, 48.0)], 1e-9),
            Err(NestViolation::NearKeepOut { distance_mm, .. }) if distance_mm == 0.0
        ));
        let remnant = SheetShape {
            outline: vec![[0.0, 0.0], [40.0, 0.0], [40.0, 40.0], [0.0, 40.0]],
            keep_outs: Vec::new(),
        };
        assert_eq!(
            verify_shape(&remnant, 0.5, 0, &[part(29.5, 1.0)], 1e-9),
            Ok(())
        );
        assert!(matches!(
            verify_shape(&remnant, 0.5, 0, &[part(35.0, 1.0)], 1e-9),
            Err(NestViolation::OutsideOutline { .. })
        ));
    }
}
