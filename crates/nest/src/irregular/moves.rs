//! Local search by ruin and recreate: the moves (ruin around a point, clear a window, repack a
//! pair of sheets, shrink the lowest sheet under a ceiling, recombine a single sheet), how the
//! removed parts go back, and the threshold-acceptance loop over them.

use jagua_rs::entities::PItemKey;
use jagua_rs::probs::bpp::entities::{BPLayoutType, BPProblem, LayKey};
use rand::seq::SliceRandom;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::construct::{Search, BEST_FIT_TIES_MM, RIGHT_WEIGHT};
use super::model::{collision_free, slide_bottom_left, Model};
use super::random::blink_shuffle;
use super::score::Score;
use crate::limit::SearchLimit;
use crate::placement::{Placement, Sheets};
use crate::problem::NestError;

/// Share of moves on two or more sheets that lower the lowest sheet's top (on one sheet, all).
const SHRINK_SHARE: f64 = 0.3;
/// Share of shrink moves on a single sheet; the others recombine (see `Model::recombine`).
const SINGLE_SHEET_SHRINK_SHARE: f64 = 0.5;
/// Share of ruins that clear a horizontal band instead of the parts around a point.
const BAND_SHARE: f64 = 0.5;
/// Range of the height of a ruined band, mm, and most parts it removes.
const BAND_HEIGHT_MM: (f32, f32) = (5.0, 40.0);
const MAX_BAND_RUIN: usize = 24;
/// Share of shrink and recombine moves that put parts back best fit (`Model::reinsert`).
const BEST_FIT_REPAIR_SHARE: f64 = 0.6;
/// Share of reinsertions in random order rather than largest first.
const RANDOM_ORDER_SHARE: f64 = 0.5;
/// Range of the drop a shrink move asks of the lowest top, mm.
const SHRINK_STEP_MM: (f32, f32) = (0.05, 3.0);
/// Share of moves that repack a sheet together with the emptiest one from scratch.
const REPACK_SHARE: f64 = 0.03;
/// Most parts removed around the ruin point, and most parts pulled from the emptiest sheet.
const MAX_RUIN: usize = 8;
const MAX_PULL: usize = 3;
/// Most parts removed around the ruin point of a shrink move.
const MAX_SHRINK_RUIN: usize = 16;

impl Model<'_> {
    /// Ruin-and-recreate moves from `start` for `budget` iterations, or until `limit` is
    /// reached (the caller then treats the result as cut short).
    pub(super) fn improve(
        &self,
        start: &Sheets,
        budget: usize,
        mut rng: ChaCha8Rng,
        limit: &SearchLimit,
    ) -> (Score, Sheets) {
        let mut problem = self.rebuild(start);
        let mut score = self.score(&problem);
        let mut best = (score, start.clone());
        let mut saved = problem.save();
        for iteration in 0..budget {
            if limit.reached() {
                break;
            }
            if self.ruin_and_recreate(&mut problem, &mut rng).is_err() {
                problem.restore(&saved);
                continue;
            }
            let trial = self.score(&problem);
            // Threshold acceptance: early on, a move may lengthen the layout or lower the
            // concentration a little (never add a sheet); the slack shrinks linearly to zero.
            let slack = 1.0 - iteration as f64 / budget as f64;
            if trial.acceptable_after(&score, slack) {
                score = trial;
                saved = problem.save();
                if score.better_than(&best.0) {
                    best = (score, self.sheets(&problem));
                }
            } else {
                problem.restore(&saved);
            }
        }
        best
    }

    /// One move: remove the parts nearest a random point of a sheet (not the emptiest) and a few
    /// from the emptiest sheet, then reinsert them, the ruined sheet first, then fuller sheets.
    pub(super) fn ruin_and_recreate(
        &self,
        problem: &mut BPProblem,
        rng: &mut ChaCha8Rng,
    ) -> Result<(), NestError> {
        if problem.layouts().len() < 2 {
            return if rng.gen_bool(SINGLE_SHEET_SHRINK_SHARE) {
                self.shrink(problem, rng)
            } else {
                self.recombine(problem, rng)
            };
        }
        if rng.gen_bool(SHRINK_SHARE) {
            return self.shrink(problem, rng);
        }
        let by_fill = self.keys_by_fill(problem);
        let (&emptiest, fuller) = by_fill.split_last().expect("two or more sheets");
        let target = fuller[rng.gen_range(0..fuller.len())];
        if rng.gen_bool(REPACK_SHARE) {
            return self.repack_pair(problem, target, emptiest, rng);
        }

        // Parts pulled from the emptiest sheet go in first, so they claim the room the ruin
        // opened; the ruined parts refill what is left. Half the moves clear a window for one
        // pulled part at a random spot instead of ruining around a random point.
        let mut donors: Vec<_> = problem.layouts()[emptiest].placed_items().keys().collect();
        donors.shuffle(rng);
        let clear_window = !donors.is_empty() && rng.gen_bool(0.5);
        let pull = if clear_window {
            1
        } else {
            rng.gen_range(0..=MAX_PULL.min(donors.len()))
        };
        let mut pulled: Vec<Placement> = donors[..pull]
            .iter()
            .map(|&key| self.remove(problem, emptiest, key))
            .collect();
        let mut ruined = if clear_window {
            let part = pulled.pop().expect("one part pulled");
            self.make_room(problem, target, part.part, rng)
        } else {
            self.ruin_around_point(problem, target, MAX_RUIN, rng)
        };

        let mut order: Vec<LayKey> = std::iter::once(target)
            .chain(fuller.iter().copied().filter(|&k| k != target))
            .chain(std::iter::once(emptiest))
            .collect();
        let area = |p: &Placement| self.job.parts[p.part].area;
        for group in [&mut pulled, &mut ruined] {
            group.sort_by(|a, b| area(b).total_cmp(&area(a)));
            blink_shuffle(group, rng);
        }
        // Where the ruined parts were is a good place to try again.
        let hints = ruined.clone();
        for spot in pulled.into_iter().chain(ruined) {
            order.retain(|&k| problem.layouts().contains_key(k));
            let search = Search {
                hints: &hints,
                ..Search::REPAIR
            };
            self.insert(problem, spot.part, &mut order, rng, search)?;
        }
        Ok(())
    }

    /// Asks the sheet with the lowest top (the one whose used length counts) to end lower, as
    /// strip packers shrink the strip: removes its parts that reach above a ceiling a little
    /// below that top and the parts around a random point of it or of another sheet, then puts
    /// them back, on the other sheets (fullest first) or under the ceiling. Fails if one does
    /// not fit.
    pub(super) fn shrink(
        &self,
        problem: &mut BPProblem,
        rng: &mut ChaCha8Rng,
    ) -> Result<(), NestError> {
        let (lowest, top) = self.lowest_sheet(problem);
        let ceiling = top - rng.gen_range(SHRINK_STEP_MM.0..=SHRINK_STEP_MM.1);
        let others: Vec<LayKey> = self
            .keys_by_fill(problem)
            .into_iter()
            .filter(|&k| k != lowest)
            .collect();
        let ruined_sheet = if others.is_empty() || rng.gen_bool(0.5) {
            lowest
        } else {
            others[rng.gen_range(0..others.len())]
        };
        let above: Vec<PItemKey> = problem.layouts()[lowest]
            .placed_items()
            .iter()
            .filter(|(_, pi)| pi.shape().bbox().y_max > ceiling)
            .map(|(key, _)| key)
            .collect();
        let mut removed: Vec<Placement> = above
            .into_iter()
            .map(|key| self.remove(problem, lowest, key))
            .collect();
        if problem.layouts().contains_key(ruined_sheet) {
            removed.extend(if ruined_sheet == lowest && rng.gen_bool(BAND_SHARE) {
                // The band just under the ceiling: where the parts above must find room.
                let height = rng.gen_range(BAND_HEIGHT_MM.0..=BAND_HEIGHT_MM.1);
                self.ruin_band(problem, ruined_sheet, ceiling - height, height)
            } else {
                self.ruin_around_point(problem, ruined_sheet, MAX_SHRINK_RUIN, rng)
            });
        }
        let hints = removed.clone();
        let search = Search {
            hints: &hints,
            ceiling: Some((lowest, ceiling)),
            ..Search::REPAIR
        };
        let mut order: Vec<LayKey> = others.into_iter().chain([lowest]).collect();
        self.reinsert(problem, removed, &mut order, rng, search)
    }

    /// Puts removed parts back: in a size or random order ([`Self::reinsertion_order`]), each
    /// on the first of `sheets` that takes it, or (a `BEST_FIT_REPAIR_SHARE` of the time) best
    /// fit: each step the part whose spot on the first sheet with room is lowest, as in
    /// [`Self::construct_best_fit`].
    pub(super) fn reinsert(
        &self,
        problem: &mut BPProblem,
        mut parts: Vec<Placement>,
        sheets: &mut Vec<LayKey>,
        rng: &mut ChaCha8Rng,
        search: Search,
    ) -> Result<(), NestError> {
        if !rng.gen_bool(BEST_FIT_REPAIR_SHARE) {
            self.reinsertion_order(&mut parts, rng);
            for spot in parts {
                sheets.retain(|&k| problem.layouts().contains_key(k));
                self.insert(problem, spot.part, sheets, rng, search)?;
            }
            return Ok(());
        }
        let mut left: Vec<usize> = parts.iter().map(|p| p.part).collect();
        // (sheet, design) pairs found full; sheets only fill up while parts go back.
        let mut full: Vec<(LayKey, usize)> = Vec::new();
        while !left.is_empty() {
            sheets.retain(|&k| problem.layouts().contains_key(k));
            let mut designs = left.clone();
            designs.sort_unstable();
            designs.dedup();
            let mut chosen = None;
            for &key in sheets.iter() {
                let layout = &problem.layouts()[key];
                let ceiling = search.ceiling.and_then(|(k, c)| (k == key).then_some(c));
                let mut fits: Vec<(f32, f64, f32, Placement)> = Vec::new();
                for &d in &designs {
                    if full.contains(&(key, d)) {
                        continue;
                    }
                    let found =
                        self.find_spot(Some(layout), d, rng, search.effort, search.hints, ceiling);
                    match found {
                        Some(spot) => {
                            let b = self.shapes[d][spot.rot].plain.bbox();
                            let cost = (b.y_max + spot.t.1) + RIGHT_WEIGHT * (b.x_max + spot.t.0);
                            fits.push((b.y_min + spot.t.1, self.job.parts[d].area, cost, spot));
                        }
                        None => full.push((key, d)),
                    }
                }
                let Some(lowest) = fits.iter().map(|f| f.0).min_by(f32::total_cmp) else {
                    continue;
                };
                chosen = fits
                    .into_iter()
                    .filter(|f| f.0 <= lowest + BEST_FIT_TIES_MM[0])
                    .min_by(|a, b| b.1.total_cmp(&a.1).then(a.2.total_cmp(&b.2)))
                    .map(|f| (key, f.3));
                break;
            }
            let part = match chosen {
                Some((key, spot)) => {
                    problem.place_item(self.bp_placement(BPLayoutType::Open(key), spot));
                    spot.part
                }
                None => {
                    let largest = *designs
                        .iter()
                        .max_by(|&&a, &&b| {
                            self.job.parts[a].area.total_cmp(&self.job.parts[b].area)
                        })
                        .expect("a part is left");
                    // Opens a sheet unless a ceiling forbids it.
                    self.insert(problem, largest, sheets, rng, search)?;
                    largest
                }
            };
            let i = left
                .iter()
                .position(|&p| p == part)
                .expect("placed part was left");
            left.swap_remove(i);
        }
        Ok(())
    }

    /// The single-sheet move that does not shrink: removes a band or the parts around a point
    /// and puts them back in a new order, possibly above the current top (the acceptance
    /// threshold decides). It lets rows of parts be recombined, which a shrink move, bound to
    /// fit under a lower ceiling at once, rarely manages.
    pub(super) fn recombine(
        &self,
        problem: &mut BPProblem,
        rng: &mut ChaCha8Rng,
    ) -> Result<(), NestError> {
        let mut sheets: Vec<LayKey> = problem.layouts().keys().collect();
        let target = sheets[0];
        let removed = if rng.gen_bool(BAND_SHARE) {
            let top = self.top(&problem.layouts()[target]);
            let height = rng.gen_range(BAND_HEIGHT_MM.0..=BAND_HEIGHT_MM.1);
            let low = rng.gen_range(self.usable.y_min - height / 2.0..=top - height / 2.0);
            self.ruin_band(problem, target, low, height)
        } else {
            self.ruin_around_point(problem, target, MAX_SHRINK_RUIN, rng)
        };
        let hints = removed.clone();
        let search = Search {
            hints: &hints,
            ..Search::REPAIR
        };
        self.reinsert(problem, removed, &mut sheets, rng, search)
    }

    /// Orders parts for reinsertion: mostly largest first (slightly perturbed), sometimes at
    /// random, so that small and large parts can trade places and rows get new mixes.
    pub(super) fn reinsertion_order(&self, parts: &mut [Placement], rng: &mut ChaCha8Rng) {
        if rng.gen_bool(RANDOM_ORDER_SHARE) {
            parts.shuffle(rng);
        } else {
            let area = |p: &Placement| self.job.parts[p.part].area;
            parts.sort_by(|a, b| area(b).total_cmp(&area(a)));
            blink_shuffle(parts, rng);
        }
    }

    /// Removes the parts of sheet `target` whose centres lie in the horizontal band
    /// `[low, low + height]` across the whole sheet (at most `MAX_BAND_RUIN`); returns them.
    pub(super) fn ruin_band(
        &self,
        problem: &mut BPProblem,
        target: LayKey,
        low: f32,
        height: f32,
    ) -> Vec<Placement> {
        let keys: Vec<PItemKey> = problem.layouts()[target]
            .placed_items()
            .iter()
            .filter(|(_, pi)| {
                let b = pi.shape().bbox();
                let c = (b.y_min + b.y_max) / 2.0;
                (low..=low + height).contains(&c)
            })
            .map(|(key, _)| key)
            .take(MAX_BAND_RUIN)
            .collect();
        keys.into_iter()
            .map(|key| self.remove(problem, target, key))
            .collect()
    }

    /// Empties sheet `target` and the emptiest sheet and nests all their parts afresh, in a
    /// perturbed size order, on new sheets: on one, if they fit.
    pub(super) fn repack_pair(
        &self,
        problem: &mut BPProblem,
        target: LayKey,
        emptiest: LayKey,
        rng: &mut ChaCha8Rng,
    ) -> Result<(), NestError> {
        let mut parts = Vec::new();
        for sheet in [target, emptiest] {
            let keys: Vec<PItemKey> = problem.layouts()[sheet].placed_items().keys().collect();
            parts.extend(keys.into_iter().map(|key| self.remove(problem, sheet, key)));
        }
        let area = |p: &Placement| self.job.parts[p.part].area;
        parts.sort_by(|a, b| area(b).total_cmp(&area(a)));
        blink_shuffle(&mut parts, rng);
        let mut sheets = Vec::new();
        for spot in parts {
            self.insert(problem, spot.part, &mut sheets, rng, Search::REPAIR)?;
        }
        Ok(())
    }

    /// Removes up to `max_ruin` parts of sheet `target` nearest a random point; returns them.
    pub(super) fn ruin_around_point(
        &self,
        problem: &mut BPProblem,
        target: LayKey,
        max_ruin: usize,
        rng: &mut ChaCha8Rng,
    ) -> Vec<Placement> {
        let top = self.top(&problem.layouts()[target]);
        let centre = (
            rng.gen_range(self.usable.x_min..=self.usable.x_max),
            rng.gen_range(self.usable.y_min..=top),
        );
        let mut near: Vec<(f32, PItemKey)> = problem.layouts()[target]
            .placed_items()
            .iter()
            .map(|(key, pi)| {
                let b = pi.shape().bbox();
                let (dx, dy) = (
                    (b.x_min + b.x_max) / 2.0 - centre.0,
                    (b.y_min + b.y_max) / 2.0 - centre.1,
                );
                (dx * dx + dy * dy, key)
            })
            .collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        let ruin = rng.gen_range(1..=max_ruin.min(near.len()));
        near[..ruin]
            .iter()
            .map(|&(_, key)| self.remove(problem, target, key))
            .collect()
    }

    /// Puts `part` at a random position of sheet `target`, removing the parts whose bounding
    /// boxes are in the way, then slides it bottom-left; returns the removed parts (and `part`,
    /// placement meaningless, if it could not be placed so).
    pub(super) fn make_room(
        &self,
        problem: &mut BPProblem,
        target: LayKey,
        part: usize,
        rng: &mut ChaCha8Rng,
    ) -> Vec<Placement> {
        let fitting: Vec<usize> = (0..self.shapes[part].len())
            .filter(|&r| self.shapes[part][r].fits())
            .collect();
        let rot = fitting[rng.gen_range(0..fitting.len())];
        let shape = &self.shapes[part][rot];
        let t = (
            rng.gen_range(shape.x.0..=shape.x.1),
            rng.gen_range(shape.y.0..=shape.y.1),
        );
        let b = shape.plain.bbox();
        let in_way: Vec<PItemKey> = problem.layouts()[target]
            .placed_items()
            .iter()
            .filter(|(_, pi)| {
                let o = pi.shape().bbox();
                o.x_min < b.x_max + t.0
                    && b.x_min + t.0 < o.x_max
                    && o.y_min < b.y_max + t.1
                    && b.y_min + t.1 < o.y_max
            })
            .map(|(key, _)| key)
            .collect();
        let mut removed: Vec<Placement> = in_way
            .into_iter()
            .map(|key| self.remove(problem, target, key))
            .collect();
        if let Some(layout) = problem.layouts().get(target) {
            let mut buffer = shape.plain.clone();
            if collision_free(layout.cde(), shape, &mut buffer, t) {
                let t = slide_bottom_left(layout.cde(), shape, &mut buffer, t);
                let spot = Placement { part, rot, t };
                problem.place_item(self.bp_placement(BPLayoutType::Open(target), spot));
                return removed;
            }
        }
        removed.insert(0, Placement { part, rot, t });
        removed
    }
}
