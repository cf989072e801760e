//! Report: `report.json` (issue 6 keys), `report.md`, SVG parity and residual plots, and the model file,
//! all rendered in memory and written at once through a temporary directory.

use super::baseline::{group_residuals, ErrorTable, OutputErrors};
use super::csv::Dataset;
use super::library::EffectId;
use super::model_file;
use super::select::{Candidate, Role, Verdict};
use super::variables::design_variables;
use super::Calibration;
use actuator_model::Performance;
use anyhow::Context;
use serde_json::{json, Map, Value};
use std::fmt::Write as _;
use std::path::Path;

/// Round to 6 significant digits so the text is short and the same on every run.
fn sig(x: f64) -> Value {
    if !x.is_finite() {
        return Value::Null;
    }
    let rounded: f64 = format!("{x:.5e}").parse().unwrap_or(x);
    json!(rounded)
}

fn output_json(e: &Option<OutputErrors>) -> Value {
    match e {
        None => Value::Null,
        Some(e) => json!({
            "n": e.n,
            "k_mean": sig(e.k_mean),
            "k_std": sig(e.k_std),
            "rmse_log": sig(e.rmse_log),
            "mape": sig(e.mape),
            "max_error": sig(e.max_error),
            "within_10": sig(e.within_10),
            "within_20": sig(e.within_20),
        }),
    }
}

fn table_json(t: &ErrorTable, cv: Option<f64>) -> Value {
    let mut v = json!({
        "mass": output_json(&t.mass),
        "free_deflection": output_json(&t.free_deflection),
        "blocked_force": output_json(&t.blocked_force),
        "stiffness": output_json(&t.stiffness),
        "rmse_log_actuation": sig(t.rmse_log_actuation),
    });
    if let Some(cv) = cv {
        v["cv_rmse_log_actuation"] = sig(cv);
    }
    v
}

fn names(effects: &[EffectId]) -> Vec<&'static str> {
    effects.iter().map(|e| e.name()).collect()
}

fn candidate_json(c: &Candidate) -> Value {
    let mut params = Map::new();
    for (k, id) in c.effects.iter().enumerate() {
        params.insert(id.param().name.into(), sig(c.values[k]));
    }
    json!({
        "stage": match c.stage { super::library::Stage::Mass => "mass", super::library::Stage::Actuation => "actuation" },
        "role": match c.role { Role::Original => "original", Role::Null => "null", Role::Candidate => "candidate" },
        "effects": names(&c.effects),
        "parameters": params,
        "aicc": sig(c.aicc),
        "bic": sig(c.bic),
        "cv_rmse": sig(c.cv_rmse),
        "rss": sig(c.rss),
        "n": c.n,
        "accepted": c.accepted,
        "note": c.note,
    })
}

/// Where each selected effect's parameter was fitted.
fn selected_params(cal: &Calibration) -> Vec<(EffectId, &Candidate, usize)> {
    let s = &cal.selection;
    s.selected
        .iter()
        .filter_map(|id| {
            let mass = s.final_mass_index.map(|i| &s.mass_candidates[i]);
            let act = &s.candidates[s.final_index];
            [mass, Some(act)]
                .into_iter()
                .flatten()
                .find_map(|c| c.effects.iter().position(|e| e == id).map(|k| (*id, c, k)))
        })
        .collect()
}

/// The report.json object.
pub fn report_json(cal: &Calibration, data: &Dataset, source: &str) -> Value {
    let s = &cal.selection;
    let selected: Vec<Value> = selected_params(cal)
        .into_iter()
        .map(|(id, c, k)| {
            let p = id.param().name;
            let (lo, hi) = c.intervals[k];
            json!({
                "name": id.name(),
                "parameters": { p: sig(c.values[k]) },
                "intervals": { p: [sig(lo), sig(hi)] },
                "std_errors": { p: sig(c.std_errors[k]) },
            })
        })
        .collect();
    let final_c = &s.candidates[s.final_index];
    let correlations: Vec<Value> = final_c
        .effects
        .iter()
        .enumerate()
        .flat_map(|(a, ea)| {
            final_c.effects.iter().enumerate().skip(a + 1).map(move |(b, eb)| {
                json!({"a": ea.param().name, "b": eb.param().name, "rho": sig(final_c.correlation[a][b])})
            })
        })
        .collect();
    let mut verdict_detail = json!({});
    match &s.verdict {
        Verdict::Ambiguous { contenders } => verdict_detail["contenders"] = json!(contenders),
        Verdict::NotExplained { variable } => verdict_detail["follows"] = json!(variable),
        _ => {}
    }
    let adequacy = json!({
        "passed": s.adequacy.passed,
        "lack_of_fit": s.adequacy.lack_of_fit.map(|l| json!({
            "f": sig(l.f), "df1": l.df1, "df2": l.df2, "p": sig(l.p), "sigma_pure_log": sig(l.sigma_pure)
        })),
        "worst_variable": s.adequacy.worst_variable,
        "correlations": s.adequacy.correlations.iter().map(|t| json!({
            "residual": t.residual, "variable": t.variable, "r": sig(t.r), "n": t.n,
            "p": sig(t.p), "p_holm": sig(t.p_holm)
        })).collect::<Vec<_>>(),
    });
    let corr_json = |v: &Vec<super::baseline::ResidualCorrelation>| {
        v.iter()
            .map(|c| {
                json!({"variable": c.variable, "deflection": c.deflection.map(sig),
                "stiffness": c.stiffness.map(sig), "mass": c.mass.map(sig)})
            })
            .collect::<Vec<_>>()
    };
    let mut before = table_json(&cal.before, Some(cal.cv_rmse_before));
    before["residual_correlations"] = json!(corr_json(&cal.correlations_before));
    let mut after = table_json(&cal.after, Some(cal.cv_rmse_after));
    after["residual_correlations"] = json!(corr_json(&cal.correlations_after));
    json!({
        "verdict": s.verdict.name(),
        "verdict_detail": verdict_detail,
        "selected_effects": selected,
        "parameter_correlations": correlations,
        "candidates": s.mass_candidates.iter().chain(&s.candidates).map(candidate_json).collect::<Vec<_>>(),
        "before": before,
        "after": after,
        "thesis_adjusted": table_json(&cal.thesis_adjusted, None),
        "adequacy": adequacy,
        "outliers": s.outliers.iter().map(|o| json!({
            "id": o.id, "line": o.line, "output": o.output,
            "studentised": sig(o.studentised), "cooks_distance": sig(o.cooks_distance)
        })).collect::<Vec<_>>(),
        "separating_designs": s.separating_designs.iter().map(|d| json!({
            "l_tot_mm": sig(d.l_tot_mm), "l_r": sig(d.l_r), "w0_mm": sig(d.w0_mm), "w_r": sig(d.w_r),
            "t_p_mm": sig(d.t_p_mm), "layup": d.layup, "voltage_V": sig(d.voltage_v),
            "deflection_ratio": sig(d.deflection_ratio), "force_ratio": sig(d.force_ratio)
        })).collect::<Vec<_>>(),
        "notes": s.notes,
        "data": { "source": source, "actuators": data.actuators(), "rows": data.rows.len() },
        "model_file": model_file::FILE_NAME,
    })
}

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

/// Markdown table of before / after (and the thesis' fits).
pub fn error_tables_md(cal: &Calibration) -> String {
    let mut s = String::new();
    s.push_str("| output | model | k = model/measured | RMSE log | MAPE % | max % | within 10% | within 20% |\n");
    s.push_str("|---|---|---|---|---|---|---|---|\n");
    for (name, pick) in [
        ("mass", 0usize),
        ("free deflection", 1),
        ("blocked force", 2),
        ("stiffness", 3),
    ] {
        for (label, t) in [
            ("original", &cal.before),
            ("calibrated", &cal.after),
            ("thesis fits", &cal.thesis_adjusted),
        ] {
            let e = [&t.mass, &t.free_deflection, &t.blocked_force, &t.stiffness][pick];
            s.push_str(&fmt_row(&format!("{name} | {label}"), e));
        }
    }
    let _ = writeln!(
        s,
        "\nCross-validated RMSE of the log residuals (δ, F_b; whole actuators held out): original {:.3}, calibrated {:.3}.",
        cal.cv_rmse_before, cal.cv_rmse_after
    );
    s
}

/// Short terminal summary.
pub fn summary(cal: &Calibration) -> String {
    let s = &cal.selection;
    let mut out = format!("verdict: {}", s.verdict.name());
    match &s.verdict {
        Verdict::Ambiguous { contenders } => {
            let c: Vec<String> = contenders
                .iter()
                .map(|c| format!("{{{}}}", c.join(", ")))
                .collect();
            let _ = write!(out, " ({})", c.join(" vs "));
        }
        Verdict::NotExplained { variable } => {
            let _ = write!(out, " (residual still follows {variable})");
        }
        _ => {}
    }
    out.push('\n');
    for (id, c, k) in selected_params(cal) {
        let (lo, hi) = c.intervals[k];
        let _ = writeln!(
            out,
            "  {}: {} = {:.4} [{:.4}, {:.4}]",
            id.name(),
            id.param().name,
            c.values[k],
            lo,
            hi
        );
    }
    out.push_str(&error_tables_md(cal));
    out
}

fn markdown(cal: &Calibration, data: &Dataset, source: &str) -> String {
    let s = &cal.selection;
    let mut md = format!(
        "# Calibration of `{source}`\n\n{} actuators, {} rows.\n\n## Verdict: {}\n\n",
        data.actuators(),
        data.rows.len(),
        s.verdict.name()
    );
    md.push_str(&summary(cal).lines().take(1).collect::<String>());
    md.push_str("\n\n## Parameters\n\n| effect | parameter | estimate | 95% interval | std. error |\n|---|---|---|---|---|\n");
    for (id, c, k) in selected_params(cal) {
        let (lo, hi) = c.intervals[k];
        let _ = writeln!(
            md,
            "| {} | {} | {:.5} | [{:.5}, {:.5}] | {:.5} |",
            id.name(),
            id.param().name,
            c.values[k],
            lo,
            hi,
            c.std_errors[k]
        );
    }
    md.push_str("\n## Error before and after\n\n");
    md.push_str(&error_tables_md(cal));
    md.push_str("\nThe thesis fits are eqs. 4.3-4.5 (ζ = 0.94) applied to the same data: multipliers in l_r and w_0·t_p, not physics.\n");
    md.push_str("\n## Candidates\n\n| stage | effects | AICc | CV RMSE | accepted | note |\n|---|---|---|---|---|---|\n");
    for c in s.mass_candidates.iter().chain(&s.candidates) {
        let _ = writeln!(
            md,
            "| {} | {} | {:.2} | {:.4} | {} | {} |",
            match c.stage {
                super::library::Stage::Mass => "mass",
                super::library::Stage::Actuation => "δ, F_b",
            },
            c.label(),
            c.aicc,
            c.cv_rmse,
            if c.accepted { "yes" } else { "" },
            c.note
        );
    }
    md.push_str("\n## Adequacy\n\n");
    if let Some(l) = s.adequacy.lack_of_fit {
        let _ = writeln!(
            md,
            "Lack of fit against per-actuator lines in the field: F = {:.2} ({:.0}, {:.0}), p = {:.3}; pure-error σ(log) = {:.4}.\n",
            l.f, l.df1, l.df2, l.p, l.sigma_pure
        );
    } else {
        md.push_str("No voltage sweeps of 3+ levels: no lack-of-fit test.\n\n");
    }
    md.push_str("| residual | variable | r | p (Holm) |\n|---|---|---|---|\n");
    let mut tests = s.adequacy.correlations.clone();
    tests.sort_by(|a, b| a.p.total_cmp(&b.p));
    for t in tests.iter().take(8) {
        let _ = writeln!(
            md,
            "| {} | {} | {:.3} | {:.3} |",
            t.residual, t.variable, t.r, t.p_holm
        );
    }
    if !s.separating_designs.is_empty() {
        md.push_str("\n## Designs that would separate the contenders\n\n| l_tot mm | l_r | w0 mm | w_r | t_p mm | layup | V | δ ratio | F ratio |\n|---|---|---|---|---|---|---|---|---|\n");
        for d in &s.separating_designs {
            let _ = writeln!(
                md,
                "| {:.1} | {:.2} | {:.1} | {:.2} | {:.3} | {} | {:.0} | {:.3} | {:.3} |",
                d.l_tot_mm,
                d.l_r,
                d.w0_mm,
                d.w_r,
                d.t_p_mm,
                d.layup,
                d.voltage_v,
                d.deflection_ratio,
                d.force_ratio
            );
        }
    }
    if !s.outliers.is_empty() {
        md.push_str("\n## Flagged rows\n\n");
        for o in &s.outliers {
            let _ = writeln!(
                md,
                "- {} (line {}), {}: studentised {:.2}, Cook's D {:.2}",
                o.id, o.line, o.output, o.studentised, o.cooks_distance
            );
        }
    }
    for n in &s.notes {
        let _ = writeln!(md, "\nNote: {n}");
    }
    md.push_str("\n## Plots\n\n![parity before](parity-before.svg) ![parity after](parity-after.svg)\n\n![residuals before](residuals-before.svg) ![residuals after](residuals-after.svg)\n");
    md
}

/// A minimal SVG scatter panel.
struct Panel<'a> {
    title: &'a str,
    xlabel: &'a str,
    points: Vec<(f64, f64)>,
    log: bool,
    /// Draw y = x with a ±20% band (parity) or y = 0 (residuals).
    parity: bool,
}

fn svg(panels: &[Panel], cols: usize) -> String {
    let (pw, ph) = (320.0, 280.0);
    let rows = panels.len().div_ceil(cols);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"11\">\n",
        pw * cols as f64,
        ph * rows as f64
    );
    for (i, p) in panels.iter().enumerate() {
        let (ox, oy) = ((i % cols) as f64 * pw, (i / cols) as f64 * ph);
        let (l, r, t, b) = (ox + 50.0, ox + pw - 15.0, oy + 25.0, oy + ph - 40.0);
        let tr = |v: f64| if p.log { v.max(1e-30).log10() } else { v };
        let pts: Vec<(f64, f64)> = p.points.iter().map(|&(x, y)| (tr(x), tr(y))).collect();
        let (mut x0, mut x1, mut y0, mut y1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for &(x, y) in &pts {
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        if p.parity {
            x0 = x0.min(y0);
            y0 = x0;
            x1 = x1.max(y1);
            y1 = x1;
        } else {
            let m = y0.abs().max(y1.abs()).max(0.05);
            y0 = -m;
            y1 = m;
        }
        if !x0.is_finite() {
            (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
        }
        let padx = ((x1 - x0) * 0.05).max(1e-9);
        let pady = ((y1 - y0) * 0.05).max(1e-9);
        let (x0, x1, y0, y1) = (x0 - padx, x1 + padx, y0 - pady, y1 + pady);
        let sx = |x: f64| l + (x - x0) / (x1 - x0) * (r - l);
        let sy = |y: f64| b - (y - y0) / (y1 - y0) * (b - t);
        let _ = writeln!(s, "<rect x=\"{l:.1}\" y=\"{t:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"none\" stroke=\"#444\"/>", r - l, b - t);
        let _ = writeln!(
            s,
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\" font-weight=\"bold\">{}</text>",
            (l + r) / 2.0,
            oy + 15.0,
            p.title
        );
        let _ = writeln!(
            s,
            "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>",
            (l + r) / 2.0,
            b + 30.0,
            p.xlabel
        );
        let _ = writeln!(s, "<text x=\"{:.1}\" y=\"{:.1}\">{:.3}</text><text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{:.3}</text>", l, b + 14.0, if p.log { 10f64.powf(x0) } else { x0 }, r, b + 14.0, if p.log { 10f64.powf(x1) } else { x1 });
        let _ = writeln!(s, "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{:.3}</text><text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{:.3}</text>", l - 3.0, b, if p.log { 10f64.powf(y0) } else { y0 }, l - 3.0, t + 10.0, if p.log { 10f64.powf(y1) } else { y1 });
        if p.parity {
            for (f, dash) in [
                (1.0f64, ""),
                (1.2, " stroke-dasharray=\"4 3\""),
                (1.0 / 1.2, " stroke-dasharray=\"4 3\""),
            ] {
                let d = if p.log { f.log10() } else { 0.0 };
                let _ = writeln!(s, "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"#999\"{dash}/>", sx(x0), sy(x0 + d), sx(x1), sy(x1 + d));
            }
        } else {
            let _ = writeln!(
                s,
                "<line x1=\"{l:.1}\" y1=\"{:.1}\" x2=\"{r:.1}\" y2=\"{:.1}\" stroke=\"#999\"/>",
                sy(0.0),
                sy(0.0)
            );
        }
        for &(x, y) in &pts {
            let _ = writeln!(s, "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"2.5\" fill=\"#1f77b4\" fill-opacity=\"0.7\"/>", sx(x), sy(y));
        }
    }
    s.push_str("</svg>\n");
    s
}

fn parity_svg(data: &Dataset, preds: &[Performance], when: &str) -> String {
    let mut d = Vec::new();
    let mut f = Vec::new();
    for (m, p) in data.rows.iter().zip(preds) {
        if let Some(v) = m.free_deflection {
            d.push((v * 1e3, p.free_deflection * 1e3));
        }
        if let Some(v) = m.blocked_force {
            f.push((v * 1e3, p.blocked_force * 1e3));
        }
    }
    let t1 = format!("free deflection mm ({when})");
    let t2 = format!("blocked force mN ({when})");
    svg(
        &[
            Panel {
                title: &t1,
                xlabel: "measured (y: model), ±20% dashed",
                points: d,
                log: true,
                parity: true,
            },
            Panel {
                title: &t2,
                xlabel: "measured (y: model), ±20% dashed",
                points: f,
                log: true,
                parity: true,
            },
        ],
        2,
    )
}

fn residual_svg(data: &Dataset, preds: &[Performance], when: &str) -> String {
    let res = group_residuals(data, preds);
    let vars: Vec<_> = data
        .groups
        .iter()
        .map(|g| design_variables(&data.rows[g[0]]))
        .collect();
    let picks = [1usize, 2, 3, 5, 7];
    let mut titles = Vec::new();
    for kind in ["ln(δ meas/model)", "ln(k meas/model)"] {
        for &k in &picks {
            titles.push((kind, k));
        }
    }
    let labels: Vec<String> = titles
        .iter()
        .map(|(kind, _)| format!("{kind} ({when})"))
        .collect();
    let panels: Vec<Panel> = titles
        .iter()
        .zip(&labels)
        .map(|(&(kind, k), title)| Panel {
            title,
            xlabel: vars.first().map(|v| v[k].0).unwrap_or(""),
            points: vars
                .iter()
                .zip(&res)
                .filter_map(|(v, r)| {
                    let y = if kind.starts_with("ln(δ") {
                        r.deflection
                    } else {
                        r.stiffness
                    };
                    y.map(|y| (v[k].1, y))
                })
                .collect(),
            log: false,
            parity: false,
        })
        .collect();
    svg(&panels, picks.len())
}

/// Every output file, name and text.
pub fn render(
    cal: &Calibration,
    data: &Dataset,
    source: &str,
) -> anyhow::Result<Vec<(String, String)>> {
    let json = serde_json::to_string_pretty(&report_json(cal, data, source))?;
    Ok(vec![
        (
            model_file::FILE_NAME.into(),
            model_file::to_toml(&cal.model)?,
        ),
        ("report.json".into(), json),
        ("report.md".into(), markdown(cal, data, source)),
        (
            "parity-before.svg".into(),
            parity_svg(data, &cal.predictions_before, "original"),
        ),
        (
            "parity-after.svg".into(),
            parity_svg(data, &cal.predictions_after, "calibrated"),
        ),
        (
            "residuals-before.svg".into(),
            residual_svg(data, &cal.predictions_before, "original"),
        ),
        (
            "residuals-after.svg".into(),
            residual_svg(data, &cal.predictions_after, "calibrated"),
        ),
    ])
}

/// Write the files into a temporary directory beside `dir`, then move them into place.
pub fn write_atomically(dir: &Path, files: &[(String, String)]) -> anyhow::Result<()> {
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    std::fs::create_dir_all(&parent).with_context(|| format!("creating {}", parent.display()))?;
    let tmp = tempfile::Builder::new()
        .prefix(".calibrate-")
        .tempdir_in(&parent)
        .with_context(|| format!("creating a temporary directory in {}", parent.display()))?;
    for (name, text) in files {
        std::fs::write(tmp.path().join(name), text).with_context(|| format!("writing {name}"))?;
    }
    if !dir.exists() {
        let staged = tmp.keep();
        std::fs::rename(&staged, dir)
            .with_context(|| format!("moving the results to {}", dir.display()))?;
    } else {
        for (name, _) in files {
            std::fs::rename(tmp.path().join(name), dir.join(name))
                .with_context(|| format!("moving {name} into {}", dir.display()))?;
        }
    }
    Ok(())
}
