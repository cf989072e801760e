//! The last check before anything is printed or written: every number is finite. The input ranges
//! (`limits`) and the derived-geometry checks are meant to make a non-finite output impossible; this
//! turns one that slips through into an error naming the input fields instead of a `NaN` on screen or a
//! `null` in JSON.

use super::{short_number, InputError};
use std::path::Path;

/// Refuse the first output value that is not finite. `fields` names the input fields that produced the
/// values and `values_as_written` their values (`length_mm = 42.2, …`); `values` are the outputs by name.
pub fn ensure_finite<'a>(
    file: &Path,
    fields: &str,
    values_as_written: &str,
    values: impl IntoIterator<Item = (&'a str, f64)>,
) -> Result<(), InputError> {
    let bad: Vec<String> = values
        .into_iter()
        .filter(|(_, v)| !v.is_finite())
        .map(|(name, v)| format!("{name} = {}", short_number(v)))
        .collect();
    if bad.is_empty() {
        return Ok(());
    }
    Err(InputError::invalid(
        file,
        fields,
        values_as_written,
        format!(
            "these values give a result that is not a finite number ({}); the model cannot predict this design",
            bad.join(", ")
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_the_inputs_and_the_bad_outputs() {
        let f = Path::new("d.toml");
        assert!(ensure_finite(f, "geometry", "length_mm = 1", [("mass_mg", 1.0)]).is_ok());
        let e = ensure_finite(
            f,
            "geometry",
            "length_mm = 1",
            [
                ("mass_mg", 1.0),
                ("stiffness_N_per_m", f64::NAN),
                ("energy_mJ", f64::INFINITY),
            ],
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            e,
            "d.toml: geometry = length_mm = 1: these values give a result that is not a finite number \
             (stiffness_N_per_m = NaN, energy_mJ = inf); the model cannot predict this design"
        );
    }
}
