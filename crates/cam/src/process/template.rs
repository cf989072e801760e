//! Process templates (`templates/*.toml`): data that names each layer of a manufacturing process, its
//! material, sheet, kerf and clearances, the clamp panel and the cure recipe. The two thesis methods are
//! embedded in the binary; any other template is read from a path.

use super::features::FeatureMap;
use crate::drawing::palette::Palette;
use crate::input::{parse_toml, read_toml, InputError, TableReader};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A stock sheet of a cut material.
#[derive(Debug, Clone, PartialEq)]
pub struct SheetSpec {
    /// Material as bought.
    pub material: String,
    /// Sheet width, mm.
    pub width_mm: f64,
    /// Sheet height, mm.
    pub height_mm: f64,
    /// Laser kerf on this material, mm.
    pub kerf_mm: f64,
    /// Gap between parts on top of the kerf, mm; also to the sheet edge unless `edge_gap_mm` is given.
    pub spacing_mm: f64,
    /// Gap from the parts to the sheet edge on top of the kerf, mm, when it differs from `spacing_mm`
    /// (the edge gap depends on the fixture, the part gap on the kerf and heat-affected zone); `None`
    /// keeps `spacing_mm`. Cut-through layers only: the PZT plates keep `edge_margin_mm`.
    pub edge_gap_mm: Option<f64>,
    /// Unusable border of the sheet (chipped PZT edges), mm.
    pub edge_margin_mm: f64,
    /// Narrowest strip a score line may leave to be snapped off, in sheet thicknesses (PZT sheets:
    /// `[layers.pzt] min_snap_strip_thicknesses`, docs/cam.md §4 "Snappable strips"); 0 for sheets
    /// that are cut through.
    pub min_snap_strip_thicknesses: f64,
    /// How far a score line that ends on the sheet edge runs past it, mm (`[layers.pzt]
    /// score_overrun_mm`, default [`DEFAULT_SCORE_OVERRUN_MM`]); 0 for sheets that are cut through.
    pub score_overrun_mm: f64,
    /// Sheets in stock, if limited.
    pub stock: Option<usize>,
    /// Price of one sheet (any currency), if known: reports show material cost only when it is.
    pub price_per_sheet: Option<f64>,
    /// Roll stock: `width_mm` wide, as long as the parts need (`nest` nests a strip and reports its
    /// used length; `height_mm` is then not used). Set by a batch's `[sheets]` (`strip = true`).
    pub roll: bool,
    /// Where the sheet's size was written.
    pub origin: SheetOrigin,
    /// Sheets of this stock given as drawings (remnants, sheets with flaws; a batch's `[[stock]]`),
    /// nested on before whole sheets; none in a template.
    pub drawn: Vec<super::DrawnSheet>,
}

impl SheetSpec {
    /// Gap from the parts to the sheet edge on top of the kerf, mm ([`SheetSpec::edge_gap_mm`]).
    pub fn edge_gap(&self) -> f64 {
        self.edge_gap_mm.unwrap_or(self.spacing_mm)
    }

    /// How much farther from the sheet edge than from each other the parts stay, mm (negative:
    /// nearer). The packers keep one gap to everything; they pack on the sheet shrunk by this on
    /// every side ([`SheetSpec::packing_room`]) and the layout is moved back by it.
    pub fn edge_shift_mm(&self) -> f64 {
        self.edge_gap() - self.spacing_mm
    }

    /// The sheet the packers work on, width and height, mm: this one shrunk by
    /// [`SheetSpec::edge_shift_mm`] on every side (a roll only across its width).
    pub fn packing_room(&self) -> [f64; 2] {
        let d = 2.0 * self.edge_shift_mm();
        if self.roll {
            [self.width_mm - d, f64::INFINITY]
        } else {
            [self.width_mm - d, self.height_mm - d]
        }
    }

    /// Whether `outline` fits an empty sheet of this stock at one of `rotations_deg` as the nester
    /// places a cut part: kerf + edge gap to every edge, a roll unbounded in length. The readers of
    /// extra parts refuse on it before any nesting, naming the drawing, so that what passes them also
    /// passes the nester; on a roll, all but a part within hundredths of a millimetre of its width,
    /// which the nester refuses with the width it needs ([`cam_nest::fits_empty_sheet`]).
    pub fn empty_sheet_fit(
        &self,
        outline: &[[f64; 2]],
        rotations_deg: &[f64],
    ) -> cam_nest::EmptySheetFit {
        let [width_mm, height_mm] = self.packing_room();
        let fit = cam_nest::fits_empty_sheet(
            outline,
            rotations_deg,
            width_mm,
            height_mm,
            self.kerf_mm + self.spacing_mm,
        );
        cam_nest::EmptySheetFit {
            edge_gap_mm: fit.edge_gap_mm + self.edge_shift_mm(),
            ..fit
        }
    }
}

/// Where a sheet's size was written (a template's `[layers.NAME]` or a batch's `[sheets.NAME]`), so a
/// layout that does not fit names the file and the field to change.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SheetOrigin {
    /// The template or batch file.
    pub file: PathBuf,
    /// Dotted path of the width field as written (`layers.pzt.sheet_width_mm`).
    pub width_field: String,
    /// Dotted path of the height field as written.
    pub height_field: String,
}

impl SheetOrigin {
    /// The sheet fields `width_key` and `height_key` of the table `t`.
    pub fn of(t: &TableReader<'_>, width_key: &str, height_key: &str) -> SheetOrigin {
        SheetOrigin {
            file: t.file().to_path_buf(),
            width_field: t.path(width_key),
            height_field: t.path(height_key),
        }
    }
}

/// A clamp layer (mold, felt, Teflon, bleeder): material, thickness and kerf; cut on the clamp panel.
#[derive(Debug, Clone, PartialEq)]
pub struct ClampLayerSpec {
    /// Material.
    pub material: String,
    /// Thickness, mm.
    pub thickness_mm: f64,
    /// Density, kg/m³.
    pub density_kg_per_m3: f64,
    /// Kerf, mm.
    pub kerf_mm: f64,
}

/// Mold films a lab stocks (`[layers.mold] stock_thicknesses_mm`, default the one `thickness_mm`) and
/// the press-fit tolerance (`height_tolerance_mm`): every part stands at most this far proud of the
/// mold film over it, with at most this much void under it (docs/cam.md §1, "Mold layers").
#[derive(Debug, Clone, PartialEq)]
pub struct MoldStock {
    /// Film thicknesses in stock, mm.
    pub films_mm: Vec<f64>,
    /// Largest allowed height of a part above the film over it, and void under it, mm.
    pub tolerance_mm: f64,
}

pub use super::cure::{Cure, CureStep};

/// Default inset of a Pyralux bond part from the PZT plate edge, mm (docs/cam.md §1, "Method 1 bond
/// parts"): a starting point, to be set from the squeeze-out a lab sees on its first clamp.
pub const DEFAULT_BOND_INSET_MM: f64 = 0.15;

/// Default ground tab, mm (docs/cam.md §6, "Ground access"): the passive plies run this far behind
/// the PZT root of a design with no base tab, bare carbon for the ground wire's drop of silver epoxy
/// (about 1 mm across) with room for the engraved label.
pub const DEFAULT_GROUND_TAB_MM: f64 = 1.5;

/// Default run of a score line past the sheet edge, mm: docs/cam.md §4, "Scoring the ceramic".
pub const DEFAULT_SCORE_OVERRUN_MM: f64 = 0.5;

/// Default narrowest snappable PZT strip, in sheet thicknesses: docs/cam.md §4, "Snappable strips".
pub const DEFAULT_SNAP_STRIP_THICKNESSES: f64 = 5.0;

/// Default mold height tolerance, mm: docs/cam.md §1.
pub const DEFAULT_MOLD_TOLERANCE_MM: f64 = 0.025;

/// Pyralux bond layers of method 1.
#[derive(Debug, Clone, PartialEq)]
pub struct BondSpec {
    /// Sheet the bond parts are cut from.
    pub sheet: SheetSpec,
    /// Material name in the model library (for the predicted mass).
    pub bond_material: String,
    /// Film thickness, mm.
    pub thickness_mm: f64,
    /// Density, kg/m³.
    pub density_kg_per_m3: f64,
    /// Via for silver epoxy, diameter mm.
    pub via_diameter_mm: f64,
    /// Via centre as a fraction of the plate length from the base.
    pub via_position: f64,
    /// How far each bond part's edge sits inside the PZT plate's, mm: room for the adhesive that the
    /// clamp squeezes out, so it does not bridge the plate's electrode to the carbon (thesis §4.9.3,
    /// docs/cam.md §1).
    pub inset_mm: f64,
}

/// The clamp panel every clamp layer shares.
#[derive(Debug, Clone, PartialEq)]
pub struct ClampSpec {
    /// Panel width, mm.
    pub panel_width_mm: f64,
    /// Panel height, mm.
    pub panel_height_mm: f64,
    /// Frame border around the cavity region, mm.
    pub border_mm: f64,
    /// Gap between a part and its mold cavity wall, mm.
    pub cavity_clearance_mm: f64,
    /// Wall between neighbouring cavities, mm.
    pub cavity_spacing_mm: f64,
    /// Registration pin hole radius, mm.
    pub pin_radius_mm: f64,
    /// Pin centre distance from the panel edges, mm.
    pub pin_inset_mm: f64,
    /// Diameter of the dowels the pins are, mm (`dowel_diameter_mm`), when the template gives it: the
    /// book states the fit in the pin holes.
    pub dowel_diameter_mm: Option<f64>,
    /// Fiducial crosshair size, mm.
    pub fiducial_size_mm: f64,
    /// Stacking-order window width, mm.
    pub window_width_mm: f64,
    /// Stacking-order window height, mm.
    pub window_height_mm: f64,
    /// Layers bottom to top; `mold` stands for all mold layers.
    pub stack: Vec<String>,
}

/// How the passive layer is cut.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PassiveCut {
    /// One outline per actuator from the laid-up stack.
    Stack,
    /// Each ply on its own sheet, turned so its fibres run at the ply angle.
    PlyByPly,
}

/// A validated process template.
#[derive(Debug, Clone, PartialEq)]
pub struct Template {
    /// The template file (a built-in one is named `templates/NAME.toml (built in)`): refusals of a
    /// template value name it.
    pub source: PathBuf,
    /// Template name.
    pub name: String,
    /// One-line description.
    pub description: String,
    /// How the passive layer is cut.
    pub passive_cut: PassiveCut,
    /// Engraved label text height, mm.
    pub label_height_mm: f64,
    /// The cure in the clamp, and the passive pre-cure of method 1.
    pub cure: Cure,
    /// Clamp panel.
    pub clamp: ClampSpec,
    /// PZT sheets.
    pub pzt: SheetSpec,
    /// Passive (CF) sheets.
    pub passive: SheetSpec,
    /// Bond layers (method 1 only).
    pub bond: Option<BondSpec>,
    /// Mold layers.
    pub mold: ClampLayerSpec,
    /// Mold films the lab stocks and how far below the laminate the mold top may sit.
    pub mold_stock: MoldStock,
    /// Other clamp layers by name (felt, teflon-cover, …).
    pub covers: BTreeMap<String, ClampLayerSpec>,
    /// Colour of each laser operation in the files (`[operations]`; default docs/cam.md §3).
    pub palette: Palette,
    /// Operation of each drawn feature (`[features]`; default the builders' long-standing mapping).
    pub features: FeatureMap,
    /// PZT-to-CF edge margin: the PZT plates' sides and tip end sit this far inside the passive part's
    /// edge, mm (`[layers.pzt] passive_edge_margin_mm`, default 0).
    pub pzt_edge_margin_mm: f64,
    /// The flexure linkage laminate (`[linkage]`), if the process cuts one.
    pub linkage: Option<super::linkage::LinkageProcess>,
    /// Laser settings by layer and operation (`[laser.LAYER]`), as far as the template gives them.
    pub laser: super::laser::LaserSettings,
    /// The base tab the process gives a design that has none, mm (`[layers.passive] ground_tab_mm`,
    /// default `DEFAULT_GROUND_TAB_MM`; 0 adds none): the wiring needs bare carbon to reach.
    pub ground_tab_mm: f64,
}

pub(super) const METHOD_1: &str = include_str!("../../../../templates/method-1.toml");
pub(super) const METHOD_2: &str = include_str!("../../../../templates/method-2.toml");

impl Template {
    /// The template file a design's `process` names, relative to the design file; `None` for the built-in
    /// processes. (Also an input the output writer must never overwrite.)
    pub fn file_of(process: &str, design_file: &Path) -> Option<PathBuf> {
        process
            .ends_with(".toml")
            .then(|| design_file.parent().unwrap_or(Path::new(".")).join(process))
    }

    /// `method-1`, `method-2`, or a template file (relative paths resolved against the design's folder).
    pub fn resolve(process: &str, design_file: &Path) -> Result<Template, InputError> {
        match process {
            "method-1" => Self::parse(Path::new("templates/method-1.toml (built in)"), METHOD_1),
            "method-2" => Self::parse(Path::new("templates/method-2.toml (built in)"), METHOD_2),
            other if other.ends_with(".toml") => {
                let path = Self::file_of(other, design_file).unwrap_or_default();
                let table = read_toml(&path)?;
                Self::from_table(&path, &table)
            }
            other => Err(InputError::invalid(
                design_file,
                "process",
                format!("{other:?}"),
                "expected \"method-1\", \"method-2\" or a path to a template .toml",
            )),
        }
    }

    fn parse(name: &Path, text: &str) -> Result<Template, InputError> {
        let table = parse_toml(name, text)?;
        Self::from_table(name, &table)
    }

    /// Set every layer's kerf (the `--kerf-mm` override).
    pub fn override_kerf(&mut self, kerf_mm: f64) {
        self.pzt.kerf_mm = kerf_mm;
        self.passive.kerf_mm = kerf_mm;
        if let Some(b) = &mut self.bond {
            b.sheet.kerf_mm = kerf_mm;
        }
        self.mold.kerf_mm = kerf_mm;
        for c in self.covers.values_mut() {
            c.kerf_mm = kerf_mm;
        }
        if let Some(l) = &mut self.linkage {
            l.kerf_mm = kerf_mm;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shipped_carbon_layup_cures_flat_and_a_0_90_pair_is_refused() {
        // Classical laminate theory (Jones, Mechanics of Composite Materials, eq. 4.28): two plies of
        // thickness h at 0° (z from -h to 0) and 90° (0 to h) give B11 = ½ h² (Q22 - Q11), with
        // Q11 = E1 / (1 - ν12 ν21), Q22 = E2 / (1 - ν12 ν21), ν21 = ν12 E2 / E1; `actuator-cam laminate
        // --layup 0/90` prints -792.17 N for CF-thesis.
        let ply = actuator_model::Material::builtin("CF-thesis").unwrap();
        let h = ply.ply_thickness.unwrap();
        let nu21 = ply.nu12 * ply.e2 / ply.e1;
        let d = 1.0 - ply.nu12 * nu21;
        let closed = 0.5 * h * h * (ply.e2 - ply.e1) / d;
        let (b11, _) = crate::process::linkage::coupling(&ply, &[0.0, 90.0]).unwrap();
        assert!(
            (b11 - closed).abs() < 1e-9 * closed.abs(),
            "{b11} vs {closed}"
        );
        assert!((b11 + 792.17).abs() < 0.01, "{b11}");
        // Every cured layup a shipped template names is symmetric: no coupling.
        for (name, text) in [("method-1", METHOD_1), ("method-2", METHOD_2)] {
            let t = Template::resolve(name, Path::new("d.toml")).unwrap();
            let l = t.linkage.unwrap();
            assert_eq!(
                crate::process::linkage::coupling(&ply, &l.carbon_layup_deg),
                None,
                "{name}"
            );
            // The same template with a 0/90 pair is refused in one line naming the field and B11.
            let pair = text.replacen(
                "carbon_layup_deg = [0, 90, 0]",
                "carbon_layup_deg = [0, 90]",
                1,
            );
            assert_ne!(pair, text);
            let path = Path::new("my-process.toml");
            let table = crate::input::parse_toml(path, &pair).unwrap();
            let err = Template::from_table(path, &table).unwrap_err().to_string();
            assert!(
                err.starts_with(
                    "my-process.toml: linkage.carbon_layup_deg = [0, 90]: a layup symmetric"
                ) && err.contains("B11 = -792 N")
                    && !err.contains('\n'),
                "{err}"
            );
        }
    }

    #[test]
    fn built_in_templates_load() {
        let m1 = Template::resolve("method-1", Path::new("d.toml")).unwrap();
        let m2 = Template::resolve("method-2", Path::new("d.toml")).unwrap();
        assert!(m1.bond.is_some() && m2.bond.is_none());
        assert_eq!(m2.pzt.width_mm, 72.4);
        assert!(m2.covers.contains_key("bleeder") && !m1.covers.contains_key("bleeder"));
        assert!(Template::resolve("method-3", Path::new("d.toml")).is_err());
        // The shipped [features] tables spell out the defaults.
        assert_eq!(m1.features, FeatureMap::default());
        assert_eq!(m2.features, FeatureMap::default());
        // Both state the narrowest snappable PZT strip, and only on the PZT sheet.
        for m in [&m1, &m2] {
            assert_eq!(m.pzt.min_snap_strip_thicknesses, 5.0);
            assert_eq!(m.passive.min_snap_strip_thicknesses, 0.0);
        }
    }

    #[test]
    fn the_snappable_strip_is_at_least_one_thickness_and_defaults_to_five() {
        let path = Path::new("my-process.toml");
        let read = |text: &str| Template::from_table(path, &parse_toml(path, text).unwrap());
        let thin = METHOD_2.replacen(
            "min_snap_strip_thicknesses = 5.0",
            "min_snap_strip_thicknesses = 0.5",
            1,
        );
        assert_ne!(thin, METHOD_2);
        assert_eq!(
            read(&thin).unwrap_err().to_string(),
            "my-process.toml: layers.pzt.min_snap_strip_thicknesses = 0.5: outside the allowed range [1, 50] thicknesses"
        );
        let unstated = METHOD_2.replacen("min_snap_strip_thicknesses = 5.0", "", 1);
        assert_eq!(
            read(&unstated).unwrap().pzt.min_snap_strip_thicknesses,
            DEFAULT_SNAP_STRIP_THICKNESSES
        );
    }

    #[test]
    fn a_bad_field_is_one_line_naming_file_field_value_and_range() {
        let text = METHOD_2.replacen("kerf_mm = 0.03", "kerf_mm = 3", 1);
        assert_ne!(text, METHOD_2);
        let path = Path::new("my-process.toml");
        let err = Template::from_table(path, &parse_toml(path, &text).unwrap())
            .unwrap_err()
            .to_string();
        assert_eq!(
            err,
            "my-process.toml: layers.pzt.kerf_mm = 3: outside the allowed range [0, 2] mm"
        );
    }

    #[test]
    fn the_edge_gap_defaults_to_the_spacing_and_is_refused_on_pzt() {
        let path = Path::new("my-process.toml");
        let read = |text: &str| Template::from_table(path, &parse_toml(path, text).unwrap());
        let m2 = read(METHOD_2).unwrap();
        assert_eq!(m2.passive.edge_gap(), m2.passive.spacing_mm);
        assert_eq!(m2.passive.edge_shift_mm(), 0.0);
        let wide = METHOD_2.replacen(
            "# gap between parts (spacing_mm, the default): edge_gap_mm",
            "edge_gap_mm",
            1,
        );
        assert_ne!(wide, METHOD_2);
        let passive = read(&wide).unwrap().passive;
        assert_eq!((passive.edge_gap(), passive.spacing_mm), (2.0, 0.5));
        // The packers work on the sheet shrunk by 1.5 mm on every side.
        assert_eq!(passive.packing_room(), [147.0, 147.0]);
        let negative = wide.replacen("edge_gap_mm = 2.0", "edge_gap_mm = -2", 1);
        assert_eq!(
            read(&negative).unwrap_err().to_string(),
            "my-process.toml: layers.passive.edge_gap_mm = -2: outside the allowed range [0, 50] mm"
        );
        let on_pzt = METHOD_2.replacen(
            "edge_margin_mm = 0.3",
            "edge_margin_mm = 0.3\nedge_gap_mm = 1",
            1,
        );
        assert!(read(&on_pzt)
            .unwrap_err()
            .to_string()
            .contains("layers.pzt.edge_gap_mm"));
    }
}
