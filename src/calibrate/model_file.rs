//! `calibrated-model.toml`: the TOML text of [`CalibratedModel`] (the model crate knows serde, not TOML).

use actuator_model::CalibratedModel;
use anyhow::{bail, Context};
use std::path::Path;

/// Name of the file `calibrate` writes.
pub const FILE_NAME: &str = "calibrated-model.toml";

/// TOML text of a calibrated model, with a header saying what it is.
pub fn to_toml(model: &CalibratedModel) -> anyhow::Result<String> {
    let body = toml::to_string(model).context("serialising the calibrated model")?;
    Ok(format!(
        "# actuator-cam calibrated model: the original model plus the physical effects below (SI units,\n\
         # null values = effect off). Use with predict/optimize/cut-sheet --model FILE.\n{body}"
    ))
}

/// Parse and validate a calibrated model.
pub fn from_toml(text: &str) -> anyhow::Result<CalibratedModel> {
    let model: CalibratedModel = toml::from_str(text).context("parsing a calibrated model")?;
    if model.model != "calibrated" {
        bail!("`model = \"{}\"`: expected \"calibrated\"", model.model);
    }
    model.effects.validate()?;
    Ok(model)
}

/// Read a calibrated model from a file (`--model FILE`).
pub fn load(path: &Path) -> anyhow::Result<CalibratedModel> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    from_toml(&text).with_context(|| format!("in {}", path.display()))
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
}
