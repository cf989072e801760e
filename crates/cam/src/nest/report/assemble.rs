//! Assembling the batch report from the batch and what the planner drew: each section's rows, the
//! totals priced, the linkages and the build book.

use super::{
    ActuatorRef, ItemRow, NestLinkageRow, NestReport, PanelRow, PartItemRow, PartRow, RollRow,
    SheetAlternativeRow, SheetRow, TotalRow, COORDINATES,
};
use crate::book::{BuildBook, DesignFacts, Section};
use crate::linkage::checklist::coupon_steps;
use crate::nest::file::Batch;
use crate::parts::PartSheet;
use crate::pipeline::{Build, NestOptions, WORKERS};
use crate::process::template::PassiveCut;

impl NestReport {
    /// Assemble the report from what the planner drew; `files` is filled in by the writer.
    /// `on_sheets[i]`: the sheets the parts of cut layer `i`, nested on a priced roll, take on the
    /// roll's compared sheets (`None` for the other layers).
    pub fn new(
        batch: &Batch,
        opts: &NestOptions,
        built: &Build,
        on_sheets: &[Option<usize>],
        linkage_prefixes: &[String],
        jig: Option<&str>,
    ) -> NestReport {
        let sheets = sheet_rows(batch, built);
        let mut totals = Vec::new();
        add_sheet_totals(&mut totals, batch, &sheets);
        let rolls = roll_rows(batch, built, &sheets, on_sheets);
        let clamp_panels = clamp_panel_rows(&mut totals, batch, built);
        price_totals(&mut totals);
        let priced: Vec<&TotalRow> = totals.iter().filter(|r| r.cost.is_some()).collect();
        let total_cost = (!priced.is_empty()).then(|| priced.iter().filter_map(|r| r.cost).sum());
        let linkages = linkage_rows(batch, built, linkage_prefixes, jig.unwrap_or_default());
        let build_book = build_book(batch, built, &linkages);
        NestReport {
            name: batch.name.clone(),
            coordinates: COORDINATES.to_string(),
            seed: opts.seed,
            iterations: opts.iterations,
            time_budget_s: opts.time.map(|t| t.seconds),
            workers: WORKERS,
            process: batch.template.name.clone(),
            batch_file: batch.source.display().to_string(),
            items: item_rows(batch),
            parts: part_item_rows(batch),
            sheets,
            baseline: built
                .cut_layers
                .iter()
                .filter_map(|l| l.baseline.clone())
                .collect(),
            clamp_panels,
            stock_list: built.stock.clone(),
            sheets_without_stock_label: built.unlabelled_sheets,
            totals,
            total_cost,
            rolls,
            placement_map: built.placement_map.clone(),
            linkages,
            build_book,
            files: Vec::new(),
        }
    }
}

/// The name a job's parts carry in the report: jobs after the designs are the extra parts, in
/// batch order.
fn job_name(batch: &Batch, job: usize) -> String {
    match batch.items.get(job) {
        Some(item) => item.design.name.clone(),
        None => batch.parts[job - batch.items.len()].name.clone(),
    }
}

/// Whether a layer's sheets are strips of roll stock, as the process template says.
fn is_roll(batch: &Batch, layer: &str) -> bool {
    let t = &batch.template;
    match layer {
        "pzt" => false,
        l if l.starts_with("linkage-") => false,
        "pyralux" => t.bond.as_ref().is_some_and(|b| b.sheet.roll),
        _ => t.passive.roll,
    }
}

/// The price of one sheet of a layer, as the process template says (linkage coupons are cut from
/// offcuts and carry none).
fn sheet_price(batch: &Batch, layer: &str) -> Option<f64> {
    let t = &batch.template;
    match layer {
        "pzt" => t.pzt.price_per_sheet,
        l if l.starts_with("linkage-") => None,
        "pyralux" => t.bond.as_ref().and_then(|b| b.sheet.price_per_sheet),
        _ => t.passive.price_per_sheet,
    }
}

/// Every cut sheet with the parts on it.
fn sheet_rows(batch: &Batch, built: &Build) -> Vec<SheetRow> {
    built
        .sheets
        .iter()
        .map(|s| SheetRow {
            layer: s.layer.clone(),
            material: s.material.clone(),
            index: s
                .stem
                .rsplit_once('-')
                .and_then(|(_, n)| n.parse().ok())
                .unwrap_or(0),
            file_stem: s.file_stem.clone(),
            width_mm: s.width_mm,
            height_mm: s.height_mm,
            utilization: s.utilization(),
            roll: is_roll(batch, &s.layer),
            stock: s.stock_file.clone(),
            remnant: crate::nest::remnant::remnant_row(s),
            parts: s
                .parts
                .iter()
                .map(|p| PartRow {
                    design: job_name(batch, p.job),
                    actuator: p.actuator + 1,
                    part: p.part.clone(),
                    rotation_deg: p.rotation_deg,
                    x_mm: p.offset[0],
                    y_mm: p.offset[1],
                })
                .collect(),
        })
        .collect()
}

/// Count the cut sheets (and the roll their strips use) into the totals.
fn add_sheet_totals(totals: &mut Vec<TotalRow>, batch: &Batch, sheets: &[SheetRow]) {
    for s in sheets {
        let roll = s.roll.then(|| {
            (
                s.height_mm,
                batch.roll_price(&s.layer).map(|p| p.price_per_m),
            )
        });
        total(
            totals,
            &s.layer,
            &s.material,
            1,
            sheet_price(batch, &s.layer),
            roll,
        );
    }
}

/// The strips of roll stock, each with its cost and the cut sheets it is compared with.
fn roll_rows(
    batch: &Batch,
    built: &Build,
    sheets: &[SheetRow],
    on_sheets: &[Option<usize>],
) -> Vec<RollRow> {
    // Each cut layer on a roll is one strip: its sheet row follows the sheets of the layers
    // before it.
    let mut rolls = Vec::new();
    let mut first_sheet = built.pzt_sheets;
    for (i, l) in built.cut_layers.iter().enumerate() {
        let sheet = sheets.get(first_sheet);
        first_sheet += l.sheets;
        let Some(sheet) = sheet.filter(|s| s.roll && l.layer.spec.roll) else {
            continue;
        };
        let price = batch.roll_price(&l.layer.layer);
        let length_mm = sheet.height_mm;
        rolls.push(RollRow {
            layer: sheet.layer.clone(),
            material: sheet.material.clone(),
            file_stem: sheet.file_stem.clone(),
            width_mm: sheet.width_mm,
            length_mm,
            price_per_m: price.map(|p| p.price_per_m),
            cost: price.map(|p| roll_cost(length_mm, p.price_per_m)),
            on_sheets: price
                .zip(on_sheets.get(i).copied().flatten())
                .map(|(p, n)| SheetAlternativeRow {
                    width_mm: p.sheet_width_mm,
                    height_mm: p.sheet_height_mm,
                    sheets: n,
                    price_per_sheet: p.price_per_sheet,
                    cost: p.price_per_sheet.map(|c| c * n as f64),
                }),
        });
    }
    rolls
}

/// The clamp panels with the actuators each holds; their mold and cover sheets are counted into
/// the totals.
fn clamp_panel_rows(totals: &mut Vec<TotalRow>, batch: &Batch, built: &Build) -> Vec<PanelRow> {
    let t = &batch.template;
    let mut clamp_panels = Vec::new();
    for c in &built.clamps {
        for stem in &c.stack {
            let kind = stem.rsplit_once('-').map(|(k, _)| k).unwrap_or(stem);
            let material = if kind == "mold" {
                &t.mold.material
            } else {
                t.covers
                    .get(kind)
                    .map(|s| &s.material)
                    .unwrap_or(&t.mold.material)
            };
            total(totals, kind, material, c.panels.len(), None, None);
        }
        let press_fit =
            crate::cutsheet::report::MoldReport::new(&c.mold, t.mold_stock.tolerance_mm).press_fit;
        for (p, members) in c.panels.iter().enumerate() {
            clamp_panels.push(PanelRow {
                index: c.first_panel + p,
                stacking_order: c.stack.clone(),
                mold_films_mm: c.mold.films_mm.clone(),
                press_fit: press_fit.clone(),
                actuators: members
                    .iter()
                    .map(|(j, a)| ActuatorRef {
                        design: job_name(batch, *j),
                        actuator: a + 1,
                    })
                    .collect(),
            });
        }
    }
    clamp_panels
}

/// Price each total: a roll by the length used, sheets by the sheet.
fn price_totals(totals: &mut [TotalRow]) {
    for r in totals {
        r.cost = match (r.roll_length_mm, r.price_per_m) {
            (Some(length), Some(p)) => Some(roll_cost(length, p)),
            (Some(_), None) => None,
            _ => r.price_per_sheet.map(|p| p * r.sheets as f64),
        };
    }
}

/// The nested sheet files of layer `layer` (`linkage-film`) whose stock is `thickness_mm` thick.
fn sheet_files(built: &Build, layer: &str, thickness_mm: f64) -> Vec<String> {
    built
        .drawings
        .iter()
        .filter(|d| d.layer == layer)
        .filter(|d| {
            d.drawing
                .stock
                .as_ref()
                .is_some_and(|s| (s.thickness_mm - thickness_mm).abs() < 1e-9)
        })
        .map(|d| format!("`{}`", d.stem))
        .collect()
}

/// Where a linkage's coupons are cut, each sheet with its files (`layer 3 on linkage-film:
/// `linkage-film-1_…``); and, when its carbon is on sheets of its own, the step that lays that
/// prepreg up.
fn coupon_sheets(
    built: &Build,
    l: &crate::nest::linkage::BatchLinkage,
    laminate: &crate::linkage::LinkageReport,
) -> (Vec<(Vec<usize>, String)>, Option<String>) {
    let mut layup = None;
    let sheets = l
        .sheets
        .iter()
        .map(|(layers, label)| {
            let layer = label.split(' ').next().unwrap_or_default();
            let thickness = laminate.layers[layers[0] - 1].thickness_mm;
            let files = sheet_files(built, layer, thickness);
            if files.is_empty() {
                return (layers.clone(), label.clone());
            }
            if layer == "linkage-carbon" {
                let p = &l.laminate.process;
                let angles: Vec<String> = p.carbon_layup_deg.iter().map(|a| a.to_string()).collect();
                layup = Some(format!(
                    "Lay up the linkage carbon's prepreg: {} plies of {} at {} from the stack's 0° direction (the links' direction), laid with that direction along the sheet's y axis (up the page), as each file says, and cut {} from it last, just before stacking: the prepreg must still be tacky.",
                    angles.len(),
                    p.carbon_ply.0,
                    angles.join("/"),
                    files.join(", ")
                ));
            }
            (layers.clone(), format!("{label} ({})", files.join(", ")))
        })
        .collect();
    (sheets, layup)
}

/// Each item's linkage: its laminate, coupon, sheets and build steps. `jig` names the jig file the
/// coupons stack on.
fn linkage_rows(
    batch: &Batch,
    built: &Build,
    linkage_prefixes: &[String],
    jig: &str,
) -> Vec<NestLinkageRow> {
    batch
        .linkages
        .iter()
        .zip(linkage_prefixes)
        .map(|(l, prefix)| {
            let laminate = l.laminate.report();
            let (sheets, layup) = coupon_sheets(built, l, &laminate);
            let design = &batch.items[l.item].design.name;
            let jig_step = crate::linkage::jig::jig_step(
                jig,
                (design, l.quantity),
                &l.coupon.clamp,
                &l.laminate.process,
                l.laminate.stack_thickness_mm(),
            );
            NestLinkageRow {
                design: batch.items[l.item].design.name.clone(),
                drive_file: l.drive.display().to_string(),
                quantity: l.quantity,
                prefix: prefix.clone(),
                panels: 1,
                coupon_width_mm: l.coupon.clamp.panel_width_mm,
                coupon_height_mm: l.coupon.clamp.panel_height_mm,
                sheets: l
                    .sheets
                    .iter()
                    .map(|(layers, sheet)| {
                        let n: Vec<String> = layers.iter().map(|k| k.to_string()).collect();
                        format!("layer {} on {sheet}", n.join(" and "))
                    })
                    .collect(),
                build_steps: {
                    let mut steps = coupon_steps(
                        &laminate,
                        l.quantity,
                        &sheets,
                        prefix,
                        &crate::book::pin_fit_text(&l.coupon.clamp),
                        (&jig_step, jig),
                    );
                    steps.splice(1..1, layup);
                    steps
                },
                laminate,
            }
        })
        .collect()
}

/// The build book of the batch, the linkages' steps as its last sections.
fn build_book(batch: &Batch, built: &Build, linkages: &[NestLinkageRow]) -> BuildBook {
    let mut build_book = BuildBook::new(
        &batch.template,
        built,
        &batch
            .items
            .iter()
            .enumerate()
            .map(|(job, item)| DesignFacts {
                name: item.design.name.clone(),
                base_tab_mm: item.design.planform.base_tab * 1e3,
                ground_tab_added: item.ground_tab_mm.is_some(),
                expected: crate::book::Expected::of(&item.design, built.drawn_bond_mg(job)),
            })
            .collect::<Vec<_>>(),
    );
    for l in linkages {
        build_book.sections.push(Section {
            title: format!("Linkages of {} (docs/cam.md §7)", l.design),
            steps: l.build_steps.clone(),
        });
    }
    build_book
}

/// The batch's `[[item]]`s as built.
fn item_rows(batch: &Batch) -> Vec<ItemRow> {
    batch
        .items
        .iter()
        .map(|i| ItemRow {
            design: i.design.name.clone(),
            file: i.design.source.display().to_string(),
            quantity: i.quantity,
            pzt_thickness_mm: i.design.pzt_thickness * 1e3,
            layup_deg: i.design.layup_text(),
            ground_tab_mm: i.ground_tab_mm,
        })
        .collect()
}

/// The batch's extra parts from drawings, with the sheet each is cut from.
fn part_item_rows(batch: &Batch) -> Vec<PartItemRow> {
    let by_ply = batch.template.passive_cut == PassiveCut::PlyByPly;
    batch
        .parts
        .iter()
        .map(|p| PartItemRow {
            name: p.name.clone(),
            file: p.part.file.display().to_string(),
            entity: p.part.entity.clone(),
            quantity: p.quantity,
            sheet: match &p.sheet {
                PartSheet::Prepreg { like, .. } if by_ply => format!(
                    "prepreg, layup {}, cut ply by ply",
                    batch.items[*like].design.layup_text()
                ),
                PartSheet::Prepreg { like, .. } => {
                    format!("prepreg, layup {}", batch.items[*like].design.layup_text())
                }
                PartSheet::Pyralux => "pyralux".into(),
                PartSheet::Own(o) => format!("{}, {}", o.layer, o.material),
            },
            rotations_deg: p.rotations_deg.clone(),
            fibre_axis_deg: match &p.sheet {
                PartSheet::Prepreg { fibre_axis_deg, .. } => Some(*fibre_axis_deg),
                PartSheet::Pyralux | PartSheet::Own(_) => None,
            },
            pieces_per_part: match &p.sheet {
                PartSheet::Prepreg { layup_deg, .. } if by_ply => Some(layup_deg.len()),
                _ => None,
            },
            area_mm2: p.part.area_mm2(),
            cutouts: p.part.holes.len(),
        })
        .collect()
}

/// Add `sheets` of a material to the totals; `roll`: the length of roll they use, mm, and the price
/// per metre.
fn total(
    rows: &mut Vec<TotalRow>,
    layer: &str,
    material: &str,
    sheets: usize,
    price: Option<f64>,
    roll: Option<(f64, Option<f64>)>,
) {
    match rows
        .iter_mut()
        .find(|r| r.layer == layer && r.material == material)
    {
        Some(r) => {
            r.sheets += sheets;
            if let (Some(total), Some((length, _))) = (&mut r.roll_length_mm, roll) {
                *total += length;
            }
        }
        None => rows.push(TotalRow {
            layer: layer.into(),
            material: material.into(),
            sheets,
            price_per_sheet: price,
            roll_length_mm: roll.map(|(length, _)| length),
            price_per_m: roll.and_then(|(_, p)| p),
            cost: None,
        }),
    }
}

/// The cost of `length_mm` of roll at `price_per_m`.
fn roll_cost(length_mm: f64, price_per_m: f64) -> f64 {
    length_mm * price_per_m / 1000.0
}
