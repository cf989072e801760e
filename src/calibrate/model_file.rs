//! `calibrated-model.toml`: the TOML text of [`CalibratedModel`] (the model crate knows serde, not TOML).

use actuator_model::{CalibratedModel, ModelError};
use std::path::{Path, PathBuf};

/// Name of the file `calibrate` writes.
pub const FILE_NAME: &str = "calibrated-model.toml";

/// A model file that cannot be written, read or used. Each layer names its own step and keeps the cause
/// as its source, so the command line prints the whole chain.
#[derive(Debug, thiserror::Error)]
pub enum ModelFileError {
    /// The model does not serialise (not expected for a valid model).
    #[error("serialising the calibrated model")]
    Serialise(#[source] toml::ser::Error),
    /// Not TOML of a calibrated model.
    #[error("parsing a calibrated model")]
    Parse(#[source] toml::de::Error),
    /// `model = "..."` names another model.
    #[error("`model = \"{0}\"`: expected \"calibrated\"")]
    NotCalibrated(String),
    /// An effect value out of its physical range.
    #[error(transparent)]
    Invalid(#[from] ModelError),
    /// The file cannot be read.
    #[error("cannot read {}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The file's content is not a valid model.
    #[error("in {}", path.display())]
    In {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        #[source]
        source: Box<ModelFileError>,
    },
}

/// TOML text of a calibrated model, with a header saying what it is.
pub fn to_toml(model: &CalibratedModel) -> Result<String, ModelFileError> {
    let body = toml::to_string(model).map_err(ModelFileError::Serialise)?;
    Ok(format!(
        "# actuator-cam calibrated model: the original model plus the physical effects below (SI units,\n\
         # null values = effect off). Use with predict/optimize/cut-sheet --model FILE.\n{body}"
    ))
}

/// Parse and validate a calibrated model.
pub fn from_toml(text: &str) -> Result<CalibratedModel, ModelFileError> {
    let model: CalibratedModel = toml::from_str(text).map_err(ModelFileError::Parse)?;
    if model.model != "calibrated" {
        return Err(ModelFileError::NotCalibrated(model.model));
    }
    model.validate()?;
    Ok(model)
}

/// Read a calibrated model from a file (`--model FILE`).
pub fn load(path: &Path) -> Result<CalibratedModel, ModelFileError> {
    let text = std::fs::read_to_string(path).map_err(|source| ModelFileError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    from_toml(&text).map_err(|e| ModelFileError::In {
        path: path.to_path_buf(),
        source: Box::new(e),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use actuator_model::Effects;

    #[test]
    fn round_trips_exactly() {
        let model = CalibratedModel {
            model: "calibrated".into(),
            verdict: "explained".into(),
            selected_effects: vec!["dead-length".into()],
            effects: Effects {
                dead_length: 2.345_678_9e-3,
                d31_scale: 0.812_345_678_9,
                ..Effects::default()
            },
            declared: vec![],
        };
        let back = from_toml(&to_toml(&model).unwrap()).unwrap();
        assert_eq!(back, model);
    }

    #[test]
    fn rejects_unknown_keys_and_unphysical_values() {
        assert!(from_toml("model = \"calibrated\"\nverdict = \"x\"\nselected_effects = []\n[effects]\nwarp = 1.0\n").is_err());
        assert!(from_toml("model = \"calibrated\"\nverdict = \"x\"\nselected_effects = []\n[effects]\ndead_length_m = -1.0\n").is_err());
        let ok = from_toml(
            "model = \"calibrated\"\nverdict = \"x\"\nselected_effects = []\n[effects]\n",
        )
        .unwrap();
        assert!(ok.effects.is_null());
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
            verdict: "explained".into(),
            selected_effects: vec!["stiff-glue".into()],
            effects: Effects {
                bond_thickness: 20e-6,
                ..Effects::default()
            },
            declared: vec![bond(property)],
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

    #[test]
    fn load_errors_name_the_file_then_the_step_then_the_cause() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.toml");
        std::fs::write(&path, "model = ").unwrap();
        let e = load(&path).unwrap_err();
        assert_eq!(e.to_string(), format!("in {}", path.display()));
        let step = std::error::Error::source(&e).unwrap();
        assert_eq!(step.to_string(), "parsing a calibrated model");
        assert!(
            step.source().is_some(),
            "the TOML error is kept as the cause"
        );
        let missing = load(&dir.path().join("none.toml")).unwrap_err();
        assert!(missing.to_string().starts_with("cannot read "));
        assert!(
            from_toml("model = \"x\"\nverdict = \"x\"\nselected_effects = []\n[effects]\n")
                .unwrap_err()
                .to_string()
                .contains("expected \"calibrated\"")
        );
    }
}
