//! Measured values that share one model value, pooled for the grouped search
//! ([`crate::calibrate::fit::least_squares_grouped`]).
//!
//! The values `c_i` of a pool all have the residual `c_i - v` for one model value `v` (an actuator's
//! deflections at one drive mode less their own constant terms, or the deflections and masses of
//! actuators built to one design), so their sum of squares is `spread + n (mean - v)²`, with `n` their
//! number, `mean` their mean and `spread = Σ (c_i - mean)²`: the search needs one residual per pool,
//! `√n (mean - v)`, and the spread as a constant. Cross-validation leaves whole actuators out, so the
//! sums are also kept per keep mask (its folds are the same for every model fitted).

use std::sync::{Arc, Mutex};

/// A pool's values as the search sees them, for each of `M` ways of writing the values.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Sums<const M: usize> {
    pub(crate) root_count: f64,
    pub(crate) mean: [f64; M],
    pub(crate) spread: [f64; M],
}

/// One value: its pool, its actuator, and the value in each of the `M` ways.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Member<const M: usize> {
    pub(crate) pool: usize,
    pub(crate) actuator: usize,
    pub(crate) value: [f64; M],
}

/// A keep mask and the sums of the values of the actuators it keeps.
type Kept<const M: usize> = (Vec<bool>, Arc<Vec<Sums<M>>>);

/// Keep masks whose sums are held (two repeats of five folds, and room to spare).
const KEPT_MASKS: usize = 32;

/// The values of some pools, and their sums.
#[derive(Debug)]
pub(crate) struct Pools<const M: usize> {
    members: Vec<Member<M>>,
    all: Vec<Sums<M>>,
    kept: Mutex<Vec<Kept<M>>>,
}

impl<const M: usize> Pools<M> {
    /// `count` pools of `members`.
    pub(crate) fn new(count: usize, members: Vec<Member<M>>) -> Self {
        Pools {
            all: sums(count, members.iter()),
            members,
            kept: Mutex::default(),
        }
    }

    /// Whether a pool has more than one value: else the pooled residuals are the values themselves.
    pub(crate) fn pools(&self) -> bool {
        self.all.iter().any(|s| s.root_count > 1.0)
    }

    /// `f` of the sums of the values of the actuators `keep` marks (None: all); a pool none of whose
    /// values is kept has a zero count.
    pub(crate) fn with_sums<R>(&self, keep: Option<&[bool]>, f: impl FnOnce(&[Sums<M>]) -> R) -> R {
        let Some(keep) = keep else {
            return f(&self.all);
        };
        let found = {
            let mut held = self.kept.lock().unwrap_or_else(|e| e.into_inner());
            match held.iter().find(|(mask, _)| mask == keep) {
                Some((_, sums)) => Arc::clone(sums),
                None => {
                    let kept = self.members.iter().filter(|m| keep[m.actuator]);
                    let sums = Arc::new(sums(self.all.len(), kept));
                    if held.len() >= KEPT_MASKS {
                        held.remove(0);
                    }
                    held.push((keep.to_vec(), Arc::clone(&sums)));
                    sums
                }
            }
        };
        f(&found)
    }
}

/// The sums of `count` pools from their members (two passes: the means, then the spreads about them).
fn sums<'m, const M: usize>(
    count: usize,
    members: impl Iterator<Item = &'m Member<M>> + Clone,
) -> Vec<Sums<M>> {
    let mut number = vec![0usize; count];
    let mut total = vec![[0.0; M]; count];
    for m in members.clone() {
        number[m.pool] += 1;
        for (t, v) in total[m.pool].iter_mut().zip(m.value) {
            *t += v;
        }
    }
    let mut sums: Vec<Sums<M>> = (0..count)
        .map(|p| Sums {
            root_count: (number[p] as f64).sqrt(),
            mean: total[p].map(|t| t / number[p].max(1) as f64),
            spread: [0.0; M],
        })
        .collect();
    for m in members {
        let s = &mut sums[m.pool];
        for ((spread, mean), v) in s.spread.iter_mut().zip(s.mean).zip(m.value) {
            *spread += (v - mean).powi(2);
        }
    }
    sums
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pooled residuals' squares and the spread add up to the values' own sum of squares about any
    /// model values, for all the actuators and for those a mask keeps (asked twice: held).
    #[test]
    fn pooled_residuals_keep_the_sum_of_squares() {
        let values = [
            (0, 0, 1.0),
            (0, 1, 1.5),
            (1, 1, -0.5),
            (0, 2, 0.7),
            (1, 3, 0.1),
        ];
        let members: Vec<Member<1>> = values
            .iter()
            .map(|&(pool, actuator, v)| Member {
                pool,
                actuator,
                value: [v],
            })
            .collect();
        let pools = Pools::new(2, members);
        assert!(pools.pools());
        let model = [0.4, -0.2];
        for keep in [
            None,
            Some(&[true, false, true, true][..]),
            Some(&[true, false, true, true][..]),
        ] {
            let kept = |a: usize| keep.is_none_or(|k| k[a]);
            let want: f64 = values
                .iter()
                .filter(|v| kept(v.1))
                .map(|&(p, _, v)| (v - model[p]).powi(2))
                .sum();
            let got = pools.with_sums(keep, |sums| {
                sums.iter()
                    .zip(model)
                    .map(|(s, v)| s.spread[0] + (s.root_count * (s.mean[0] - v)).powi(2))
                    .sum::<f64>()
            });
            assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        }
        assert_eq!(pools.kept.lock().unwrap().len(), 1);
    }
}
