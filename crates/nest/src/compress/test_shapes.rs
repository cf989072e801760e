//! Shapes and layouts the compression's unit tests share: unit squares, bars of two lengths,
//! and the judges that say, independently of the overlap measure, when they are clear.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::{Chain, Footprint, Footprints, Pace};
use crate::placement::Placement;

/// Unit squares on a sheet 2.1 wide: left edges in `[0, 1.1]`, bottoms in `[0, 10]`.
pub(super) fn squares() -> Footprints {
    Footprints::new(vec![square_footprints()])
}

pub(super) fn square_footprints() -> Vec<Footprint> {
    vec![Footprint::rectangle(1.0, 1.0, 1.1, 10.0)]
}

/// Independent of the overlap measure: axis-aligned unit squares are clear iff their boxes
/// do not overlap.
pub(super) fn boxes_clear(items: &[Placement]) -> bool {
    items.iter().enumerate().all(|(i, a)| {
        items[i + 1..]
            .iter()
            .all(|b| (a.t.0 - b.t.0).abs() >= 1.0 || (a.t.1 - b.t.1).abs() >= 1.0)
    })
}

pub(super) fn column(n: usize) -> Vec<Placement> {
    (0..n)
        .map(|k| Placement {
            part: 0,
            rot: 0,
            t: (0.0, 1.01 * k as f32),
        })
        .collect()
}

/// Bars 6 x 1 (design 0) and 4 x 1 (design 1) on a sheet 10.2 wide.
pub(super) fn bars() -> Footprints {
    Footprints::new(vec![bar(6.0), bar(4.0)])
}

/// A bar `length` x 1 on a sheet 10.2 wide.
pub(super) fn bar(length: f32) -> Vec<Footprint> {
    vec![Footprint::rectangle(length, 1.0, 10.2 - length, 10.0)]
}

/// Independent of the overlap measure: axis-aligned bars are clear iff their boxes do not
/// overlap.
pub(super) fn bars_clear(items: &[Placement]) -> bool {
    let length = |s: &Placement| if s.part == 0 { 6.0 } else { 4.0 };
    items.iter().enumerate().all(|(i, a)| {
        items[i + 1..].iter().all(|b| {
            a.t.0 + length(a) <= b.t.0 || b.t.0 + length(b) <= a.t.0 || (a.t.1 - b.t.1).abs() >= 1.0
        })
    })
}

pub(super) fn at(part: usize, x: f32, y: f32) -> Placement {
    Placement {
        part,
        rot: 0,
        t: (x, y),
    }
}

/// A long and a short bar in each of two rows: a top of 2 (plus the gap), the least four
/// bars of height 1 in rows of at most two can have.
pub(super) fn two_rows_of_bars() -> Vec<Placement> {
    vec![
        at(0, 0.0, 0.0),
        at(1, 6.1, 0.0),
        at(0, 0.0, 1.01),
        at(1, 6.1, 1.01),
    ]
}

/// A chain of `pace` from `start` on stream 5, the stream every chain test draws from.
pub(super) fn chain_from<'f>(
    footprints: &'f Footprints,
    start: &[Placement],
    pace: Pace,
) -> Chain<'f> {
    Chain::new(footprints, start, ChaCha8Rng::seed_from_u64(5), pace)
}

/// The `stop` of a compression that only its budget and stall rules end.
pub(super) fn never() -> bool {
    false
}
