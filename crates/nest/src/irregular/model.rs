//! The jagua-rs adapter: the validated job as a jagua-rs bin-packing instance, its parts'
//! collision shapes at every allowed rotation, collision queries and the bottom-left slide, and
//! the conversions between jagua-rs layouts, our [`Sheets`] and the caller's frame.

use std::sync::Arc;

use cam_geometry::rotate;
use jagua_rs::collision_detection::hazards::filter::NoFilter;
use jagua_rs::collision_detection::{CDEConfig, CDEngine};
use jagua_rs::entities::{PItemKey, PlacedItem};
use jagua_rs::geometry::fail_fast::SPSurrogateConfig;
use jagua_rs::geometry::geo_traits::{Transformable, TransformableFrom};
use jagua_rs::geometry::primitives::{Rect, SPolygon};
use jagua_rs::geometry::{DTransformation, Transformation};
use jagua_rs::io::ext_repr::{
    ExtContainer, ExtItem, ExtOrientation, ExtPolygon, ExtRotation, ExtSPolygon, ExtShape,
};
use jagua_rs::io::import::Importer;
use jagua_rs::probs::bpp::entities::{
    BPInstance, BPLayoutType, BPPlacement, BPProblem, Bin, LayKey,
};
use rayon::prelude::*;

use crate::compress::{Footprint, Footprints};
use crate::job::{clean_ring, Job, Placed};
use crate::overlap::Pieces;
use crate::placement::{Placement, Sheets};
use crate::problem::NestError;
use cam_geometry::Point;

/// First and last step of the bottom-left slide.
const SLIDE_FIRST_STEP_MM: f32 = 16.0;
const SLIDE_LAST_STEP_MM: f32 = 0.01;
/// Last step of a candidate's slide in a spot search (`COARSE_SLIDE`); only the winner slides
/// on to `SLIDE_LAST_STEP_MM` (`FINISH_SLIDE`). The fine steps are the dear ones: a part that
/// nearly touches a neighbour passes the cheap surrogate test and needs the polygon test, and
/// candidates that end a fraction of a millimetre apart rarely swap ranks.
const SLIDE_COARSE_LAST_STEP_MM: f32 = 0.125;
/// Bounds of the collision engine's quadtree depth ([`quadtree_depth`]): 3 for sheets of up to
/// 512 parts, deeper for more, up to 4^8 leaves.
const MIN_QUADTREE_DEPTH: f64 = 3.0;
const MAX_QUADTREE_DEPTH: f64 = 8.0;
/// Parts a quadtree leaf should hold at most when the sheet is full ([`quadtree_depth`]).
const PARTS_PER_LEAF: f64 = 8.0;
/// Area the collision shape may grow by (as a fraction of its own area) when jagua-rs replaces
/// the many-vertex round joins of its separation offset by fewer, outward edges. The shape stays
/// a superset, so the separation still holds; fewer edges make every collision query cheaper.
const SIMPLIFY_AREA_RATIO: f32 = 0.005;

/// A part's collision shape at one allowed rotation, at the origin.
pub(super) struct RotatedShape {
    pub(super) rotation_rad: f32,
    /// Rotated shape with its fail-fast surrogate.
    pub(super) with_surrogate: SPolygon,
    /// The same vertices without surrogate: the template translated copies are made from.
    pub(super) plain: SPolygon,
    /// Translations that keep the shape's bounding box inside the usable sheet; empty when
    /// `x.0 > x.1` or `y.0 > y.1`.
    pub(super) x: (f32, f32),
    pub(super) y: (f32, f32),
}

impl RotatedShape {
    pub(super) fn fits(&self) -> bool {
        self.x.0 <= self.x.1 && self.y.0 <= self.y.1
    }
}

/// The validated job as a jagua-rs bin-packing instance plus what the optimiser precomputes.
pub(super) struct Model<'a> {
    pub(super) job: &'a Job,
    pub(super) instance: BPInstance,
    /// `[part][rotation]`.
    pub(super) shapes: Vec<Vec<RotatedShape>>,
    /// Translation jagua-rs applied to centre each part (its `pre_transform`).
    pub(super) centring: Vec<[f64; 2]>,
    /// Usable sheet: the deflated container's bounding box.
    pub(super) usable: Rect,
    /// `[part][rotation]`: the collision shapes as convex pieces, for compression; `None` if
    /// one did not decompose (then the layout is not compressed).
    pub(super) footprints: Option<Footprints>,
    /// Gap that keeps a start position clear of the exact contact with a sheet edge or
    /// neighbour, mm: half the model's f32 margin ([`Job::model_margin`]), as each edge is a
    /// contact.
    pub(super) nudge_mm: f32,
}

impl<'a> Model<'a> {
    pub(super) fn new(job: &'a Job) -> Result<Self, NestError> {
        let instance = build_instance(job)?;
        let usable = instance.bins[0].container.outer_cd().bbox();
        let nudge_mm = (job.model_margin() / 2.0) as f32;
        let mut shapes = Vec::with_capacity(job.parts.len());
        let mut centring = Vec::with_capacity(job.parts.len());
        for (p, part) in job.parts.iter().enumerate() {
            let item = instance.item(p);
            let (cx, cy) = item.shape_orig().pre_transform.translation();
            centring.push([f64::from(cx), f64::from(cy)]);
            let rotated = part
                .rotations_deg
                .iter()
                .map(|&deg| rotated_shape(item.shape_cd(), deg, usable, nudge_mm))
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
            .collect::<Option<Vec<_>>>()
            .map(Footprints::new);
        Ok(Self {
            job,
            instance,
            shapes,
            centring,
            usable,
            footprints,
            nudge_mm,
        })
    }

    /// Whether jagua-rs finds the parts of one sheet clear of each other and inside it: each
    /// checked against those placed before it.
    pub(super) fn clear(&self, sheet: &[Placement]) -> bool {
        let mut problem = BPProblem::new(self.instance.clone());
        let mut key = None;
        for &spot in sheet {
            let shape = &self.shapes[spot.part][spot.rot];
            let nudge = self.nudge_mm;
            if spot.t.0 < shape.x.0 - nudge
                || spot.t.0 > shape.x.1 + nudge
                || spot.t.1 < shape.y.0 - nudge
                || spot.t.1 > shape.y.1 + nudge
            {
                return false;
            }
            // The first part of a whole rectangle is inside it when its box is; on a shaped
            // sheet it is checked against the outline and keep-outs too.
            let cde = match key {
                Some(k) => Some(problem.layouts()[k].cde()),
                None if !self.job.shape.is_whole() => {
                    Some(self.instance.bins[0].container.base_cde().as_ref())
                }
                None => None,
            };
            if cde.is_some_and(|cde| !collision_free(cde, shape, &mut shape.plain.clone(), spot.t))
            {
                return false;
            }
            let layout_id = key.map_or(BPLayoutType::Closed { bin_id: 0 }, BPLayoutType::Open);
            key = Some(problem.place_item(self.bp_placement(layout_id, spot)).0);
        }
        true
    }

    /// Takes a part off a sheet, returning where it was.
    pub(super) fn remove(
        &self,
        problem: &mut BPProblem,
        sheet: LayKey,
        key: PItemKey,
    ) -> Placement {
        let spot = self.placement_of(&problem.layouts()[sheet].placed_items()[key]);
        problem.remove_item(sheet, key);
        spot
    }

    /// Where a placed item sits, in our terms.
    pub(super) fn placement_of(&self, pi: &PlacedItem) -> Placement {
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

    pub(super) fn bp_placement(&self, layout_id: BPLayoutType, spot: Placement) -> BPPlacement {
        BPPlacement {
            layout_id,
            item_idx: spot.part,
            d_transf: DTransformation::new(self.shapes[spot.part][spot.rot].rotation_rad, spot.t),
        }
    }

    /// The layout of a problem, sheet by sheet in key order.
    pub(super) fn sheets(&self, problem: &BPProblem) -> Sheets {
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

    pub(super) fn rebuild(&self, sheets: &Sheets) -> BPProblem {
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
    pub(super) fn export(&self, sheets: &Sheets) -> Vec<Vec<Placed>> {
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
}

/// The job as a jagua-rs bin-packing instance: one item per part (same index), one sheet type
/// with enough stock for one part per sheet (the real stock is checked on the result, so the
/// error can say how many sheets are needed). Items are imported one by one so that an outline
/// jagua-rs cannot take (e.g. it cannot be offset in f32) is named in the error.
fn build_instance(job: &Job) -> Result<BPInstance, NestError> {
    let importer = Importer::new(
        CDEConfig {
            quadtree_depth: quadtree_depth(job),
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
    let rectangle = ExtShape::Rectangle {
        x_min: 0.0,
        y_min: 0.0,
        width: job.bin.width_mm as f32,
        height: job.bin.height_mm as f32,
    };
    let ring = |r: &[Point]| ExtSPolygon(r.iter().map(|q| (q[0] as f32, q[1] as f32)).collect());
    let shape = &job.shape;
    // A shaped sheet: its outline (or the rectangle) with the keep-outs as holes, which jagua-rs
    // inflates by half the separation as it deflates the outline.
    let sheet = ExtContainer {
        id: 0,
        shape: if shape.is_whole() {
            rectangle
        } else {
            let w = job.bin.width_mm;
            let h = job.bin.height_mm;
            let outer = if shape.outline.is_empty() {
                ring(&[[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]])
            } else {
                ring(&clean_ring(&shape.outline))
            };
            ExtShape::Polygon(ExtPolygon {
                outer,
                inner: shape
                    .keep_outs
                    .iter()
                    .map(|k| ring(&clean_ring(k)))
                    .collect(),
            })
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

/// Quadtree depth of the jagua-rs collision engine for `job`. A shallow quadtree suits a few dozen
/// parts of 10-70 mm on a 150 mm sheet: depth 3 with 32 edges per leaf took about 25 % less CPU
/// than depth 5 with 16 on the 300-part job. A leaf deeper than the tree can split holds every part
/// that lies in it, and a collision query tests them all, so with thousands of small parts on a
/// sheet a fixed depth makes each query, and the fill, grow with the number of parts (2,000 circles
/// of 1 mm radius took 90 s to place at depth 3, 40 s at depth 5). The depth grows with the parts a
/// sheet can hold (the sheet's area over the mean part's, at most all of them) so that a leaf holds
/// about `PARTS_PER_LEAF`; collision answers do not depend on the depth, only their cost does.
fn quadtree_depth(job: &Job) -> u8 {
    let copies = job.copies() as f64;
    let mean_area = job.part_area() / copies.max(1.0);
    let per_sheet = copies.min(job.bin.width_mm * job.bin.height_mm / mean_area);
    let depth = (per_sheet / PARTS_PER_LEAF).log(4.0).ceil();
    depth.clamp(MIN_QUADTREE_DEPTH, MAX_QUADTREE_DEPTH) as u8
}

fn rotated_shape(
    shape_cd: &Arc<SPolygon>,
    deg: f64,
    usable: Rect,
    nudge_mm: f32,
) -> Result<RotatedShape, String> {
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
            usable.x_min - b.x_min + nudge_mm,
            usable.x_max - b.x_max - nudge_mm,
        ),
        y: (
            usable.y_min - b.y_min + nudge_mm,
            usable.y_max - b.y_max - nudge_mm,
        ),
        with_surrogate,
        plain,
    })
}

/// Whether `shape` moved by `t` is clear of every part and inside the sheet. The surrogate
/// (inscribed circles and segments) rejects most colliding positions cheaply; the polygon test
/// decides the rest.
pub(super) fn collision_free(
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
pub(super) fn slide_bottom_left(
    cde: &CDEngine,
    shape: &RotatedShape,
    buffer: &mut SPolygon,
    t: (f32, f32),
) -> (f32, f32) {
    slide(
        cde,
        shape,
        buffer,
        t,
        (SLIDE_FIRST_STEP_MM, SLIDE_LAST_STEP_MM),
    )
}

/// Steps (first, last) of a candidate's slide in a spot search, stopped after the
/// `SLIDE_COARSE_LAST_STEP_MM` steps: a spot search ranks its candidates by where this leaves
/// them.
pub(super) const COARSE_SLIDE: (f32, f32) = (SLIDE_FIRST_STEP_MM, SLIDE_COARSE_LAST_STEP_MM);
/// The rest of the slide after [`COARSE_SLIDE`] (the winner's): coarse then finish is exactly
/// [`slide_bottom_left`].
pub(super) const FINISH_SLIDE: (f32, f32) = (SLIDE_COARSE_LAST_STEP_MM / 2.0, SLIDE_LAST_STEP_MM);

/// The slide with steps halving from `first` while they are at least `last`.
pub(super) fn slide(
    cde: &CDEngine,
    shape: &RotatedShape,
    buffer: &mut SPolygon,
    mut t: (f32, f32),
    (first, last): (f32, f32),
) -> (f32, f32) {
    let mut step = first;
    while step >= last {
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
