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
//! compression turns to sparrow's exploration ([`explore::Exploration`]): it stays at the ceiling
//! it failed at, keeps the failed layouts in a pool ordered by their overlap, takes one back (the
//! better ones more often), swaps two large parts of different shapes in it (the parts a swapped
//! part now covers go to the room it left) and separates again. A swap moves a part into another
//! row, which is how rows whose lengths do not add up to the sheet width get re-partitioned. A
//! clear layout sends compression back to its small steps; `EXPLORE_FAILURES` failures in a row, or
//! the budget, end it. A [`Chain`] holds all of this state, so that the anytime rounds can resume a
//! *patient* chain, slice after slice of budget, down to a separation a slice ended in the middle
//! of ([`separate::Outcome::Paused`]): a separation cut short would count as failed however near it
//! was to clear. A patient chain is sparrow's exploration alone: it shrinks by the smallest step,
//! explores from its first failure and never gives an exploration up. A *fine* chain is sparrow's
//! compression phase: steps of 0.05 % down to 0.001 % and no exploration, for the rounds'
//! compression passes.
//!
//! Work is counted in overlap evaluations, never time, and the random stream is the caller's,
//! so the same input gives the same layout on any machine.
//!
//! The code follows these concerns: `chain` holds a chain's state and how it lowers its
//! ceiling, `explore` the exploration at a fixed ceiling and its disruption, `separate` the
//! guided local search of one separation (sweeps, weights, strikes), `sample` one part's move
//! within it (samples on the sheet and near the part, refined by coordinate descent).

mod chain;
mod explore;
mod sample;
mod separate;
#[cfg(test)]
mod test_shapes;

pub(crate) use chain::{Chain, Pace};

use rand_chacha::ChaCha8Rng;

use crate::overlap::{Pieces, Projections};
use crate::placement::Placement;

/// The most parts a sheet may hold for compression to take it. A separation keeps tables of
/// the overlap and the weight of every pair of parts, and a sweep reads them whole, so its
/// memory and time grow with the square of the parts (a sheet of 10,000 small parts would take
/// 400 MB a table); a sheet of more parts is left as the search leaves it.
pub(crate) const MAX_PARTS: usize = 1000;

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

#[cfg(test)]
mod tests {
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    use super::*;
    use crate::compress::test_shapes::*;

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
