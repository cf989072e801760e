//! How good a layout is: the lexicographic [`Score`] the search accepts moves by, and the
//! measures of a jagua-rs layout it is made of (fills, tops, the sheet whose used length counts).

use jagua_rs::entities::Layout;
use jagua_rs::probs::bpp::entities::{BPProblem, LayKey};

use super::model::Model;

/// Largest drop in the sum of squared fills a move may cause at the start of a worker's budget.
const ACCEPT_SLACK: f64 = 0.005;
/// Largest growth of the used length a move may cause at the start of a worker's budget, mm.
const LENGTH_SLACK_MM: f64 = 1.0;
/// Largest rise of the area-weighted mean top a move that keeps length and fills may cause at
/// the start of a worker's budget, mm.
const ENERGY_SLACK_MM: f64 = 0.3;
/// Used lengths closer than this are equal (the model works in f32), mm.
const LENGTH_TOLERANCE_MM: f64 = 1e-3;

/// Lexicographic quality of a layout: fewer sheets, then a shorter used length (all sheets but
/// the one with the lowest top counted whole, plus that top), then a higher sum of squared
/// fills, then lower parts.
#[derive(Debug, Clone, Copy)]
pub(super) struct Score {
    pub(super) sheets: usize,
    /// `(sheets - 1) * usable height + lowest sheet top`, mm above the usable bottom.
    pub(super) length: f64,
    pub(super) concentration: f64,
    /// Sum of the parts' tops over the usable height.
    pub(super) height: f64,
    /// Area-weighted mean top of the parts above their sheet's usable bottom, mm: where the
    /// mass sits. Moves that change neither the length nor the fills are accepted by it, so
    /// they pack the parts down and leave the free room at the top, where a later shrink needs
    /// it, instead of drifting at random.
    pub(super) energy: f64,
}

impl Score {
    pub(super) fn at_least_as_good_as(&self, other: &Score) -> bool {
        if self.sheets != other.sheets {
            return self.sheets < other.sheets;
        }
        if (self.length - other.length).abs() > LENGTH_TOLERANCE_MM {
            return self.length < other.length;
        }
        let tol = 1e-12;
        if (self.concentration - other.concentration).abs() > tol {
            return self.concentration > other.concentration;
        }
        self.height <= other.height + 1e-9
    }

    /// Fewer sheets, or a used length shorter by more than the tolerance: an improvement of
    /// what the layout is judged by (the other terms only steer the search).
    pub(super) fn shorter_than(&self, other: &Score) -> bool {
        self.sheets < other.sheets
            || (self.sheets == other.sheets && self.length < other.length - LENGTH_TOLERANCE_MM)
    }

    pub(super) fn better_than(&self, other: &Score) -> bool {
        !other.at_least_as_good_as(self)
    }

    /// Threshold acceptance of a move from `current`: never an extra sheet; a shorter layout
    /// always; one longer by more than `slack * LENGTH_SLACK_MM` never; otherwise if the
    /// concentration drops by at most `slack * ACCEPT_SLACK`. `slack` falls from 1 to 0 over a
    /// worker's budget.
    pub(super) fn acceptable_after(&self, current: &Score, slack: f64) -> bool {
        if self.sheets != current.sheets {
            return self.sheets < current.sheets;
        }
        if self.length < current.length - LENGTH_TOLERANCE_MM {
            return true;
        }
        if self.length > current.length + LENGTH_TOLERANCE_MM + LENGTH_SLACK_MM * slack {
            return false;
        }
        if (self.concentration - current.concentration).abs() <= 1e-12 {
            return self.energy <= current.energy + 1e-9 + ENERGY_SLACK_MM * slack;
        }
        self.concentration >= current.concentration - 1e-12 - ACCEPT_SLACK * slack
    }
}

impl Model<'_> {
    /// Open sheets, fullest first (ties in key order).
    pub(super) fn keys_by_fill(&self, problem: &BPProblem) -> Vec<LayKey> {
        let mut keys: Vec<(f64, LayKey)> = problem
            .layouts()
            .iter()
            .map(|(k, l)| (self.fill(l), k))
            .collect();
        keys.sort_by(|a, b| b.0.total_cmp(&a.0));
        keys.into_iter().map(|(_, k)| k).collect()
    }

    /// Part area over sheet area, in f64 from our own outlines.
    pub(super) fn fill(&self, layout: &Layout) -> f64 {
        let area: f64 = layout
            .placed_items()
            .values()
            .map(|pi| self.job.parts[pi.item().idx()].area)
            .sum();
        area / (self.job.bin.width_mm * self.job.bin.height_mm)
    }

    pub(super) fn score(&self, problem: &BPProblem) -> Score {
        let usable_height = f64::from(self.usable.y_max - self.usable.y_min);
        let sheets = problem.layouts().len();
        let mut score = Score {
            sheets,
            length: 0.0,
            concentration: 0.0,
            height: 0.0,
            energy: 0.0,
        };
        let mut mass = 0.0;
        let mut lowest_top = f64::INFINITY;
        for layout in problem.layouts().values() {
            score.concentration += self.fill(layout).powi(2);
            lowest_top = lowest_top.min(f64::from(self.top(layout) - self.usable.y_min));
            for pi in layout.placed_items().values() {
                let area = self.job.parts[pi.item().idx()].area;
                score.energy += area * f64::from(pi.shape().bbox().y_max - self.usable.y_min);
                mass += area;
            }
            score.height += layout
                .placed_items()
                .values()
                .map(|pi| f64::from(pi.shape().bbox().y_max - self.usable.y_min))
                .sum::<f64>()
                / usable_height;
        }
        if mass > 0.0 {
            score.energy /= mass;
        }
        if sheets > 0 {
            score.length = (sheets - 1) as f64 * usable_height + lowest_top;
        }
        score
    }

    /// Top of the highest collision shape of a sheet (the usable bottom when empty).
    pub(super) fn top(&self, layout: &Layout) -> f32 {
        layout
            .placed_items()
            .values()
            .map(|pi| pi.shape().bbox().y_max)
            .fold(self.usable.y_min, f32::max)
    }

    /// The sheet with the lowest top (ties to the emptier, then the later key): the one whose
    /// used length counts.
    pub(super) fn lowest_sheet(&self, problem: &BPProblem) -> (LayKey, f32) {
        problem
            .layouts()
            .iter()
            .map(|(k, l)| (k, self.top(l), self.fill(l)))
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.2.total_cmp(&b.2)))
            .map(|(k, top, _)| (k, top))
            .expect("at least one sheet")
    }
}
