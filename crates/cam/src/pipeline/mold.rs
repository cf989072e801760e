//! Which mold films make up the mold stack around one laminate (docs/cam.md §1, "Mold layers").
//!
//! The rule: the mold top sits flush with the laminate or below it, never above, so the clamp presses
//! through the felt onto the PZT and prepreg rather than onto the Teflon. Of all combinations of the
//! stocked film thicknesses whose height does not exceed the laminate, the tallest is taken (ties: the
//! fewest layers, then the thicker films). It is within tolerance when the laminate stands at most the
//! template's `height_tolerance_mm` above it; otherwise the report warns.

use crate::process::template::MoldStock;

/// Most mold layers a stack may have: the clamp panel shows one stacking window per level, and the
/// window numbers are checked for up to 20 levels.
pub const MAX_MOLD_LAYERS: usize = 16;

/// Heights closer than this are equal, mm (well below any film's thickness tolerance).
const EPS_MM: f64 = 1e-9;

/// The chosen mold stack.
#[derive(Debug, Clone, PartialEq)]
pub struct MoldChoice {
    /// Film thickness of each mold layer, bottom to top (thickest first), mm.
    pub films_mm: Vec<f64>,
    /// Laminate height, mm.
    pub laminate_mm: f64,
    /// Sum of the films, mm.
    pub mold_mm: f64,
    /// Whether `laminate - mold` is within the tolerance.
    pub within_tolerance: bool,
}

impl MoldChoice {
    /// Laminate height minus mold height, µm (never negative by the rule).
    pub fn difference_um(&self) -> f64 {
        (self.laminate_mm - self.mold_mm) * 1e3
    }
}

/// The mold stack for a laminate `laminate_mm` tall from the films in `stock`, by the rule above.
/// With no combination at or below the laminate (a laminate thinner than every film), the thinnest
/// film alone, flagged out of tolerance.
pub fn choose_mold(laminate_mm: f64, stock: &MoldStock) -> MoldChoice {
    let mut films: Vec<f64> = stock.films_mm.clone();
    films.sort_by(|a, b| b.total_cmp(a));
    films.dedup();
    // (height, layer count, counts per film) of the best combination so far.
    let mut best: Option<(f64, usize, Vec<usize>)> = None;
    let mut counts = vec![0; films.len()];
    search(&films, 0, 0.0, 0, laminate_mm, &mut counts, &mut best);
    let films_mm: Vec<f64> = match &best {
        Some((_, _, c)) => films
            .iter()
            .zip(c)
            .flat_map(|(t, n)| std::iter::repeat_n(*t, *n))
            .collect(),
        None => vec![films.last().copied().unwrap_or(laminate_mm)],
    };
    let mold_mm: f64 = films_mm.iter().sum();
    MoldChoice {
        within_tolerance: best.is_some() && laminate_mm - mold_mm <= stock.tolerance_mm + EPS_MM,
        films_mm,
        laminate_mm,
        mold_mm,
    }
}

/// Exhaustive search over the count of each film (thickest first), pruned by the laminate height
/// and the layer limit. Stocks hold at most six films and stacks at most [`MAX_MOLD_LAYERS`] layers.
fn search(
    films: &[f64],
    i: usize,
    height: f64,
    layers: usize,
    limit: f64,
    counts: &mut Vec<usize>,
    best: &mut Option<(f64, usize, Vec<usize>)>,
) {
    if i == films.len() {
        if layers == 0 {
            return;
        }
        let better = match best {
            None => true,
            Some((h, n, _)) => {
                height > *h + EPS_MM || ((height - *h).abs() <= EPS_MM && layers < *n)
            }
        };
        if better {
            *best = Some((height, layers, counts.clone()));
        }
        return;
    }
    let mut n = 0;
    loop {
        let h = height + n as f64 * films[i];
        if h > limit + EPS_MM || layers + n > MAX_MOLD_LAYERS {
            break;
        }
        counts[i] = n;
        search(films, i + 1, h, layers + n, limit, counts, best);
        n += 1;
    }
    counts[i] = 0;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stock(films: &[f64], tolerance_mm: f64) -> MoldStock {
        MoldStock {
            films_mm: films.to_vec(),
            tolerance_mm,
        }
    }

    #[test]
    fn design_c_method_2_no_longer_stands_above_the_laminate() {
        // A rule of whole 0.127 mm films, ceil(0.7194 / 0.127) = 6 layers, gives 0.762 mm, 42.6 µm above
        // the 0.7194 mm laminate. From 0.05 / 0.127 / 0.25 mm films the tallest stack not above it is,
        // by hand: 4 x 0.127 + 4 x 0.05 = 0.708 mm; every other count of the three films is either
        // above 0.7194 or lower (e.g. 2 x 0.25 + 4 x 0.05 = 0.700, 0.25 + 2 x 0.127 + 4 x 0.05 = 0.704).
        let c = choose_mold(0.7194, &stock(&[0.05, 0.127, 0.25], 0.025));
        assert!((c.mold_mm - 0.708).abs() < 1e-12, "{c:?}");
        assert_eq!(
            c.films_mm,
            [0.127, 0.127, 0.127, 0.127, 0.05, 0.05, 0.05, 0.05]
        );
        assert!((c.difference_um() - 11.4).abs() < 1e-9);
        assert!(c.within_tolerance);
    }

    #[test]
    fn mold_is_never_above_the_laminate_and_is_the_tallest_below() {
        // Brute force over every count of every film up to the layer limit, independent of the
        // pruned search.
        let films = [0.05, 0.127, 0.25];
        for k in 0..200 {
            let laminate = 0.06 + 0.011 * k as f64;
            let c = choose_mold(laminate, &stock(&films, 0.025));
            assert!(c.mold_mm <= laminate + 1e-9, "{laminate}: {c:?}");
            let mut tallest: f64 = 0.0;
            for a in 0..=MAX_MOLD_LAYERS {
                for b in 0..=MAX_MOLD_LAYERS - a {
                    for d in 0..=MAX_MOLD_LAYERS - a - b {
                        let h = a as f64 * 0.05 + b as f64 * 0.127 + d as f64 * 0.25;
                        if h <= laminate + 1e-9 {
                            tallest = tallest.max(h);
                        }
                    }
                }
            }
            assert!(
                (c.mold_mm - tallest).abs() < 1e-9,
                "{laminate}: {c:?} vs {tallest}"
            );
        }
    }

    #[test]
    fn one_film_out_of_tolerance_is_flagged() {
        // 0.127 mm only: 5 layers = 0.635 mm under 0.7194 mm, 84.4 µm short of a 25 µm tolerance.
        let c = choose_mold(0.7194, &stock(&[0.127], 0.025));
        assert_eq!(c.films_mm.len(), 5);
        assert!(!c.within_tolerance);
        // A laminate thinner than every film: the thinnest alone, flagged.
        let c = choose_mold(0.04, &stock(&[0.05, 0.127], 0.025));
        assert_eq!(c.films_mm, [0.05]);
        assert!(!c.within_tolerance);
    }
}
