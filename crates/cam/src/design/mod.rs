//! The design file (`design.toml`): one place that names each field, its unit and its allowed range, and
//! one conversion from the parsed file into a validated [`Design`] that later code trusts.

mod geometry;
pub mod layup;
mod materials;
pub mod transmission;

pub use geometry::check_planform;
pub use materials::{material_from_table, resolve_material};

use crate::design::transmission::TransmissionSpec;
use crate::input::library::{read_drive_bias, read_drive_mode, BiasedSignal};
use crate::input::limits::{
    BASE_TAB_MM, BASE_WIDTH_MM, EXTENSION_RATIO, FIELD_V_PER_MM, LENGTH_MM, MAX_PLIES,
    MAX_QUANTITY, PLY_ANGLE_DEG, PLY_THICKNESS_MM, PZT_THICKNESS_MM, STROKE_DEG, VOLTAGE_V,
    WIDTH_RATIO,
};
use crate::input::{read_toml, short_number, InputError, TableReader};
use actuator_model::{Drive, Laminate, Material, ModelError, Planform};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A validated actuator design, SI inside.
#[derive(Debug, Clone, PartialEq)]
pub struct Design {
    /// Name used in labels and reports.
    pub name: String,
    /// Actuators to build.
    pub quantity: usize,
    /// Process template: `method-1`, `method-2` or a path (resolved against the design file).
    pub process: String,
    /// Outline.
    pub planform: Planform,
    /// PZT material.
    pub pzt: Material,
    /// One PZT plate, m.
    pub pzt_thickness: f64,
    /// Passive ply material.
    pub ply: Material,
    /// One passive ply, m.
    pub ply_thickness: f64,
    /// Ply angles, bottom to top, degrees.
    pub layup_deg: Vec<f64>,
    /// Optional bond layer between each PZT plate and the passive core: material and thickness (m).
    pub bond: Option<(Material, f64)>,
    /// Drive mode and field.
    pub drive: Drive,
    /// The transmission cut with it (`[transmission]`, docs/cam.md §7), if the file gives one.
    pub transmission: Option<TransmissionSpec>,
    /// The file it came from (for relative paths and messages).
    pub source: PathBuf,
}

impl Design {
    /// Read and validate a design file.
    pub fn load(path: &Path) -> Result<Design, InputError> {
        let table = read_toml(path)?;
        Self::from_table(path, &table)
    }

    /// Validate a parsed design file.
    pub fn from_table(path: &Path, table: &toml::Table) -> Result<Design, InputError> {
        let root = TableReader::new(path, "", table);
        let name = root.name("name", "a design name (text)")?;
        let quantity = root
            .optional_count("quantity", 1, MAX_QUANTITY)?
            .unwrap_or(1);
        let process = root
            .optional_string("process", "\"method-1\", \"method-2\" or a template path")?
            .unwrap_or("method-2")
            .to_string();
        let materials = read_materials(&root)?;

        let planform = read_planform(path, &root)?;

        let l = root.table("laminate")?;
        let pzt_name = l.string("pzt", "a PZT material name")?;
        let pzt = resolve_material(path, &l.path("pzt"), pzt_name, &materials)?;
        if !pzt.is_piezoelectric() {
            return Err(InputError::invalid(
                path,
                &l.path("pzt"),
                pzt_name,
                "expected a piezoelectric material (d31 != 0)",
            ));
        }
        let pzt_thickness = l.number_in("pzt_thickness_mm", PZT_THICKNESS_MM)? * 1e-3;
        let ply_name = l.string("ply", "a passive ply material name")?;
        let ply = resolve_material(path, &l.path("ply"), ply_name, &materials)?;
        let ply_thickness = match l.optional_number_in("ply_thickness_mm", PLY_THICKNESS_MM)? {
            Some(t) => t * 1e-3,
            None => ply.ply_thickness.ok_or_else(|| {
                InputError::missing(
                    path,
                    &l.path("ply_thickness_mm"),
                    &format!("a ply thickness: {ply_name} has no standard ply, {PLY_THICKNESS_MM}"),
                )
            })?,
        };
        let layup_deg = l.numbers_in("layup_deg", PLY_ANGLE_DEG, 1, MAX_PLIES)?;
        let bond = read_bond(path, &l, &materials)?;
        l.finish()?;

        let drive = read_drive(path, &root, pzt_thickness)?;
        // The drive file's `[transmission]`, with the stroke its linkage is built for, which a drive
        // file gives at its top level.
        let transmission = match root.optional_table("transmission")? {
            Some(t) => {
                let stroke = t.number_in("stroke_deg", STROKE_DEG)?.to_radians();
                let spec = TransmissionSpec::read(&t, stroke)?;
                t.finish()?;
                Some(spec)
            }
            None => None,
        };
        root.finish()?;

        Ok(Design {
            name,
            quantity,
            process,
            planform,
            pzt,
            pzt_thickness,
            ply,
            ply_thickness,
            layup_deg,
            bond,
            drive,
            transmission,
            source: path.to_path_buf(),
        })
    }

    /// The laminate stack of this design.
    pub fn laminate(&self) -> Result<Laminate, ModelError> {
        Laminate::bimorph(
            &self.pzt,
            self.pzt_thickness,
            &self.ply,
            self.ply_thickness,
            &self.layup_deg,
            self.bond.as_ref().map(|(m, t)| (m, *t)),
        )
    }

    /// Layup as `0/90/0`.
    pub fn layup_text(&self) -> String {
        layup::layup_text(&self.layup_deg)
    }
}
/// `[geometry]`: the planform, mm in the file, m inside.
fn read_planform(path: &Path, root: &TableReader<'_>) -> Result<Planform, InputError> {
    let g = root.table("geometry")?;
    let length = g.number_in("length_mm", LENGTH_MM)?;
    let extension_ratio = g.number_in("extension_ratio", EXTENSION_RATIO)?;
    let base_width = g.number_in("base_width_mm", BASE_WIDTH_MM)?;
    let width_ratio = g.number_in("width_ratio", WIDTH_RATIO)?;
    let base_tab = g
        .optional_number_in("base_tab_mm", BASE_TAB_MM)?
        .unwrap_or(0.0);
    g.finish()?;
    let planform = Planform::new(
        length * 1e-3,
        extension_ratio,
        base_width * 1e-3,
        width_ratio,
        base_tab * 1e-3,
    )
    .map_err(|e| model_error(path, "geometry", e))?;
    check_planform(path, "geometry", &planform)?;
    Ok(planform)
}

/// `laminate.bond` and `laminate.bond_thickness_mm`: the bond layer, if the laminate has one, and
/// its thickness (the material's standard ply unless given), m.
fn read_bond(
    path: &Path,
    l: &TableReader<'_>,
    materials: &BTreeMap<String, Material>,
) -> Result<Option<(Material, f64)>, InputError> {
    Ok(
        match l.optional_string("bond", "a bond-layer material name")? {
            Some(bond_name) => {
                let m = resolve_material(path, &l.path("bond"), bond_name, materials)?;
                let t = match l.optional_number_in("bond_thickness_mm", PLY_THICKNESS_MM)? {
                    Some(t) => t * 1e-3,
                    None => m.ply_thickness.ok_or_else(|| {
                        InputError::missing(
                            path,
                            &l.path("bond_thickness_mm"),
                            &format!("a bond thickness, {PLY_THICKNESS_MM}"),
                        )
                    })?,
                };
                Some((m, t))
            }
            None => {
                if l.has("bond_thickness_mm") {
                    return Err(InputError::invalid(
                        path,
                        &l.path("bond_thickness_mm"),
                        "(set)",
                        "needs laminate.bond (the bond material)",
                    ));
                }
                None
            }
        },
    )
}

/// `[drive]`: the drive mode and the plate field, given as a field or as a voltage over the PZT
/// plate (`pzt_thickness`, m), V/m.
fn read_drive(
    path: &Path,
    root: &TableReader<'_>,
    pzt_thickness: f64,
) -> Result<Drive, InputError> {
    let d = root.table("drive")?;
    let mode = read_drive_mode(&d)?;
    let field = d.optional_number_in("field_V_per_mm", FIELD_V_PER_MM)?;
    let voltage = d.optional_number_in("voltage_V", VOLTAGE_V)?;
    let field = match (field, voltage) {
        (Some(f), None) => f * 1e3,
        (None, Some(v)) => mode.field_from_voltage(v, pzt_thickness),
        (Some(f), Some(v)) => {
            return Err(InputError::invalid(
                path,
                "drive",
                format!("field_V_per_mm = {f} and voltage_V = {v}"),
                "give exactly one of field_V_per_mm and voltage_V",
            ))
        }
        (None, None) => {
            return Err(d.missing_one_of(
                &["field_V_per_mm", "voltage_V"],
                "exactly one of field_V_per_mm and voltage_V",
            ))
        }
    };
    if !(field > 0.0 && field <= FIELD_V_PER_MM.hi * 1e3) {
        return Err(InputError::invalid(
            path,
            "drive.voltage_V",
            voltage.unwrap_or(0.0),
            format!(
                "with laminate.pzt_thickness_mm = {} gives a plate field of {} V/mm, outside the {FIELD_V_PER_MM}",
                short_number(pzt_thickness * 1e3),
                short_number(field * 1e-3)
            ),
        ));
    }
    let bias = read_drive_bias(&d, mode, Some(pzt_thickness))?;
    let signal = match voltage {
        Some(v) => BiasedSignal {
            key: "voltage_V",
            value: v,
            per_field: pzt_thickness,
            unit: "V",
        },
        None => BiasedSignal {
            key: "field_V_per_mm",
            value: field * 1e-3,
            per_field: 1e-3,
            unit: "V/mm",
        },
    };
    signal.check(&d, mode, field, bias)?;
    d.finish()?;
    Ok(Drive { mode, field, bias })
}

fn read_materials(root: &TableReader<'_>) -> Result<BTreeMap<String, Material>, InputError> {
    let mut out = BTreeMap::new();
    if let Some(mats) = root.optional_table("materials")? {
        for name in mats.keys() {
            let t = mats.table(name)?;
            out.insert(name.to_string(), material_from_table(name, &t)?);
        }
        mats.finish()?;
    }
    Ok(out)
}

/// A model error on validated-looking input (should not happen; reported, never a panic).
fn model_error(path: &Path, field: &str, e: ModelError) -> InputError {
    InputError::invalid(path, field, "(combination)", e.to_string())
}
