//! report.md and the terminal summary, rendered from the same [`Report`] tree as report.json.

use super::tree::{Errors, LibraryOnlyErrors, Report, SelectedEffect, VerdictDetail};
use crate::calibrate::baseline::OutputErrors;
use crate::calibrate::discover::Discovery;
use crate::calibrate::rounded::{finite_or_word, interval_text};
use crate::calibrate::select::separating::DesignPoint;
use std::fmt::Write as _;

fn fmt_row(label: &str, e: &Option<OutputErrors>) -> String {
    match e {
        None => format!("| {label} | – | – | – | – | – | – |\n"),
        Some(e) => format!(
            "| {label} | {:.3} ± {:.3} | {:.3} | {:.1} | {:.1} | {:.0}% | {:.0}% |\n",
            e.k_mean,
            e.k_std,
            e.rmse_log,
            e.mape,
            e.max_error,
            100.0 * e.within_10,
            100.0 * e.within_20
        ),
    }
}

/// Markdown table of before / after (and the thesis' fits), then the cross-validated errors.
pub fn error_tables(
    before: &Errors,
    library_only: Option<&LibraryOnlyErrors>,
    after: &Errors,
    thesis: &Errors,
) -> String {
    let mut s = String::new();
    s.push_str("| output | model | k = model/measured | RMSE log | MAPE % | max % | within 10% | within 20% |\n");
    s.push_str("|---|---|---|---|---|---|---|---|\n");
    let library = library_only.map(|l| ("library only", l.errors.table));
    for (name, pick) in [
        ("mass", 0usize),
        ("free deflection", 1),
        ("blocked force", 2),
        ("stiffness", 3),
    ] {
        let models = [("original", before.table)]
            .into_iter()
            .chain(library)
            .chain([("calibrated", after.table), ("thesis fits", thesis.table)]);
        for (label, t) in models {
            let e = [&t.mass, &t.free_deflection, &t.blocked_force, &t.stiffness][pick];
            s.push_str(&fmt_row(&format!("{name} | {label}"), e));
        }
    }
    let library_cv = library_only
        .map(|l| format!(", library only {:.3}", l.errors.cv_rmse.unwrap_or(f64::NAN)))
        .unwrap_or_default();
    let _ = writeln!(
        s,
        "\nCross-validated RMSE of the log residuals (δ, F_b; whole actuators held out): original {:.3}{library_cv}, calibrated {:.3}.",
        before.cv_rmse.unwrap_or(f64::NAN),
        after.cv_rmse.unwrap_or(f64::NAN)
    );
    if let Some(l) = library_only {
        let _ = writeln!(
            s,
            "Library only (the same data without the declared effects): {}.",
            verdict_line(l.verdict, &l.verdict_detail)
        );
    }
    s
}

/// One line for the terminal: the variable the residual follows and the leading candidates.
pub fn discovery_line(d: &Discovery) -> String {
    let lead: Vec<&str> = d
        .candidates
        .iter()
        .take(3)
        .map(|c| c.name.as_str())
        .collect();
    format!(
        "discovery: the residual follows {}; leading candidates {} (report.md, \"Discovery\")\n",
        d.leading_variable
            .as_deref()
            .unwrap_or("no single variable"),
        lead.join(", ")
    )
}

/// The discovery section: power laws, the leading trends, the ranked candidates, the separating designs.
fn discovery(d: &Discovery) -> String {
    let mut md = String::from("\n## Discovery: what the residual looks like\n\n");
    if let Some(v) = &d.leading_variable {
        let _ = writeln!(md, "The residual follows {v} most.\n");
    }
    md.push_str("Power law of each residual factor (measured/model) in the design variables together, exponent [95% interval]:\n\n| residual | n | R² | exponents |\n|---|---|---|---|\n");
    for law in &d.power_laws {
        let terms: Vec<String> = law
            .exponents
            .iter()
            .map(|e| {
                format!(
                    "{} {} {}",
                    e.variable,
                    finite_or_word(e.estimate, |v| format!("{v:+.3}")),
                    interval_text(e.interval, |v| format!("{v:+.3}"))
                )
            })
            .collect();
        let _ = writeln!(
            md,
            "| {} | {} | {:.3} | {} |",
            law.residual,
            law.n,
            law.r_squared,
            terms.join("; ")
        );
    }
    md.push_str("\nStrongest one-variable power laws:\n\n| residual | variable | exponent | 95% interval | R² | p |\n|---|---|---|---|---|---|\n");
    for t in d.trends.iter().take(6) {
        let e = &t.exponent;
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.3} | {:.2e} |",
            t.residual,
            e.variable,
            finite_or_word(e.estimate, |v| format!("{v:+.3}")),
            interval_text(e.interval, |v| format!("{v:+.3}")),
            t.r_squared,
            e.p
        );
    }
    let _ = writeln!(
        md,
        "\nEffects and combinations that would produce it, ranked by {}:\n\n| rank | effect or primitive | library | parameter | estimate | 95% interval | η | ΔAICc | gain over {{η}} | RMSE log |\n|---|---|---|---|---|---|---|---|---|---|",
        d.ranked_by
    );
    for (i, c) in d.candidates.iter().take(8).enumerate() {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {:.3} | {:.1} | {:.1} | {:.4} |",
            i + 1,
            c.name,
            if c.library { "yes" } else { "no" },
            c.parameter,
            finite_or_word(c.estimate, |v| format!("{v:.4e}")),
            interval_text(c.interval, |v| format!("{v:.4e}")),
            c.eta,
            c.delta_aicc,
            c.gain_over_eta,
            c.rmse_log
        );
    }
    if !d.designs.is_empty() {
        let names: Vec<&str> = d.designs[0]
            .predictions
            .iter()
            .map(|p| p.candidate.as_str())
            .collect();
        let _ = writeln!(
            md,
            "\nDesigns whose measurement would separate {} (predicted δ mm / F_b N of each):\n\n| l_tot mm | l_r | w0 mm | w_r | t_p mm | layup | V | separation (log) | predictions |\n|---|---|---|---|---|---|---|---|---|",
            names.join(", ")
        );
        for x in &d.designs {
            let preds: Vec<String> = x
                .predictions
                .iter()
                .map(|p| {
                    format!(
                        "{}: {:.4} / {:.4}",
                        p.candidate, p.free_deflection_mm, p.blocked_force_n
                    )
                })
                .collect();
            let _ = writeln!(
                md,
                "| {} | {:.3} | {} |",
                design_cells(&x.design),
                x.separation_log,
                preds.join("; ")
            );
        }
    }
    if !d.mass_forms.is_empty() {
        md.push_str("\nThe mass residual on its own, ranked by AICc on the log masses (the selection's mass models and each mass-only form, alone and on top of the chosen one):\n\n| rank | mass model or form | parameter | estimate | 95% interval | ΔAICc | gain over the chosen | RMSE log |\n|---|---|---|---|---|---|---|---|\n");
        for (i, f) in d.mass_forms.iter().take(8).enumerate() {
            let (estimate, interval) = if f.library {
                ("–".to_string(), "–".to_string())
            } else {
                (
                    finite_or_word(f.estimate, |v| format!("{v:.4e}")),
                    interval_text(f.interval, |v| format!("{v:.4e}")),
                )
            };
            let _ = writeln!(
                md,
                "| {} | {} | {} | {estimate} | {interval} | {:.1} | {:.1} | {:.4} |",
                i + 1,
                f.name,
                f.parameter,
                f.delta_aicc,
                f.gain_over_chosen,
                f.rmse_log
            );
        }
    }
    md.push_str("\nThe leading candidates are written as effects to declare in `suggested-effects.toml` (when one lies outside the library); `calibrate --effects suggested-effects.toml` runs the next step.\n");
    md
}

/// The cells `l_tot mm | l_r | w0 mm | w_r | t_p mm | layup | V` of a design to build.
fn design_cells(d: &DesignPoint) -> String {
    d.cells()
}

/// `verdict: NAME` and what it rests on, one line.
pub fn verdict_line(verdict: &str, detail: &VerdictDetail) -> String {
    let mut out = format!("verdict: {verdict}");
    if let Some(contenders) = detail.contenders {
        let c: Vec<String> = contenders
            .iter()
            .map(|c| format!("{{{}}}", c.join(", ")))
            .collect();
        let _ = write!(out, " ({})", c.join(" vs "));
    }
    if let Some(variable) = detail.follows {
        let _ = write!(out, " (residual still follows {variable})");
    }
    if let Some(reason) = detail.reason {
        let _ = write!(out, " ({reason})");
    }
    out
}

/// A fitted parameter to `decimals` places, or to as many significant digits in scientific notation when
/// it is smaller than one unit in the last of those places: a parameter in SI (a length or a mass in a
/// declared effect, 2e-5 kg) would otherwise print as zero.
fn param(v: f64, decimals: usize) -> String {
    finite_or_word(v, |v| {
        if v != 0.0 && v.abs() < 10f64.powi(-(decimals as i32) + 2) {
            format!("{:.*e}", decimals - 1, v)
        } else {
            format!("{v:.decimals$}")
        }
    })
}

/// Terminal summary: verdict, fitted parameters with intervals, error tables.
pub fn summary(
    verdict: &str,
    detail: &VerdictDetail,
    selected: &[SelectedEffect],
    tables: [&Errors; 3],
    library_only: Option<&LibraryOnlyErrors>,
) -> String {
    let mut out = verdict_line(verdict, detail);
    out.push('\n');
    for e in selected {
        let _ = writeln!(
            out,
            "  {}: {} = {} {}",
            e.name,
            e.parameter,
            param(e.estimate, 4),
            interval_text(e.interval, |v| param(v, 4))
        );
    }
    out.push_str(&error_tables(tables[0], library_only, tables[1], tables[2]));
    out
}

/// report.md.
pub fn markdown(r: &Report) -> String {
    let mut md = format!(
        "# Calibration of `{}`\n\n{} actuators, {} rows.\n\n## Verdict: {}\n\n",
        r.data.source, r.data.actuators, r.data.rows, r.verdict
    );
    md.push_str(&verdict_line(r.verdict, &r.verdict_detail));
    md.push_str("\n\n## Parameters\n\n| effect | parameter | estimate | 95% interval | std. error |\n|---|---|---|---|---|\n");
    for e in &r.selected_effects {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} |",
            e.name,
            e.parameter,
            param(e.estimate, 5),
            interval_text(e.interval, |v| param(v, 5)),
            param(e.std_error, 5)
        );
    }
    md.push_str("\n## Error before and after\n\n");
    md.push_str(&error_tables(
        &r.before,
        r.library_only.as_ref(),
        &r.after,
        &r.thesis_adjusted,
    ));
    md.push_str("\nThe thesis fits are eqs. 4.3-4.5 (ζ = 0.94) applied to the same data: multipliers in l_r and w_0·t_p, not physics.\n");
    md.push_str("\n## Candidates\n\n| stage | effects | AICc | CV RMSE | accepted | note |\n|---|---|---|---|---|---|\n");
    for c in &r.candidates {
        let _ = writeln!(
            md,
            "| {} | {} | {:.2} | {:.4} | {} | {} |",
            if c.stage == "mass" { "mass" } else { "δ, F_b" },
            c.label(),
            c.aicc,
            c.cv_rmse,
            if c.accepted { "yes" } else { "" },
            c.note
        );
    }
    md.push_str("\n## Adequacy\n\n");
    if let Some(l) = r.adequacy.lack_of_fit {
        let _ = writeln!(
            md,
            "Lack of fit against per-actuator lines in the field: F = {:.2} ({:.0}, {:.0}), p = {:.3}; pure-error σ(log) = {:.4}.\n",
            l.f, l.df1, l.df2, l.p, l.sigma_pure
        );
    } else {
        md.push_str("No voltage sweeps of 3+ levels: no lack-of-fit test.\n\n");
    }
    if let Some(t) = &r.adequacy.resonance {
        resonance_line(&mut md, t);
    }
    md.push_str("| residual | variable | r | p (Holm) |\n|---|---|---|---|\n");
    let mut tests: Vec<_> = r.adequacy.correlations.iter().collect();
    tests.sort_by(|a, b| a.p.total_cmp(&b.p));
    for t in tests.iter().take(8) {
        let _ = writeln!(
            md,
            "| {} | {} | {:.3} | {:.3} |",
            t.residual, t.variable, t.r, t.p_holm
        );
    }
    if !r.separating_designs.is_empty() {
        md.push_str("\n## Designs that would separate the contenders\n\n| l_tot mm | l_r | w0 mm | w_r | t_p mm | layup | V | δ ratio | F ratio |\n|---|---|---|---|---|---|---|---|---|\n");
        for d in r.separating_designs {
            let _ = writeln!(
                md,
                "| {} | {:.3} | {:.3} |",
                design_cells(&d.design),
                d.deflection_ratio,
                d.force_ratio
            );
        }
    }
    if let Some(d) = r.discovery {
        md.push_str(&discovery(d));
    }
    if !r.broken_actuators.is_empty() {
        md.push_str("\n## Broken actuators\n\n| id | deflection % | force % | robust z | likely cause | excluded |\n|---|---|---|---|---|---|\n");
        let pct = |p: Option<f64>| p.map_or("–".to_string(), |p| format!("{p:+.0}"));
        for b in r.broken_actuators {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {:.1} | {} | {} |",
                b.id,
                pct(b.deflection_percent),
                pct(b.force_percent),
                b.robust_z,
                b.likely_cause,
                if b.excluded { "yes" } else { "no" }
            );
        }
    }
    if !r.outliers.is_empty() {
        md.push_str("\n## Flagged rows\n\n");
        for o in r.outliers {
            let _ = writeln!(
                md,
                "- {} (line {}), {}: studentised {:.2}, Cook's D {:.2}",
                o.id, o.line, o.output, o.studentised, o.cooks_distance
            );
        }
    }
    for n in r.notes {
        let _ = writeln!(md, "\nNote: {n}");
    }
    md.push_str("\n## Plots\n\n![parity before](parity-before.svg) ![parity after](parity-after.svg)\n\n![residuals before](residuals-before.svg) ![residuals after](residuals-after.svg)\n");
    md
}

/// The resonance tests' line of the adequacy section (docs/calibration.md §3, "The resonance").
fn resonance_line(md: &mut String, t: &crate::calibrate::select::resonance_tests::ResonanceTests) {
    let _ = writeln!(
        md,
        "Resonances of {} actuators against a precision σ(log) = {:.4} ({}): mean offset {:+.2} %, t = {:.2} on {} df, p = {:.3}; size χ² = {:.1} on {} df, p = {:.3} (each test at {}).\n",
        t.n,
        t.sigma,
        t.precision,
        100.0 * t.mean.exp_m1(),
        t.t,
        t.t_df,
        t.p_mean,
        t.chi_square,
        t.n,
        t.p_size,
        0.5 * t.alpha
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibrate::report::tree::tests::sample;

    #[test]
    fn verdict_line_names_contenders_or_the_followed_variable() {
        let r = sample();
        assert_eq!(
            verdict_line(r.verdict, &r.verdict_detail),
            "verdict: ambiguous ({dead-length} vs {clamp-compliance})"
        );
        let follows = VerdictDetail {
            follows: Some("l_r"),
            ..VerdictDetail::default()
        };
        assert_eq!(
            verdict_line("not-explained", &follows),
            "verdict: not-explained (residual still follows l_r)"
        );
        assert_eq!(
            verdict_line("explained", &VerdictDetail::default()),
            "verdict: explained"
        );
    }

    #[test]
    fn error_tables_list_every_output_and_model() {
        let r = sample();
        let t = error_tables(&r.before, None, &r.after, &r.thesis_adjusted);
        assert_eq!(t.lines().filter(|l| l.starts_with("| ")).count(), 13);
        assert!(t.contains("| mass | original | – | – | – | – | – | – |\n"));
        assert!(t.contains(
            "| free deflection | calibrated | 1.799 ± 0.123 | 0.050 | 4.0 | 7.9 | 100% | 100% |\n"
        ));
        assert!(t.contains("original 0.610, calibrated 0.052."));
    }

    #[test]
    fn summary_lists_parameters_with_intervals() {
        let r = sample();
        let s = summary(
            r.verdict,
            &r.verdict_detail,
            &r.selected_effects,
            [&r.before, &r.after, &r.thesis_adjusted],
            None,
        );
        let lines: Vec<&str> = s.lines().collect();
        assert_eq!(
            lines[0],
            "verdict: ambiguous ({dead-length} vs {clamp-compliance})"
        );
        assert_eq!(
            lines[1],
            "  dead-length: dead_length_mm = 2.2931 [1.9080, unbounded]"
        );
    }

    #[test]
    fn a_parameter_in_si_keeps_its_digits() {
        assert_eq!(param(2.29312, 4), "2.2931");
        assert_eq!(param(0.0123, 4), "0.0123");
        assert_eq!(param(0.0, 4), "0.0000");
        assert_eq!(param(f64::INFINITY, 4), "unbounded");
        assert_eq!(param(f64::NAN, 4), "none");
        // 20 mg in kg and 0.3 mm in m, which four places would print as 0.0000 and 0.0003.
        assert_eq!(param(2.034e-5, 4), "2.034e-5");
        assert_eq!(param(3.07e-4, 4), "3.070e-4");
        assert_eq!(param(-4.1e-6, 5), "-4.1000e-6");
    }

    #[test]
    fn markdown_renders_every_section_from_the_tree() {
        let md = markdown(&sample());
        assert!(md.starts_with("# Calibration of `measured.csv`\n\n12 actuators, 40 rows.\n\n## Verdict: ambiguous\n\nverdict: ambiguous ("));
        assert!(md.contains(
            "| dead-length | dead_length_mm | 2.29312 | [1.90800, unbounded] | 0.19000 |\n"
        ));
        assert!(md.contains("| δ, F_b | {d31-scale, dead-length} | -120.50 | 0.0500 | yes |  |\n"));
        assert!(md.contains("| δ, F_b | original | -10.00 | 0.6000 |  |  |\n"));
        assert!(md.contains("F = 1.50 (3, 20), p = 0.250; pure-error σ(log) = 0.0400."));
        // Correlations sorted by p: w_r (0.06) before l_r (0.4).
        assert!(md.find("| stiffness | w_r |").unwrap() < md.find("| deflection | l_r |").unwrap());
        assert!(!md.contains("## Designs that would separate"));
        assert!(md.contains("- A7 (line 9), blocked_force: studentised 3.75, Cook's D 0.50\n"));
        assert!(md.contains("\nNote: a remark\n"));
        assert!(md.ends_with("![residuals after](residuals-after.svg)\n"));
    }
}
