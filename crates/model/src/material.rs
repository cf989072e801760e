//! Lamina materials and the built-in material library (docs/physics.md §8, thesis Table 3.3).

use serde::{Deserialize, Serialize};

/// Vacuum permittivity ε0 in F/m.
pub const VACUUM_PERMITTIVITY: f64 = 8.854_187_812_8e-12;

/// Orthotropic lamina properties in SI units. Piezoelectric materials carry `d31 != 0`.
///
/// A PZT ceramic is in-plane isotropic: `e1 = e2`, `g12 = e1 / (2 (1 + ν12))`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Library or user name (`PZT-5H`, `CF-thesis`).
    pub name: String,
    /// Modulus along the fibre (1) direction, Pa.
    pub e1: f64,
    /// Transverse modulus, Pa.
    pub e2: f64,
    /// In-plane shear modulus, Pa.
    pub g12: f64,
    /// Major Poisson ratio ν12.
    pub nu12: f64,
    /// Density, kg/m³.
    pub density: f64,
    /// Piezoelectric coefficient d31 (= d32), m/V; 0 for passive materials.
    pub d31: f64,
    /// Relative permittivity K33 (only meaningful for piezo materials).
    pub relative_permittivity: f64,
    /// Nominal thickness of one ply or sheet, m, where the material comes in a standard ply.
    pub ply_thickness: Option<f64>,
    /// Highest field a piezoelectric plate may carry against its poling without depoling, V/m (the
    /// initial depolarizing field, docs/physics.md §2.1); 0 for passive materials.
    #[serde(default)]
    pub depolarization_field: f64,
}

impl Material {
    /// Minor Poisson ratio ν21 = ν12 E2 / E1 (reciprocity).
    pub fn nu21(&self) -> f64 {
        self.nu12 * self.e2 / self.e1
    }

    /// True for a material with a piezoelectric response.
    pub fn is_piezoelectric(&self) -> bool {
        self.d31 != 0.0
    }

    fn isotropic(name: &str, e: f64, nu: f64, density: f64) -> Self {
        Material {
            name: name.to_string(),
            e1: e,
            e2: e,
            g12: e / (2.0 * (1.0 + nu)),
            nu12: nu,
            density,
            d31: 0.0,
            relative_permittivity: 0.0,
            ply_thickness: None,
            depolarization_field: 0.0,
        }
    }

    fn pzt(name: &str, e: f64, d31: f64, depolarization_field: f64) -> Self {
        Material {
            d31,
            relative_permittivity: 3800.0,
            depolarization_field,
            ..Self::isotropic(name, e, 0.31, 7800.0)
        }
    }

    fn ply(name: &str, e1: f64, e2: f64, g12: f64, nu12: f64, density: f64, t: f64) -> Self {
        Material {
            name: name.to_string(),
            e1,
            e2,
            g12,
            nu12,
            density,
            d31: 0.0,
            relative_permittivity: 0.0,
            ply_thickness: Some(t),
            depolarization_field: 0.0,
        }
    }

    /// Look a material up in the built-in library (docs/physics.md §8).
    pub fn builtin(name: &str) -> Option<Material> {
        builtin_library().into_iter().find(|m| m.name == name)
    }
}

/// Names of the built-in materials, in library order.
pub fn builtin_names() -> Vec<String> {
    builtin_library().into_iter().map(|m| m.name).collect()
}

/// The built-in library: docs/physics.md §8.
///
/// - PZT-5H (PSI-5H4E): E = 62 GPa, ν = 0.31, ρ = 7800, d31 = -320 pm/V, K33 = 3800; depolarization
///   field against the poling 300 V/mm (the initial depolarizing field E_C,i of Piezo Systems' PZT-5H,
///   thesis Table 2.1; its coercive field E_C,f is 800 V/mm).
/// - PZT-5A: E = 66 GPa, d31 = -190 pm/V; depolarization field 500 V/mm (thesis Table 2.1).
/// - CF-thesis: thesis Table 3.3 (420 / 5.51 / 4.83 GPa, ν12 = 0.25, 61.8 µm) with the density read as
///   1390 kg/m³ (the table's "1.39 kg/m³" is a unit slip for g/cm³).
/// - M60J-epoxy: mid-range 300 GPa, 50 µm ply; S2-glass-epoxy; stainless steel; Pyralux LF (25 µm).
pub fn builtin_library() -> Vec<Material> {
    vec![
        Material::pzt("PZT-5H", 62e9, -320e-12, 300e3),
        Material::pzt("PZT-5A", 66e9, -190e-12, 500e3),
        Material::ply("CF-thesis", 420e9, 5.51e9, 4.83e9, 0.25, 1390.0, 61.8e-6),
        Material::ply("M60J-epoxy", 300e9, 7e9, 5e9, 0.33, 1500.0, 50e-6),
        Material::ply("S2-glass-epoxy", 55e9, 14e9, 5e9, 0.28, 1780.0, 100e-6),
        Material {
            ply_thickness: Some(100e-6),
            ..Material::isotropic("stainless-steel", 196e9, 0.3, 8000.0)
        },
        Material {
            ply_thickness: Some(25e-6),
            ..Material::isotropic("Pyralux-LF", 2.5e9, 0.35, 1100.0)
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn library_holds_the_materials_the_design_files_name() {
        for name in [
            "PZT-5H",
            "PZT-5A",
            "CF-thesis",
            "M60J-epoxy",
            "S2-glass-epoxy",
            "stainless-steel",
            "Pyralux-LF",
        ] {
            assert!(Material::builtin(name).is_some(), "{name} missing");
        }
        assert!(Material::builtin("unobtainium").is_none());
    }

    #[test]
    fn pzt_is_isotropic_in_plane() {
        let p = Material::builtin("PZT-5H").unwrap();
        assert_eq!(p.e1, p.e2);
        assert!((p.g12 - 62e9 / 2.62).abs() < 1.0);
        assert!(p.is_piezoelectric());
        assert!(!Material::builtin("CF-thesis").unwrap().is_piezoelectric());
    }
}
