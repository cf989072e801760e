//! Which mold films make up the mold stack around one laminate (docs/cam.md §1, "Mold layers"), and
//! whether every part is pressed.
//!
//! The laminate is three bands: the lower PZT plate `[0, t_p]`, the passive core (plies and bond layers)
//! `[t_p, t_p + core]`, and the upper plate. A mold layer cut with the PZT outline holds a plate; one cut
//! with the passive outline holds the core, extension included. Over the extension, the layers of the
//! lower band carry it and the first layer of the upper band presses on it, so each band gets films of its
//! own: the press-fit rule. Band by band, bottom to top, the films are the tallest combination whose top
//! does not rise above the top of the part band (ties: the fewest layers, then the thicker films). So
//! no cavity is deeper than the part it holds: the press bears on the PZT over the plates and on the
//! prepreg over the extension, never on Teflon.
//!
//! A part is pressed within tolerance when the void under it and the height it stands proud of its
//! cavity are both within the template's `height_tolerance_mm` ([`PressFit`]); otherwise the report
//! warns and says which part.

use crate::process::template::MoldStock;

/// Most mold layers a stack may have: the clamp panel shows one stacking window per level, and the
/// window numbers are checked for up to 20 levels.
pub const MAX_MOLD_LAYERS: usize = 16;

/// Heights closer than this are equal, mm (well below any film's thickness tolerance).
const EPS_MM: f64 = 1e-9;

/// The heights of a laminate's bands, mm: what the mold must hold.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaminateBands {
    /// Thickness of one PZT plate, mm.
    pub plate_mm: f64,
    /// Thickness of the passive core between the plates (plies and bond layers), mm.
    pub core_mm: f64,
    /// Thickness of one bond layer, mm (0 without): each bond part lies on its plate, inside the
    /// plate's outline, so it goes with the plate's band, and the passive part (the extension
    /// included, which has no bond under or over it) lies from one bond's top to the other's bottom.
    pub bond_mm: f64,
}

impl LaminateBands {
    /// Height of the whole laminate, mm.
    pub fn laminate_mm(&self) -> f64 {
        2.0 * self.plate_mm + self.core_mm
    }

    /// The passive part's underside and top, mm.
    pub fn passive_mm(&self) -> (f64, f64) {
        (
            self.plate_mm + self.bond_mm,
            self.plate_mm + self.core_mm - self.bond_mm,
        )
    }
}

/// Which band of the laminate a mold layer belongs to, and so which outline its cavity has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MoldBand {
    /// Holds the lower PZT plate: cavity of the PZT outline.
    LowerPlate,
    /// Holds the passive core: cavity of the passive outline, extension included.
    Core,
    /// Holds the upper PZT plate: cavity of the PZT outline.
    UpperPlate,
}

/// How one part region sits in its cavity, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PressFit {
    /// The region: `laminate` (plates and core over the PZT) or `extension` (the core alone).
    pub region: &'static str,
    /// Gap between the part's underside and the mold that carries it (0 for the laminate, which lies
    /// on the cover film), mm.
    pub void_below_mm: f64,
    /// How far the part's top stands above the mold layer over it (over the laminate: above the mold
    /// top); never negative by the rule, mm.
    pub proud_mm: f64,
}

impl PressFit {
    /// Whether both the void and the proud height are within `tolerance_mm`.
    pub fn within(&self, tolerance_mm: f64) -> bool {
        self.void_below_mm <= tolerance_mm + EPS_MM && self.proud_mm <= tolerance_mm + EPS_MM
    }
}

/// The chosen mold stack.
#[derive(Debug, Clone, PartialEq)]
pub struct MoldChoice {
    /// Film thickness of each mold layer, bottom to top, mm.
    pub films_mm: Vec<f64>,
    /// The band of each mold layer, bottom to top.
    pub bands: Vec<MoldBand>,
    /// Laminate height, mm.
    pub laminate_mm: f64,
    /// Sum of the films, mm.
    pub mold_mm: f64,
    /// How the laminate and the extension sit in their cavities.
    pub fits: Vec<PressFit>,
    /// Whether every part is pressed within the tolerance.
    pub within_tolerance: bool,
}

impl MoldChoice {
    /// Laminate height minus mold height, µm (never negative by the rule).
    pub fn difference_um(&self) -> f64 {
        (self.laminate_mm - self.mold_mm) * 1e3
    }

    /// The height band `(bottom, top)` of each mold layer, mm, bottom to top.
    pub fn layer_heights_mm(&self) -> Vec<(f64, f64)> {
        self.films_mm
            .iter()
            .scan(0.0, |top, t| {
                let band = (*top, *top + t);
                *top += t;
                Some(band)
            })
            .collect()
    }
}

/// The mold stack for a laminate of `bands` from the films in `stock`, by the press-fit rule above.
/// A band no film fits under (a plate thinner than every film) gets no layer, and the parts it should
/// carry are flagged out of tolerance.
pub fn choose_mold(bands: LaminateBands, stock: &MoldStock) -> MoldChoice {
    let mut films: Vec<f64> = stock.films_mm.clone();
    films.sort_by(|a, b| b.total_cmp(a));
    films.dedup();
    let (passive_bottom, passive_top) = bands.passive_mm();
    let tops = [
        (MoldBand::LowerPlate, passive_bottom),
        (MoldBand::Core, passive_top),
        (MoldBand::UpperPlate, bands.laminate_mm()),
    ];
    let mut films_mm = Vec::new();
    let mut layer_bands = Vec::new();
    // The top of each band's films, mm.
    let mut band_top = [0.0; 3];
    let mut height = 0.0;
    for (k, (band, top)) in tops.into_iter().enumerate() {
        let left = MAX_MOLD_LAYERS - films_mm.len();
        let mut best: Option<(f64, usize, Vec<usize>)> = None;
        let mut counts = vec![0; films.len()];
        search(
            &films,
            0,
            0.0,
            0,
            top - height,
            left,
            &mut counts,
            &mut best,
        );
        if let Some((h, _, c)) = best {
            for (t, n) in films.iter().zip(c) {
                films_mm.extend(std::iter::repeat_n(*t, n));
                layer_bands.extend(std::iter::repeat_n(band, n));
            }
            height += h;
        }
        band_top[k] = height;
    }
    let laminate_mm = bands.laminate_mm();
    let fits = vec![
        PressFit {
            region: "laminate",
            void_below_mm: 0.0,
            proud_mm: laminate_mm - height,
        },
        PressFit {
            region: "extension",
            void_below_mm: passive_bottom - band_top[0],
            proud_mm: passive_top - band_top[1],
        },
    ];
    MoldChoice {
        within_tolerance: !films_mm.is_empty() && fits.iter().all(|f| f.within(stock.tolerance_mm)),
        films_mm,
        bands: layer_bands,
        laminate_mm,
        mold_mm: height,
        fits,
    }
}

/// Exhaustive search over the count of each film (thickest first) for the tallest combination not
/// above `limit`, pruned by the limit and by `max_layers`. Stocks hold at most six films and stacks at
/// most [`MAX_MOLD_LAYERS`] layers.
#[allow(clippy::too_many_arguments)]
fn search(
    films: &[f64],
    i: usize,
    height: f64,
    layers: usize,
    limit: f64,
    max_layers: usize,
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
        if h > limit + EPS_MM || layers + n > max_layers {
            break;
        }
        counts[i] = n;
        search(films, i + 1, h, layers + n, limit, max_layers, counts, best);
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

    /// Thesis design C, method 2: 0.267 mm plates around three 0.0618 mm plies.
    const C: LaminateBands = LaminateBands {
        plate_mm: 0.267,
        core_mm: 3.0 * 0.0618,
        bond_mm: 0.0,
    };

    #[test]
    fn design_c_method_2_presses_the_plates_and_the_extension() {
        // By hand, from 0.05 / 0.127 / 0.25 mm films, band by band:
        // - under the 0.267 mm plate: 2 x 0.127 = 0.254 (0.25 alone, 5 x 0.05 = 0.25 are lower);
        // - up to the core top at 0.4524: 0.1984 left, 0.127 + 0.05 = 0.177 (top 0.431);
        // - up to the laminate top at 0.7194: 0.2884 left, 0.127 + 3 x 0.05 = 0.277 (top 0.708).
        // The extension has 13 µm under it and stands 21.4 µm proud of the layer over it; the
        // laminate stands 11.4 µm above the mold. Thickest-first films (4 x 0.127 + 4 x 0.05) would put
        // a layer boundary at 0.508 over the extension: a 56 µm void above it, not pressed.
        let c = choose_mold(C, &stock(&[0.05, 0.127, 0.25], 0.025));
        assert_eq!(
            c.films_mm,
            [0.127, 0.127, 0.127, 0.05, 0.127, 0.05, 0.05, 0.05]
        );
        use MoldBand::*;
        assert_eq!(
            c.bands,
            [LowerPlate, LowerPlate, Core, Core, UpperPlate, UpperPlate, UpperPlate, UpperPlate]
        );
        assert!((c.mold_mm - 0.708).abs() < 1e-12, "{c:?}");
        assert!((c.difference_um() - 11.4).abs() < 1e-9);
        let ext = c.fits[1];
        assert!((ext.void_below_mm - 0.013).abs() < 1e-12, "{ext:?}");
        assert!((ext.proud_mm - 0.0214).abs() < 1e-12, "{ext:?}");
        assert!(c.within_tolerance);
    }

    #[test]
    fn a_bond_layer_goes_with_its_plate_and_the_extension_lies_on_the_bond() {
        // Design C, method 1: 0.025 mm Pyralux on each plate's inner face. The passive part (the
        // extension has no Pyralux under or over it) lies from 0.292 to 0.4774 mm. By hand:
        // - under 0.292: 2 x 0.127 + 0.05 = 0.304 is too tall; 0.25 + 0.05 = 0.3 too; 2 x 0.127 =
        //   0.254, 0.127 + 3 x 0.05 = 0.277, 0.25 = 0.25, 5 x 0.05 = 0.25: 0.277 (top 0.277);
        // - up to 0.4774: 0.2004 left: 4 x 0.05 = 0.2 (top 0.477);
        // - up to 0.7694: 0.2924 left: 0.127 + 3 x 0.05 = 0.277 (top 0.754).
        // Under the extension 15 µm of void (it lies on the lower Pyralux's top, not on the plate's),
        // 0.4 µm proud; the laminate 15.4 µm above the mold.
        let bonded = LaminateBands {
            core_mm: 3.0 * 0.0618 + 2.0 * 0.025,
            bond_mm: 0.025,
            ..C
        };
        let c = choose_mold(bonded, &stock(&[0.05, 0.127, 0.25], 0.025));
        let tops: Vec<f64> = c.layer_heights_mm().iter().map(|(_, t)| *t).collect();
        let band_top = |b: MoldBand| {
            c.bands
                .iter()
                .rposition(|x| *x == b)
                .map(|k| tops[k])
                .unwrap()
        };
        assert!(
            (band_top(MoldBand::LowerPlate) - 0.277).abs() < 1e-12,
            "{c:?}"
        );
        assert!((band_top(MoldBand::Core) - 0.477).abs() < 1e-12, "{c:?}");
        assert!((c.mold_mm - 0.754).abs() < 1e-12, "{c:?}");
        let ext = c.fits[1];
        assert!((ext.void_below_mm - 0.015).abs() < 1e-12, "{ext:?}");
        assert!((ext.proud_mm - 0.0004).abs() < 1e-12, "{ext:?}");
        assert!((c.difference_um() - 15.4).abs() < 1e-9);
        assert!(c.within_tolerance);
    }

    /// The tallest sum of at most `max_layers` films not above `limit`, by brute force over counts.
    fn tallest(films: &[f64], limit: f64, max_layers: usize) -> f64 {
        let mut best: f64 = 0.0;
        for a in 0..=max_layers {
            for b in 0..=max_layers - a {
                for d in 0..=max_layers - a - b {
                    let h = a as f64 * films[0] + b as f64 * films[1] + d as f64 * films[2];
                    if h <= limit + 1e-9 {
                        best = best.max(h);
                    }
                }
            }
        }
        best
    }

    #[test]
    fn every_band_is_the_tallest_stack_not_above_its_part() {
        // Brute force band by band, independent of the pruned search.
        let films = [0.05, 0.127, 0.25];
        for k in 0..60 {
            let bands = LaminateBands {
                plate_mm: 0.1 + 0.007 * k as f64,
                core_mm: 0.06 + 0.011 * (k % 23) as f64,
                bond_mm: 0.0,
            };
            let c = choose_mold(bands, &stock(&films, 0.025));
            let mut top = 0.0;
            for (band, part_top) in [
                (MoldBand::LowerPlate, bands.plate_mm),
                (MoldBand::Core, bands.plate_mm + bands.core_mm),
                (MoldBand::UpperPlate, bands.laminate_mm()),
            ] {
                let layers_before = c.bands.iter().take_while(|b| **b != band).count();
                let own: f64 = c
                    .films_mm
                    .iter()
                    .zip(&c.bands)
                    .filter(|(_, b)| **b == band)
                    .map(|(t, _)| t)
                    .sum();
                let expected = tallest(&films, part_top - top, MAX_MOLD_LAYERS - layers_before);
                assert!((own - expected).abs() < 1e-9, "{bands:?} {band:?}: {c:?}");
                top += own;
                assert!(top <= part_top + 1e-9, "{bands:?}: a cavity above its part");
            }
            assert!(c.films_mm.len() <= MAX_MOLD_LAYERS);
        }
    }

    #[test]
    fn one_film_out_of_tolerance_is_flagged() {
        // 0.127 mm only: the core band takes one film (top 0.381), so the extension stands 71.4 µm proud
        // of the layer over it: no press there within 25 µm.
        let c = choose_mold(C, &stock(&[0.127], 0.025));
        assert_eq!(c.films_mm.len(), 5);
        assert!(!c.fits[1].within(0.025));
        assert!(!c.within_tolerance);
        // Plates thinner than every film: no layer can carry them.
        let thin = LaminateBands {
            plate_mm: 0.01,
            core_mm: 0.02,
            bond_mm: 0.0,
        };
        let c = choose_mold(thin, &stock(&[0.05, 0.127], 0.025));
        assert!(c.films_mm.is_empty());
        assert!(!c.within_tolerance);
    }
}
