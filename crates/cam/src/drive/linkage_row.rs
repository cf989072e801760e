//! The transmission in the drive report: the one-stage slider-crank's lengths, the two-stage linkage's
//! lengths with its flexures checked, or a ratio law, which no drawing can be made of.

use crate::input::fixed;
use crate::linkage::flexures::FlexureRow;
use serde::Serialize;

/// The linkage and the transmission's inputs (JSON `linkage`); the lengths are the slider-crank's, the
/// first stage's of a two-stage linkage, and 0 for a ratio law.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct LinkageRow {
    pub coupler_mm: f64,
    pub crank_mm: f64,
    pub offset_mm: f64,
    pub ratio_at_rest_deg_per_mm: f64,
    pub flexure_stiffness_uNm_per_rad: f64,
    pub link_inertia_mg_mm2: f64,
    /// The four-bar of a two-stage linkage, `[input, coupler, output]`, mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub four_bar_mm: Option<[f64; 3]>,
    /// A ratio law's ratio at rest and at the required stroke.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ratio_law: Option<RatioLawRow>,
    /// A two-stage linkage's flexures, each the shortest the template's film allows at its width, checked
    /// over the stroke as a drawn linkage's are (docs/physics.md §16.8).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flexures: Option<Vec<FlexureRow>>,
}

/// A ratio law in the report (JSON `linkage.ratio_law`): its ratio at rest and at the required stroke,
/// where the law's nonlinearity shows (docs/physics.md §12.4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RatioLawRow {
    pub at_rest_rad_per_m: f64,
    pub stroke_deg: f64,
    pub at_stroke_rad_per_m: f64,
}

impl LinkageRow {
    /// The summary's transmission lines: name, value and unit.
    pub fn summary(&self) -> Vec<(&'static str, String, &'static str)> {
        if let Some(law) = self.ratio_law {
            // Each value with its unit after it, as every other line of the summary.
            return vec![
                (
                    "transmission ratio at rest",
                    fixed(law.at_rest_rad_per_m, 0),
                    "rad/m",
                ),
                (
                    "  at the required stroke",
                    fixed(law.at_stroke_rad_per_m, 0),
                    "rad/m",
                ),
                ("  linkage", "none drawn (a ratio law)".into(), ""),
            ];
        }
        let lengths = format!(
            "{} / {}",
            fixed(self.coupler_mm, 3),
            fixed(self.crank_mm, 3)
        );
        let Some([a, b, c]) = self.four_bar_mm else {
            return vec![("linkage coupler / crank", lengths, "mm")];
        };
        let four_bar = format!("{} / {} / {}", fixed(a, 3), fixed(b, 3), fixed(c, 3));
        let ratio = self.ratio_at_rest_deg_per_mm.to_radians() * 1e3;
        vec![
            ("linkage coupler / crank", lengths, "mm"),
            ("  four-bar input / coupler / output", four_bar, "mm"),
            ("  ratio at rest, both stages", fixed(ratio, 0), "rad/m"),
        ]
    }

    /// The two-stage linkage's flexures as a table, if it has them.
    pub fn flexure_table(&self) -> Option<String> {
        self.flexures.as_ref().map(|rows| {
            format!(
                "\nthe two-stage linkage's flexures (docs/physics.md §16.8; not drawn):\n{}",
                crate::linkage::flexure_rows_table(rows)
            )
        })
    }
}
