//! The cut-sheet report: the design, its predicted performance, per-layer material use and mass, and the
//! build checklist; as `report.json` and a readable `report.md`.

use super::layers::LayerRow;
use super::template::Template;
use crate::book::{BuildBook, DesignFacts};
use crate::design::Design;
use crate::input::{ensure_finite, short_number, InputError};
use crate::markdown::{code, text as md};
use crate::pipeline::{Build, Label, MoldBand, MoldChoice, StockCount};
use crate::prediction::Prediction;
use serde::Serialize;
use std::fmt::Write;

/// The design as built, in file units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DesignSummary {
    pub name: String,
    pub file: String,
    pub process: String,
    pub length_mm: f64,
    pub extension_ratio: f64,
    pub base_width_mm: f64,
    pub width_ratio: f64,
    pub base_tab_mm: f64,
    pub piezo_length_mm: f64,
    pub extension_length_mm: f64,
    pub tip_width_mm: f64,
    pub pzt: String,
    pub pzt_thickness_mm: f64,
    pub ply: String,
    pub ply_thickness_mm: f64,
    pub layup_deg: Vec<f64>,
    pub bond: Option<String>,
    pub drive_mode: String,
}

/// The mold stack against the laminate: every part stands at most the tolerance proud of the mold layer
/// over it, with at most the tolerance of void under it, so the clamp presses on the parts (plates and
/// extension) and not on the Teflon.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MoldReport {
    /// Mold film thicknesses, bottom to top, mm.
    pub films_mm: Vec<f64>,
    /// What each mold layer holds, bottom to top: `lower plate`, `core` or `upper plate`.
    pub holds: Vec<String>,
    pub laminate_height_mm: f64,
    pub mold_height_mm: f64,
    /// Laminate height minus mold height, µm.
    pub difference_um: f64,
    /// How each part region sits in its cavity.
    pub press_fit: Vec<PressFitRow>,
    pub tolerance_um: f64,
    pub within_tolerance: bool,
    /// Set when a part is not pressed within the tolerance.
    pub warning: Option<String>,
}

/// One part region in its cavity, µm (rounded to 0.1 µm).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PressFitRow {
    /// `laminate` or `extension`.
    pub region: String,
    /// Gap under the part.
    pub void_below_um: f64,
    /// Height the part stands above the mold layer over it.
    pub proud_um: f64,
    pub within_tolerance: bool,
}

impl PressFitRow {
    /// `extension: 0.4 µm proud of the mold layer over it, 15 µm void under it`, and whether it is out
    /// of tolerance.
    pub fn text(&self) -> String {
        format!(
            "{}: {} µm proud of the mold layer over it, {} µm void under it{}",
            self.region,
            self.proud_um,
            self.void_below_um,
            if self.within_tolerance {
                ""
            } else {
                " (out of tolerance)"
            }
        )
    }
}

/// What a mold layer of `band` holds, as the report says it.
fn band_name(band: MoldBand) -> &'static str {
    match band {
        MoldBand::LowerPlate => "lower plate",
        MoldBand::Core => "core",
        MoldBand::UpperPlate => "upper plate",
    }
}

impl MoldReport {
    /// The report of mold `m` against `tolerance_mm` (a `nest` panel's press fit too).
    pub(crate) fn new(m: &MoldChoice, tolerance_mm: f64) -> MoldReport {
        // Rounded to 0.1 µm and 1 nm so float noise does not reach the report.
        let um = |v: f64| (v * 10.0).round() / 10.0;
        let mm = |v: f64| (v * 1e6).round() / 1e6;
        let difference_um = um(m.difference_um());
        let press_fit: Vec<PressFitRow> = m
            .fits
            .iter()
            .map(|f| PressFitRow {
                region: f.region.to_string(),
                void_below_um: um(f.void_below_mm * 1e3),
                proud_um: um(f.proud_mm * 1e3),
                within_tolerance: f.within(tolerance_mm),
            })
            .collect();
        let loose: Vec<String> = press_fit
            .iter()
            .filter(|f| !f.within_tolerance)
            .map(|f| {
                format!(
                    "the {} stands {} µm proud of its mold layer with {} µm void under it",
                    f.region, f.proud_um, f.void_below_um
                )
            })
            .collect();
        MoldReport {
            films_mm: m.films_mm.clone(),
            holds: m.bands.iter().map(|b| band_name(*b).to_string()).collect(),
            laminate_height_mm: mm(m.laminate_mm),
            mold_height_mm: mm(m.mold_mm),
            difference_um,
            press_fit,
            tolerance_um: um(tolerance_mm * 1e3),
            within_tolerance: m.within_tolerance,
            warning: (!m.within_tolerance).then(|| {
                let why = if m.films_mm.is_empty() {
                    "no stocked mold film is as thin as a plate".to_string()
                } else {
                    loose.join("; ")
                };
                format!(
                    "no combination of the stocked mold films presses every part within {} µm: {why}; \
                     stock another film thickness or accept a weaker bond",
                    um(tolerance_mm * 1e3),
                )
            }),
        }
    }
}

/// `report.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    pub design: DesignSummary,
    pub quantity: usize,
    pub predicted: Prediction,
    pub layers: Vec<LayerRow>,
    /// Σ area x thickness x density over the nominal part outlines of one actuator.
    pub mass_from_geometry_mg: f64,
    /// The template's PZT-to-CF edge margin: the plates are this much inside the passive edge, so
    /// narrower and shorter than the design the model predicts.
    pub pzt_edge_margin_mm: f64,
    /// Set when some passive parts carry no engraved label: no room off the bonded PZT zone.
    pub label_note: Option<String>,
    /// The ground tab the process added to a design that has no base tab (docs/cam.md §6).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ground_tab: Option<GroundTab>,
    pub clamp_panels: usize,
    /// Sheets of each stock the files are cut from (material, thickness, sheet size).
    pub stock_list: Vec<StockCount>,
    /// Part sheets with no room for a drawn stock label (docs/cam.md §3, "Stock labels").
    pub sheets_without_stock_label: usize,
    /// How the mold stack meets the laminate (docs/cam.md §1, "Mold layers").
    pub mold: MoldReport,
    pub stacking_order: Vec<String>,
    /// The build book: the process step by step (crate::book).
    pub build_book: BuildBook,
    pub placement_map: Vec<String>,
    pub files: Vec<String>,
    /// The drive's linkage laminate, when cut with the actuator (`--drive`, docs/cam.md §7).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub linkage: Option<LinkageSection>,
}

/// A ground tab the process added behind the PZT root: its length and the mass it adds, which the
/// predicted mass and the drawn parts include.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GroundTab {
    pub length_mm: f64,
    pub mass_mg: f64,
}

/// The linkage part of the report: the laminate, its panels, its build steps and how it compares with
/// a drive file that gives the transmission instead of its flexures.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinkageSection {
    pub drive_file: String,
    pub panels: usize,
    #[serde(flatten)]
    pub laminate: crate::linkage::LinkageReport,
    pub build_steps: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

impl LinkageSection {
    /// The section of a cut linkage on the pins of `template`'s clamp.
    pub fn new(cut: &super::linkage::LinkageCut, template: &Template) -> LinkageSection {
        let laminate = cut.laminate.report();
        LinkageSection {
            drive_file: cut.source.display().to_string(),
            panels: cut.panels,
            build_steps: crate::linkage::checklist::linkage_steps(
                &laminate,
                cut.panels,
                &crate::book::pin_fit_text(&template.clamp),
            ),
            laminate,
            note: cut.note.clone(),
        }
    }

    fn markdown(&self, s: &mut String) {
        let _ = writeln!(
            s,
            "\n## Linkage (docs/cam.md §7)\n\nThe transmission of `{}`, {} panel(s):\n\n```text\n{}```",
            self.drive_file,
            self.panels,
            self.laminate.table()
        );
        if let Some(n) = &self.note {
            let _ = writeln!(s, "\n**Note:** {n}.");
        }
        let _ = writeln!(s, "\n### Linkage build checklist\n");
        for (i, step) in self.build_steps.iter().enumerate() {
            let _ = writeln!(s, "{}. [ ] {step}", i + 1);
        }
    }
}

impl Report {
    /// Assemble the report; `files` is filled in by the caller once the formats are known.
    pub fn new(
        design: &Design,
        template: &Template,
        predicted: Prediction,
        layers: Vec<LayerRow>,
        built: &Build,
        ground_tab: Option<GroundTab>,
    ) -> Report {
        let p = &design.planform;
        let mass_from_geometry_mg = layers
            .iter()
            .map(|l| l.mass_per_actuator_mg)
            .fold(0.0, |a, b| a + b);
        let build_book = BuildBook::new(
            template,
            built,
            &[DesignFacts {
                name: design.name.clone(),
                base_tab_mm: p.base_tab * 1e3,
                ground_tab_added: ground_tab.is_some(),
                expected: crate::book::Expected::of(design, built.drawn_bond_mg(0)),
            }],
        );
        Report {
            design: DesignSummary {
                name: design.name.clone(),
                file: design.source.display().to_string(),
                process: template.name.clone(),
                length_mm: p.length * 1e3,
                extension_ratio: p.extension_ratio,
                base_width_mm: p.base_width * 1e3,
                width_ratio: p.width_ratio,
                base_tab_mm: p.base_tab * 1e3,
                piezo_length_mm: p.piezo_length() * 1e3,
                extension_length_mm: p.extension_length() * 1e3,
                tip_width_mm: p.tip_width() * 1e3,
                pzt: design.pzt.name.clone(),
                pzt_thickness_mm: design.pzt_thickness * 1e3,
                ply: design.ply.name.clone(),
                ply_thickness_mm: design.ply_thickness * 1e3,
                layup_deg: design.layup_deg.clone(),
                bond: design
                    .bond
                    .as_ref()
                    .map(|(m, t)| format!("{} {} mm", m.name, t * 1e3)),
                drive_mode: design.drive.mode.name().to_string(),
            },
            quantity: design.quantity,
            predicted,
            layers,
            mass_from_geometry_mg,
            pzt_edge_margin_mm: template.pzt_edge_margin_mm,
            label_note: Label::passive(built.geometry[0], &design.name, template)
                .note(design.quantity),
            ground_tab,
            clamp_panels: built.panels,
            stock_list: built.stock.clone(),
            sheets_without_stock_label: built.unlabelled_sheets,
            mold: MoldReport::new(&built.clamps[0].mold, template.mold_stock.tolerance_mm),
            stacking_order: built.clamps[0].stack.clone(),
            build_book,
            placement_map: built.placement_map.clone(),
            files: Vec::new(),
            linkage: None,
        }
    }

    /// Refuse a report with a number that is not finite (the prediction, the geometry's mass, a layer
    /// row), naming the design fields that produced it: no `null` in `report.json`.
    pub fn ensure_finite(&self, design: &Design) -> Result<(), InputError> {
        self.predicted.ensure_finite(design)?;
        let mut numbers = vec![(
            "mass_from_geometry_mg".to_string(),
            self.mass_from_geometry_mg,
        )];
        for l in &self.layers {
            numbers.push((format!("layers.{}.part_area_mm2", l.layer), l.part_area_mm2));
            numbers.push((
                format!("layers.{}.mass_per_actuator_mg", l.layer),
                l.mass_per_actuator_mg,
            ));
            if let Some(u) = l.utilization {
                numbers.push((format!("layers.{}.utilization", l.layer), u));
            }
        }
        let d = &self.design;
        ensure_finite(
            &design.source,
            "geometry, laminate",
            &format!(
                "length_mm = {}, base_width_mm = {}, width_ratio = {}, pzt_thickness_mm = {}, ply_thickness_mm = {}",
                short_number(d.length_mm),
                short_number(d.base_width_mm),
                short_number(d.width_ratio),
                short_number(d.pzt_thickness_mm),
                short_number(d.ply_thickness_mm)
            ),
            numbers.iter().map(|(n, v)| (n.as_str(), *v)),
        )
    }

    /// The readable report (Markdown, with the sheet SVGs as images).
    pub fn markdown(&self) -> String {
        let d = &self.design;
        let mut s = String::new();
        let _ = writeln!(s, "# Cut sheet: {} x {}\n", md(&d.name), self.quantity);
        let _ = writeln!(
            s,
            "Process {}; design file {}.\n",
            code(&d.process),
            code(&d.file)
        );
        let _ = writeln!(s, "![assembled actuator](preview-actuator.svg)\n");
        self.write_design(&mut s);
        self.write_layers(&mut s);
        let _ = writeln!(s, "\n## Stock list\n");
        let _ = write!(s, "{}", StockCount::markdown(&self.stock_list));
        if let Some(note) = crate::pipeline::unlabelled_note(self.sheets_without_stock_label) {
            let _ = writeln!(s, "\n{note}");
        }
        let _ = writeln!(s, "\n## Build book\n");
        let _ = writeln!(
            s,
            "Clamp stack, bottom to top ({} panel(s)): {}",
            self.clamp_panels,
            self.stacking_order
                .iter()
                .map(|l| md(l))
                .collect::<Vec<_>>()
                .join(" → ")
        );
        let _ = write!(s, "{}", self.build_book.markdown());
        if let Some(l) = &self.linkage {
            l.markdown(&mut s);
        }
        let _ = writeln!(
            s,
            "\nKerf values are starting points: calibrate them on a coupon of each material.\n"
        );
        let _ = writeln!(s, "## Placement map\n");
        for line in &self.placement_map {
            let _ = writeln!(s, "- {}", md(line));
        }
        let _ = writeln!(s, "\n## Files\n");
        for f in &self.files {
            if f.ends_with(".svg") {
                let _ = writeln!(s, "- `{f}`\n\n  ![{f}]({f})");
            } else {
                let _ = writeln!(s, "- `{f}`");
            }
        }
        s
    }

    /// The design section: its geometry and laminate, the predicted performance, the masses and
    /// what the process changes of the design.
    fn write_design(&self, s: &mut String) {
        let d = &self.design;
        let p = &self.predicted;
        let _ = writeln!(s, "## Design\n");
        let _ = writeln!(s, "| l_tot mm | l_r | l_p mm | l_ext mm | w_0 mm | w_r | w_tip mm | tab mm | t_p mm | layup | drive |");
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|");
        let layup = d
            .layup_deg
            .iter()
            .map(|a| a.to_string())
            .collect::<Vec<_>>()
            .join("/");
        let _ = writeln!(
            s,
            "| {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {} {} | {} |\n",
            d.length_mm, d.extension_ratio, d.piezo_length_mm, d.extension_length_mm, d.base_width_mm, d.width_ratio, d.tip_width_mm, d.base_tab_mm, d.pzt_thickness_mm, md(&d.ply), layup, d.drive_mode
        );
        let _ = writeln!(s, "## Predicted performance ({} model)\n", p.model);
        let _ = writeln!(s, "```\n{}```\n", p.table());
        let _ = writeln!(
            s,
            "Mass from the cut geometry: **{:.3} mg** per actuator; model: **{:.3} mg**.\n",
            self.mass_from_geometry_mg, p.mass_mg
        );
        if self.pzt_edge_margin_mm > 0.0 {
            let _ = writeln!(
                s,
                "The process template insets the PZT plates {} mm from the passive edge (sides and tip end), so they are smaller than the design the model predicts; the geometry mass counts the plates as cut.\n",
                self.pzt_edge_margin_mm
            );
        }
        if let Some(g) = &self.ground_tab {
            let _ = writeln!(
                s,
                "**Ground tab:** the design has no base tab, so the process adds {} mm of passive plies behind the PZT root, bare carbon for the ground wire (docs/cam.md §6): {:.2} mg, counted in both masses above.\n",
                g.length_mm, g.mass_mg
            );
        }
        if let Some(note) = &self.label_note {
            let _ = writeln!(s, "**Labels:** {note}.\n");
        }
    }

    /// The layers table, and the mold stack against the laminate.
    fn write_layers(&self, s: &mut String) {
        let _ = writeln!(s, "## Layers\n");
        let _ = writeln!(s, "| layer | material | thickness mm | density kg/m³ | part area mm² | parts/actuator | mass/actuator mg | sheets | utilisation |");
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
        for l in &self.layers {
            let util = l
                .utilization
                .map(|u| format!("{:.1}%", u * 100.0))
                .unwrap_or_else(|| "-".into());
            let _ = writeln!(
                s,
                "| {} | {} | {:.4} | {:.0} | {:.3} | {} | {:.3} | {} | {} |",
                md(&l.layer),
                md(&l.material),
                l.thickness_mm,
                l.density_kg_per_m3,
                l.part_area_mm2,
                l.parts_per_actuator,
                l.mass_per_actuator_mg,
                l.sheets,
                util
            );
        }
        let m = &self.mold;
        let films: Vec<String> = m
            .films_mm
            .iter()
            .zip(&m.holds)
            .enumerate()
            .map(|(k, (t, holds))| format!("mold-{} {t} ({holds})", k + 1))
            .collect();
        let _ = writeln!(
            s,
            "\nMold stack, bottom to top: {} mm = **{} mm** around a **{} mm** laminate: {} µm below it (tolerance {} µm).",
            films.join(" + "),
            m.mold_height_mm,
            m.laminate_height_mm,
            m.difference_um,
            m.tolerance_um
        );
        for f in &m.press_fit {
            let _ = writeln!(s, "- press fit, {}", f.text());
        }
        if let Some(w) = &m.warning {
            let _ = writeln!(s, "\n**Warning:** {w}.");
        }
    }
}
