//! The batch report: every sheet with the parts on it, nesting against the bounding-box baseline,
//! clamp panels, totals (and cost when the sheets have prices); as `nest-report.json` and a readable
//! `nest-report.md`.

use crate::book::BuildBook;
use crate::pipeline::{BaselineRow, StockCount};
use serde::Serialize;

mod assemble;
mod markdown;

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
    /// The drawing of the stock it is cut from, when it is a drawn sheet (a batch's `[[stock]]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stock: Option<String>,
    /// What is left of it to cut from later: a drawing a later batch names in `[[stock]]`
    /// (cut-through sheets; not PZT or roll stock).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub remnant: Option<super::remnant::RemnantRow>,
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
    /// How each part region sits in the panel's cavities, as `cut-sheet` reports it.
    pub press_fit: Vec<crate::cutsheet::report::PressFitRow>,
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
}
