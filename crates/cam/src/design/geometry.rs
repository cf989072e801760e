//! Checks on geometry derived from several design fields: the PZT plate length `l_p = l_tot / (1 + l_r)`,
//! the tip width `(2 - w_r) w_0 / w_r`, and (for a build) every feature against the kerf and the PZT edge
//! margin. Each refusal names the fields the user wrote, with their values; the bounds are justified in
//! `docs/limits.md`.

use super::Design;
use crate::input::limits::{MIN_FEATURE_MM, MIN_PLATE_LENGTH_MM};
use crate::input::{short_number, InputError};
use actuator_model::Planform;
use std::path::Path;

/// The `[geometry]` fields that set a planform, as the design file writes them (mm and ratios).
fn fields(p: &Planform) -> String {
    format!(
        "length_mm = {}, extension_ratio = {}, base_width_mm = {}, width_ratio = {}",
        short_number(p.length * 1e3),
        short_number(p.extension_ratio),
        short_number(p.base_width * 1e3),
        short_number(p.width_ratio)
    )
}

/// A planform a laser can cut and a lab can handle, whatever the process: the PZT plate at least
/// [`MIN_PLATE_LENGTH_MM`] long and the tip at least [`MIN_FEATURE_MM`] wide. `prefix` is the table the
/// fields sit in (`geometry` in a design file); errors name `prefix.length_mm` and `prefix.width_ratio`.
pub fn check_planform(file: &Path, prefix: &str, p: &Planform) -> Result<(), InputError> {
    let plate_mm = p.piezo_length() * 1e3;
    if plate_mm < MIN_PLATE_LENGTH_MM {
        return Err(InputError::invalid(
            file,
            &format!("{prefix}.length_mm"),
            fields(p),
            format!(
                "the PZT plate length_mm / (1 + extension_ratio) = {} mm is shorter than {MIN_PLATE_LENGTH_MM} mm",
                short_number(plate_mm)
            ),
        ));
    }
    let tip_mm = p.tip_width() * 1e3;
    if tip_mm < MIN_FEATURE_MM {
        return Err(InputError::invalid(
            file,
            &format!("{prefix}.width_ratio"),
            fields(p),
            format!(
                "the tip width (2 - width_ratio) base_width_mm / width_ratio = {} mm is narrower than {MIN_FEATURE_MM} mm; lower width_ratio or widen the base",
                short_number(tip_mm)
            ),
        ));
    }
    Ok(())
}

impl Design {
    /// The design's features against a process: the laser removes about one kerf along every cut, so the
    /// tip, the base, the PZT plate (inset by `pzt_margin_mm` at its tip end and sides) and a non-zero
    /// base tab must each be at least two kerfs (`kerf_mm`, the widest kerf of the cut layers). Errors
    /// name the design fields; cut-sheet calls this once per design before planning any sheet.
    pub fn check_cut(&self, kerf_mm: f64, pzt_margin_mm: f64) -> Result<(), InputError> {
        let p = &self.planform;
        let two_kerfs = 2.0 * kerf_mm;
        let kerf = short_number(kerf_mm);
        let checks = [
            (
                "geometry.width_ratio",
                "the tip width",
                p.tip_width() * 1e3 - 2.0 * pzt_margin_mm,
            ),
            (
                "geometry.base_width_mm",
                "the base width",
                p.base_width * 1e3 - 2.0 * pzt_margin_mm,
            ),
            (
                "geometry.length_mm",
                "the PZT plate length",
                p.piezo_length() * 1e3 - pzt_margin_mm,
            ),
        ];
        for (field, what, size_mm) in checks {
            if size_mm < two_kerfs {
                let inset = if pzt_margin_mm > 0.0 {
                    format!(
                        " inside the {} mm PZT edge margin",
                        short_number(pzt_margin_mm)
                    )
                } else {
                    String::new()
                };
                return Err(InputError::invalid(
                    &self.source,
                    field,
                    fields(p),
                    format!(
                        "{what}{inset} is {} mm, narrower than twice the kerf (2 x {kerf} mm): the laser would cut it away",
                        short_number(size_mm)
                    ),
                ));
            }
        }
        let tab_mm = p.base_tab * 1e3;
        if tab_mm > 0.0 && tab_mm < two_kerfs {
            return Err(InputError::invalid(
                &self.source,
                "geometry.base_tab_mm",
                short_number(tab_mm),
                format!("a base tab must be 0 or at least twice the kerf (2 x {kerf} mm)"),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn planform(l_mm: f64, l_r: f64, w0_mm: f64, w_r: f64) -> Planform {
        Planform::new(l_mm * 1e-3, l_r, w0_mm * 1e-3, w_r, 0.0).unwrap()
    }

    #[test]
    fn plate_and_tip_bounds_name_the_fields() {
        let f = Path::new("d.toml");
        // Thesis design C (Table 4.14) passes.
        assert!(check_planform(f, "geometry", &planform(42.2, 0.833, 5.0, 1.667)).is_ok());
        // l_p = 10 / 21 mm.
        let e = check_planform(f, "geometry", &planform(10.0, 20.0, 5.0, 1.0))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("d.toml: geometry.length_mm = length_mm = 10, extension_ratio = 20"),
            "{e}"
        );
        assert!(e.contains("0.47619 mm is shorter than 1 mm"), "{e}");
        // Tip (2 - 1.99) * 5 / 1.99 = 0.0251 mm.
        let e = check_planform(f, "geometry", &planform(42.2, 0.0, 5.0, 1.99))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("geometry.width_ratio") && e.contains("0.0251256 mm"),
            "{e}"
        );
    }

    fn design_c(width_ratio: f64, base_tab_mm: f64) -> Design {
        let text = format!(
            "name = \"c\"\n[geometry]\nlength_mm = 42.2\nextension_ratio = 0.833\nbase_width_mm = 5\n\
             width_ratio = {width_ratio}\nbase_tab_mm = {base_tab_mm}\n[laminate]\npzt = \"PZT-5H\"\n\
             pzt_thickness_mm = 0.267\nply = \"CF-thesis\"\nlayup_deg = [0, 90, 0]\n[drive]\n\
             mode = \"parallel\"\nfield_V_per_mm = 800\n"
        );
        let path = Path::new("c.toml");
        Design::from_table(path, &crate::input::parse_toml(path, &text).unwrap()).unwrap()
    }

    #[test]
    fn cut_check_needs_two_kerfs_per_feature() {
        // Design C: tip (2 - 1.667) 5 / 1.667 = 0.999 mm, plate 42.2 / 1.833 = 23.0 mm.
        let c = design_c(1.667, 0.0);
        assert!(c.check_cut(0.05, 0.0).is_ok());
        assert!(c.check_cut(0.49, 0.0).is_ok());
        let e = c.check_cut(0.5, 0.0).unwrap_err().to_string();
        assert!(
            e.starts_with("c.toml: geometry.width_ratio = length_mm = 42.2,")
                && e.contains(
                    "the tip width is 0.9988 mm, narrower than twice the kerf (2 x 0.5 mm)"
                ),
            "{e}"
        );
        // A 0.3 mm PZT edge margin takes 0.6 mm off the tip: 0.399 mm left, less than 2 x 0.2 mm.
        let e = c.check_cut(0.2, 0.3).unwrap_err().to_string();
        assert!(
            e.contains("inside the 0.3 mm PZT edge margin is 0.3988 mm"),
            "{e}"
        );
        let e = design_c(1.667, 0.05)
            .check_cut(0.03, 0.0)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "c.toml: geometry.base_tab_mm = 0.05: a base tab must be 0 or at least twice the kerf (2 x 0.03 mm)"
        );
    }
}
