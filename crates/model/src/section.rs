//! A laminate solved at one drive level: the per-unit-width quantities every planform shares.

use crate::drive::Drive;
use crate::error::ModelError;
use crate::laminate::{Laminate, LayerRole};

/// Everything the planform-dependent formulas need from the laminate at one drive level.
///
/// Computing it costs one pass over the layers; evaluating a planform against it
/// ([`crate::performance::evaluate`]) costs a few dozen flops and allocates nothing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    /// Drive mode and peak plate field.
    pub drive: Drive,
    /// Supply voltage for that field, V.
    pub voltage: f64,
    /// Magnitude of the free curvature `|P|` (thesis eq. 2.24), 1/m.
    pub free_curvature: f64,
    /// Bending compliance `C44`, 1/(N·m).
    pub bending_compliance: f64,
    /// Total thickness, m.
    pub thickness: f64,
    /// Thickness of one PZT plate, m.
    pub pzt_thickness: f64,
    /// Areal mass of both PZT plates, kg/m².
    pub pzt_areal_mass: f64,
    /// Areal mass of the passive plies, kg/m².
    pub passive_areal_mass: f64,
    /// Areal mass of bond layers, kg/m².
    pub bond_areal_mass: f64,
    /// Relative permittivity K33 of the PZT.
    pub relative_permittivity: f64,
    /// Peak |ε_x| on a PZT surface in free deflection (`ε0 + z κ`, thesis eq. 2.18).
    pub peak_pzt_strain: f64,
    /// σ_x on the PZT layers' surfaces (bottom plate then top plate, each layer bottom/top: four for
    /// plain plates, eight when each plate has an inactive surface layer) in free deflection, Pa.
    surface_stress_free: [f64; 8],
    /// σ_x on the same surfaces per unit external moment (N·m/m) opposing the free curvature.
    surface_stress_per_moment: [f64; 8],
    /// ε_x on the same surfaces in free deflection.
    surface_strain_free: [f64; 8],
    /// ε_x on the same surfaces per unit external moment (N·m/m) opposing the free curvature.
    surface_strain_per_moment: [f64; 8],
    /// How many of the surfaces are used.
    surfaces: usize,
}

impl Section {
    /// Solve the laminate at a drive level. The laminate must have exactly two piezo layers.
    pub fn new(laminate: &Laminate, drive: Drive) -> Result<Self, ModelError> {
        if laminate.piezo_count() != 2 {
            return Err(ModelError::Laminate(format!(
                "a bimorph needs 2 piezo layers, this stack has {}",
                laminate.piezo_count()
            )));
        }
        if !(drive.field.is_finite() && drive.field >= 0.0) {
            return Err(ModelError::OutOfRange {
                name: "field",
                value: drive.field,
                range: "at least 0 V/m",
            });
        }
        let fields = drive.mode.layer_fields(drive.field);
        let free = laminate.free_response(&fields);
        let curvature = free[3];
        // The blocking moment bends the beam back against its free curvature.
        let opposing = if curvature >= 0.0 { -1.0 } else { 1.0 };
        let unit_moment = laminate.moment_response(opposing);
        let none = [0.0, 0.0];
        let z = laminate.interfaces();
        let mut surface_stress_free = [0.0; 8];
        let mut surface_stress_per_moment = [0.0; 8];
        let mut surface_strain_free = [0.0; 8];
        let mut surface_strain_per_moment = [0.0; 8];
        let mut surfaces = 0;
        let mut peak_strain: f64 = 0.0;
        // Both sides of every PZT layer: the plate's outer and inner surfaces and, with an inactive
        // surface layer, both sides of the interface, where the piezoelectric term of σ jumps.
        for plate in 0..2 {
            for k in laminate.piezo_plate(plate) {
                for zz in [z[k], z[k + 1]] {
                    if surfaces == surface_stress_free.len() {
                        return Err(ModelError::Laminate(
                            "a PZT plate of more than two layers".into(),
                        ));
                    }
                    surface_stress_free[surfaces] = laminate.stress_at(k, zz, &free, &fields)[0];
                    surface_stress_per_moment[surfaces] =
                        laminate.stress_at(k, zz, &unit_moment, &none)[0];
                    surface_strain_free[surfaces] = Laminate::strain_at(&free, zz)[0];
                    surface_strain_per_moment[surfaces] = Laminate::strain_at(&unit_moment, zz)[0];
                    surfaces += 1;
                    peak_strain = peak_strain.max(Laminate::strain_at(&free, zz)[0].abs());
                }
            }
        }
        let layers = laminate.layers();
        let pzt = &layers[laminate.piezo_layer(0)];
        // The field is V/t_p over the whole plate: an inactive surface layer is in series with the
        // driven part at the same permittivity.
        let plate_thickness: f64 = laminate.piezo_plate(0).map(|k| layers[k].thickness).sum();
        Ok(Section {
            drive,
            voltage: drive.mode.voltage_from_field(drive.field, plate_thickness),
            free_curvature: curvature.abs(),
            bending_compliance: laminate.bending_compliance(),
            thickness: laminate.thickness(),
            pzt_thickness: plate_thickness,
            pzt_areal_mass: laminate.areal_mass(LayerRole::Piezo)
                + laminate.areal_mass(LayerRole::InactivePiezo),
            passive_areal_mass: laminate.areal_mass(LayerRole::Passive),
            bond_areal_mass: laminate.areal_mass(LayerRole::Bond),
            relative_permittivity: pzt.material.relative_permittivity,
            peak_pzt_strain: peak_strain,
            surface_stress_free,
            surface_stress_per_moment,
            surface_strain_free,
            surface_strain_per_moment,
            surfaces,
        })
    }

    /// Peak |σ_x| over the PZT surfaces at the root under an external moment per unit width `m` (N·m/m)
    /// opposing the free curvature: CLT `σ = Q̄ (ε0 + z κ - d E3)` (thesis eqs. 2.18, 2.23).
    pub fn peak_pzt_stress(&self, moment_per_width: f64) -> f64 {
        (0..self.surfaces)
            .map(|i| {
                (self.surface_stress_free[i] + moment_per_width * self.surface_stress_per_moment[i])
                    .abs()
            })
            .fold(0.0, f64::max)
    }

    /// Peak |σ_x| and |ε_x| over the PZT surfaces at the root with the field at `share` of the
    /// section's drive field (signed: the field reverses over a drive period) and an external moment per
    /// unit width `m` (N·m/m) opposing the free curvature. The laminate is linear, so both are the free
    /// response scaled by `share` plus the moment's response.
    pub fn peak_pzt_stress_and_strain(&self, share: f64, moment_per_width: f64) -> (f64, f64) {
        (0..self.surfaces).fold((0.0f64, 0.0f64), |(s, e), i| {
            (
                s.max(
                    (share * self.surface_stress_free[i]
                        + moment_per_width * self.surface_stress_per_moment[i])
                        .abs(),
                ),
                e.max(
                    (share * self.surface_strain_free[i]
                        + moment_per_width * self.surface_strain_per_moment[i])
                        .abs(),
                ),
            )
        })
    }
}

/// A thesis laminate (PZT-5H plates of `t_p` on the thesis CF plies of 61.8 µm in `layup`) solved in
/// parallel drive at the thesis' 800 V/mm: the section the unit tests share.
#[cfg(test)]
pub(crate) fn thesis_section(t_p: f64, layup: &[f64]) -> Section {
    let pzt = crate::material::Material::builtin("PZT-5H").unwrap();
    let cf = crate::material::Material::builtin("CF-thesis").unwrap();
    let lam = Laminate::bimorph(&pzt, t_p, &cf, 61.8e-6, layup, None).unwrap();
    Section::new(&lam, Drive::new(crate::drive::DriveMode::Parallel, 800e3)).unwrap()
}
