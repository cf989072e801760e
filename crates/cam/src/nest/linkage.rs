//! A batch item's linkage (`drive = "drive.toml"` on an `[[item]]`, or its design's `[transmission]`;
//! docs/cam.md §7): the
//! linkage laminate for as many linkages as the item has actuators, its layers as coupons nested with
//! the actuators' parts ([`crate::linkage::coupon`]). The carbon goes on the prepreg sheets of a design
//! of the batch laid up as the linkage's carbon (the template's `[linkage] carbon_ply` and
//! `carbon_layup_deg`), else on prepreg sheets of its own; the film and the adhesive on sheets of their
//! own, the prepreg sheet's size.

use crate::cutsheet::linkage::transmission_of;
use crate::design::Design;
use crate::drive::{linkage_laminate_in, DriveError};
use crate::input::InputError;
use crate::linkage::checks::{check_linkage_drawings, Expected};
use crate::linkage::coupon::Coupon;
use crate::linkage::pattern::Ply;
use crate::linkage::LinkageLaminate;
use crate::parts::{OwnSheet, PartOrder, PartSheet};
use crate::pipeline::{BuildError, SheetDrawing};
use crate::process::linkage::LinkageProcess;
use crate::process::template::{PassiveCut, SheetSpec, Template};
use actuator_model::model::{ModelChoice, ModelKind};
use std::path::{Path, PathBuf};

/// Rotations of a carbon coupon: half turns keep its fibres (the links along the sheet's fibres).
const CARBON_ROTATIONS_DEG: [f64; 2] = [0.0, 180.0];

/// Rotations of a film or adhesive coupon: no fibres, quarter turns.
const SHEET_ROTATIONS_DEG: [f64; 4] = [0.0, 90.0, 180.0, 270.0];

/// The linkage of one batch item.
#[derive(Debug, Clone, PartialEq)]
pub struct BatchLinkage {
    /// The item (index into the batch's items).
    pub item: usize,
    /// The file that gives the transmission: the drive file, or the design file.
    pub drive: PathBuf,
    /// Linkages to build: one per actuator of the item.
    pub quantity: usize,
    /// The laminate, designed with the batch's kerf ([`linkage_template`]).
    pub laminate: LinkageLaminate,
    /// One linkage's coupon.
    pub coupon: Coupon,
    /// Where each layer is cut: `(stack positions, sheet)` in stack order of first use.
    pub sheets: Vec<(Vec<usize>, String)>,
}

/// The template a batch designs a linkage with: when its carbon is cut on the prepreg sheets beside the
/// actuators' parts (`on_prepreg`), the kerf is the larger of `[linkage] kerf_mm` and the prepreg
/// sheet's, and the film and adhesive are cut with that kerf too, so one kerf draws the laminate;
/// otherwise the linkage's. `None` without a `[linkage]` table.
pub fn linkage_template(template: &Template, on_prepreg: bool) -> Option<Template> {
    let mut t = template.clone();
    let l = t.linkage.as_mut()?;
    if on_prepreg {
        l.kerf_mm = l.kerf_mm.max(template.passive.kerf_mm);
    }
    Some(t)
}

/// The design of the batch whose prepreg sheets the linkage's carbon shares: the first laid up as the
/// template's `[linkage]` carbon (ply, ply thickness and layup).
fn carbon_like(items: &[(&Design, usize)], template: &Template) -> Option<usize> {
    let process = template.linkage.as_ref()?;
    let (ply_name, ply_thickness) = &process.carbon_ply;
    items.iter().position(|i| {
        i.0.layup_deg == process.carbon_layup_deg
            && i.0.ply.name == *ply_name
            && (i.0.ply_thickness - ply_thickness).abs() <= 1e-12
    })
}

/// A sheet of the linkage's own: the prepreg sheet's size and spacing, `material` and the linkage kerf.
fn own_sheet(
    layer: &str,
    material: &str,
    thickness_mm: f64,
    density_kg_per_m3: f64,
    passive: &SheetSpec,
    kerf_mm: f64,
) -> PartSheet {
    PartSheet::Own(Box::new(OwnSheet {
        layer: layer.to_string(),
        material: material.to_string(),
        thickness_mm,
        density_kg_per_m3,
        spec: SheetSpec {
            material: material.to_string(),
            kerf_mm,
            stock: None,
            price_per_sheet: None,
            roll: false,
            drawn: Vec::new(),
            ..passive.clone()
        },
        prepreg: layer == "linkage-carbon",
    }))
}

/// The linkage of item `index` and its coupons as extra parts: of its `drive` file (`field` of the
/// batch file `batch`) or its design's `[transmission]`, which must agree when both are given
/// ([`transmission_of`]); `None` without either.
pub fn item_linkage(
    batch: &Path,
    field: &str,
    drive: Option<&Path>,
    index: usize,
    items: &[(&Design, usize)],
    template: &Template,
) -> Result<Option<(BatchLinkage, Vec<PartOrder>)>, InputError> {
    let (design, quantity) = items[index];
    let Some((drive_file, spec)) = transmission_of(drive, design)? else {
        return Ok(None);
    };
    let drive_file = drive_file.as_path();
    // The design's own `[transmission]` is named by the item's design.
    let field = match drive {
        Some(_) => field.to_string(),
        None => field.replace(".drive", ".design"),
    };
    let refuse = |what: String| {
        InputError::invalid(batch, &field, format!("{:?}", drive_file.display()), what)
    };
    let like = carbon_like(items, template);
    let Some(tpl) = linkage_template(template, like.is_some()) else {
        return Err(refuse(format!(
            "a process with a [linkage] table (process {:?} has none)",
            template.name
        )));
    };
    let model = ModelChoice::Kind(ModelKind::Original);
    let laminate =
        linkage_laminate_in(&spec, drive_file, design, &model, &tpl).map_err(|e| match e {
            DriveError::Input(e) => e,
            DriveError::Model(e) => refuse(e.to_string()),
        })?;
    let process = &laminate.process;
    let coupon = Coupon::of(&laminate, &tpl);
    let name = &design.name;
    let mut orders = Vec::new();
    let mut sheets = Vec::new();
    for part in coupon.parts(&laminate, drive_file) {
        let (sheet, rotations, label) = coupon_sheet(part.ply, like, items, template, process);
        let spec = match &sheet {
            PartSheet::Own(o) => &o.spec,
            _ => &template.passive,
        };
        let fit = spec.empty_sheet_fit(&part.part.outer, rotations);
        if !fit.fits {
            return Err(refuse(format!(
                "a linkage coupon that fits its sheet: the {:.3} x {:.3} mm coupon of layer(s) {:?} does not fit the {} x {} mm sheet with {} mm (kerf + edge gap) to every edge",
                fit.size_mm[0],
                fit.size_mm[1],
                part.layers,
                spec.width_mm,
                spec.height_mm,
                spec.kerf_mm + spec.edge_gap()
            )));
        }
        sheets.push((part.layers.clone(), label));
        let layer_name = match part.ply {
            Ply::Carbon => "carbon",
            Ply::Adhesive => "adhesive",
            Ply::Film => "film",
        };
        orders.push(PartOrder {
            name: format!("{name}-linkage-{layer_name}"),
            quantity: quantity * part.layers.len(),
            rotations_deg: rotations.to_vec(),
            sheet,
            pin_holes: part.pins,
            part: part.part,
            // The coupon's layers are laminated face to face over the linkage; the border, which
            // the release cut leaves as scrap, carries the engraving.
            bonded_zone: Some(part.zone),
            labels: coupon.labels(name, layer_name, quantity * part.layers.len()),
        });
    }
    Ok(Some((
        BatchLinkage {
            item: index,
            drive: drive_file.to_path_buf(),
            quantity,
            laminate,
            coupon,
            sheets,
        },
        orders,
    )))
}

/// The sheet a coupon layer of `ply` is cut from, its rotations and how the report names the
/// sheet: the carbon on the prepreg of the batch's design `like` laid up as the linkage's carbon,
/// else each ply on a sheet of its own the prepreg sheet's size.
fn coupon_sheet(
    ply: Ply,
    like: Option<usize>,
    items: &[(&Design, usize)],
    template: &Template,
    process: &LinkageProcess,
) -> (PartSheet, &'static [f64], String) {
    let kerf = process.kerf_mm;
    let layup = &process.carbon_layup_deg;
    match ply {
        Ply::Carbon => match like {
            Some(like) => (
                // The coupon is drawn with its links along its y axis, the sheet's fibres.
                PartSheet::Prepreg {
                    layup_deg: layup.clone(),
                    like,
                    fibre_axis_deg: 90.0,
                },
                &CARBON_ROTATIONS_DEG,
                format!(
                    "prepreg, layup {}{}",
                    items[like].0.layup_text(),
                    if template.passive_cut == PassiveCut::PlyByPly {
                        ", cut ply by ply"
                    } else {
                        ""
                    }
                ),
            ),
            None => (
                own_sheet(
                    "linkage-carbon",
                    &format!(
                        "{} ({})",
                        process.carbon.material, template.passive.material
                    ),
                    process.carbon.thickness_mm,
                    process.carbon.density_kg_per_m3,
                    &template.passive,
                    kerf,
                ),
                &CARBON_ROTATIONS_DEG,
                "linkage-carbon (no design of the batch has its layup)".to_string(),
            ),
        },
        Ply::Adhesive => (
            own_sheet(
                "linkage-adhesive",
                &process.adhesive.material,
                process.adhesive.thickness_mm,
                process.adhesive.density_kg_per_m3,
                &template.passive,
                kerf,
            ),
            &SHEET_ROTATIONS_DEG,
            "linkage-adhesive".to_string(),
        ),
        Ply::Film => (
            own_sheet(
                "linkage-film",
                &process.film.material,
                process.film.thickness_mm,
                process.film.density_kg_per_m3,
                &template.passive,
                kerf,
            ),
            &SHEET_ROTATIONS_DEG,
            "linkage-film".to_string(),
        ),
    }
}

/// The coupon files of the batch's linkages, `linkage-<design>-N-<layer>-1` (the design's name as a
/// file name carries it, [`crate::drawing::model::slug`], numbered by item when two items share it), checked across their
/// layers as a panel's are; with each linkage's file prefix.
pub fn coupon_drawings(
    linkages: &[BatchLinkage],
    items: &[(&Design, usize)],
    template: &Template,
) -> Result<Vec<(String, Vec<SheetDrawing>)>, BuildError> {
    let mut out: Vec<(String, Vec<SheetDrawing>)> = Vec::new();
    for l in linkages {
        let name = &items[l.item].0.name;
        let slug = crate::drawing::model::slug(name, 32);
        let mut prefix = format!("linkage-{slug}-");
        if out.iter().any(|(p, _)| *p == prefix) {
            prefix = format!("linkage-{slug}-item{}-", l.item + 1);
        }
        let tpl = linkage_template(template, carbon_like(items, template).is_some())
            .unwrap_or_else(|| template.clone());
        let mut drawings = l.coupon.drawings(
            &l.laminate,
            &tpl,
            &format!("{name} linkage coupon"),
            &prefix,
        )?;
        // The stack layers are cut on the nested sheets; these files show one coupon of each, and
        // say so where the laser software shows a file's name. The release cut is run as it is.
        for d in drawings.iter_mut().filter(|d| d.layer != "linkage-release") {
            d.drawing.title = format!(
                "{}: REFERENCE ONLY, not to be cut: the nested linkage sheets cut this coupon",
                d.drawing.title
            );
        }
        let problems = check_linkage_drawings(&drawings, &Expected::of(&l.laminate.report()));
        if !problems.is_empty() {
            return Err(BuildError::Geometry {
                file: l.drive.display().to_string(),
                what: format!(
                    "the linkage coupon fails its checks: {}",
                    problems.join("; ")
                ),
            });
        }
        out.push((prefix, drawings));
    }
    Ok(out)
}
