//! A residual named by what it touches (docs/calibration.md §3, "Verdicts"): a load cell that gives
//! under the tip lowers only the measured blocked force, by `1 / (1 + k_a / k_s)` with `k_a = F_b / δ`
//! the actuator's stiffness and `k_s` the cell's (springs in series, Hooke's law), so a stiff actuator
//! loses more. No effect of the actuator does that to the force alone, and the verdict must say so.

use crate::synthetic;

use actuator_cam::{calibrate, parse_measured as parse, Settings};
use actuator_model::Effects;
use synthetic::*;

/// The CSV with every blocked force measured through a load cell of stiffness `k_s_n_per_mm`.
pub(crate) fn through_compliant_load_cell(csv: &str, k_s_n_per_mm: f64) -> String {
    csv.lines()
        .enumerate()
        .map(|(i, line)| {
            let mut cells: Vec<String> = line.split(',').map(str::to_string).collect();
            if i > 0 {
                let delta_mm: f64 = cells[9].parse().unwrap();
                let force: f64 = cells[10].parse().unwrap();
                let k_a = force / delta_mm;
                cells[10] = format!("{:.8}", force / (1.0 + k_a / k_s_n_per_mm));
            }
            cells.join(",") + "\n"
        })
        .collect()
}

#[test]
fn a_compliant_load_cell_is_named_a_force_only_residual() {
    let csv = random_csv(Truth::Library(Effects::default()), 310);
    let cal = calibrate(
        &parse(&through_compliant_load_cell(&csv, 1.0)).unwrap(),
        &Settings::default(),
    )
    .unwrap();
    let verdict = format!("{:?}", cal.selection.verdict);
    eprintln!("{verdict} {:?}", cal.model.selected_effects);
    assert_eq!(cal.model.verdict, "not-explained", "{verdict}");
    assert!(
        verdict.contains("a force-only residual: the deflections and masses fit"),
        "{verdict}"
    );
}
