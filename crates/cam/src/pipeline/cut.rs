//! Cut-through parts (passive layer, ply-by-ply plies, Pyralux bond layers): the parts each job needs per
//! layer, and the drawing of finished sheet layouts (holes, labels, then outer contours, in cut order).
//! Where the parts go is up to the caller (shelf layout for one design, the irregular nester for batches).

use super::cut_order::{cut_order, in_cutouts};
use super::jobs::{design_error, kerfed, Drawn, Job, Names, PartRecord, SheetRecord};
use super::label::Label;
use super::sheet_label::part_box;
use super::BuildError;
use crate::drawing::model::{file_stem, Drawing, FibreAxis, Operation, Shape, Stock};
use crate::input::{short_number, InputError};
use crate::parts::PartOrder;
use crate::process::template::{BondSpec, PassiveCut, SheetSpec, Template};
use crate::process::{DrawnSheet, Feature, FeatureMap};
use cam_geometry::offset::offset_ring;
use cam_geometry::signed_area;
use cam_geometry::Point;
use cam_geometry::{place_point, place_ring};
use cam_nest::{NestedBin, PlacedPart, SheetShape};

/// Diameter of the ply registration holes (ply-by-ply cutting), mm: a 0.5 mm pin.
pub const REGISTRATION_HOLE_MM: f64 = 0.5;

/// Rotations a cut-through part may take: 0° and 180° keep the fibre direction.
pub const CUT_ROTATIONS_DEG: [f64; 2] = [0.0, 180.0];

/// One part design of a cut layer: `per_actuator` copies for each actuator of a job.
#[derive(Debug, Clone)]
pub struct CutItem {
    /// Index of the job.
    pub job: usize,
    /// Part kind in reports (`passive`, `pyralux`); numbered when an actuator has several.
    pub part: String,
    /// Nominal outline, actuator axis along +y, base centred on the origin.
    pub nominal: Vec<Point>,
    /// The cut path: nominal outline grown by kerf/2.
    pub cut: Vec<Point>,
    /// Holes (centre, nominal radius) in part coordinates.
    pub holes: Vec<(Point, f64)>,
    /// What the holes are (vias, registration holes), for their operation.
    pub hole: Feature,
    /// Copies per actuator.
    pub per_actuator: usize,
    /// Copies in all.
    pub count: usize,
    /// Engraved label.
    pub label: Label,
    /// Where a face of the part is bonded in the stack (part coordinates): the PZT zone of a passive
    /// part, the whole of a ply, a Pyralux part or a linkage coupon; `None` for an extra part, whose
    /// use the tool does not know. Written into the sheet's SVG as data, so nothing is engraved there.
    pub bonded_zone: Option<Vec<Point>>,
    /// Cut-outs of the part (a flexure's slot), nominal, part coordinates; empty for actuator parts.
    pub cutouts: Vec<Vec<Point>>,
    /// Their cut paths: each cut-out shrunk by kerf/2, so the hole comes out as drawn.
    pub cutout_paths: Vec<Vec<Point>>,
    /// Rotations it may be cut at, degrees.
    pub rotations_deg: Vec<f64>,
    /// What errors call it: the design's name, or the extra part with its file and entity.
    pub owner: String,
}

impl CutItem {
    /// Nominal area of material, mm²: outline less cut-outs.
    pub fn area_mm2(&self) -> f64 {
        signed_area(&self.nominal) - self.cutouts.iter().map(|c| signed_area(c)).sum::<f64>()
    }
}

/// One cut layer of a build: its name, sheet, material and parts.
#[derive(Debug, Clone)]
pub struct CutLayer {
    /// Layer name and file-stem prefix (`passive`, `passive-ply2-90deg`, `pyralux`).
    pub layer: String,
    /// Material for the report.
    pub material: String,
    /// Thickness of the cut sheet, mm.
    pub thickness_mm: f64,
    /// Density, kg/m³.
    pub density_kg_per_m3: f64,
    /// The sheet.
    pub spec: SheetSpec,
    /// Parts, one per job.
    pub items: Vec<CutItem>,
    /// Operation of each feature, from the template.
    pub features: FeatureMap,
    /// The fibre angle of the one ply this layer cuts (ply-by-ply cutting), degrees CCW from a
    /// part's axis; `None` for a layer cut from the laid-up stack or with no fibres.
    pub ply_deg: Option<f64>,
    /// Prepreg (cured or not): the parts lie with their 0° fibres along the sheet's y axis.
    pub prepreg: bool,
}

#[allow(clippy::too_many_arguments)]
fn item(
    job_index: usize,
    job: &Job<'_>,
    part: &str,
    spec: &SheetSpec,
    nominal: Vec<Point>,
    (hole, holes): (Feature, Vec<(Point, f64)>),
    per_actuator: usize,
    label: Label,
    layer: &str,
) -> Result<CutItem, BuildError> {
    // Parts are laid out by their cut paths (nominal outline grown by kerf/2, mitred corners included):
    // the web of material between two cuts is what must survive.
    let cut = kerfed(
        job.design,
        &nominal,
        spec.kerf_mm / 2.0,
        &format!("{layer} part outline"),
    )?;
    for (_, radius) in &holes {
        if radius - spec.kerf_mm / 2.0 <= 0.0 {
            return Err(design_error(
                job.design,
                format!(
                    "{layer}: a {:.3} mm hole vanishes inside the {} mm kerf",
                    2.0 * radius,
                    spec.kerf_mm
                ),
            ));
        }
    }
    Ok(CutItem {
        job: job_index,
        part: part.into(),
        cut,
        holes,
        hole,
        per_actuator,
        count: per_actuator * job.quantity,
        label,
        // Plies and bond parts are bonded all over; a passive part's zone is set by its layer.
        bonded_zone: Some(nominal.clone()),
        nominal,
        cutouts: Vec::new(),
        cutout_paths: Vec::new(),
        rotations_deg: CUT_ROTATIONS_DEG.to_vec(),
        owner: job.design.name.clone(),
    })
}

/// The passive layers of jobs that share one layup: one layer cut from the laid-up stack, or one per
/// ply (ply-by-ply cutting), each with one part per actuator.
pub fn passive_layers(
    jobs: &[(usize, Job<'_>)],
    template: &Template,
    spec: &SheetSpec,
) -> Result<Vec<CutLayer>, BuildError> {
    let Some((_, first)) = jobs.first() else {
        return Ok(Vec::new());
    };
    let d0 = first.design;
    let material = format!("{} ({})", d0.ply.name, spec.material);
    match template.passive_cut {
        PassiveCut::Stack => {
            let items = jobs
                .iter()
                .map(|(i, job)| {
                    let label = Label::passive(job.geometry, &job.design.name, template);
                    let outline = job.geometry.passive_outline();
                    let mut part = item(
                        *i,
                        job,
                        "passive",
                        spec,
                        outline,
                        (Feature::RegistrationHole, Vec::new()),
                        1,
                        label,
                        "passive",
                    )?;
                    // The plates are bonded over the PZT zone; the tab and the extension stay free.
                    part.bonded_zone = Some(job.geometry.pzt_outline());
                    Ok(part)
                })
                .collect::<Result<Vec<_>, BuildError>>()?;
            Ok(vec![CutLayer {
                layer: "passive".into(),
                material,
                thickness_mm: d0.ply_thickness * 1e3 * d0.layup_deg.len() as f64,
                density_kg_per_m3: d0.ply.density,
                spec: spec.clone(),
                items,
                features: template.features,
                ply_deg: None,
                prepreg: true,
            }])
        }
        PassiveCut::PlyByPly => {
            let mut plies: Vec<CutLayer> = d0
                .layup_deg
                .iter()
                .enumerate()
                .map(|(i, angle)| CutLayer {
                    layer: format!("passive-ply{}-{}deg", i + 1, angle),
                    material: material.clone(),
                    thickness_mm: d0.ply_thickness * 1e3,
                    density_kg_per_m3: d0.ply.density,
                    spec: spec.clone(),
                    items: Vec::new(),
                    features: template.features,
                    ply_deg: Some(*angle),
                    prepreg: true,
                })
                .collect();
            for (i, job) in jobs {
                let g = &job.geometry;
                let holes = registration_holes(job, spec)?;
                let outline = g.passive_outline();
                for (ply, angle) in plies.iter_mut().zip(&job.design.layup_deg) {
                    // Prepreg fibres run along the sheet's y axis; turning the part by -θ puts them at
                    // +θ (counter-clockwise) from its axis.
                    let turned = place_ring(&outline, -angle, [0.0, 0.0]);
                    let turned_holes: Vec<(Point, f64)> = holes
                        .iter()
                        .map(|(c, r)| (place_point(*c, -angle, [0.0, 0.0]), *r))
                        .collect();
                    let layer = ply.layer.clone();
                    ply.items.push(item(
                        *i,
                        job,
                        &layer,
                        spec,
                        turned,
                        (Feature::RegistrationHole, turned_holes),
                        1,
                        Label::None,
                        &layer,
                    )?);
                }
            }
            Ok(plies)
        }
    }
}

/// Registration holes through every ply, in the passive-only base tab (clamped, so they do not touch
/// the active part): two pins stack one actuator's plies in register.
fn registration_holes(job: &Job<'_>, spec: &SheetSpec) -> Result<Vec<(Point, f64)>, BuildError> {
    let g = &job.geometry;
    let d = REGISTRATION_HOLE_MM;
    let web = spec.kerf_mm.max(0.2);
    if g.base_tab_mm < d + 2.0 * web || g.base_width_mm / 4.0 < d / 2.0 + web {
        return Err(design_error(
            job.design,
            format!(
                "geometry.base_tab_mm = {}: ply-by-ply cutting puts two {d} mm registration holes in the base tab; it needs a tab of at least {:.2} mm and a base width of at least {:.2} mm",
                g.base_tab_mm,
                d + 2.0 * web,
                4.0 * (d / 2.0 + web)
            ),
        ));
    }
    Ok([-1.0, 1.0]
        .iter()
        .map(|side| {
            (
                [side * g.base_width_mm / 4.0, -g.base_tab_mm / 2.0],
                d / 2.0,
            )
        })
        .collect())
}

/// The Pyralux bond layer of method 1: two PZT-shaped parts per actuator, each with a via for silver
/// epoxy. `None` when the process has no bond layer.
pub fn pyralux_layer(
    jobs: &[Job<'_>],
    template: &Template,
    spec: Option<&SheetSpec>,
) -> Result<Option<CutLayer>, BuildError> {
    let Some(bond) = template.bond.as_ref() else {
        return Ok(None);
    };
    let spec = spec.unwrap_or(&bond.sheet);
    let mut items = Vec::new();
    for (i, job) in jobs.iter().enumerate() {
        let g = &job.geometry;
        let via = (
            [0.0, bond.via_position * g.piezo_length_mm],
            bond.via_diameter_mm / 2.0,
        );
        check_via(job, template, bond, spec.kerf_mm, via)?;
        let outline = kerfed(
            job.design,
            &g.pzt_outline(),
            -bond.inset_mm,
            "pyralux inset",
        )?;
        items.push(item(
            i,
            job,
            "pyralux",
            spec,
            outline,
            (Feature::Via, vec![via]),
            2,
            Label::None,
            "pyralux",
        )?);
    }
    Ok(Some(CutLayer {
        layer: "pyralux".into(),
        material: spec.material.clone(),
        thickness_mm: bond.thickness_mm,
        density_kg_per_m3: bond.density_kg_per_m3,
        spec: spec.clone(),
        items,
        features: template.features,
        ply_deg: None,
        prepreg: false,
    }))
}

/// The via must leave twice the kerf of Pyralux to every edge of the PZT-shaped bond part: its ends
/// (the via's position along the plate) and its sides (the via's diameter against the plate's width
/// there). A refusal names the template field to change, with the range this design allows.
fn check_via(
    job: &Job<'_>,
    template: &Template,
    bond: &BondSpec,
    kerf_mm: f64,
    (centre, radius): (Point, f64),
) -> Result<(), BuildError> {
    let g = &job.geometry;
    // The bond part is the plate inset by `inset_mm` on every side: the via must fit in that.
    let length = g.plate_length_mm() - bond.inset_mm;
    let end_room = radius + 2.0 * kerf_mm + bond.inset_mm;
    let design = job.design.source.display();
    if centre[1] < end_room || centre[1] > length - end_room {
        // The via's centre is `via_position` of l_p from the base; the plate (inset by the template's
        // edge margin) may end short of l_p.
        let (lo, hi) = (
            end_room / g.piezo_length_mm,
            (length - end_room) / g.piezo_length_mm,
        );
        let allowed = if lo < hi {
            format!(
                "allowed range [{}, {}] for this design",
                short_number(lo),
                short_number(hi)
            )
        } else {
            "no position fits: the via is as long as the plate".to_string()
        };
        return Err(InputError::invalid(
            &template.source,
            "layers.pyralux.via_position",
            short_number(bond.via_position),
            format!(
                "the {} mm via would sit {} mm from the end of {design}'s bond part (its {} mm plate \
                 inset by {} mm), less than its radius and twice the {kerf_mm} mm kerf; {allowed}",
                short_number(bond.via_diameter_mm),
                short_number((centre[1] - bond.inset_mm).min(length - centre[1])),
                short_number(g.plate_length_mm()),
                short_number(bond.inset_mm)
            ),
        )
        .into());
    }
    let side_room = g.plate_width_at_mm(centre[1]) / 2.0 - bond.inset_mm - radius;
    if side_room < 2.0 * kerf_mm {
        let largest = g.plate_width_at_mm(centre[1]) - 2.0 * bond.inset_mm - 4.0 * kerf_mm;
        return Err(InputError::invalid(
            &template.source,
            "layers.pyralux.via_diameter_mm",
            short_number(bond.via_diameter_mm),
            format!(
                "the via leaves {} mm to the side of {design}'s bond part (the plate inset by {} mm), \
                 less than twice the {kerf_mm} mm kerf; at most {} mm fits there",
                short_number(side_room),
                short_number(bond.inset_mm),
                short_number(largest.max(0.0))
            ),
        )
        .into());
    }
    Ok(())
}

/// Draw finished layouts of a cut layer. Each placement's `item` indexes `layer.items`, its outline is
/// the item's cut path placed, its `copy` counts over the item's copies. Holes first, then labels, then
/// the outer contours (cut order), each with the operation the layer's feature map gives it.
pub fn draw_cut_sheets(
    layer: &CutLayer,
    layouts: &[NestedBin],
    from_drawn: &[usize],
    names: &Names,
    drawn: &mut Drawn,
) {
    let spec = &layer.spec;
    let op = |feature| layer.features.op(feature);
    for (k, layout) in layouts.iter().enumerate() {
        let stock_sheet = from_drawn.get(k).map(|&d| &spec.drawn[d]);
        let n = drawn.next_number(&layer.layer);
        let mut d = Drawing::on_stock(
            &format!("{} {}, sheet {n}", names.title, layer.layer),
            spec.width_mm,
            spec.height_mm,
            Stock {
                material: layer.material.clone(),
                thickness_mm: layer.thickness_mm,
                kerf_mm: spec.kerf_mm,
                fibre_axis: layer.prepreg.then_some(FibreAxis::Y),
            },
        );
        // Parts in cut-outs first, each group along a short path ([`cut_order`]).
        let inner = in_cutouts(&layout.parts);
        let order = cut_order(&layout.parts, &inner);
        for &i in &order {
            let p = &layout.parts[i];
            let item = &layer.items[p.item];
            for path in &item.cutout_paths {
                d.add(
                    op(Feature::PartOutline),
                    Shape::Polygon(place_ring(path, p.rotation_deg, p.translation)),
                );
            }
            for (centre, radius) in &item.holes {
                d.add(
                    op(item.hole),
                    Shape::Circle {
                        center: place_point(*centre, p.rotation_deg, p.translation),
                        radius: radius - spec.kerf_mm / 2.0,
                    },
                );
            }
            if inner[i] {
                d.add(op(Feature::PartOutline), Shape::Polygon(p.outline.clone()));
            }
        }
        for p in &layout.parts {
            let item = &layer.items[p.item];
            if let Some(zone) = &item.bonded_zone {
                d.add_guide(
                    "bonded-zone",
                    place_ring(zone, p.rotation_deg, p.translation),
                );
            }
            if let Some(strokes) = item.label.strokes(p.copy / item.per_actuator) {
                for s in strokes {
                    d.add(
                        op(Feature::PartLabel),
                        Shape::Polyline(place_ring(&s, p.rotation_deg, p.translation)),
                    );
                }
            }
        }
        let mut parts: Vec<_> = layout.parts.iter().map(|p| part_box(&p.outline)).collect();
        if let Some(sheet) = stock_sheet {
            // To lay the drawn sheet on; the label keeps off its keep-outs.
            draw_stock_shape(&mut d, &sheet.shape);
            parts.extend(sheet.shape.keep_outs.iter().map(|k| part_box(k)));
        }
        let name = format!("{}-{n}", layer.layer);
        drawn.label_sheet(
            &mut d,
            &name,
            spec.edge_margin_mm,
            &parts,
            op(Feature::SheetLabel),
        );
        let mut record = SheetRecord {
            stem: format!("{}-{n}", layer.layer),
            file_stem: file_stem(&format!("{}-{n}", layer.layer), d.stock.as_ref()),
            layer: layer.layer.clone(),
            material: layer.material.clone(),
            width_mm: spec.width_mm,
            height_mm: spec.height_mm,
            parts: Vec::new(),
            stock_file: stock_sheet.map(|s| s.file.clone()),
            remnant: (!spec.roll).then(|| remnant(stock_sheet, &layout.parts, &inner)),
        };
        for &i in order.iter().filter(|&&i| !inner[i]) {
            let outline = layout.parts[i].outline.clone();
            d.add(op(Feature::PartOutline), Shape::Polygon(outline));
        }
        for p in &layout.parts {
            let item = &layer.items[p.item];
            record.parts.push(PartRecord {
                job: item.job,
                actuator: p.copy / item.per_actuator,
                part: if item.per_actuator > 1 {
                    format!("{}-{}", item.part, p.copy % item.per_actuator + 1)
                } else {
                    item.part.clone()
                },
                rotation_deg: p.rotation_deg,
                offset: p.translation,
                area_mm2: item.area_mm2(),
            });
        }
        drawn.sheets.push(record);
        let copies = usize::from(stock_sheet.is_none());
        drawn.push_copies(format!("{}-{n}", layer.layer), &layer.layer, d, copies);
    }
}

/// A drawn sheet's outline and keep-outs as reference lines.
fn draw_stock_shape(d: &mut Drawing, shape: &SheetShape) {
    for ring in std::iter::once(&shape.outline)
        .filter(|o| !o.is_empty())
        .chain(&shape.keep_outs)
    {
        d.add(Operation::Reference, Shape::Polygon(ring.clone()));
    }
}

/// What is left of a sheet (drawn, or whole when `stock_sheet` is `None`) once `parts` are cut:
/// its outline and keep-outs, and the cut outline of each part not `inner` (a part in another's
/// cut-out is in that part's keep-out already).
fn remnant(stock_sheet: Option<&DrawnSheet>, parts: &[PlacedPart], inner: &[bool]) -> SheetShape {
    let mut shape = stock_sheet.map(|s| s.shape.clone()).unwrap_or_default();
    let outer = parts.iter().zip(inner).filter(|(_, i)| !**i);
    shape
        .keep_outs
        .extend(outer.map(|(p, _)| p.outline.clone()));
    shape
}

/// An extra part from a drawing as an item of a cut layer: outline and cut-outs with their cut
/// paths (outline grown, cut-outs shrunk by kerf/2), no label. `job` numbers it after the
/// build's designs. On a layer that cuts one ply of the layup ([`CutLayer::ply_deg`]) the part is
/// turned by -θ first, as the actuators' plies are: the sheet's fibres, along its y axis, then run
/// at +θ from the part's drawn x-y frame, and the part's own rotations come on top of that turn.
pub fn extra_item(
    job: usize,
    order: &PartOrder,
    layer: &CutLayer,
    names: &Names,
) -> Result<CutItem, BuildError> {
    let spec = &layer.spec;
    let part = &order.part;
    let owner = format!(
        "part {} ({}: {})",
        order.name,
        part.file.display(),
        part.entity
    );
    let turn = -layer.ply_deg.unwrap_or(0.0);
    let turned = |ring: &[Point]| {
        if turn == 0.0 {
            ring.to_vec()
        } else {
            place_ring(ring, turn, [0.0, 0.0])
        }
    };
    let outer = turned(&part.outer);
    let cutouts: Vec<Vec<Point>> = part.holes.iter().map(|h| turned(h)).collect();
    let mut pins = Vec::with_capacity(order.pin_holes.len());
    for (centre, radius) in &order.pin_holes {
        if radius - spec.kerf_mm / 2.0 <= 0.0 {
            return Err(names.error(format!(
                "{owner}: a {:.3} mm pin hole vanishes inside the {} mm kerf",
                2.0 * radius,
                spec.kerf_mm
            )));
        }
        let c = if turn == 0.0 {
            *centre
        } else {
            place_point(*centre, turn, [0.0, 0.0])
        };
        pins.push((c, *radius));
    }
    let offset = |ring: &[Point], delta: f64, what: &str| {
        if delta == 0.0 {
            return Ok(ring.to_vec());
        }
        offset_ring(ring, delta).map_err(|e| {
            names.error(format!(
                "{owner}: the {what} with the {} mm kerf: {e}",
                spec.kerf_mm
            ))
        })
    };
    Ok(CutItem {
        job,
        part: "part".into(),
        cut: offset(&outer, spec.kerf_mm / 2.0, "outline")?,
        bonded_zone: order.bonded_zone.clone(),
        nominal: outer,
        holes: pins,
        hole: Feature::RegistrationHole,
        per_actuator: 1,
        count: order.quantity,
        label: Label::per_copy(&order.labels),
        cutout_paths: cutouts
            .iter()
            .map(|h| offset(h, -spec.kerf_mm / 2.0, "cut-out"))
            .collect::<Result<_, _>>()?,
        cutouts,
        rotations_deg: order.rotations_deg.clone(),
        owner,
    })
}
