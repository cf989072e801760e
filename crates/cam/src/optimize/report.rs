//! What `optimize` prints and writes: the text report (fixed formatting, no timestamps) and the winning
//! design as a `design.toml` that `cut-sheet` reads.

use super::search::{Candidate, Design, FieldLimit, Objective, Problem};
use super::spec::{FieldSource, Range, Spec};
use super::Outcome;
use actuator_model::Performance;
use std::fmt::Write;

/// Relative distance within which a design is "at" a bound or a constraint limit.
const AT_LIMIT: f64 = 1e-6;

/// `x` with at most `places` decimals, trailing zeros dropped: `59`, `0.127`, `7.5`.
pub fn decimal(x: f64, places: usize) -> String {
    let s = format!("{x:.places$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// `[0/90/0]`.
pub fn layup_label(layup: &[f64]) -> String {
    format!("[{}]", crate::design::layup::layup_text(layup))
}

fn describe(range: &Range, scale: f64, unit: &str) -> String {
    if range.is_fixed() {
        format!("{}{unit}", decimal(range.lo * scale, 9))
    } else {
        format!(
            "[{}, {}]{unit}",
            decimal(range.lo * scale, 9),
            decimal(range.hi * scale, 9)
        )
    }
}

/// A design's stack and planform on one line, lengths to `digits` decimals (`t_p` always to µm).
pub(super) fn geometry_line(problem: &Problem, d: &Design, digits: usize) -> String {
    let c = &problem.candidates[d.candidate];
    format!(
        "t_p {:.3} mm {}, l_tot {:.digits$} mm, l_r {:.digits$}, w_0 {:.digits$} mm, w_r {:.digits$}",
        c.pzt_thickness * 1e3,
        layup_label(&c.layup),
        d.length * 1e3,
        d.extension_ratio,
        d.base_width * 1e3,
        d.width_ratio,
    )
}

/// One-line summary of a design.
fn one_line(problem: &Problem, d: &Design) -> String {
    format!(
        "{}: mass {:.3} mg, U {:.6} mJ",
        geometry_line(problem, d, 4),
        d.mass * 1e6,
        d.energy * 1e3
    )
}

fn field_note(c: &Candidate) -> &'static str {
    match c.field_limit {
        FieldLimit::Requested => "requested",
        FieldLimit::Voltage => "capped by max_voltage_V",
        FieldLimit::Strain => "capped by max_peak_pzt_strain",
        FieldLimit::Poling(b) => match b {
            actuator_model::poling::Binding::Failure => "capped by the failure fit",
            actuator_model::poling::Binding::Depolarization => "capped by depolarization",
            actuator_model::poling::Binding::Bias => "capped at half the bias",
        },
    }
}

/// The full text report.
pub fn text(spec: &Spec, file: &str, outcome: &Outcome, perf: &Performance) -> String {
    let mut s = String::new();
    search_text(&mut s, spec, file, outcome);
    let _ = writeln!(s);
    grid_against_refined(&mut s, outcome);
    optimum_text(&mut s, spec, outcome, perf);
    let _ = writeln!(s);
    let _ = writeln!(s, "binding constraints");
    let binding = binding(spec, &outcome.problem, &outcome.best, perf);
    if binding.is_empty() {
        let _ = writeln!(s, "  none");
    }
    for line in binding {
        let _ = writeln!(s, "  {line}");
    }
    let _ = writeln!(s);
    per_laminate_text(&mut s, outcome);
    s
}

/// The search: model, objective, drive, requirement, bounds, grid and constraints.
fn search_text(s: &mut String, spec: &Spec, file: &str, outcome: &Outcome) {
    let p = &outcome.problem;
    let _ = writeln!(s, "actuator-cam optimize {file}");
    let field = match spec.field_source {
        FieldSource::Given => format!("{} V/mm", decimal(spec.field * 1e-3, 9)),
        FieldSource::Survival(share) => format!(
            "{:.1} V/mm (survival {share} from the {} Weibull fit)",
            spec.field * 1e-3,
            spec.mode.name()
        ),
    };
    let _ = writeln!(
        s,
        "model {}, objective {}, drive {} at {field}",
        p.model.name(),
        p.objective.name(),
        spec.mode.name()
    );
    let _ = writeln!(s, "requirement: U >= {} mJ", decimal(spec.energy * 1e3, 12));
    let b = &p.bounds;
    let _ = writeln!(
        s,
        "search: l_tot {}, w_0 {}, l_r {}, w_r {}; {} laminates (PZT {} x {} layups of {}); grid {} per axis, {} designs",
        describe(&b.length, 1e3, " mm"),
        describe(&b.base_width, 1e3, " mm"),
        describe(&b.extension_ratio, 1.0, ""),
        describe(&b.width_ratio, 1.0, ""),
        p.candidates.len(),
        spec.pzt.name,
        spec.layups.len(),
        spec.ply.name,
        p.grid,
        outcome.grid.evaluated
    );
    let mut limits = Vec::new();
    if p.min_tip_width > 0.0 {
        limits.push(format!(
            "tip width >= {} mm",
            decimal(p.min_tip_width * 1e3, 9)
        ));
    }
    if let Some(e) = spec.max_peak_pzt_strain {
        limits.push(format!("peak PZT strain <= {e}"));
    }
    if let Some(v) = spec.max_voltage {
        limits.push(format!("supply <= {v} V"));
    }
    if !limits.is_empty() {
        let _ = writeln!(s, "constraints: {}", limits.join(", "));
    }
}

/// The exhaustive grid's best against the refined optimum.
fn grid_against_refined(s: &mut String, outcome: &Outcome) {
    let p = &outcome.problem;
    let best = &outcome.best;
    let grid_best = outcome.grid.best;
    match &grid_best {
        Some(g) => {
            let _ = writeln!(s, "exhaustive grid: {}", one_line(p, g));
        }
        None => {
            let _ = writeln!(s, "exhaustive grid: no grid point meets the requirement");
        }
    }
    let _ = write!(s, "refined:         {}", one_line(p, best));
    if let Some(g) = &grid_best {
        let _ = match p.objective {
            Objective::MinMass => write!(
                s,
                " ({:+.3}% mass against the grid)",
                (best.mass / g.mass - 1.0) * 100.0
            ),
            Objective::MaxEnergyDensity => write!(
                s,
                " ({:+.3}% energy density against the grid)",
                (best.energy / best.mass / (g.energy / g.mass) - 1.0) * 100.0
            ),
        };
    }
    let _ = writeln!(s);
    let _ = writeln!(s);
}

/// The optimum: laminate, drive, planform and its predicted performance.
fn optimum_text(s: &mut String, spec: &Spec, outcome: &Outcome, perf: &Performance) {
    let p = &outcome.problem;
    let best = &outcome.best;
    let c = &p.candidates[best.candidate];
    let pl = best.planform();
    let _ = writeln!(s, "optimum, predicted by the {} model", p.model.name());
    let rows: Vec<(&str, String)> = vec![
        (
            "PZT",
            format!(
                "{} {:.3} mm per plate",
                spec.pzt.name,
                c.pzt_thickness * 1e3
            ),
        ),
        (
            "passive layup",
            format!(
                "{} {} ({} plies)",
                spec.ply.name,
                layup_label(&c.layup),
                c.layup.len()
            ),
        ),
        (
            "drive",
            format!(
                "{} at {:.1} V/mm ({}), {:.1} V, field survival {:.4}",
                c.section.drive.mode.name(),
                c.section.drive.field * 1e-3,
                field_note(c),
                c.section.voltage,
                c.section.drive.survival()
            ),
        ),
        (
            "total length",
            format!(
                "{:.4} mm (piezo {:.4} mm, extension {:.4} mm)",
                pl.length * 1e3,
                pl.piezo_length() * 1e3,
                pl.extension_length() * 1e3
            ),
        ),
        ("extension ratio", format!("{:.4}", pl.extension_ratio)),
        ("base width", format!("{:.4} mm", pl.base_width * 1e3)),
        ("width ratio", format!("{:.4}", pl.width_ratio)),
        ("tip width", format!("{:.4} mm", pl.tip_width() * 1e3)),
        (
            "free deflection",
            format!("{:.4} mm", perf.free_deflection * 1e3),
        ),
        (
            "blocked force",
            format!("{:.3} mN", perf.blocked_force * 1e3),
        ),
        ("energy", format!("{:.6} mJ", perf.energy * 1e3)),
        (
            "mass",
            format!(
                "{:.3} mg (PZT {:.3}, passive {:.3})",
                perf.mass * 1e6,
                perf.mass_breakdown.pzt * 1e6,
                perf.mass_breakdown.passive * 1e6
            ),
        ),
        ("energy density", format!("{:.5} J/kg", perf.energy_density)),
        ("stiffness", format!("{:.2} N/m", perf.stiffness)),
        (
            "peak PZT strain",
            format!(
                "{:.6} at x/l_p {:.2} (free to blocked, along the plate)",
                perf.peak_pzt_strain, perf.peak_pzt_strain_at
            ),
        ),
        (
            "peak PZT stress",
            format!(
                "{:.3} MPa at x/l_p {:.2}",
                perf.peak_pzt_stress * 1e-6,
                perf.peak_pzt_stress_at
            ),
        ),
    ];
    for (k, v) in rows {
        let _ = writeln!(s, "  {k:<16} {v}");
    }
}

/// Each laminate's best design, on the grid and refined, or the most energy it reaches.
fn per_laminate_text(s: &mut String, outcome: &Outcome) {
    let p = &outcome.problem;
    let best = &outcome.best;
    let _ = writeln!(s, "best per laminate (refined; * = optimum)");
    let _ = writeln!(
        s,
        "  {:>6}  {:<16} {:>7}  {:>10}  {:>10}  {:>9}  {:>7}  {:>8}  {:>7}  {:>9}",
        "t_p_mm",
        "layup_deg",
        "V/mm",
        "grid_mg",
        "mass_mg",
        "l_tot_mm",
        "l_r",
        "w_0_mm",
        "w_r",
        "U_mJ"
    );
    for (i, cand) in p.candidates.iter().enumerate() {
        let mark = if i == best.candidate { "*" } else { " " };
        let grid = outcome.grid.per_candidate[i]
            .best
            .map(|g| format!("{:.3}", g.mass * 1e6))
            .unwrap_or_else(|| "-".into());
        let head = format!(
            "{mark} {:>6.3}  {:<16} {:>7.1}  {grid:>10}",
            cand.pzt_thickness * 1e3,
            layup_label(&cand.layup),
            cand.section.drive.field * 1e-3,
        );
        match &outcome.refined[i] {
            Some(d) => {
                let _ = writeln!(
                    s,
                    "{head}  {:>10.3}  {:>9.4}  {:>7.4}  {:>8.4}  {:>7.4}  {:>9.6}",
                    d.mass * 1e6,
                    d.length * 1e3,
                    d.extension_ratio,
                    d.base_width * 1e3,
                    d.width_ratio,
                    d.energy * 1e3
                );
            }
            None => {
                let _ = writeln!(
                    s,
                    "{head}  cannot reach the energy (at most {:.6} mJ)",
                    outcome.most_energy[i].map_or(0.0, |d| d.energy * 1e3)
                );
            }
        }
    }
}

/// The search bounds a design sits on, in words (none when it is inside every range).
pub(super) fn bounds_reached(p: &Problem, d: &Design) -> Vec<String> {
    let mut out = Vec::new();
    let at = |x: f64, bound: f64| (x - bound).abs() <= AT_LIMIT * bound.abs().max(1e-12);
    let b = &p.bounds;
    let vars = [
        ("total length", d.length, &b.length, 1e3, " mm"),
        ("base width", d.base_width, &b.base_width, 1e3, " mm"),
        (
            "extension ratio",
            d.extension_ratio,
            &b.extension_ratio,
            1.0,
            "",
        ),
        ("width ratio", d.width_ratio, &b.width_ratio, 1.0, ""),
    ];
    for (name, x, range, scale, unit) in vars {
        if range.is_fixed() {
            continue;
        }
        if at(x, range.lo) {
            out.push(format!(
                "{name} at its lower bound {}{unit}",
                range.lo * scale
            ));
        } else if at(x, range.hi) {
            out.push(format!(
                "{name} at its upper bound {}{unit}",
                range.hi * scale
            ));
        }
    }
    out
}

/// The constraints and bounds the optimum sits on.
fn binding(spec: &Spec, p: &Problem, d: &Design, perf: &Performance) -> Vec<String> {
    let mut out = Vec::new();
    if perf.energy <= p.energy * (1.0 + AT_LIMIT) {
        out.push(format!(
            "energy: U = {:.6} mJ meets U_min = {} mJ (active)",
            perf.energy * 1e3,
            decimal(p.energy * 1e3, 12)
        ));
    }
    out.extend(bounds_reached(p, d));
    if p.min_tip_width > 0.0 && d.tip_width() <= p.min_tip_width * (1.0 + AT_LIMIT) {
        out.push(format!(
            "tip width {:.4} mm at min_tip_width_mm = {}",
            d.tip_width() * 1e3,
            decimal(p.min_tip_width * 1e3, 9)
        ));
    }
    let c = &p.candidates[d.candidate];
    match c.field_limit {
        FieldLimit::Requested => {}
        FieldLimit::Voltage => out.push(format!(
            "max_voltage_V = {}: field capped at {:.1} V/mm (requested {:.1} V/mm)",
            spec.max_voltage.unwrap_or(f64::NAN),
            c.section.drive.field * 1e-3,
            spec.field * 1e-3
        )),
        FieldLimit::Strain => out.push(format!(
            "max_peak_pzt_strain = {}: field capped at {:.1} V/mm (requested {:.1} V/mm)",
            spec.max_peak_pzt_strain.unwrap_or(f64::NAN),
            c.section.drive.field * 1e-3,
            spec.field * 1e-3
        )),
        FieldLimit::Poling(b) => out.push(format!(
            "the {} limit of {} drive: field capped at {:.1} V/mm (requested {:.1} V/mm)",
            b.name(),
            spec.mode.name(),
            c.section.drive.field * 1e-3,
            spec.field * 1e-3
        )),
    }
    out
}

/// A TOML float that reads back to the same `f64`.
fn toml_float(x: f64) -> String {
    // Debug prints the shortest round-trip form and always a '.' or an exponent.
    format!("{x:?}")
}

/// A ply angle: an integer when it is one (as design files write layups).
fn toml_angle(a: f64) -> String {
    if a.fract() == 0.0 && a.abs() < 1e15 {
        format!("{}", a as i64)
    } else {
        toml_float(a)
    }
}

/// The design as a `design.toml` for `cut-sheet` (no base tab; the ply thickness is the library's).
pub fn design_toml(spec: &Spec, problem: &Problem, d: &Design) -> String {
    let c = &problem.candidates[d.candidate];
    let angles: Vec<String> = c.layup.iter().map(|a| toml_angle(*a)).collect();
    format!(
        "name = \"optimized\"\n\
         quantity = 1\n\
         process = \"method-2\"\n\
         \n\
         [geometry]\n\
         length_mm = {}\n\
         extension_ratio = {}\n\
         base_width_mm = {}\n\
         width_ratio = {}\n\
         base_tab_mm = 0.0\n\
         \n\
         [laminate]\n\
         pzt = \"{}\"\n\
         pzt_thickness_mm = {}\n\
         ply = \"{}\"\n\
         layup_deg = [{}]\n\
         \n\
         [drive]\n\
         mode = \"{}\"\n\
         field_V_per_mm = {}\n{}",
        toml_float(d.length * 1e3),
        toml_float(d.extension_ratio),
        toml_float(d.base_width * 1e3),
        toml_float(d.width_ratio),
        spec.pzt.name,
        toml_float(c.pzt_thickness * 1e3),
        spec.ply.name,
        angles.join(", "),
        c.section.drive.mode.name(),
        toml_float(c.section.drive.field * 1e-3),
        if c.section.drive.mode == actuator_model::DriveMode::Biased {
            format!(
                "bias_V_per_mm = {}\n",
                toml_float(c.section.drive.bias * 1e-3)
            )
        } else {
            String::new()
        },
    )
}
