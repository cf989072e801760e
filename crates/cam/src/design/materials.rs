//! Materials named in a design file: the built-in library, or a `[materials.NAME]` table.

use crate::input::limits::{
    D31_PM_PER_V, DENSITY_KG_PER_M3 as DENSITY, DEPOLARIZATION_V_PER_MM, MODULUS_GPA, PERMITTIVITY,
    PLY_THICKNESS_MM, POISSON,
};
use crate::input::{short_number, InputError, TableReader};
use actuator_model::material::builtin_names;
use actuator_model::Material;
use std::collections::BTreeMap;
use std::path::Path;

/// A user material from `[materials.NAME]`: `e1_GPa`, optional `e2_GPa` (default e1), `g12_GPa`
/// (default `e1 / (2 (1 + ν12))`), `nu12`, `density_kg_per_m3`, optional `d31_pm_per_V`,
/// `relative_permittivity`, `ply_thickness_mm`, `depolarization_field_V_per_mm` (default PZT-5H's for a
/// piezoelectric material).
pub fn material_from_table(name: &str, t: &TableReader<'_>) -> Result<Material, InputError> {
    let e1 = t.number_in("e1_GPa", MODULUS_GPA)? * 1e9;
    let e2 = t
        .optional_number_in("e2_GPa", MODULUS_GPA)?
        .map(|e| e * 1e9)
        .unwrap_or(e1);
    let nu12 = t.number_in("nu12", POISSON)?;
    let g12 = t
        .optional_number_in("g12_GPa", MODULUS_GPA)?
        .map(|g| g * 1e9)
        .unwrap_or(e1 / (2.0 * (1.0 + nu12)));
    let m = Material {
        name: name.to_string(),
        e1,
        e2,
        g12,
        nu12,
        density: t.number_in("density_kg_per_m3", DENSITY)?,
        d31: t
            .optional_number_in("d31_pm_per_V", D31_PM_PER_V)?
            .unwrap_or(0.0)
            * 1e-12,
        relative_permittivity: t
            .optional_number_in("relative_permittivity", PERMITTIVITY)?
            .unwrap_or(0.0),
        ply_thickness: t
            .optional_number_in("ply_thickness_mm", PLY_THICKNESS_MM)?
            .map(|x| x * 1e-3),
        depolarization_field: 0.0,
    };
    // A piezoelectric material without its own figure takes PZT-5H's (docs/physics.md §2.1): every
    // plate driven against its poling is then held to a depolarization limit.
    let m = Material {
        depolarization_field: match t
            .optional_number_in("depolarization_field_V_per_mm", DEPOLARIZATION_V_PER_MM)?
        {
            Some(e) => e * 1e3,
            None if m.is_piezoelectric() => {
                Material::builtin("PZT-5H").map_or(0.0, |p| p.depolarization_field)
            }
            None => 0.0,
        },
        ..m
    };
    // Plane-stress stiffness needs 1 - ν12 ν21 = 1 - ν12² E2 / E1 > 0. Only E1 is in the
    // denominator, and a small E1 is what breaks it (E2 and ν12 are bounded by their ranges), so E1 is
    // the field blamed, with the bound the other two set.
    if m.nu12 * m.nu21() >= 1.0 {
        let floor_gpa = nu12 * nu12 * e2 * 1e-9;
        return Err(InputError::invalid(
            t.file(),
            &t.path("e1_GPa"),
            short_number(e1 * 1e-9),
            format!(
                "with e2_GPa = {} and nu12 = {}, ν12² E2 / E1 >= 1: no plane-stress stiffness; \
                 e1_GPa must be greater than {}",
                short_number(e2 * 1e-9),
                short_number(nu12),
                short_number(floor_gpa)
            ),
        ));
    }
    t.finish()?;
    Ok(m)
}

/// Find a material by name: the file's own `[materials]` first, then the built-in library.
pub fn resolve_material(
    file: &Path,
    field: &str,
    name: &str,
    own: &BTreeMap<String, Material>,
) -> Result<Material, InputError> {
    own.get(name)
        .cloned()
        .or_else(|| Material::builtin(name))
        .ok_or_else(|| {
            let mut known: Vec<String> = own.keys().cloned().collect();
            known.extend(builtin_names());
            InputError::invalid(
                file,
                field,
                format!("{name:?}"),
                format!("unknown material; known: {}", known.join(", ")),
            )
        })
}
