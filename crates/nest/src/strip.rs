//! Strip mode: roll stock, a bin of fixed width and unbounded length, where the objective is the
//! used length (strip packing, the form of the published irregular-nesting benchmarks).
//!
//! The irregular nester works on bounded sheets; a strip is one sheet long enough never to bind.
//! Its length is first a generous reserve (twice the length the part area needs at full
//! density, plus the longest part); if the parts do not go onto that, once more with a length
//! that always takes them (every copy on a row of its own). On one sheet the nester's objective
//! is exactly the used length (see [`crate::irregular`]), so nothing else changes, and the
//! result stays deterministic.

use crate::irregular::nest_until;
use crate::job::Job;
use crate::limit::{Reached, SearchLimit};
use crate::problem::{NestBin, NestError, NestItem, NestSettings, NestSolution};
use crate::progress::NestProgress;

/// A layout on roll stock.
#[derive(Debug, Clone, PartialEq)]
pub struct StripLayout {
    /// The parts, on one sheet of `bin`'s length.
    pub solution: NestSolution,
    /// The strip as nested: the width asked for and the reserve length the nester worked in.
    pub bin: NestBin,
    /// Used length: the top of the highest part plus the separation, mm.
    pub length_mm: f64,
    /// Part area over width x used length, in 0..=1.
    pub density: f64,
}

/// Nests the items on a strip `width_mm` wide, as short as the budget finds.
pub fn nest_strip(
    items: &[NestItem],
    width_mm: f64,
    settings: &NestSettings,
    observe: &dyn Fn(&NestProgress),
) -> Result<StripLayout, NestError> {
    nest_strip_until(items, width_mm, settings, &SearchLimit::default(), observe)
        .map(|(strip, _)| strip)
}

/// [`nest_strip`] that also ends at `limit`, as [`crate::nest_until`] does, and says how far it
/// got.
pub fn nest_strip_until(
    items: &[NestItem],
    width_mm: f64,
    settings: &NestSettings,
    limit: &SearchLimit,
    observe: &dyn Fn(&NestProgress),
) -> Result<(StripLayout, Reached), NestError> {
    let probe = NestBin {
        width_mm,
        height_mm: f64::MAX / 4.0,
        stock: 1,
    };
    // Validates the input against the width alone (the probe is endless, and a refusal says so).
    let job = Job::new(items, &probe, settings).map_err(|mut e| {
        if let NestError::PartLargerThanBin { bin_height_mm, .. } = &mut e {
            *bin_height_mm = f64::INFINITY;
        }
        e
    })?;
    // A part's box plus the gap it needs at both edges, as the size check counts it.
    let gap = 2.0 * job.edge_gap_mm();
    let area = job.part_area();
    // Per part, the shortest extent along the strip at a rotation that fits the width.
    let along: Vec<f64> = job
        .parts
        .iter()
        .map(|p| {
            p.rotations_deg
                .iter()
                .map(|&r| p.bbox_size(r))
                .filter(|s| s[0] + gap < width_mm)
                .map(|s| s[1])
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    let longest = along.iter().copied().fold(0.0, f64::max);
    let stacked: f64 = job
        .parts
        .iter()
        .zip(&along)
        .map(|(p, a)| (a + gap) * p.demand as f64)
        .sum::<f64>()
        + gap;
    let reserve = (2.0 * area / width_mm + longest + gap + 10.0).min(stacked);
    let attempt = |length: f64| {
        let bin = NestBin {
            width_mm,
            height_mm: length.ceil(),
            stock: 1,
        };
        let (solution, reached) = nest_until(items, &bin, settings, limit, observe)?;
        let strip = StripLayout {
            length_mm: solution.used_length_mm(&bin, settings.separation_mm),
            density: solution.used_length_utilization(&bin, settings.separation_mm),
            solution,
            bin,
        };
        Ok((strip, reached))
    };
    match attempt(reserve) {
        // The reserve was too short: once more on the length that always takes them.
        Err(NestError::StockTooSmall { .. }) if reserve < stacked => attempt(stacked),
        result => result,
    }
}
