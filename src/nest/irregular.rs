//! Irregular nesting on jagua-rs's bin-packing model, with an optimiser of our own.
//!
//! jagua-rs (`probs::bpp`) keeps one layout per open sheet and answers "does this polygon collide
//! with anything placed, or leave the sheet?" Parts are inflated and the sheet deflated by half
//! the separation, so a collision-free layout keeps the full separation between parts and to the
//! sheet edge. Everything else is ours:
//!
//! * **Placement** (`Model::find_spot`): start positions at the sheet corner, next to and above
//!   placed parts, where parts of the same design sat before a ruin, and at random; each is
//!   pushed down and left in halving steps (a bottom-left slide) while it stays collision-free,
//!   and the end position with the lowest `top + λ·right` wins. The slide drops a part turned by
//!   180° into the slanted gap its neighbour leaves, which is where trapezoids gain over their
//!   bounding boxes.
//! * **Greedy fills** (`Model::construct`): each worker builds several starts (five on jobs of
//!   up to 150 copies, else one) and keeps the best. Even recipes place copies in decreasing
//!   size (area, length or box area; later ones slightly shuffled), each on the first sheet
//!   that takes it. Odd recipes fill *best fit*: each step finds a spot for every design still
//!   to place and takes the lowest (ties within a recipe's width: the largest part), so low
//!   gaps get whatever fits them and rows mix designs whose lengths add up to the sheet width,
//!   where a size order leaves every row of one design short of the right edge. The search
//!   below rarely leaves the basin of its start (five times the iterations gained 0.6 points),
//!   so a portfolio of starts buys more than iterations do. The collision shapes come from
//!   jagua-rs's separation offset, simplified outwards (a superset, so the gap holds) to keep
//!   queries cheap.
//! * **Local search** (`Model::improve`): ruin and recreate. Either remove the parts nearest a
//!   random point of a sheet and pull up to three parts from the emptiest sheet, or pull one part
//!   and put it at a random spot of a sheet, removing what is in its way. Pulled parts go in
//!   first, then the removed ones: the ruined sheet first, then fuller sheets, the emptiest last.
//!   A few moves instead repack a sheet and the emptiest one from scratch in a perturbed order.
//!   A share of the moves (half of them on a single sheet) *shrink*, as strip packers shrink
//!   the strip: put a ceiling a little below the top of the sheet with the lowest top, remove
//!   the parts above it and either a band just under the ceiling or up to 16 parts around a
//!   random point, and reinsert them on the other sheets or under the ceiling, or fail. On a
//!   single sheet the other moves *recombine*: ruin a band across the sheet or around a point
//!   and reinsert without a ceiling. Shrink and recombine moves reinsert in a size or random
//!   order, or best fit as the greedy fill does.
//!   The objective is lexicographic: fewer sheets, a shorter *used length* (all sheets but the
//!   one with the lowest top counted whole, plus that top: what
//!   [`NestSolution::used_length_mm`](super::NestSolution::used_length_mm) measures), a higher
//!   sum of squared fills (it rises as parts move into fuller sheets, i.e. as the last sheet
//!   empties), then lower parts. Moves are accepted by thresholds on the length, the fills and,
//!   when neither changes, the area-weighted mean top (so such moves pack parts down instead of
//!   drifting), all shrinking to zero over the budget; the best layout is kept.
//! * **Compression** (`Model::compressed`, [`super::compress`]): the moves above only place parts
//!   where they are clear, so the parts under a sheet's top seldom get past one another. Last,
//!   the sheet with the lowest top is compressed through overlap as sparrow does: lower its
//!   ceiling, push the parts above it into their neighbours, and move parts to where they overlap
//!   least until none do (guided local search on the penetration of convex pieces,
//!   [`super::overlap`]); jagua-rs checks every layout it keeps. Each worker compresses on its
//!   own stream for `COMPRESSION_EVALUATIONS` overlap evaluations per iteration; the lowest top
//!   wins. On the bench's strips it took the density from 75.4 to 77.9 % (seed 1).
//! * **Determinism**: a fixed number of workers, each with its own ChaCha8 stream derived from the
//!   seed; work is cut into epochs by iteration count. In the first half of the epochs each
//!   worker improves its own start; after each later epoch the best layout (ties to the lower
//!   worker index) seeds all workers. Thread timing never enters a decision.
//! * **Where it stands**: on the bench's 60-part strips about 1 point of density behind
//!   sparrow, the state-of-the-art strip packer (README, "Nesting engine: figures").

use std::sync::Arc;

use jagua_rs::collision_detection::hazards::filter::NoFilter;
use jagua_rs::collision_detection::{CDEConfig, CDEngine};
use jagua_rs::entities::{Layout, PItemKey, PlacedItem};
use jagua_rs::geometry::fail_fast::SPSurrogateConfig;
use jagua_rs::geometry::geo_traits::{Transformable, TransformableFrom};
use jagua_rs::geometry::primitives::{Rect, SPolygon};
use jagua_rs::geometry::{DTransformation, Transformation};
use jagua_rs::io::ext_repr::{
    ExtContainer, ExtItem, ExtOrientation, ExtRotation, ExtSPolygon, ExtShape,
};
use jagua_rs::io::import::Importer;
use jagua_rs::probs::bpp::entities::{
    BPInstance, BPLayoutType, BPPlacement, BPProblem, Bin, LayKey,
};
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::compress::{compress, Footprint};
use super::overlap::Pieces;
use super::problem::{
    rotate, Job, NestBin, NestError, NestItem, NestSettings, NestSolution, Placed,
};

/// Nests the items on as few sheets as the budget finds, keeping `separation_mm` between parts
/// and to the sheet edges and cutting each part only at its allowed rotations.
pub fn nest(
    items: &[NestItem],
    bin: &NestBin,
    settings: &NestSettings,
) -> Result<NestSolution, NestError> {
    let job = Job::new(items, bin, settings)?;
    if job.parts.is_empty() {
        return job.solution(Vec::new());
    }
    let model = Model::new(&job)?;
    let best = model.run()?;
    job.solution(model.export(&best))
}

/// Gap that keeps a start position clear of the exact contact with a sheet edge or neighbour.
const NUDGE_MM: f32 = 1e-3;
/// First and last step of the bottom-left slide.
const SLIDE_FIRST_STEP_MM: f32 = 16.0;
const SLIDE_LAST_STEP_MM: f32 = 0.01;
/// Area the collision shape may grow by (as a fraction of its own area) when jagua-rs replaces
/// the many-vertex round joins of its separation offset by fewer, outward edges. The shape stays
/// a superset, so the separation still holds; fewer edges make every collision query cheaper.
const SIMPLIFY_AREA_RATIO: f32 = 0.005;
/// Weight of the right edge against the top edge in the placement cost.
const RIGHT_WEIGHT: f32 = 0.25;
/// Overlap evaluations of the final compression per iteration of the budget, per worker.
const COMPRESSION_EVALUATIONS: usize = 3000;

/// How hard one insertion looks.
#[derive(Debug, Clone, Copy)]
struct Effort {
    /// Random start positions per rotation.
    random: usize,
    /// Start positions next to placed parts, per rotation (sampled when there are more).
    anchors: usize,
}

const GREEDY_EFFORT: Effort = Effort {
    random: 100,
    anchors: 200,
};
const REPAIR_EFFORT: Effort = Effort {
    random: 20,
    anchors: 50,
};

/// Least effort per design of a best-fit step (`Model::construct_best_fit`), which searches a
/// spot for every design still to place.
const BEST_FIT_MIN_EFFORT: Effort = Effort {
    random: 10,
    anchors: 25,
};
/// Starts each worker builds (see `Model::construct`) on jobs of at most this many copies.
const STARTS_PER_WORKER: usize = 5;
/// Tie widths of the best-fit starts (odd recipes), mm: spots whose bottoms are this close
/// count as equally low.
const BEST_FIT_TIES_MM: [f32; 5] = [2.0, 0.5, 5.0, 1.0, 3.0];
const PORTFOLIO_MAX_COPIES: usize = 150;

/// What an insertion tries: how hard, which earlier placements to try first, and an optional
/// ceiling on one sheet (then no new sheet is opened).
#[derive(Clone, Copy)]
struct Search<'h> {
    effort: Effort,
    hints: &'h [Placement],
    ceiling: Option<(LayKey, f32)>,
}

impl Search<'_> {
    const GREEDY: Search<'static> = Search {
        effort: GREEDY_EFFORT,
        hints: &[],
        ceiling: None,
    };
    const REPAIR: Search<'static> = Search {
        effort: REPAIR_EFFORT,
        hints: &[],
        ceiling: None,
    };
}
/// Largest drop in the sum of squared fills a move may cause at the start of a worker's budget.
const ACCEPT_SLACK: f64 = 0.005;
/// Largest growth of the used length a move may cause at the start of a worker's budget, mm.
const LENGTH_SLACK_MM: f64 = 1.0;
/// Largest rise of the area-weighted mean top a move that keeps length and fills may cause at
/// the start of a worker's budget, mm.
const ENERGY_SLACK_MM: f64 = 0.3;
/// Used lengths closer than this are equal (the model works in f32), mm.
const LENGTH_TOLERANCE_MM: f64 = 1e-3;
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
/// Epochs split the budget so workers share progress; each epoch gives a worker at least this
/// many iterations, and there are at most this many epochs.
const MIN_EPOCH_ITERATIONS: usize = 25;
const MAX_EPOCHS: usize = 16;
/// Share of the epochs in which workers keep to their own starts (see `Model::run`).
const INDEPENDENT_EPOCHS: f64 = 0.5;

/// One part placed in the jagua-rs frame: its centred, inflated shape turned by rotation `rot`
/// and moved by `t`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Placement {
    pub(super) part: usize,
    pub(super) rot: usize,
    pub(super) t: (f32, f32),
}

/// A whole layout, independent of any `BPProblem`: what workers exchange.
type Sheets = Vec<Vec<Placement>>;

/// A part's collision shape at one allowed rotation, at the origin.
struct RotatedShape {
    rotation_rad: f32,
    /// Rotated shape with its fail-fast surrogate.
    with_surrogate: SPolygon,
    /// The same vertices without surrogate: the template translated copies are made from.
    plain: SPolygon,
    /// Translations that keep the shape's bounding box inside the usable sheet; empty when
    /// `x.0 > x.1` or `y.0 > y.1`.
    x: (f32, f32),
    y: (f32, f32),
}

impl RotatedShape {
    fn fits(&self) -> bool {
        self.x.0 <= self.x.1 && self.y.0 <= self.y.1
    }
}

/// Lexicographic quality of a layout: fewer sheets, then a shorter used length (all sheets but
/// the one with the lowest top counted whole, plus that top), then a higher sum of squared
/// fills, then lower parts.
#[derive(Debug, Clone, Copy)]
struct Score {
    sheets: usize,
    /// `(sheets - 1) * usable height + lowest sheet top`, mm above the usable bottom.
    length: f64,
    concentration: f64,
    /// Sum of the parts' tops over the usable height.
    height: f64,
    /// Area-weighted mean top of the parts above their sheet's usable bottom, mm: where the
    /// mass sits. Moves that change neither the length nor the fills are accepted by it, so
    /// they pack the parts down and leave the free room at the top, where a later shrink needs
    /// it, instead of drifting at random.
    energy: f64,
}

impl Score {
    fn at_least_as_good_as(&self, other: &Score) -> bool {
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

    fn better_than(&self, other: &Score) -> bool {
        !other.at_least_as_good_as(self)
    }

    /// Threshold acceptance of a move from `current`: never an extra sheet; a shorter layout
    /// always; one longer by more than `slack * LENGTH_SLACK_MM` never; otherwise if the
    /// concentration drops by at most `slack * ACCEPT_SLACK`. `slack` falls from 1 to 0 over a
    /// worker's budget.
    fn acceptable_after(&self, current: &Score, slack: f64) -> bool {
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

/// The validated job as a jagua-rs bin-packing instance plus what the optimiser precomputes.
struct Model<'a> {
    job: &'a Job,
    instance: BPInstance,
    /// `[part][rotation]`.
    shapes: Vec<Vec<RotatedShape>>,
    /// Translation jagua-rs applied to centre each part (its `pre_transform`).
    centring: Vec<[f64; 2]>,
    /// Usable sheet: the deflated container's bounding box.
    usable: Rect,
    /// `[part][rotation]`: the collision shapes as convex pieces, for compression; `None` if
    /// one did not decompose (then the layout is not compressed).
    footprints: Option<Vec<Vec<Footprint>>>,
}

impl<'a> Model<'a> {
    fn new(job: &'a Job) -> Result<Self, NestError> {
        let instance = build_instance(job)?;
        let usable = instance.bins[0].container.outer_cd().bbox();
        let mut shapes = Vec::with_capacity(job.parts.len());
        let mut centring = Vec::with_capacity(job.parts.len());
        for (p, part) in job.parts.iter().enumerate() {
            let item = instance.item(p);
            let (cx, cy) = item.shape_orig().pre_transform.translation();
            centring.push([f64::from(cx), f64::from(cy)]);
            let rotated = part
                .rotations_deg
                .iter()
                .map(|&deg| rotated_shape(item.shape_cd(), deg, usable))
                .collect::<Result<Vec<_>, _>>()
                .map_err(|reason| NestError::DegenerateOutline {
                    item: part.item,
                    reason,
                })?;
            shapes.push(rotated);
        }
        let footprints = shapes
            .iter()
            .map(|rotations| {
                rotations
                    .iter()
                    .map(|shape| {
                        let ring: Vec<[f32; 2]> =
                            shape.plain.vertices().iter().map(|v| [v.0, v.1]).collect();
                        Some(Footprint {
                            pieces: Pieces::new(&ring)?,
                            x: shape.x,
                            y: shape.y,
                        })
                    })
                    .collect::<Option<Vec<_>>>()
            })
            .collect::<Option<Vec<_>>>();
        Ok(Self {
            job,
            instance,
            shapes,
            centring,
            usable,
            footprints,
        })
    }

    /// Greedy fill per worker, then epochs of local search; returns the best layout found. In
    /// the first `INDEPENDENT_EPOCHS` share of the epochs each worker improves its own start,
    /// so the basins of different starts are all explored; after that, every epoch starts all
    /// workers from the best layout so far.
    fn run(&self) -> Result<Sheets, NestError> {
        let settings = &self.job.settings;
        let workers = settings.workers;
        let mut own: Vec<(Score, Sheets)> = parallel(workers, |w| self.construct(w))
            .into_iter()
            .collect::<Result<_, _>>()?;
        let mut best = own[0].clone();
        let iterations = self.job.iteration_budget();
        let epochs = (iterations / (workers * MIN_EPOCH_ITERATIONS)).clamp(1, MAX_EPOCHS);
        let independent = (epochs as f64 * INDEPENDENT_EPOCHS) as usize;
        let slots = epochs * workers;
        for epoch in 0..=epochs {
            for start in &own {
                if start.0.better_than(&best.0) {
                    best = start.clone();
                }
            }
            if epoch == epochs {
                break;
            }
            let incumbents: Vec<&Sheets> = (0..workers)
                .map(|w| {
                    if epoch < independent {
                        &own[w].1
                    } else {
                        &best.1
                    }
                })
                .collect();
            own = parallel(workers, |w| {
                let slot = epoch * workers + w;
                let budget = iterations / slots + usize::from(slot < iterations % slots);
                self.improve(
                    incumbents[w],
                    budget,
                    worker_rng(settings.seed, epoch + 1, w),
                )
            });
        }
        Ok(self.compressed(best.1, epochs + 1))
    }

    /// The layout with its lowest-topped sheet (the one whose used length counts) compressed
    /// through overlap ([`super::compress`]), each worker on its own random stream with
    /// `COMPRESSION_EVALUATIONS` per iteration of the budget; the lowest top wins (ties to the
    /// lower worker).
    fn compressed(&self, mut sheets: Sheets, epoch: usize) -> Sheets {
        let Some(footprints) = self.footprints.as_ref().filter(|_| !sheets.is_empty()) else {
            return sheets;
        };
        let top = |sheet: &[Placement]| {
            sheet
                .iter()
                .map(|s| self.shapes[s.part][s.rot].plain.bbox().y_max + s.t.1)
                .fold(self.usable.y_min, f32::max)
        };
        // The sheet whose used length counts, found as the score finds it: `sheets` lists the
        // sheets in key order and `rebuild` keeps that order.
        let problem = self.rebuild(&sheets);
        debug_assert!(problem
            .layouts()
            .values()
            .zip(&sheets)
            .all(|(layout, sheet)| layout.placed_items().len() == sheet.len()));
        let (key, _) = self.lowest_sheet(&problem);
        let lowest = problem
            .layouts()
            .keys()
            .position(|k| k == key)
            .expect("the lowest sheet is one of them");
        let settings = &self.job.settings;
        let budget = self.job.iteration_budget() * COMPRESSION_EVALUATIONS;
        let candidates = parallel(settings.workers, |w| {
            let mut rng = worker_rng(settings.seed, epoch, w);
            compress(footprints, &sheets[lowest], budget, &mut rng, |items| {
                self.clear(items)
            })
        });
        let best = candidates
            .into_iter()
            .min_by(|a, b| top(a).total_cmp(&top(b)))
            .expect("at least one worker");
        if top(&best) < top(&sheets[lowest]) {
            sheets[lowest] = best;
        }
        sheets
    }

    /// Whether jagua-rs finds the parts of one sheet clear of each other and inside it: each
    /// checked against those placed before it.
    fn clear(&self, sheet: &[Placement]) -> bool {
        let mut problem = BPProblem::new(self.instance.clone());
        let mut key = None;
        for &spot in sheet {
            let shape = &self.shapes[spot.part][spot.rot];
            if spot.t.0 < shape.x.0 - NUDGE_MM
                || spot.t.0 > shape.x.1 + NUDGE_MM
                || spot.t.1 < shape.y.0 - NUDGE_MM
                || spot.t.1 > shape.y.1 + NUDGE_MM
            {
                return false;
            }
            if let Some(k) = key {
                let cde = problem.layouts()[k].cde();
                if !collision_free(cde, shape, &mut shape.plain.clone(), spot.t) {
                    return false;
                }
            }
            let layout_id = key.map_or(BPLayoutType::Closed { bin_id: 0 }, BPLayoutType::Open);
            key = Some(problem.place_item(self.bp_placement(layout_id, spot)).0);
        }
        true
    }

    /// Best-fit fill: instead of placing parts in a fixed order, each step looks at every
    /// design still to place, finds its best spot on the first sheet where any design fits, and
    /// takes the one whose spot is lowest (ties within `tie_mm`: the largest part, then
    /// the lower placement cost). Low gaps are filled with whatever fits them, so rows mix
    /// designs whose widths add up to the sheet's, where a size order leaves every row of one
    /// design short of the right edge.
    fn construct_best_fit(&self, recipe: usize, tie_mm: f32) -> Result<(Score, Sheets), NestError> {
        let mut rng = worker_rng(self.job.settings.seed, 0, recipe);
        let mut remaining: Vec<usize> = self.job.parts.iter().map(|p| p.demand).collect();
        let mut problem = BPProblem::new(self.instance.clone());
        let mut sheets: Vec<LayKey> = Vec::new();
        // `full[s][p]`: design `p` found no room on sheet `s`; sheets only fill up, so it never will.
        let mut full: Vec<Vec<bool>> = Vec::new();
        while remaining.iter().any(|&r| r > 0) {
            let designs = remaining.iter().filter(|&&r| r > 0).count();
            let effort = Effort {
                random: (GREEDY_EFFORT.random / designs).max(BEST_FIT_MIN_EFFORT.random),
                anchors: (GREEDY_EFFORT.anchors / designs).max(BEST_FIT_MIN_EFFORT.anchors),
            };
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
                        .find_spot(None, p, &mut rng, GREEDY_EFFORT, &[], None)
                        .ok_or_else(|| self.too_large(p))?;
                    let (key, _) = problem
                        .place_item(self.bp_placement(BPLayoutType::Closed { bin_id: 0 }, spot));
                    sheets.push(key);
                    full.push(vec![false; remaining.len()]);
                    spot
                }
            };
            remaining[spot.part] -= 1;
        }
        Ok((self.score(&problem), self.sheets(&problem)))
    }

    /// The starts of one worker: recipes `worker`, `worker + workers`, ... (`STARTS_PER_WORKER`
    /// of them on jobs of up to `PORTFOLIO_MAX_COPIES` copies, else one); the best is kept. The
    /// local search rarely leaves the basin of its start, so several kinds of start buy more
    /// than more iterations.
    fn construct(&self, worker: usize) -> Result<(Score, Sheets), NestError> {
        let workers = self.job.settings.workers;
        let starts = if self.job.copies() <= PORTFOLIO_MAX_COPIES {
            STARTS_PER_WORKER
        } else {
            1
        };
        let mut best: Option<(Score, Sheets)> = None;
        for k in 0..starts {
            let recipe = worker + k * workers;
            let start = if recipe % 2 == 1 {
                let ties = BEST_FIT_TIES_MM;
                self.construct_best_fit(recipe, ties[recipe / 2 % ties.len()])?
            } else {
                self.construct_in_order(recipe)?
            };
            if best.as_ref().is_none_or(|(s, _)| start.0.better_than(s)) {
                best = Some(start);
            }
        }
        Ok(best.expect("at least one start"))
    }

    /// Greedy fill in a size order (area, length or box area, by even recipe; perturbed from
    /// recipe 6 on), first sheet that takes a part.
    fn construct_in_order(&self, recipe: usize) -> Result<(Score, Sheets), NestError> {
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
        for part in order {
            self.insert(&mut problem, part, &mut sheets, &mut rng, Search::GREEDY)?;
        }
        Ok((self.score(&problem), self.sheets(&problem)))
    }

    /// Ruin-and-recreate moves from `start` for `budget` iterations.
    fn improve(&self, start: &Sheets, budget: usize, mut rng: ChaCha8Rng) -> (Score, Sheets) {
        let mut problem = self.rebuild(start);
        let mut score = self.score(&problem);
        let mut best = (score, start.clone());
        let mut saved = problem.save();
        for iteration in 0..budget {
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
    fn ruin_and_recreate(
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
    fn shrink(&self, problem: &mut BPProblem, rng: &mut ChaCha8Rng) -> Result<(), NestError> {
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
    fn reinsert(
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
    fn recombine(&self, problem: &mut BPProblem, rng: &mut ChaCha8Rng) -> Result<(), NestError> {
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
    fn reinsertion_order(&self, parts: &mut [Placement], rng: &mut ChaCha8Rng) {
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
    fn ruin_band(
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
    fn repack_pair(
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
    fn ruin_around_point(
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
    fn make_room(
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

    /// Takes a part off a sheet, returning where it was.
    fn remove(&self, problem: &mut BPProblem, sheet: LayKey, key: PItemKey) -> Placement {
        let spot = self.placement_of(&problem.layouts()[sheet].placed_items()[key]);
        problem.remove_item(sheet, key);
        spot
    }

    /// Where a placed item sits, in our terms.
    fn placement_of(&self, pi: &PlacedItem) -> Placement {
        let part = pi.item().idx();
        let dt = pi.d_transf();
        let rot = self.shapes[part]
            .iter()
            .position(|s| s.rotation_rad == dt.rotation())
            .expect("placed at one of the part's rotations");
        Placement {
            part,
            rot,
            t: dt.translation(),
        }
    }

    /// Places `part` in the first of `sheets` with room, else on a new sheet (appended to
    /// `sheets`). `hints` are earlier placements worth trying as start positions.
    fn insert(
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
            return Err(self.too_large(part));
        }
        let spot = self
            .find_spot(None, part, rng, search.effort, &[], None)
            .ok_or_else(|| self.too_large(part))?;
        let (key, _) =
            problem.place_item(self.bp_placement(BPLayoutType::Closed { bin_id: 0 }, spot));
        sheets.push(key);
        Ok(())
    }

    fn bp_placement(&self, layout_id: BPLayoutType, spot: Placement) -> BPPlacement {
        BPPlacement {
            layout_id,
            item_idx: spot.part,
            d_transf: DTransformation::new(self.shapes[spot.part][spot.rot].rotation_rad, spot.t),
        }
    }

    /// Best bottom-left spot for `part` in `layout` (an empty sheet if `None`), with the part's
    /// top at most `ceiling` if given.
    fn find_spot(
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
        let placed: Vec<Rect> = layout
            .map(|l| {
                l.placed_items()
                    .values()
                    .map(|pi| pi.shape().bbox())
                    .collect()
            })
            .unwrap_or_default();
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
            if !placed.is_empty() {
                let mut anchors: Vec<(f32, f32)> = placed
                    .iter()
                    .flat_map(|o| {
                        [
                            (o.x_max - b.x_min + NUDGE_MM, o.y_min - b.y_min),
                            (o.x_min - b.x_min, o.y_max - b.y_min + NUDGE_MM),
                            (o.x_max - b.x_max, o.y_max - b.y_min + NUDGE_MM),
                        ]
                    })
                    .filter(|&(x, y)| {
                        (shape.x.0..=shape.x.1).contains(&x) && (shape.y.0..=y_max).contains(&y)
                    })
                    .collect();
                if anchors.len() > effort.anchors {
                    anchors = anchors
                        .choose_multiple(rng, effort.anchors)
                        .copied()
                        .collect();
                }
                starts.extend(anchors);
                starts.extend((0..effort.random).map(|_| {
                    (
                        rng.gen_range(shape.x.0..=shape.x.1),
                        rng.gen_range(shape.y.0..=y_max),
                    )
                }));
            }
            for start in starts {
                if !collision_free(cde, shape, &mut buffer, start) {
                    continue;
                }
                let t = slide_bottom_left(cde, shape, &mut buffer, start);
                let cost = (b.y_max + t.1) + RIGHT_WEIGHT * (b.x_max + t.0);
                if best.as_ref().is_none_or(|(c, _)| cost < *c) {
                    best = Some((cost, Placement { part, rot, t }));
                }
            }
        }
        best.map(|(_, spot)| spot)
    }

    /// Open sheets, fullest first (ties in key order).
    fn keys_by_fill(&self, problem: &BPProblem) -> Vec<LayKey> {
        let mut keys: Vec<(f64, LayKey)> = problem
            .layouts()
            .iter()
            .map(|(k, l)| (self.fill(l), k))
            .collect();
        keys.sort_by(|a, b| b.0.total_cmp(&a.0));
        keys.into_iter().map(|(_, k)| k).collect()
    }

    /// Part area over sheet area, in f64 from our own outlines.
    fn fill(&self, layout: &Layout) -> f64 {
        let area: f64 = layout
            .placed_items()
            .values()
            .map(|pi| self.job.parts[pi.item().idx()].area)
            .sum();
        area / (self.job.bin.width_mm * self.job.bin.height_mm)
    }

    fn score(&self, problem: &BPProblem) -> Score {
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
    fn top(&self, layout: &Layout) -> f32 {
        layout
            .placed_items()
            .values()
            .map(|pi| pi.shape().bbox().y_max)
            .fold(self.usable.y_min, f32::max)
    }

    /// The sheet with the lowest top (ties to the emptier, then the later key): the one whose
    /// used length counts.
    fn lowest_sheet(&self, problem: &BPProblem) -> (LayKey, f32) {
        problem
            .layouts()
            .iter()
            .map(|(k, l)| (k, self.top(l), self.fill(l)))
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.2.total_cmp(&b.2)))
            .map(|(k, top, _)| (k, top))
            .expect("at least one sheet")
    }

    /// The layout of a problem, sheet by sheet in key order.
    fn sheets(&self, problem: &BPProblem) -> Sheets {
        problem
            .layouts()
            .values()
            .map(|layout| {
                layout
                    .placed_items()
                    .values()
                    .map(|pi| self.placement_of(pi))
                    .collect()
            })
            .collect()
    }

    fn rebuild(&self, sheets: &Sheets) -> BPProblem {
        let mut problem = BPProblem::new(self.instance.clone());
        for sheet in sheets {
            let mut key = None;
            for &spot in sheet {
                let layout_id = key.map_or(BPLayoutType::Closed { bin_id: 0 }, BPLayoutType::Open);
                key = Some(problem.place_item(self.bp_placement(layout_id, spot)).0);
            }
        }
        problem
    }

    /// Converts to our frame: jagua-rs placed `R·(p + c) + t` for outline point `p` and centring
    /// `c`, so the translation of the caller's outline is `t + R·c`.
    fn export(&self, sheets: &Sheets) -> Vec<Vec<Placed>> {
        sheets
            .iter()
            .map(|sheet| {
                sheet
                    .iter()
                    .map(|s| {
                        let deg = self.job.parts[s.part].rotations_deg[s.rot];
                        let c = rotate(self.centring[s.part], deg);
                        Placed {
                            part: s.part,
                            rot: s.rot,
                            translation: [f64::from(s.t.0) + c[0], f64::from(s.t.1) + c[1]],
                        }
                    })
                    .collect()
            })
            .collect()
    }

    fn too_large(&self, part: usize) -> NestError {
        let p = &self.job.parts[part];
        let size = p.bbox_size(p.rotations_deg[0]);
        NestError::PartLargerThanBin {
            item: p.item,
            part_width_mm: size[0],
            part_height_mm: size[1],
            bin_width_mm: self.job.bin.width_mm,
            bin_height_mm: self.job.bin.height_mm,
            separation_mm: self.job.settings.separation_mm,
        }
    }
}

/// The job as a jagua-rs bin-packing instance: one item per part (same index), one sheet type
/// with enough stock for one part per sheet (the real stock is checked on the result, so the
/// error can say how many sheets are needed). Items are imported one by one so that an outline
/// jagua-rs cannot take (e.g. it cannot be offset in f32) is named in the error.
fn build_instance(job: &Job) -> Result<BPInstance, NestError> {
    // A shallow quadtree suits a few dozen parts of 10-70 mm on a 150 mm sheet: depth 3 with 32
    // edges per leaf took about 25 % less CPU than depth 5 with 16 on the 300-part job.
    let importer = Importer::new(
        CDEConfig {
            quadtree_depth: 3,
            cd_threshold: 32,
            item_surrogate_config: SPSurrogateConfig {
                n_pole_limits: [(32, 0.0), (16, 0.8), (8, 0.9)],
                ff_pole_area_ratio: 0.1,
                n_ff_piers: 0,
            },
        },
        Some(SIMPLIFY_AREA_RATIO),
        None,
    )
    .with_min_item_separation(job.model_separation() as f32)
    .map_err(|e| NestError::BadSettings(format!("{e:#}")))?;
    let items = job
        .parts
        .par_iter()
        .enumerate()
        .map(|(p, part)| {
            let ext = ExtItem {
                id: p as u64,
                orientation: ExtOrientation {
                    rotation: ExtRotation::Discrete {
                        angles: part.rotations_deg.iter().map(|&r| r as f32).collect(),
                    },
                    reflection_axes: Vec::new(),
                },
                shape: ExtShape::SimplePolygon(ExtSPolygon(
                    part.outline
                        .iter()
                        .map(|q| (q[0] as f32, q[1] as f32))
                        .collect(),
                )),
                min_quality: None,
            };
            let item = importer
                .import_item(&ext, p)
                .map_err(|e| NestError::DegenerateOutline {
                    item: part.item,
                    reason: format!("jagua-rs cannot use it: {e:#}"),
                })?;
            Ok((item, part.demand))
        })
        .collect::<Result<Vec<_>, NestError>>()?;
    let sheet = ExtContainer {
        id: 0,
        shape: ExtShape::Rectangle {
            x_min: 0.0,
            y_min: 0.0,
            width: job.bin.width_mm as f32,
            height: job.bin.height_mm as f32,
        },
        zones: Vec::new(),
    };
    let container = importer
        .import_container(&sheet)
        .map_err(|e| NestError::BadSettings(format!("sheet rejected by jagua-rs: {e:#}")))?;
    Ok(BPInstance::new(
        items,
        vec![Bin::new(0, 0, container, job.copies(), 1)],
    ))
}

fn rotated_shape(shape_cd: &Arc<SPolygon>, deg: f64, usable: Rect) -> Result<RotatedShape, String> {
    let rotation_rad = (deg as f32).to_radians();
    let with_surrogate = shape_cd.transform_clone(&Transformation::from_rotation(rotation_rad));
    // A translated copy without surrogate is cheaper to move around; if rebuilding it fails
    // (f32 duplicates), the full shape serves as template.
    let plain = SPolygon::new(with_surrogate.vertices().to_vec())
        .unwrap_or_else(|_| with_surrogate.clone());
    if plain.n_vertices() != with_surrogate.n_vertices() {
        return Err("collision shape changed when rebuilt".into());
    }
    let b = plain.bbox();
    Ok(RotatedShape {
        rotation_rad,
        x: (
            usable.x_min - b.x_min + NUDGE_MM,
            usable.x_max - b.x_max - NUDGE_MM,
        ),
        y: (
            usable.y_min - b.y_min + NUDGE_MM,
            usable.y_max - b.y_max - NUDGE_MM,
        ),
        with_surrogate,
        plain,
    })
}

/// Whether `shape` moved by `t` is clear of every part and inside the sheet. The surrogate
/// (inscribed circles and segments) rejects most colliding positions cheaply; the polygon test
/// decides the rest.
fn collision_free(
    cde: &CDEngine,
    shape: &RotatedShape,
    buffer: &mut SPolygon,
    t: (f32, f32),
) -> bool {
    let transform = Transformation::from_translation(t);
    if cde.detect_surrogate_collision(shape.with_surrogate.surrogate(), &transform, &NoFilter) {
        return false;
    }
    buffer.transform_from(&shape.plain, &transform);
    !cde.detect_poly_collision(buffer, &NoFilter)
}

/// Pushes a collision-free position down, then left, as far as it stays collision-free, in
/// steps halving from 16 mm to 0.01 mm. A step may jump a thin obstacle; the end position is
/// checked all the same, so that only finds more room.
fn slide_bottom_left(
    cde: &CDEngine,
    shape: &RotatedShape,
    buffer: &mut SPolygon,
    mut t: (f32, f32),
) -> (f32, f32) {
    let mut step = SLIDE_FIRST_STEP_MM;
    while step >= SLIDE_LAST_STEP_MM {
        let mut moved = false;
        loop {
            let next = (t.0, (t.1 - step).max(shape.y.0));
            if next.1 < t.1 && collision_free(cde, shape, buffer, next) {
                t = next;
                moved = true;
            } else {
                break;
            }
        }
        loop {
            let next = ((t.0 - step).max(shape.x.0), t.1);
            if next.0 < t.0 && collision_free(cde, shape, buffer, next) {
                t = next;
                moved = true;
            } else {
                break;
            }
        }
        if !moved {
            step /= 2.0;
        }
    }
    t
}

/// Swaps each element with the next one with probability 1/8: a small perturbation of a
/// size order that keeps it mostly large-first.
fn blink_shuffle<T>(order: &mut [T], rng: &mut ChaCha8Rng) {
    for i in 1..order.len() {
        if rng.gen_ratio(1, 8) {
            order.swap(i - 1, i);
        }
    }
}

/// The random stream of one worker in one epoch (epoch 0 is the greedy fill): SplitMix64 of the
/// seed, epoch and worker, so streams differ and do not depend on thread timing.
fn worker_rng(seed: u64, epoch: usize, worker: usize) -> ChaCha8Rng {
    let mut z = seed
        ^ (epoch as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (worker as u64).wrapping_mul(0xD1B5_4A32_D192_ED03);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ChaCha8Rng::seed_from_u64(z ^ (z >> 31))
}

/// Runs `job(w)` for `w in 0..workers` on that many threads; results in worker order.
fn parallel<T: Send>(workers: usize, job: impl Fn(usize) -> T + Sync) -> Vec<T> {
    if workers == 1 {
        return vec![job(0)];
    }
    std::thread::scope(|scope| {
        let handles: Vec<_> = (1..workers)
            .map(|w| {
                let job = &job;
                scope.spawn(move || job(w))
            })
            .collect();
        let mut results = vec![job(0)];
        results.extend(
            handles
                .into_iter()
                .map(|h| h.join().expect("nesting worker panicked")),
        );
        results
    })
}
