//! The exhaustive grid's row kernels: the best point of one row of lengths at a fixed laminate, shape
//! and base width ([`super::search::exhaustive`]).

/// Row kernel, min-mass: the lightest point with `l e >= U_min` and its index (first on ties).
///
/// Written for the vectoriser: the masked masses of a block of [`LANES`] points are reduced lane-wise
/// without branches; only a block that improves on the row's best is searched for its first index.
#[inline]
pub(super) fn lightest_in_row(lengths: &[f64], e: f64, mu: f64, energy_min: f64) -> (f64, usize) {
    let mut best = f64::INFINITY;
    let mut at = usize::MAX;
    let masked = |l: f64| {
        if l * e >= energy_min {
            l * mu
        } else {
            f64::INFINITY
        }
    };
    let mut start = 0;
    for block in lengths.chunks(LANES) {
        let mut lane_min = [f64::INFINITY; LANES];
        for (m, &l) in lane_min.iter_mut().zip(block) {
            *m = masked(l);
        }
        let block_min = lane_min
            .iter()
            .fold(f64::INFINITY, |a, &b| if b < a { b } else { a });
        if block_min < best {
            best = block_min;
            at = start + lane_min.iter().position(|&m| m == block_min).unwrap_or(0);
        }
        start += block.len();
    }
    (best, at)
}

/// Points per block in [`lightest_in_row`].
const LANES: usize = 8;

/// Row kernel, max energy density: `U/m = e/μ` is the same at every length of the row, so the best point
/// is the first (lightest) one with `l e >= U_min`.
#[inline]
pub(super) fn first_feasible_in_row(lengths: &[f64], e: f64, energy_min: f64) -> usize {
    let mut at = usize::MAX;
    for (i, &l) in lengths.iter().enumerate().rev() {
        if l * e >= energy_min {
            at = i;
        }
    }
    at
}

/// Row kernel of a model that is not linear in `l_tot`: the lengths evaluated through the model
/// (`energy` at a length), the best feasible point by the objective (`value` of energy and mass, the
/// first on ties) and its index. The `mass` at a length, `l w_0 μ`, grows along the row, so for the
/// lightest design (`lightest_to_beat` given, the shape's best so far, which only a strictly better
/// point replaces) the first feasible point is the row's best, and a row that starts no lighter than
/// the one to beat has nothing to offer: neither is evaluated further.
pub(super) fn general_row(
    lengths: &[f64],
    mass: impl Fn(f64) -> f64,
    energy_min: f64,
    lightest_to_beat: Option<f64>,
    energy: impl Fn(f64) -> f64,
    value: impl Fn(f64, f64) -> f64,
) -> (f64, usize) {
    let mut best = (f64::INFINITY, usize::MAX);
    if let (Some(beat), Some(&l)) = (lightest_to_beat, lengths.first()) {
        if mass(l) >= beat {
            return best;
        }
    }
    for (i, &l) in lengths.iter().enumerate() {
        let energy = energy(l);
        if energy >= energy_min {
            let value = value(energy, mass(l));
            if value < best.0 {
                best = (value, i);
            }
            if lightest_to_beat.is_some() {
                break;
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn the_bounded_row_finds_what_a_full_scan_finds() {
        // Random rows: energy not monotone in the length, feasibility anywhere, and a best of the
        // shape so far above, below and between the row's masses. Against every point scanned.
        let mut rng = ChaCha8Rng::seed_from_u64(60);
        for _ in 0..2000 {
            let lengths: Vec<f64> = (0..12).map(|i| 0.04 + 0.002 * i as f64).collect();
            let energies: Vec<f64> = (0..12).map(|_| rng.gen_range(0.0..1.0)).collect();
            let rate = rng.gen_range(0.5..2.0);
            let energy_min = rng.gen_range(0.3..1.1);
            let beat = rng.gen_range(0.0..0.12);
            let at = |l: f64| lengths.iter().position(|&x| x == l).unwrap();
            let mass = |l: f64| l * rate;
            let scanned = lengths
                .iter()
                .enumerate()
                .filter(|&(i, _)| energies[i] >= energy_min)
                .map(|(i, &l)| (mass(l), i))
                .find(|&(m, _)| m < beat);
            let (m, i) = general_row(
                &lengths,
                mass,
                energy_min,
                Some(beat),
                |l| energies[at(l)],
                |_, m| m,
            );
            match scanned {
                Some(want) => assert_eq!((m, i), want),
                // Nothing lighter than the best so far: whatever the row returns must not replace it.
                None => assert!(i == usize::MAX || m >= beat, "{m} {i} {beat}"),
            }
        }
    }
}
