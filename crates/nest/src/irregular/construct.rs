//! Construction: where one part goes (the bottom-left spot search), how it is inserted on the
//! first sheet with room, and the greedy fills (size orders and best fit) that start the search.

use jagua_rs::entities::Layout;
use jagua_rs::geometry::primitives::{Rect, SPolygon};
use jagua_rs::probs::bpp::entities::{BPLayoutType, BPProblem, LayKey};
use rand::seq::SliceRandom;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::model::{collision_free, slide, Model, RotatedShape, COARSE_SLIDE, FINISH_SLIDE};
use super::random::{blink_shuffle, worker_rng};
use super::score::Score;
use super::threads::shared_out;
use crate::limit::SearchLimit;
use crate::placement::{Placement, Sheets};
use crate::problem::NestError;

/// Weight of the right edge against the top edge in the placement cost.
pub(super) const RIGHT_WEIGHT: f32 = 0.25;

/// How hard one insertion looks.
#[derive(Debug, Clone, Copy)]
pub(super) struct Effort {
    /// Random start positions per rotation.
    pub(super) random: usize,
    /// Start positions next to placed parts, per rotation (sampled when there are more).
    pub(super) anchors: usize,
    /// Whether the anchors are those of the parts placed last rather than a sample of all:
    /// on a fill of many copies (`Effort::for_fill`), where a handful of anchors drawn from
    /// thousands of parts would nearly all lie among buried parts, the last placed are where a
    /// fill in a size order goes on.
    pub(super) last_placed: bool,
}

const GREEDY_EFFORT: Effort = Effort {
    random: 100,
    anchors: 200,
    last_placed: false,
};
const REPAIR_EFFORT: Effort = Effort {
    random: 20,
    anchors: 50,
    last_placed: false,
};

/// Least effort per design of a best-fit step (`Model::construct_best_fit`), which searches a
/// spot for every design still to place.
const BEST_FIT_MIN_EFFORT: Effort = Effort {
    random: 10,
    anchors: 25,
    last_placed: false,
};
/// Starts each worker builds (see `Model::construct`) on jobs of at most this many copies: a
/// size-order fill and a best-fit fill each. More starts cost CPU for little: on sheet layers
/// of a few designs the starts come out at the same used length, and the final compression,
/// not the choice of start, decides how short the layout gets.
const STARTS_PER_WORKER: usize = 2;
/// Tie widths of the best-fit starts (odd recipes), mm: spots whose bottoms are this close
/// count as equally low.
pub(super) const BEST_FIT_TIES_MM: [f32; 5] = [2.0, 0.5, 5.0, 1.0, 3.0];
const PORTFOLIO_MAX_COPIES: usize = 150;
/// Copies up to which a greedy fill gives every part its whole effort. A part's insertion costs
/// about the same however many parts there are (its starts are counted), so a fill of thousands
/// of parts at the whole effort takes minutes (2,000 circles of 1 mm radius: 40 s);
/// above this many copies each insertion gets this share of the effort over the copies, which
/// holds a fill's starts, and its time, near those of this many copies.
const FULL_EFFORT_COPIES: usize = 300;
/// The least effort of a greedy fill's insertion, however many copies: the corner and a few
/// starts next to placed parts and at random.
const LEAST_EFFORT: Effort = Effort {
    random: 2,
    anchors: 4,
    last_placed: true,
};

/// A start tried at a rotation: clear, slid down and left by the coarse steps, with its cost
/// ([`Model::find_spot`]).
type CoarseStart<'a> = dyn Fn(usize, (f32, f32), &mut SPolygon) -> Option<(f32, Placement)> + 'a;

/// Steps of the grid of starts across a shaped sheet when no sampled start finds room
/// ([`Model::find_spot`]): a start in every 1/24 of the sheet each way.
const SHAPED_GRID: usize = 24;

impl Effort {
    /// This effort for a fill of `copies` parts (`FULL_EFFORT_COPIES`, `LEAST_EFFORT`).
    fn for_fill(self, copies: usize) -> Effort {
        if copies <= FULL_EFFORT_COPIES {
            return self;
        }
        let share = |n: usize| n * FULL_EFFORT_COPIES / copies;
        Effort {
            random: share(self.random).max(LEAST_EFFORT.random),
            anchors: share(self.anchors).max(LEAST_EFFORT.anchors),
            last_placed: true,
        }
    }
}

/// What an insertion tries: how hard, which earlier placements to try first, and an optional
/// ceiling on one sheet (then no new sheet is opened).
#[derive(Clone, Copy)]
pub(super) struct Search<'h> {
    pub(super) effort: Effort,
    pub(super) hints: &'h [Placement],
    pub(super) ceiling: Option<(LayKey, f32)>,
}

impl Search<'_> {
    pub(super) const GREEDY: Search<'static> = Search {
        effort: GREEDY_EFFORT,
        hints: &[],
        ceiling: None,
    };
    pub(super) const REPAIR: Search<'static> = Search {
        effort: REPAIR_EFFORT,
        hints: &[],
        ceiling: None,
    };
}

impl Model<'_> {
    /// The starts of every worker: worker `w` builds recipes `w`, `w + workers`, ...
    /// (`STARTS_PER_WORKER` of them on jobs of up to `PORTFOLIO_MAX_COPIES` copies, else one)
    /// and keeps the best. The local search rarely leaves the basin of its start, so several
    /// kinds of start buy more than more iterations. The recipes are shared out to the threads
    /// as they come free (best-fit recipes cost several times a size order, and with two
    /// workers they would all fall to the second one); which thread builds a recipe does not
    /// change what it builds, so the starts are the same as built in worker order.
    ///
    /// `limit` cuts the fill: a best-fit recipe it strikes in is dropped (`None`), a recipe not
    /// yet begun is not built, and recipe 0, which every layout needs, finishes at the repair
    /// effort. A worker left without a start takes recipe 0's. The flag says the limit struck,
    /// so that the starts are not those of any budget.
    pub(super) fn construct_all(
        &self,
        limit: &SearchLimit,
    ) -> Result<(Vec<(Score, Sheets)>, bool), NestError> {
        let workers = self.job.settings.workers;
        let starts = if self.job.copies() <= PORTFOLIO_MAX_COPIES {
            STARTS_PER_WORKER
        } else {
            1
        };
        let built = shared_out(workers, starts * workers, |recipe| {
            if recipe == 0 {
                self.construct_in_order(recipe, limit).map(Some)
            } else if limit.reached() {
                Ok(None)
            } else if recipe % 2 == 1 {
                let ties = BEST_FIT_TIES_MM;
                self.construct_best_fit(recipe, ties[recipe / 2 % ties.len()], limit)
            } else {
                self.construct_in_order(recipe, limit).map(Some)
            }
        });
        let mut cut = false;
        let mut best: Vec<Option<(Score, Sheets)>> = vec![None; workers];
        for (recipe, start) in built.into_iter().enumerate() {
            let Some(start) = start? else {
                cut = true;
                continue;
            };
            let own = &mut best[recipe % workers];
            if own.as_ref().is_none_or(|(s, _)| start.0.better_than(s)) {
                *own = Some(start);
            }
        }
        // A worker whose starts the limit cut takes the first worker's (recipe 0 always ends).
        let first = best[0].clone().expect("recipe 0 always ends");
        let starts = best
            .into_iter()
            .map(|b| b.unwrap_or_else(|| first.clone()))
            .collect();
        Ok((starts, cut || limit.reached()))
    }

    /// Greedy fill in a size order (area, length or box area, by even recipe; perturbed from
    /// recipe 6 on), first sheet that takes a part.
    /// Each insertion takes the greedy effort, a share of it on jobs of many copies
    /// (`FULL_EFFORT_COPIES`). Once `limit` is reached, the parts still to place go in with the
    /// repair effort (a fraction of the greedy one, shared out alike), so that a deadline that
    /// strikes in the fill costs little more time; recipes other than 0 are then not built at
    /// all (`construct_all`).
    pub(super) fn construct_in_order(
        &self,
        recipe: usize,
        limit: &SearchLimit,
    ) -> Result<(Score, Sheets), NestError> {
        let mut rng = worker_rng(self.job.settings.seed, 0, recipe);
        let mut order: Vec<usize> = self
            .job
            .parts
            .iter()
            .enumerate()
            .flat_map(|(p, part)| std::iter::repeat_n(p, part.demand))
            .collect();
        let size = |p: usize| -> f64 {
            let part = &self.job.parts[p];
            match recipe / 2 % 3 {
                0 => part.area,
                1 => {
                    let s = part.bbox_size(part.rotations_deg[0]);
                    s[0].max(s[1])
                }
                _ => {
                    let s = part.bbox_size(part.rotations_deg[0]);
                    s[0] * s[1]
                }
            }
        };
        // Stable: equal sizes keep part order, so copies of one design stay together.
        order.sort_by(|&a, &b| size(b).total_cmp(&size(a)));
        if recipe >= 6 {
            blink_shuffle(&mut order, &mut rng);
        }
        let mut problem = BPProblem::new(self.instance.clone());
        let mut sheets = Vec::new();
        let copies = self.job.copies();
        for part in order {
            let effort = if limit.reached() {
                REPAIR_EFFORT
            } else {
                GREEDY_EFFORT
            };
            let search = Search {
                effort: effort.for_fill(copies),
                ..Search::GREEDY
            };
            self.insert(&mut problem, part, &mut sheets, &mut rng, search)?;
        }
        Ok((self.score(&problem), self.sheets(&problem)))
    }

    /// Best-fit fill: instead of placing parts in a fixed order, each step looks at every
    /// design still to place, finds its best spot on the first sheet where any design fits, and
    /// takes the one whose spot is lowest (ties within `tie_mm`: the largest part, then
    /// the lower placement cost). Low gaps are filled with whatever fits them, so rows mix
    /// designs whose widths add up to the sheet's, where a size order leaves every row of one
    /// design short of the right edge. `None` if `limit` was reached before the last part.
    pub(super) fn construct_best_fit(
        &self,
        recipe: usize,
        tie_mm: f32,
        limit: &SearchLimit,
    ) -> Result<Option<(Score, Sheets)>, NestError> {
        let mut rng = worker_rng(self.job.settings.seed, 0, recipe);
        let mut remaining: Vec<usize> = self.job.parts.iter().map(|p| p.demand).collect();
        let mut problem = BPProblem::new(self.instance.clone());
        let mut sheets: Vec<LayKey> = Vec::new();
        // `full[s][p]`: design `p` found no room on sheet `s`; sheets only fill up, so it never will.
        let mut full: Vec<Vec<bool>> = Vec::new();
        let copies = self.job.copies();
        while remaining.iter().any(|&r| r > 0) {
            if limit.reached() {
                return Ok(None);
            }
            let designs = remaining.iter().filter(|&&r| r > 0).count();
            let effort = Effort {
                random: (GREEDY_EFFORT.random / designs).max(BEST_FIT_MIN_EFFORT.random),
                anchors: (GREEDY_EFFORT.anchors / designs).max(BEST_FIT_MIN_EFFORT.anchors),
                last_placed: false,
            }
            .for_fill(copies);
            let mut chosen: Option<(LayKey, Placement)> = None;
            for (s, &key) in sheets.iter().enumerate() {
                let layout = &problem.layouts()[key];
                // (bottom, area, cost, spot) of each design that fits this sheet.
                let mut fits: Vec<(f32, f64, f32, Placement)> = Vec::new();
                for p in 0..remaining.len() {
                    if remaining[p] == 0 || full[s][p] {
                        continue;
                    }
                    match self.find_spot(Some(layout), p, &mut rng, effort, &[], None) {
                        Some(spot) => {
                            let b = self.shapes[p][spot.rot].plain.bbox();
                            let cost = (b.y_max + spot.t.1) + RIGHT_WEIGHT * (b.x_max + spot.t.0);
                            fits.push((b.y_min + spot.t.1, self.job.parts[p].area, cost, spot));
                        }
                        None => full[s][p] = true,
                    }
                }
                let Some(lowest) = fits.iter().map(|f| f.0).min_by(f32::total_cmp) else {
                    continue;
                };
                let best = fits
                    .into_iter()
                    .filter(|f| f.0 <= lowest + tie_mm)
                    .min_by(|a, b| b.1.total_cmp(&a.1).then(a.2.total_cmp(&b.2)))
                    .expect("the lowest fits");
                chosen = Some((key, best.3));
                break;
            }
            let spot = match chosen {
                Some((key, spot)) => {
                    problem.place_item(self.bp_placement(BPLayoutType::Open(key), spot));
                    spot
                }
                None => {
                    // Nothing fits the open sheets: the largest design left opens a new one.
                    let p = (0..remaining.len())
                        .filter(|&p| remaining[p] > 0)
                        .max_by(|&a, &b| {
                            self.job.parts[a]
                                .area
                                .total_cmp(&self.job.parts[b].area)
                                .then(b.cmp(&a))
                        })
                        .expect("a design is left");
                    let spot = self
                        .find_spot(None, p, &mut rng, GREEDY_EFFORT.for_fill(copies), &[], None)
                        .ok_or_else(|| self.job.too_large(p))?;
                    let (key, _) = problem
                        .place_item(self.bp_placement(BPLayoutType::Closed { bin_id: 0 }, spot));
                    sheets.push(key);
                    full.push(vec![false; remaining.len()]);
                    spot
                }
            };
            remaining[spot.part] -= 1;
        }
        Ok(Some((self.score(&problem), self.sheets(&problem))))
    }

    /// Places `part` in the first of `sheets` with room, else on a new sheet (appended to
    /// `sheets`). `hints` are earlier placements worth trying as start positions.
    pub(super) fn insert(
        &self,
        problem: &mut BPProblem,
        part: usize,
        sheets: &mut Vec<LayKey>,
        rng: &mut ChaCha8Rng,
        search: Search,
    ) -> Result<(), NestError> {
        for &key in sheets.iter() {
            let layout = &problem.layouts()[key];
            let ceiling = search.ceiling.and_then(|(k, c)| (k == key).then_some(c));
            if let Some(spot) = self.find_spot(
                Some(layout),
                part,
                rng,
                search.effort,
                search.hints,
                ceiling,
            ) {
                problem.place_item(self.bp_placement(BPLayoutType::Open(key), spot));
                return Ok(());
            }
        }
        if search.ceiling.is_some() {
            // A shrink move that did not fit: it fails rather than open a sheet.
            return Err(self.job.too_large(part));
        }
        let spot = self
            .find_spot(None, part, rng, search.effort, &[], None)
            .ok_or_else(|| self.job.too_large(part))?;
        let (key, _) =
            problem.place_item(self.bp_placement(BPLayoutType::Closed { bin_id: 0 }, spot));
        sheets.push(key);
        Ok(())
    }

    /// Start positions of `shape` next to the boxes of `anchored` (to the right of each, above
    /// it at its left edge, and above it at its right edge), inside the shape's translations
    /// and at most `y_max` up; a sample of `room` of them where there are more.
    fn anchor_starts(
        &self,
        anchored: &[Rect],
        shape: &RotatedShape,
        y_max: f32,
        room: usize,
        rng: &mut ChaCha8Rng,
    ) -> Vec<(f32, f32)> {
        let b = shape.plain.bbox();
        let nudge = self.nudge_mm;
        let anchors: Vec<(f32, f32)> = anchored
            .iter()
            .flat_map(|o| {
                [
                    (o.x_max - b.x_min + nudge, o.y_min - b.y_min),
                    (o.x_min - b.x_min, o.y_max - b.y_min + nudge),
                    (o.x_max - b.x_max, o.y_max - b.y_min + nudge),
                ]
            })
            .filter(|&(x, y)| {
                (shape.x.0..=shape.x.1).contains(&x) && (shape.y.0..=y_max).contains(&y)
            })
            .collect();
        if anchors.len() > room {
            anchors.choose_multiple(rng, room).copied().collect()
        } else {
            anchors
        }
    }

    /// Best bottom-left spot for `part` in `layout` (an empty sheet if `None`), with the part's
    /// top at most `ceiling` if given.
    pub(super) fn find_spot(
        &self,
        layout: Option<&Layout>,
        part: usize,
        rng: &mut ChaCha8Rng,
        effort: Effort,
        hints: &[Placement],
        ceiling: Option<f32>,
    ) -> Option<Placement> {
        let empty_sheet = self.instance.bins[0].container.base_cde();
        let cde = layout.map_or(empty_sheet.as_ref(), Layout::cde);
        let placed = layout.map_or(0, |l| l.placed_items().len());
        // The boxes of the parts whose sides give the anchors: all, or the last placed
        // (`Effort::last_placed`; a fill only adds parts, so the layout lists them in the order
        // they were placed), without copying every box of a sheet of thousands for each part.
        let first_anchored = if effort.last_placed {
            placed.saturating_sub(effort.anchors)
        } else {
            0
        };
        let anchored: Vec<Rect> = layout
            .map(|l| {
                l.placed_items()
                    .values()
                    .skip(first_anchored)
                    .map(|pi| pi.shape().bbox())
                    .collect()
            })
            .unwrap_or_default();
        // A start that is clear, slid down and left by the coarse steps, with its cost.
        let coarse = |rot: usize, start: (f32, f32), buffer: &mut SPolygon| {
            let shape = &self.shapes[part][rot];
            if !collision_free(cde, shape, buffer, start) {
                return None;
            }
            let b = shape.plain.bbox();
            let t = slide(cde, shape, buffer, start, COARSE_SLIDE);
            let cost = (b.y_max + t.1) + RIGHT_WEIGHT * (b.x_max + t.0);
            Some((cost, Placement { part, rot, t }))
        };
        let mut best: Option<(f32, Placement)> = None;
        for (rot, shape) in self.shapes[part].iter().enumerate() {
            if !shape.fits() {
                continue;
            }
            let mut buffer = shape.plain.clone();
            let b = shape.plain.bbox();
            // Highest translation that keeps the part inside the sheet and under the ceiling.
            let y_max = ceiling.map_or(shape.y.1, |c| shape.y.1.min(c - b.y_max));
            if y_max < shape.y.0 {
                continue;
            }
            let mut starts = vec![(shape.x.0, shape.y.0)];
            starts.extend(
                hints
                    .iter()
                    .filter(|h| h.part == part && h.rot == rot && h.t.1 <= y_max)
                    .map(|h| h.t),
            );
            // A shaped sheet's corner may be kept out: random starts on an empty one too.
            if placed > 0 || !self.job.shape.is_whole() {
                starts.extend(self.anchor_starts(&anchored, shape, y_max, effort.anchors, rng));
                starts.extend((0..effort.random).map(|_| {
                    (
                        rng.gen_range(shape.x.0..=shape.x.1),
                        rng.gen_range(shape.y.0..=y_max),
                    )
                }));
            }
            for start in starts {
                if let Some((cost, spot)) = coarse(rot, start, &mut buffer) {
                    if best.as_ref().is_none_or(|(c, _)| cost < *c) {
                        best = Some((cost, spot));
                    }
                }
            }
        }
        if best.is_none() && ceiling.is_none() {
            // Sampled starts can all miss a thin band of room, such as the top of a long strip
            // for a part nearly its width; above every placed part, at the left edge, is room
            // whenever the sheet has any there. Only a fallback, so that layouts the samples
            // find stay as they are.
            let top = layout.map_or(f32::MIN, |l| {
                l.placed_items()
                    .values()
                    .map(|pi| pi.shape().bbox().y_max)
                    .fold(f32::MIN, f32::max)
            });
            best = self.shapes[part]
                .iter()
                .enumerate()
                .filter(|(_, shape)| shape.fits())
                .filter_map(|(rot, shape)| {
                    let b = shape.plain.bbox();
                    let start = (shape.x.0, (top - b.y_min + self.nudge_mm).max(shape.y.0));
                    if start.1 > shape.y.1 {
                        return None;
                    }
                    coarse(rot, start, &mut shape.plain.clone())
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
        }
        if best.is_none() && !self.job.shape.is_whole() {
            best = self.grid_spot(part, ceiling, &coarse);
        }
        // Candidates are ranked after the coarse steps; the winner takes the fine ones.
        best.map(|(_, spot)| {
            let shape = &self.shapes[part][spot.rot];
            let mut buffer = shape.plain.clone();
            Placement {
                t: slide(cde, shape, &mut buffer, spot.t, FINISH_SLIDE),
                ..spot
            }
        })
    }

    /// The best of a grid of starts across a shaped sheet, for when random starts miss the room a
    /// remnant or keep-outs leave: a start in every 1/`SHAPED_GRID` of the sheet each way, under
    /// `ceiling`, each tried by `coarse`.
    fn grid_spot(
        &self,
        part: usize,
        ceiling: Option<f32>,
        coarse: &CoarseStart<'_>,
    ) -> Option<(f32, Placement)> {
        let at = |lo: f32, hi: f32, k: usize| lo + (hi - lo) * k as f32 / SHAPED_GRID as f32;
        let mut best: Option<(f32, Placement)> = None;
        for (rot, shape) in self.shapes[part].iter().enumerate() {
            let b = shape.plain.bbox();
            let y_max = ceiling.map_or(shape.y.1, |c| shape.y.1.min(c - b.y_max));
            if !shape.fits() || y_max < shape.y.0 {
                continue;
            }
            let mut buffer = shape.plain.clone();
            for i in 0..=SHAPED_GRID {
                for j in 0..=SHAPED_GRID {
                    let start = (at(shape.x.0, shape.x.1, i), at(shape.y.0, y_max, j));
                    if let Some(found) = coarse(rot, start, &mut buffer) {
                        if best.as_ref().is_none_or(|(c, _)| found.0 < *c) {
                            best = Some(found);
                        }
                    }
                }
            }
        }
        best
    }
}
