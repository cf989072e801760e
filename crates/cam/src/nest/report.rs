//! The batch report: every sheet with the parts on it, nesting against the bounding-box baseline,
//! clamp panels, totals (and cost when the sheets have prices); as `nest-report.json` and a readable
//! `nest-report.md`.

use super::file::Batch;
use crate::book::{BuildBook, DesignFacts, Section};
use crate::linkage::checklist::coupon_steps;
use crate::markdown::{code, text as md};
use crate::parts::PartSheet;
use crate::pipeline::{BaselineRow, Build, NestOptions, SearchRow, StockCount, WORKERS};
use crate::prediction::Prediction;
use crate::process::template::PassiveCut;
use actuator_model::ModelKind;
use serde::Serialize;
use std::fmt::Write;

/// One `[[item]]` as built.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ItemRow {
    pub design: String,
    pub file: String,
    pub quantity: usize,
    pub pzt_thickness_mm: f64,
    pub layup_deg: String,
    /// The ground tab the process added to a design with no base tab, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ground_tab_mm: Option<f64>,
}

/// One extra part from a drawing (`[[part]]`), as read.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PartItemRow {
    pub name: String,
    pub file: String,
    /// The entity of its outline in the drawing.
    pub entity: String,
    pub quantity: usize,
    /// `prepreg, layup [0/90/0]` or `pyralux`.
    pub sheet: String,
    /// Rotations on top of the fibre turn, degrees.
    pub rotations_deg: Vec<f64>,
    /// On prepreg: the direction of the part's 0° fibres in its drawing (degrees from the drawing's x
    /// axis), turned onto the sheet's fibres (its y axis) before the rotations.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fibre_axis_deg: Option<f64>,
    /// Ply-by-ply cutting: the pieces cut of each part, one per ply of its layup, each on its ply's
    /// sheet turned to the ply's fibre angle.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pieces_per_part: Option<usize>,
    /// Outline less cut-outs, as flattened (arcs within 0.01 mm), mm².
    pub area_mm2: f64,
    pub cutouts: usize,
}

/// The coordinate convention of the parts' positions, as the report states it.
pub const COORDINATES: &str = "x_mm, y_mm are where the centre of the part's base (its clamped \
root end; for a part from a drawing, the centre of its outline's bounding box) lands after the rotation, in millimetres from the sheet's lower-left corner with y up, \
as in the DXF files. In the SVG files y runs down: y_svg = page height - y_mm (the clamp-panel \
pages, grown to hold the kerf-offset outline, add their margin to both).";

/// One part on a sheet: `x_mm`, `y_mm` is where the part's origin (the centre of its base, the
/// clamped end, the "root centre") lands after the rotation, in sheet coordinates with the origin at
/// the sheet's lower-left corner and y up: the DXF's coordinates. The SVG's y runs down from the top
/// of its page: y_svg = page height - margin - y_mm, x_svg = x_mm + margin, where the margin is 0
/// unless the page grew to hold outlines past the sheet ([`COORDINATES`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PartRow {
    pub design: String,
    /// 1-based, within its design.
    pub actuator: usize,
    pub part: String,
    pub rotation_deg: f64,
    pub x_mm: f64,
    pub y_mm: f64,
}

/// One sheet of a cut material.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SheetRow {
    pub layer: String,
    pub material: String,
    /// 1-based sheet number within the layer, as in the file name.
    pub index: usize,
    pub file_stem: String,
    pub width_mm: f64,
    pub height_mm: f64,
    /// Nominal part area / sheet area.
    pub utilization: f64,
    /// A strip of roll stock: `height_mm` is the used length.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub roll: bool,
    pub parts: Vec<PartRow>,
}

/// An actuator of the batch.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ActuatorRef {
    pub design: String,
    pub actuator: usize,
}

/// One clamp panel.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PanelRow {
    pub index: usize,
    pub stacking_order: Vec<String>,
    /// The film of each mold sheet of the panel, bottom to top, mm.
    pub mold_films_mm: Vec<f64>,
    pub actuators: Vec<ActuatorRef>,
}

/// Sheets of one material (a roll's strips: their length and price per metre too).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TotalRow {
    pub layer: String,
    pub material: String,
    pub sheets: usize,
    pub price_per_sheet: Option<f64>,
    /// Roll stock: the length of roll used by these strips, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub roll_length_mm: Option<f64>,
    /// Roll stock: the price of a metre of roll.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub price_per_m: Option<f64>,
    pub cost: Option<f64>,
}

/// The cut sheets a priced roll is compared with: the same parts nested on them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SheetAlternativeRow {
    pub width_mm: f64,
    pub height_mm: f64,
    /// Sheets the parts take.
    pub sheets: usize,
    pub price_per_sheet: Option<f64>,
    /// Sheets x price per sheet, when the sheet has a price.
    pub cost: Option<f64>,
}

/// One strip of roll stock: the length used, its cost when the roll is priced, and the cut sheets
/// it is compared with.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RollRow {
    pub layer: String,
    pub material: String,
    pub file_stem: String,
    pub width_mm: f64,
    /// Roll used, as drawn (the nest's used length rounded up to 0.1 mm), mm.
    pub length_mm: f64,
    pub price_per_m: Option<f64>,
    /// Length in metres x price per metre.
    pub cost: Option<f64>,
    /// The same parts on cut sheets (priced rolls only).
    pub on_sheets: Option<SheetAlternativeRow>,
}

/// `nest-report.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NestReport {
    pub name: String,
    /// What `x_mm`/`y_mm` of the parts mean ([`COORDINATES`]).
    pub coordinates: String,
    pub seed: u64,
    pub iterations: usize,
    /// The nest's wall-clock budget, s, if it had one (each layer's `search` says how far it got).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_budget_s: Option<f64>,
    pub workers: usize,
    pub process: String,
    pub batch_file: String,
    pub items: Vec<ItemRow>,
    /// Extra parts from drawings, if any.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub parts: Vec<PartItemRow>,
    pub sheets: Vec<SheetRow>,
    pub baseline: Vec<BaselineRow>,
    pub clamp_panels: Vec<PanelRow>,
    pub totals: Vec<TotalRow>,
    /// Sheets of each stock the files are cut from (material, thickness, sheet size).
    pub stock_list: Vec<StockCount>,
    /// Part sheets with no room for a drawn stock label (docs/cam.md §3, "Stock labels").
    pub sheets_without_stock_label: usize,
    /// Sum of the costs, when every cut material has a price.
    pub total_cost: Option<f64>,
    /// Strips of roll stock: length used, cost, and the cut sheets compared (only with a roll).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub rolls: Vec<RollRow>,
    pub placement_map: Vec<String>,
    /// The items' linkages, nested as coupons (docs/cam.md §7).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub linkages: Vec<NestLinkageRow>,
    /// The build book: the process step by step for the whole batch (crate::book).
    pub build_book: BuildBook,
    pub files: Vec<String>,
}

/// One item's linkage: the laminate as designed, where its coupons are cut, the coupon's files and
/// its build steps (keys as a cut sheet's `linkage`, with `panels` the one coupon of its files).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NestLinkageRow {
    pub design: String,
    pub drive_file: String,
    /// Linkages: one per actuator of the item.
    pub quantity: usize,
    /// The coupon's files: `<prefix>N-<layer>-1`.
    pub prefix: String,
    pub panels: usize,
    pub coupon_width_mm: f64,
    pub coupon_height_mm: f64,
    /// `layer N and M on <sheet>`, in stack order of first use.
    pub sheets: Vec<String>,
    #[serde(flatten)]
    pub laminate: crate::linkage::LinkageReport,
    pub build_steps: Vec<String>,
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

impl RollRow {
    /// The roll's cost for the `nest` summary line, beside the cut sheets it is compared with:
    /// `passive roll 43.0 mm at 60.00/m costs 2.58 (instead 1 sheet(s) of 150 x 150 mm, 12.00)`.
    /// `None` for an unpriced roll (its length is in the layer's summary already).
    pub fn summary(&self) -> Option<String> {
        let (cost, per_m) = self.cost.zip(self.price_per_m)?;
        let instead = self
            .on_sheets
            .as_ref()
            .map(|a| {
                format!(
                    " (instead {} sheet(s) of {} x {} mm{})",
                    a.sheets,
                    a.width_mm,
                    a.height_mm,
                    a.cost.map(|c| format!(", {c:.2}")).unwrap_or_default()
                )
            })
            .unwrap_or_default();
        Some(format!(
            "{} roll {:.1} mm at {per_m:.2}/m costs {cost:.2}{instead}",
            self.layer, self.length_mm
        ))
    }
}

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
    ) -> NestReport {
        let t = &batch.template;
        let by_ply = t.passive_cut == PassiveCut::PlyByPly;
        // Jobs after the designs are the extra parts, in batch order.
        let design_name = |job: usize| match batch.items.get(job) {
            Some(item) => item.design.name.clone(),
            None => batch.parts[job - batch.items.len()].name.clone(),
        };
        let roll = |layer: &str| match layer {
            "pzt" => false,
            l if l.starts_with("linkage-") => false,
            "pyralux" => t.bond.as_ref().is_some_and(|b| b.sheet.roll),
            _ => t.passive.roll,
        };
        let sheets: Vec<SheetRow> = built
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
                roll: roll(&s.layer),
                parts: s
                    .parts
                    .iter()
                    .map(|p| PartRow {
                        design: design_name(p.job),
                        actuator: p.actuator + 1,
                        part: p.part.clone(),
                        rotation_deg: p.rotation_deg,
                        x_mm: p.offset[0],
                        y_mm: p.offset[1],
                    })
                    .collect(),
            })
            .collect();
        let mut totals = Vec::new();
        for s in &sheets {
            let price = match s.layer.as_str() {
                "pzt" => t.pzt.price_per_sheet,
                l if l.starts_with("linkage-") => None,
                "pyralux" => t.bond.as_ref().and_then(|b| b.sheet.price_per_sheet),
                _ => t.passive.price_per_sheet,
            };
            let roll = s.roll.then(|| {
                (
                    s.height_mm,
                    batch.roll_price(&s.layer).map(|p| p.price_per_m),
                )
            });
            total(&mut totals, &s.layer, &s.material, 1, price, roll);
        }
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
                total(&mut totals, kind, material, c.panels.len(), None, None);
            }
            for (p, members) in c.panels.iter().enumerate() {
                clamp_panels.push(PanelRow {
                    index: c.first_panel + p,
                    stacking_order: c.stack.clone(),
                    mold_films_mm: c.mold.films_mm.clone(),
                    actuators: members
                        .iter()
                        .map(|(j, a)| ActuatorRef {
                            design: design_name(*j),
                            actuator: a + 1,
                        })
                        .collect(),
                });
            }
        }
        for r in &mut totals {
            r.cost = match (r.roll_length_mm, r.price_per_m) {
                (Some(length), Some(p)) => Some(roll_cost(length, p)),
                (Some(_), None) => None,
                _ => r.price_per_sheet.map(|p| p * r.sheets as f64),
            };
        }
        let priced: Vec<&TotalRow> = totals.iter().filter(|r| r.cost.is_some()).collect();
        let total_cost = (!priced.is_empty()).then(|| priced.iter().filter_map(|r| r.cost).sum());
        let linkages: Vec<NestLinkageRow> = batch
            .linkages
            .iter()
            .zip(linkage_prefixes)
            .map(|(l, prefix)| {
                let laminate = l.laminate.report();
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
                    build_steps: coupon_steps(&laminate, l.quantity, &l.sheets, prefix),
                    laminate,
                }
            })
            .collect();
        let mut build_book = BuildBook::new(
            t,
            built,
            &batch
                .items
                .iter()
                .map(|item| DesignFacts {
                    name: item.design.name.clone(),
                    base_tab_mm: item.design.planform.base_tab * 1e3,
                    ground_tab_added: item.ground_tab_mm.is_some(),
                    capacitance_nf: Prediction::of(&item.design, ModelKind::Original)
                        .ok()
                        .map(|p| p.capacitance_nF),
                })
                .collect::<Vec<_>>(),
        );
        for l in &linkages {
            build_book.sections.push(Section {
                title: format!("Linkages of {} (docs/cam.md §7)", l.design),
                steps: l.build_steps.clone(),
            });
        }
        NestReport {
            name: batch.name.clone(),
            coordinates: COORDINATES.to_string(),
            seed: opts.seed,
            iterations: opts.iterations,
            time_budget_s: opts.time.map(|t| t.seconds),
            workers: WORKERS,
            process: t.name.clone(),
            batch_file: batch.source.display().to_string(),
            items: batch
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
                .collect(),
            parts: batch
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
                .collect(),
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

    /// Actuators in the batch.
    pub fn actuators(&self) -> usize {
        self.items.iter().map(|i| i.quantity).sum()
    }

    /// Sheets of one layer kind (`pzt`, a name starting `passive`, `pyralux`).
    pub fn sheets_of(&self, layer_prefix: &str) -> usize {
        self.sheets
            .iter()
            .filter(|s| s.layer.starts_with(layer_prefix))
            .count()
    }

    /// How each layer's search ended, when a time budget or an interrupt could end it: the
    /// iterations it reached, and whether `--iterations` replays it. Empty otherwise.
    fn search_markdown(&self) -> String {
        let rows: Vec<(&BaselineRow, &SearchRow)> = self
            .baseline
            .iter()
            .filter_map(|b| b.search.as_ref().map(|r| (b, r)))
            .collect();
        if rows.is_empty() {
            return String::new();
        }
        let mut s = String::new();
        let budget = self
            .time_budget_s
            .map_or(String::new(), |t| format!(" (time budget {t} s)"));
        let _ = writeln!(
            s,
            "## Search{budget}
"
        );
        let _ = writeln!(s, "How far a time budget gets depends on the machine and its load. The iterations a layer reached do not: `--iterations` with a layer's figure nests that layer the same way on any machine (a search cut before its base budget of 1000 iterations was done cannot be replayed).\n");
        let _ = writeln!(s, "| layer | iterations reached | ended by | replay |");
        let _ = writeln!(s, "|---|---|---|---|");
        for (b, r) in rows {
            let replay = if r.replayable {
                format!("`--iterations {}`", r.iterations)
            } else {
                "not replayable".into()
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {replay} |",
                b.layer, r.iterations, r.ended
            );
        }
        s.push('\n');
        s
    }

    /// The readable report.
    pub fn markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "# Nest: {}\n", md(&self.name));
        let _ = writeln!(
            s,
            "Process {}; batch file {}; seed {}, {} optimiser iterations on {} workers (same batch and seed, same files).\n",
            code(&self.process),
            code(&self.batch_file),
            self.seed,
            self.iterations,
            self.workers
        );
        let _ = writeln!(
            s,
            "| design | quantity | PZT mm | layup | ground tab added mm | file |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|");
        for i in &self.items {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} |",
                md(&i.design),
                i.quantity,
                i.pzt_thickness_mm,
                i.layup_deg,
                i.ground_tab_mm.map_or("-".into(), |t| t.to_string()),
                code(&i.file)
            );
        }
        if !self.parts.is_empty() {
            let _ = writeln!(s, "\n## Parts from drawings\n");
            let _ = writeln!(
                s,
                "| part | quantity | sheet | fibre axis in the drawing ° | rotations ° | area mm² | cut-outs | drawing | entity |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
            for p in &self.parts {
                let rotations: Vec<String> =
                    p.rotations_deg.iter().map(|r| r.to_string()).collect();
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | {} | {:.3} | {} | {} | {} |",
                    md(&p.name),
                    p.quantity,
                    md(&p.sheet),
                    p.fibre_axis_deg.map_or("-".into(), |a| a.to_string()),
                    rotations.join("/"),
                    p.area_mm2,
                    p.cutouts,
                    code(&p.file),
                    md(&p.entity)
                );
            }
            let _ = writeln!(
                s,
                "\nA prepreg part is turned so that its fibre axis lies along the sheet's fibres (the sheet's y axis), then rotated; a part's rotation below is from that turned position. In the sheet lists below an extra part's design column holds its name and the actuator column its copy number.\n"
            );
        }
        for l in &self.linkages {
            let _ = writeln!(
                s,
                "\n## Linkages of {} (docs/cam.md §7)\n\n{} linkage(s) of {}, each cut as five {:.3} x {:.3} mm coupons ({}) and released from its laminated coupon by {}; the coupon's files {} are its layers as nested, checked across layers:\n\n```text\n{}```",
                md(&l.design),
                l.quantity,
                code(&l.drive_file),
                l.coupon_width_mm,
                l.coupon_height_mm,
                md(&l.sheets.join("; ")),
                code(&format!("{}{}-release-1", l.prefix, l.laminate.layers.len() + 1)),
                code(&format!("{}*", l.prefix)),
                l.laminate.table()
            );
        }
        let _ = writeln!(s, "\n## Sheets\n");
        let _ = writeln!(
            s,
            "| file | layer | material | size mm | parts | utilisation |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|");
        for sh in &self.sheets {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} x {} | {} | {:.1}% |",
                code(&sh.file_stem),
                md(&sh.layer),
                md(&sh.material),
                sh.width_mm,
                sh.height_mm,
                sh.parts.len(),
                sh.utilization * 100.0
            );
        }
        for sh in self.sheets.iter().filter(|sh| sh.roll) {
            let _ = writeln!(
                s,
                "\n{} is a strip of roll stock {} mm wide: {} mm of the roll used.",
                code(&sh.file_stem),
                sh.width_mm,
                sh.height_mm
            );
        }
        let _ = writeln!(s, "\n## Irregular nest against the bounding-box baseline\n");
        let _ = writeln!(
            s,
            "| layer | material | parts | sheets | utilisation | used-length utilisation | baseline sheets | baseline utilisation | baseline used-length utilisation |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
        for b in &self.baseline {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {:.1}% | {:.1}% | {} | {:.1}% | {:.1}% |",
                md(&b.layer),
                md(&b.material),
                b.parts,
                b.sheets,
                b.utilization * 100.0,
                b.used_length_utilization * 100.0,
                b.baseline_sheets,
                b.baseline_utilization * 100.0,
                b.baseline_used_length_utilization * 100.0
            );
        }
        let _ = writeln!(
            s,
            "\nUsed-length utilisation counts the emptiest sheet only up to its highest part (plus the separation): the rest stays usable as a remnant.\n"
        );
        s.push_str(&self.search_markdown());
        let _ = writeln!(s, "\n## Totals\n");
        let _ = writeln!(s, "| layer | material | sheets | price/sheet | cost |");
        let _ = writeln!(s, "|---|---|---|---|---|");
        let money = |x: Option<f64>| x.map(|v| format!("{v:.2}")).unwrap_or_else(|| "-".into());
        for r in &self.totals {
            let (sheets, price) = match r.roll_length_mm {
                Some(length) => (
                    format!("{} strip(s), {length:.1} mm of roll", r.sheets),
                    r.price_per_m
                        .map(|p| format!("{p:.2}/m"))
                        .unwrap_or_else(|| "-".into()),
                ),
                None => (r.sheets.to_string(), money(r.price_per_sheet)),
            };
            let _ = writeln!(
                s,
                "| {} | {} | {sheets} | {price} | {} |",
                md(&r.layer),
                md(&r.material),
                money(r.cost)
            );
        }
        if let Some(c) = self.total_cost {
            let _ = writeln!(s, "\nMaterial cost of the priced sheets: **{c:.2}**.");
        }
        if !self.rolls.is_empty() {
            let _ = writeln!(s, "\n## Roll stock against cut sheets\n");
            let _ = writeln!(
                s,
                "| strip | material | width mm | roll used mm | price/m | roll cost | same parts on sheets | sheet cost |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
            for r in &self.rolls {
                let sheets = r
                    .on_sheets
                    .as_ref()
                    .map(|a| format!("{} x {} mm: {}", a.width_mm, a.height_mm, a.sheets))
                    .unwrap_or_else(|| "-".into());
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {:.1} | {} | {} | {sheets} | {} |",
                    code(&r.file_stem),
                    md(&r.material),
                    r.width_mm,
                    r.length_mm,
                    money(r.price_per_m),
                    money(r.cost),
                    money(r.on_sheets.as_ref().and_then(|a| a.cost))
                );
            }
            let _ = writeln!(
                s,
                "\nA roll is priced by the length used as drawn (the nest's used length rounded up to 0.1 mm); the sheets are the same parts nested on the sheets the batch compares the roll with (`compare_with`, by default the process template's sheet), each sheet counted whole (its unused rest may be kept as a remnant)."
            );
        }
        let _ = writeln!(s, "\n## Stock list\n");
        let _ = write!(s, "{}", StockCount::markdown(&self.stock_list));
        if let Some(note) = crate::pipeline::unlabelled_note(self.sheets_without_stock_label) {
            let _ = writeln!(s, "\n{note}");
        }
        let _ = writeln!(s, "\n## Clamp panels\n");
        for p in &self.clamp_panels {
            let who: Vec<String> = p
                .actuators
                .iter()
                .map(|a| format!("{} #{}", md(&a.design), a.actuator))
                .collect();
            let films: Vec<String> = p.mold_films_mm.iter().map(|t| t.to_string()).collect();
            let _ = writeln!(
                s,
                "- panel {} ({} layers: {}; mold films bottom to top {} mm): {}",
                p.index,
                p.stacking_order.len(),
                p.stacking_order
                    .iter()
                    .map(|l| md(l))
                    .collect::<Vec<_>>()
                    .join(" → "),
                films.join(" + "),
                who.join(", ")
            );
        }
        let _ = writeln!(s, "\n## Build book");
        let _ = write!(s, "{}", self.build_book.markdown());
        let _ = writeln!(s, "\n## Parts on each sheet\n");
        let _ = writeln!(s, "Position: {COORDINATES}\n");
        for sh in &self.sheets {
            let _ = writeln!(s, "### {} ({})\n", code(&sh.file_stem), md(&sh.material));
            let _ = writeln!(s, "| design | actuator | part | rotation ° | x mm | y mm |");
            let _ = writeln!(s, "|---|---|---|---|---|---|");
            for p in &sh.parts {
                let _ = writeln!(
                    s,
                    "| {} | {} | {} | {} | {:.3} | {:.3} |",
                    md(&p.design),
                    p.actuator,
                    md(&p.part),
                    p.rotation_deg,
                    p.x_mm,
                    p.y_mm
                );
            }
            let _ = writeln!(s);
        }
        let _ = writeln!(s, "## Placement map\n");
        for line in &self.placement_map {
            let _ = writeln!(s, "- {}", md(line));
        }
        let _ = writeln!(s, "\n## Files\n");
        for f in &self.files {
            let _ = writeln!(s, "- `{f}`");
        }
        s
    }
}
