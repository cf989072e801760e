//! `calibrated-model.toml`: the TOML text of [`CalibratedModel`] (the model crate knows serde, not TOML),
//! and its reading for `--model FILE`.
//!
//! Reading validates the file once, as the input layer does every file: each refusal is one
//! [`InputError`] naming the file, the field, the value and what is allowed. A library effect's value
//! must lie inside the bounds `calibrate` fits it in ([`EffectId::param`], in the file's SI units): a
//! file `calibrate` wrote always does, and a hand-edited `d31_scale = 1e300` is refused here, where the
//! field can be named, instead of as a non-finite prediction for the design.

use crate::calibrate::library::EffectId;
use crate::input::limits::LOSS_FACTOR;
use crate::input::{parse_toml, short_number, toml_error_line, InputError, Range, TableReader};
use actuator_model::{Base, CalibratedModel, EffectModel, Effects};
use std::path::Path;

/// The values `base` takes, as the file writes them.
const BASE_NAMES: &str = "\"original\" or \"nonlinear\"";

/// The library effects the nonlinear base takes: those that change the laminate its solver takes
/// ([`actuator_model::calibrated_base`]).
const NONLINEAR_BASE_EFFECTS: [EffectId; 2] = [EffectId::PlyThickness, EffectId::BondLayer];

/// Name of the file `calibrate` writes.
pub const FILE_NAME: &str = "calibrated-model.toml";

/// A calibrated model that cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum ModelFileError {
    /// The model does not serialise (not expected for a valid model).
    #[error("serialising the calibrated model")]
    Serialise(#[source] toml::ser::Error),
}

/// TOML text of a calibrated model, with a header saying what it is.
pub fn to_toml(model: &CalibratedModel) -> Result<String, ModelFileError> {
    let body = toml::to_string(model).map_err(ModelFileError::Serialise)?;
    Ok(format!(
        "# actuator-cam calibrated model: the {} model plus the physical effects below (SI units,\n\
         # null values = effect off). Use with predict/optimize/cut-sheet --model FILE.\n{body}",
        model.base.name()
    ))
}

/// A library effect's field in `[effects]`: the effect, the key, the value's unit and the field itself.
struct LibraryField {
    effect: EffectId,
    key: &'static str,
    unit: &'static str,
    get: fn(&Effects) -> f64,
}

/// Every library effect's field, with the effect whose fit bounds are its allowed range.
const LIBRARY_FIELDS: [LibraryField; 8] = [
    LibraryField {
        effect: EffectId::D31Scale,
        key: "d31_scale",
        unit: "",
        get: |e| e.d31_scale,
    },
    LibraryField {
        effect: EffectId::FieldDependentD31,
        key: "d31_field_coefficient_m_per_V",
        unit: "m/V",
        get: |e| e.d31_field_coefficient,
    },
    LibraryField {
        effect: EffectId::DeadLength,
        key: "dead_length_m",
        unit: "m",
        get: |e| e.dead_length,
    },
    LibraryField {
        effect: EffectId::BondLayer,
        key: "bond_thickness_m",
        unit: "m",
        get: |e| e.bond_thickness,
    },
    LibraryField {
        effect: EffectId::CompliantExtension,
        key: "extension_flexibility",
        unit: "",
        get: |e| e.extension_flexibility,
    },
    LibraryField {
        effect: EffectId::ClampCompliance,
        key: "clamp_compliance_rad_per_N_m",
        unit: "rad/(N m)",
        get: |e| e.clamp_compliance,
    },
    LibraryField {
        effect: EffectId::PlyThickness,
        key: "ply_thickness_scale",
        unit: "",
        get: |e| e.ply_thickness_scale,
    },
    LibraryField {
        effect: EffectId::StiffnessScale,
        key: "stiffness_scale",
        unit: "",
        get: |e| e.stiffness_scale,
    },
];

impl LibraryField {
    /// The fit bounds in the file's unit, converted as the fit converts its values (so a bound the fit
    /// reached is written as exactly this number).
    fn bounds(&self) -> (f64, f64) {
        let param = self.effect.param();
        let si = |x: f64| {
            let mut model = EffectModel::default();
            self.effect.apply(&mut model, x);
            (self.get)(&model.effects)
        };
        (si(param.lo), si(param.hi))
    }

    /// The field's value in `[effects]`, if given, checked against the fit bounds.
    fn check(&self, effects: &TableReader<'_>) -> Result<(), InputError> {
        let (lo, hi) = self.bounds();
        effects
            .optional_number_in(self.key, Range::closed(lo, hi, self.unit))
            .map(|_| ())
    }
}

/// Parse and validate a calibrated model (named `FILE_NAME` in errors).
pub fn from_toml(text: &str) -> Result<CalibratedModel, InputError> {
    parse(Path::new(FILE_NAME), text)
}

/// Parse and validate the calibrated model in `text`, read from `path`.
fn parse(path: &Path, text: &str) -> Result<CalibratedModel, InputError> {
    let table = parse_toml(path, text)?;
    let root = TableReader::new(path, "", &table);
    let kind = root.string("model", "\"calibrated\"")?;
    if kind != "calibrated" {
        return Err(InputError::invalid(
            path,
            "model",
            format!("{kind:?}"),
            "expected \"calibrated\"",
        ));
    }
    let base = read_base(path, &root)?;
    if let Some(effects) = root.optional_table("effects")? {
        for field in &LIBRARY_FIELDS {
            field.check(&effects)?;
        }
    }
    if let Some(loss) = root.optional_table("loss")? {
        loss.number_in("loss_factor", LOSS_FACTOR)?;
    }
    // The structure (verdict, selected effects, declared effects, no unknown key) is serde's.
    let model: CalibratedModel = toml::from_str(text).map_err(|e| {
        let line = toml_error_line(text, &e);
        InputError::invalid(
            path,
            &format!("line {line}"),
            "",
            format!("not a calibrated model: {}", e.message()),
        )
    })?;
    if base == Base::Nonlinear {
        refuse_linear_effects(path, &model)?;
    }
    model
        .validate()
        .map_err(|e| InputError::whole_file(path, e.to_string()))?;
    Ok(model)
}

/// The file's `base`, the original when it has none.
fn read_base(path: &Path, root: &TableReader<'_>) -> Result<Base, InputError> {
    let Some(text) = root.optional_string("base", BASE_NAMES)? else {
        return Ok(Base::Original);
    };
    Base::parse(text).ok_or_else(|| {
        InputError::invalid(
            path,
            "base",
            format!("{text:?}"),
            format!("expected {BASE_NAMES}"),
        )
    })
}

/// Refuse, naming the field, an effect the nonlinear base cannot take (it acts on the linear section;
/// [`actuator_model::calibrated_base`]).
fn refuse_linear_effects(path: &Path, model: &CalibratedModel) -> Result<(), InputError> {
    let null = Effects::default();
    let linear = LIBRARY_FIELDS.iter().find(|f| {
        !NONLINEAR_BASE_EFFECTS.contains(&f.effect) && (f.get)(&model.effects) != (f.get)(&null)
    });
    if let Some(field) = linear {
        let takes: Vec<&str> = NONLINEAR_BASE_EFFECTS
            .iter()
            .filter_map(|e| LIBRARY_FIELDS.iter().find(|f| f.effect == *e))
            .map(|f| f.key)
            .collect();
        return Err(InputError::invalid(
            path,
            &format!("effects.{}", field.key),
            short_number((field.get)(&model.effects)),
            format!(
                "base = \"nonlinear\" takes the effects {} only (this one acts on the linear section)",
                takes.join(" and ")
            ),
        ));
    }
    if let Some(d) = model.declared.first() {
        return Err(InputError::invalid(
            path,
            "declared",
            format!("{:?}", d.name),
            "base = \"nonlinear\" takes no declared effect (their primitives compose on the linear section)",
        ));
    }
    Ok(())
}

/// Read a calibrated model from a file (`--model FILE`).
pub fn load(path: &Path) -> Result<CalibratedModel, InputError> {
    let text = crate::input::read_text(path)?;
    parse(path, &text)
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "model = \"calibrated\"\nverdict = \"x\"\nselected_effects = []\n";

    fn model(effects: Effects) -> CalibratedModel {
        CalibratedModel {
            model: "calibrated".into(),
            base: actuator_model::Base::Original,
            verdict: "explained".into(),
            selected_effects: vec!["dead-length".into()],
            effects,
            declared: vec![],
            loss: None,
        }
    }

    #[test]
    fn round_trips_exactly() {
        let model = model(Effects {
            dead_length: 2.345_678_9e-3,
            d31_scale: 0.812_345_678_9,
            ..Effects::default()
        });
        let back = from_toml(&to_toml(&model).unwrap()).unwrap();
        assert_eq!(back, model);
    }

    #[test]
    fn the_base_round_trips_and_the_original_is_left_out() {
        // A file on the original base reads as every file written without `base`.
        let original = model(Effects::default());
        let text = to_toml(&original).unwrap();
        assert!(!text.contains("base ="), "{text}");
        assert!(text.contains("the original model plus"), "{text}");
        let nonlinear = CalibratedModel {
            base: Base::Nonlinear,
            ..model(Effects {
                ply_thickness_scale: 1.2,
                bond_thickness: 15e-6,
                ..Effects::default()
            })
        };
        let text = to_toml(&nonlinear).unwrap();
        assert!(text.contains("base = \"nonlinear\""), "{text}");
        assert!(text.contains("the nonlinear model plus"), "{text}");
        assert_eq!(from_toml(&text).unwrap(), nonlinear);
    }

    #[test]
    fn a_base_the_file_cannot_have_is_refused_naming_the_key() {
        let refused = |base: &str, effects: &str| {
            from_toml(&format!("base = {base}\n{HEAD}[effects]\n{effects}"))
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            refused("\"Nonlinear\"", ""),
            "calibrated-model.toml: base = \"Nonlinear\": expected \"original\" or \"nonlinear\""
        );
        assert_eq!(
            refused("2", ""),
            "calibrated-model.toml: base = 2: expected \"original\" or \"nonlinear\""
        );
        // Each library effect on the linear section, by its key.
        for (line, key) in [
            ("d31_scale = 0.9", "d31_scale"),
            ("stiffness_scale = 0.8", "stiffness_scale"),
            (
                "clamp_compliance_rad_per_N_m = 0.1",
                "clamp_compliance_rad_per_N_m",
            ),
        ] {
            let e = refused("\"nonlinear\"", &format!("{line}\n"));
            assert!(
                e.starts_with(&format!("calibrated-model.toml: effects.{key} = ")),
                "{e}"
            );
            assert!(e.contains("takes the effects ply_thickness_scale and bond_thickness_m only"));
        }
    }

    #[test]
    fn the_reader_refuses_on_the_nonlinear_base_exactly_what_the_model_refuses() {
        // The file's keys live here and the rule in the model crate: each library effect turned on
        // alone is refused by both or by neither.
        for field in &LIBRARY_FIELDS {
            let mut effects = EffectModel::default();
            field.effect.apply(&mut effects, field.effect.param().hi);
            let model = CalibratedModel {
                base: Base::Nonlinear,
                ..model(effects.effects)
            };
            let reader = refuse_linear_effects(Path::new("m.toml"), &model).is_err();
            let physics = actuator_model::calibrated_base::check_nonlinear(&model.effects, false);
            assert_eq!(reader, physics.is_err(), "{}", field.key);
        }
    }

    #[test]
    fn the_field_keys_are_the_serialised_names() {
        // Each field's key and getter against the model crate's own serde names: a key that does not
        // serialise, or a getter that reads another field, fails here.
        for field in &LIBRARY_FIELDS {
            let mut model = EffectModel::default();
            field.effect.apply(&mut model, field.effect.param().hi);
            let table = toml::Table::try_from(model.effects).unwrap();
            assert_eq!(
                table[field.key].as_float(),
                Some((field.get)(&model.effects)),
                "{}",
                field.key
            );
            assert_ne!(
                (field.get)(&model.effects),
                (field.get)(&Effects::default())
            );
        }
        assert_eq!(
            LIBRARY_FIELDS.len(),
            toml::Table::try_from(Effects::default()).unwrap().len(),
            "every library field is checked"
        );
    }

    /// A declared scale on the bond layer round-trips; one on a property the bond lacks (an edited file)
    /// is refused on reading.
    #[test]
    fn a_bond_scale_round_trips_and_a_property_the_bond_lacks_is_refused() {
        use actuator_model::primitives::{Link, Map, Primitive, Property, Target};
        let bond = |property| actuator_model::DeclaredEffect {
            name: "stiff-glue".into(),
            parameter: "bond_e_scale".into(),
            value: 1.5,
            null: 1.0,
            primitives: vec![Link {
                primitive: Primitive::Scale {
                    target: Target::Bond,
                    property,
                },
                map: Map::Identity,
            }],
        };
        let model = |property| CalibratedModel {
            model: "calibrated".into(),
            base: actuator_model::Base::Original,
            verdict: "explained".into(),
            selected_effects: vec!["stiff-glue".into()],
            effects: Effects {
                bond_thickness: 20e-6,
                ..Effects::default()
            },
            declared: vec![bond(property)],
            loss: None,
        };
        let good = model(Property::E1);
        let text = to_toml(&good).unwrap();
        assert!(text.contains("target = \"bond\""), "{text}");
        assert_eq!(from_toml(&text).unwrap(), good);
        let bad = to_toml(&model(Property::E1))
            .unwrap()
            .replace("property = \"e1\"", "property = \"d31\"");
        assert!(bad.contains("\"d31\""), "{bad}");
        let e = from_toml(&bad).unwrap_err().to_string();
        assert!(e.contains("bond"), "{e}");
    }

    /// The rigid root, the edge margins and the inactive surface layer are recorded as declared primitives
    /// under their kinds and read back to the same model and the same prediction; `[effects]` stays the
    /// library's (their `Effects` fields are not written).
    #[test]
    fn root_edge_and_surface_primitives_round_trip() {
        use actuator_model::primitives::{Link, Map, Primitive};
        let declared = |name: &str, value: f64, primitive| actuator_model::DeclaredEffect {
            name: name.into(),
            parameter: format!("{name}_m"),
            value,
            null: 0.0,
            primitives: vec![Link {
                primitive,
                map: Map::Identity,
            }],
        };
        let model = CalibratedModel {
            model: "calibrated".into(),
            base: actuator_model::Base::Original,
            verdict: "explained".into(),
            selected_effects: vec![
                "held".into(),
                "edges".into(),
                "skin".into(),
                "solder".into(),
                "fillet".into(),
                "glue".into(),
            ],
            effects: Effects::default(),
            declared: vec![
                declared("held", 2e-3, Primitive::RigidRoot),
                declared("edges", 0.4e-3, Primitive::EdgeMargin),
                declared("skin", 15e-6, Primitive::InactiveSurfaceLayer),
                declared("solder", 2e-6, Primitive::AddedMass),
                declared("fillet", 3e-5, Primitive::AddedMassPerLength),
                declared("glue", 0.01, Primitive::AddedMassPerArea),
            ],
            loss: None,
        };
        let text = to_toml(&model).unwrap();
        for kind in [
            "rigid-root",
            "edge-margin",
            "inactive-surface-layer",
            "added-mass",
            "added-mass-per-length",
            "added-mass-per-area",
        ] {
            assert!(text.contains(&format!("kind = \"{kind}\"")), "{text}");
        }
        assert!(
            !text.contains("rigid_root") && !text.contains("inactive_surface"),
            "{text}"
        );
        let back = from_toml(&text).unwrap();
        assert_eq!(back, model);
        let m = back.effect_model().unwrap();
        let e =
            m.boundary_effects(&actuator_model::Planform::new(30e-3, 0.5, 6e-3, 1.0, 0.0).unwrap());
        assert_eq!((e.rigid_root, e.edge_margin), (2e-3, 0.4e-3));
        // The added masses reach the mass, and only the mass.
        let pl = actuator_model::Planform::new(30e-3, 0.5, 6e-3, 1.0, 0.0).unwrap();
        let added = Effects {
            added_mass: 2e-6,
            added_mass_per_length: 3e-5,
            added_mass_per_area: 0.01,
            ..Effects::default()
        }
        .added_mass(&pl);
        let pzt = actuator_model::Material::builtin("PZT-5H").unwrap();
        let cf = actuator_model::Material::builtin("CF-thesis").unwrap();
        let a = actuator_model::effects::Actuator {
            pzt: &pzt,
            pzt_thickness: 191e-6,
            ply: &cf,
            ply_thickness: 61.8e-6,
            layup_deg: &[0.0, 90.0, 0.0],
            planform: pl,
            drive: actuator_model::effects::drive_at_voltage(
                actuator_model::DriveMode::Parallel,
                100.0,
                191e-6,
            ),
        };
        assert!((m.mass(&a).unwrap().added - added).abs() < 1e-18);
    }

    #[test]
    fn a_model_at_the_fit_bounds_is_read_back() {
        // calibrate writes a parameter the fit left at a bound as apply(bound): it must load.
        for field in &LIBRARY_FIELDS {
            let param = field.effect.param();
            for bound in [param.lo, param.hi] {
                let mut m = EffectModel::default();
                field.effect.apply(&mut m, bound);
                let written = model(m.effects);
                let back = from_toml(&to_toml(&written).unwrap());
                assert_eq!(
                    back.as_ref().ok(),
                    Some(&written),
                    "{} = {bound}: {back:?}",
                    field.key
                );
            }
        }
    }

    #[test]
    fn out_of_range_values_name_the_file_the_field_the_value_and_the_bounds() {
        let refused = |line: &str| {
            from_toml(&format!("{HEAD}[effects]\n{line}\n"))
                .unwrap_err()
                .to_string()
        };
        // ParameterRange: calibrate's fit bounds (src/calibrate/library.rs) in SI: eta [0.05, 3],
        // dead length [0, 20] mm, bond layer [0, 200] um, beta [-0.4, 3] per V/um.
        assert_eq!(
            refused("d31_scale = 1e300"),
            "calibrated-model.toml: effects.d31_scale = 1e300: outside the allowed range [0.05, 3]"
        );
        assert_eq!(
            refused("dead_length_m = -1.0"),
            "calibrated-model.toml: effects.dead_length_m = -1: outside the allowed range [0, 0.02] m"
        );
        assert_eq!(
            refused("bond_thickness_m = 0.001"),
            "calibrated-model.toml: effects.bond_thickness_m = 0.001: outside the allowed range [0, 0.0002] m"
        );
        assert_eq!(
            refused("d31_field_coefficient_m_per_V = nan"),
            "calibrated-model.toml: effects.d31_field_coefficient_m_per_V = NaN: outside the allowed range [-4e-7, 3e-6] m/V"
        );
        assert_eq!(
            refused("d31_scale = \"big\""),
            "calibrated-model.toml: effects.d31_scale = \"big\": expected a number, allowed range [0.05, 3]"
        );
        // Unknown keys are serde's refusal, with the line.
        let e = refused("warp = 1.0");
        assert!(
            e.starts_with("calibrated-model.toml: line 5: not a calibrated model: "),
            "{e}"
        );
        assert!(e.contains("warp"), "{e}");
        assert!(!e.contains('\n'), "{e}");
        assert!(from_toml(&format!("{HEAD}[effects]\n"))
            .unwrap()
            .effects
            .is_null());
    }

    #[test]
    fn load_errors_are_one_line_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.toml");
        std::fs::write(&path, "model = ").unwrap();
        let e = load(&path).unwrap_err().to_string();
        assert!(
            e.starts_with(&format!("{}: line 1: not valid TOML", path.display())),
            "{e}"
        );
        std::fs::write(
            &path,
            format!("{HEAD}[effects]\nply_thickness_scale = 0.1\n"),
        )
        .unwrap();
        assert_eq!(
            load(&path).unwrap_err().to_string(),
            format!(
                "{}: effects.ply_thickness_scale = 0.1: outside the allowed range [0.5, 3]",
                path.display()
            )
        );
        let missing = load(&dir.path().join("none.toml")).unwrap_err().to_string();
        assert!(missing.contains("none.toml"), "{missing}");
        assert_eq!(
            from_toml("model = \"x\"\nverdict = \"x\"\nselected_effects = []\n[effects]\n")
                .unwrap_err()
                .to_string(),
            "calibrated-model.toml: model = \"x\": expected \"calibrated\""
        );
    }
}
