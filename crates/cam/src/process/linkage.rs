//! The linkage laminate's materials and rules from a process template's `[linkage]` table: the carbon
//! layup of the links, the polyimide film of the flexures, the sheet adhesive, the laser kerf on the
//! laminate and the margins that keep adhesive off the hinges (docs/cam.md §7; drawn by `crate::linkage`).

use super::cure::CureStep;
use crate::input::limits::{
    DENSITY_KG_PER_M3, FATIGUE_STRAIN, FILM_MODULUS_GPA, FLEXURE_FRACTION, FLEXURE_THICKNESSES,
    GAP_MM, HOLE_DIAMETER_MM, KERF_MM, LAYER_THICKNESS_MM, PLY_ANGLE_DEG,
};
use crate::input::{InputError, TableReader};
use actuator_model::{Laminate, Layer, LayerRole, Material};

/// One sheet material of the laminate as the mass and the drawings need it.
#[derive(Debug, Clone, PartialEq)]
pub struct Sheet {
    /// Material as bought.
    pub material: String,
    /// Thickness, mm.
    pub thickness_mm: f64,
    /// Density, kg/m³.
    pub density_kg_per_m3: f64,
}

impl Sheet {
    /// Mass per area, mg/mm²: `t · ρ` (mm · kg/m³ = 1e-3 mg/mm²).
    pub fn areal_density_mg_per_mm2(&self) -> f64 {
        self.thickness_mm * self.density_kg_per_m3 * 1e-3
    }
}

/// A validated `[linkage]` table.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkageProcess {
    /// Laser kerf on every linkage layer, mm (one laser set-up for the laminate, so the pins and the
    /// gaps come out alike on every layer).
    pub kerf_mm: f64,
    /// One carbon layer of the links (two of them sandwich the film): the library ply times the layup.
    pub carbon: Sheet,
    /// Ply angles of one carbon layer from the link axis, deg.
    pub carbon_layup_deg: Vec<f64>,
    /// The library ply of the carbon and its thickness, m: a batch cuts the carbon on the prepreg
    /// sheets of a design laid up alike.
    pub carbon_ply: (String, f64),
    /// The flexure film.
    pub film: Sheet,
    /// The film's Young's modulus, Pa.
    pub film_modulus: f64,
    /// Largest bending strain the film takes cycle after cycle.
    pub film_fatigue_strain: f64,
    /// Sheet adhesive between each carbon layer and the film.
    pub adhesive: Sheet,
    /// How far the film reaches past each gap onto the links, mm.
    pub film_margin_mm: f64,
    /// How far the adhesive stops short of each gap, mm.
    pub adhesive_cutback_mm: f64,
    /// How far the gap slots and windows run past the linkage's sides, so the release cut crosses them
    /// cleanly, mm.
    pub slot_overrun_mm: f64,
    /// Tab that mounts the linkage on the airframe (with its hole), mm along the links.
    pub frame_tab_mm: f64,
    /// Tab bonded onto the actuator's extension end, mm along the links.
    pub tip_tab_mm: f64,
    /// Mounting hole in the airframe tab, diameter mm.
    pub hole_diameter_mm: f64,
    /// Gap between linkages on a panel, mm.
    pub spacing_mm: f64,
    /// Flexure width when the drive file gives none, mm.
    pub flexure_width_mm: f64,
    /// Shortest flexure, in film thicknesses: shorter gaps shear more than they bend.
    pub min_length_thicknesses: f64,
    /// Longest flexure as a share of the shorter link beside it: a longer gap is no pivot.
    pub max_length_fraction: f64,
    /// The laminate's cure on the clamp's pins (`[linkage.cure]`), if the template gives it.
    pub cure: Option<CureStep>,
    /// The plate of the jig the nested coupons stack, cure and release on (`jig_material`,
    /// `jig_thickness_mm`): the dowels stand in it at each coupon's pin pattern.
    pub jig: JigPlate,
}

/// The jig plate as bought.
#[derive(Debug, Clone, PartialEq)]
pub struct JigPlate {
    /// Material as bought.
    pub material: String,
    /// Thickness, mm.
    pub thickness_mm: f64,
}

/// The stretching-bending coupling of one cured carbon layer of `layup` (deg) in `ply`: `Some((B11,
/// max |B_ij|))`, N, when the coupling matrix `B = ½ Σ Q̄_k (z_k² − z_{k−1}²)` (classical laminate theory,
/// Jones, *Mechanics of Composite Materials*, eq. 4.28) is not zero, i.e. above 1e-9 of `A_max · h`,
/// the round-off of a layup symmetric about its mid-plane; `None` for a flat-curing layup.
pub fn coupling(ply: &Material, layup: &[f64]) -> Option<(f64, f64)> {
    let thickness = ply.ply_thickness.unwrap_or(0.0);
    let layers = layup
        .iter()
        .map(|&angle_deg| Layer {
            material: ply.clone(),
            thickness,
            angle_deg,
            role: LayerRole::Passive,
        })
        .collect();
    let laminate = Laminate::new(layers).ok()?;
    let abd = laminate.abd();
    let b = abd.fixed_view::<3, 3>(0, 3);
    let a = abd.fixed_view::<3, 3>(0, 0);
    let largest = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs())) * laminate.thickness();
    (largest > 1e-9 * scale).then_some((b[(0, 0)], largest))
}

impl LinkageProcess {
    /// Read `[linkage]`; the caller finishes the template.
    pub fn read(t: &TableReader<'_>) -> Result<LinkageProcess, InputError> {
        let ply_name = t.string("carbon_ply", "a ply material from the library")?;
        let ply = Material::builtin(ply_name)
            .filter(|m| m.ply_thickness.is_some())
            .ok_or_else(|| {
                InputError::invalid(
                    t.file(),
                    &t.path("carbon_ply"),
                    format!("{ply_name:?}"),
                    "expected a library material with a standard ply (CF-thesis, M60J-epoxy, S2-glass-epoxy)",
                )
            })?;
        let layup = t.numbers_in("carbon_layup_deg", PLY_ANGLE_DEG, 1, 12)?;
        if let Some((b11, largest)) = coupling(&ply, &layup) {
            let angles: Vec<String> = layup.iter().map(|a| a.to_string()).collect();
            return Err(InputError::invalid(
                t.file(),
                &t.path("carbon_layup_deg"),
                format!("[{}]", angles.join(", ")),
                format!(
                    "a layup symmetric about its mid-plane, e.g. [0, 90, 0]: this one couples stretching and bending (CLT B11 = {b11:.0} N, largest |B| {largest:.0} N), so the cured layer warps as it cools, and the keyed pins lay both carbon layers the same way up"
                ),
            ));
        }
        let ply_mm = ply.ply_thickness.unwrap_or(0.0) * 1e3;
        let carbon = Sheet {
            material: format!("{} ({} plies)", ply.name, layup.len()),
            thickness_mm: ply_mm * layup.len() as f64,
            density_kg_per_m3: ply.density,
        };
        let sheet = |prefix: &str| -> Result<Sheet, InputError> {
            Ok(Sheet {
                material: t
                    .string(&format!("{prefix}_material"), "a material description")?
                    .to_string(),
                thickness_mm: t.number_in(&format!("{prefix}_thickness_mm"), LAYER_THICKNESS_MM)?,
                density_kg_per_m3: t
                    .number_in(&format!("{prefix}_density_kg_per_m3"), DENSITY_KG_PER_M3)?,
            })
        };
        let process = LinkageProcess {
            kerf_mm: t.number_in("kerf_mm", KERF_MM)?,
            carbon,
            carbon_layup_deg: layup,
            carbon_ply: (ply.name.clone(), ply.ply_thickness.unwrap_or(0.0)),
            film: sheet("film")?,
            film_modulus: t.number_in("film_modulus_GPa", FILM_MODULUS_GPA)? * 1e9,
            film_fatigue_strain: t.number_in("film_fatigue_strain", FATIGUE_STRAIN)?,
            adhesive: sheet("adhesive")?,
            film_margin_mm: t.number_in("film_margin_mm", GAP_MM)?,
            adhesive_cutback_mm: t.number_in("adhesive_cutback_mm", GAP_MM)?,
            slot_overrun_mm: t.number_in("slot_overrun_mm", GAP_MM)?,
            frame_tab_mm: t.number_in("frame_tab_mm", GAP_MM)?,
            tip_tab_mm: t.number_in("tip_tab_mm", GAP_MM)?,
            hole_diameter_mm: t.number_in("hole_diameter_mm", HOLE_DIAMETER_MM)?,
            spacing_mm: t.number_in("spacing_mm", GAP_MM)?,
            flexure_width_mm: t.number_in("flexure_width_mm", GAP_MM)?,
            min_length_thicknesses: t.number_in("min_length_thicknesses", FLEXURE_THICKNESSES)?,
            max_length_fraction: t.number_in("max_length_fraction", FLEXURE_FRACTION)?,
            cure: CureStep::optional(t, "cure")?,
            jig: JigPlate {
                material: t
                    .string("jig_material", "a material description")?
                    .to_string(),
                thickness_mm: t.number_in("jig_thickness_mm", LAYER_THICKNESS_MM)?,
            },
        };
        // The film must be bonded beyond the adhesive's cut-back, or the flexure is loose film.
        if process.film_margin_mm < process.adhesive_cutback_mm + 2.0 * process.kerf_mm {
            return Err(InputError::invalid(
                t.file(),
                &t.path("film_margin_mm"),
                process.film_margin_mm,
                format!(
                    "at least adhesive_cutback_mm + 2 kerfs = {} mm, so the film is bonded to the links past the cut-back",
                    process.adhesive_cutback_mm + 2.0 * process.kerf_mm
                ),
            ));
        }
        Ok(process)
    }
}
