//! docs/validation.md: the model against published measurements. The table between the markers
//! `<!-- validation:begin -->` and `<!-- validation:end -->` is what this test computes from `predict`'s
//! output under each model, so a change in the model shows up as a changed row; `VALIDATION_UPDATE=1`
//! rewrites it. The published values and their sources are here, beside the stacks the tool needs.

use crate::common::*;
use std::fmt::Write as _;
use std::path::Path;

/// The models each row is predicted with, in the table's column order.
pub(crate) const MODELS: &[&str] = &["original", "thesis-adjusted", "nonlinear"];

const BEGIN: &str = "<!-- validation:begin -->";
const END: &str = "<!-- validation:end -->";

/// One published measurement and the tool's ratio to it under each model (`None` where a model
/// does not predict the quantity). A band (the MFI's unknown stack) has a lowest and a highest ratio.
pub(crate) struct Row {
    pub(crate) item: String,
    pub(crate) quantity: &'static str,
    pub(crate) published: String,
    /// The published scatter of the ratio, where the source gives one: a ratio within `1 ± scatter`
    /// is within it (the thesis' standard deviation `s` of k, the MFI's two actuators' half range).
    pub(crate) scatter: Option<f64>,
    pub(crate) source: &'static str,
    pub(crate) assumption: String,
    pub(crate) ratios: Vec<Option<(f64, f64)>>,
}

/// `predict --json --model MODEL FILE`; `None` where the model refuses the design.
pub(crate) fn predict(file: &Path, model: &str) -> Option<serde_json::Value> {
    let out = run(&[
        "predict",
        "--json",
        "--model",
        model,
        file.to_str().unwrap(),
    ]);
    out.status
        .success()
        .then(|| serde_json::from_slice(&out.stdout).unwrap())
}

pub(crate) fn number(j: &serde_json::Value, key: &str) -> f64 {
    j[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {j}"))
}

/// The thesis' model mass: PZT and carbon only (thesis §4.2.4: "the volume of the piezoelectric
/// ceramic and the carbon fiber … multiplying by the respective densities"), without a bond layer.
fn thesis_model_mass(j: &serde_json::Value) -> f64 {
    let b = &j["mass_breakdown_mg"];
    b["pzt"].as_f64().unwrap() + b["passive"].as_f64().unwrap()
}

/// A thesis design (examples/published/thesis-designs.csv) as a design file, built by `process` and
/// driven at `volts` in parallel.
fn thesis_design(dir: &Path, name: &str, process: &str, volts: f64) -> std::path::PathBuf {
    let table = std::fs::read_to_string(example_path("published/thesis-designs.csv")).unwrap();
    let row: Vec<&str> = table
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|r| r[0] == name)
        .unwrap_or_else(|| panic!("design {name} missing"));
    let layup = match row[7] {
        "3" => "[0, 90, 0]",
        "5" => "[0, 0, 90, 0, 0]",
        "7" => "[0, 0, 0, 90, 0, 0, 0]",
        p => panic!("{p} plies"),
    };
    let text = format!(
        "name = \"thesis-{name}\"\nquantity = 1\nprocess = \"{process}\"\n\n[geometry]\nlength_mm = {}\n\
         extension_ratio = {}\nbase_width_mm = {}\nwidth_ratio = {}\nbase_tab_mm = 0.0\n\n[laminate]\n\
         pzt = \"PZT-5H\"\npzt_thickness_mm = {}\nply = \"CF-thesis\"\nlayup_deg = {layup}\n\n[drive]\n\
         mode = \"parallel\"\nvoltage_V = {volts}\n",
        row[2], row[3], row[4], row[5], row[6]
    );
    let path = dir.join(format!("thesis-{name}-{process}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Thesis Tables 4.2-4.5: k = mean(model / measured) over a series (eq. 4.1) for mass, free
/// deflection and blocked force, measured from ±50 V sweeps (thesis §3.4). The tool's ratio to the
/// measurements under a model M is k · mean(M / thesis model) over the series' designs: exact where
/// M / thesis model is the same for every design of the series, and the thesis publishes only k.
fn thesis_series(dir: &Path) -> Vec<Row> {
    type Series = (
        &'static str,
        &'static str,
        std::ops::RangeInclusive<u32>,
        [f64; 3],
        [f64; 3],
    );
    // (table, process, designs, k, s) for mass, free deflection and blocked force.
    let series: [Series; 4] = [
        (
            "Table 4.2",
            "method-1",
            1..=12,
            [0.833, 2.72, 9.20],
            [0.130, 0.682, 4.53],
        ),
        (
            "Table 4.3",
            "method-2",
            1..=12,
            [0.734, 2.11, 4.36],
            [0.107, 0.671, 1.29],
        ),
        (
            "Table 4.4",
            "method-2",
            13..=20,
            [0.746, 2.65, 3.92],
            [0.0545, 0.212, 1.32],
        ),
        (
            "Table 4.5",
            "method-2",
            21..=24,
            [1.02, 1.56, 3.63],
            [0.0317, 0.257, 0.360],
        ),
    ];
    let quantities = [
        ("mass", "mass_mg"),
        ("free deflection", "free_deflection_mm"),
        ("blocked force", "blocked_force_N"),
    ];
    let mut rows = Vec::new();
    for (table, process, designs, k, sd) in series {
        let files: Vec<_> = designs
            .clone()
            .map(|n| thesis_design(dir, &n.to_string(), process, 50.0))
            .collect();
        let by_model: Vec<Vec<Option<serde_json::Value>>> = MODELS
            .iter()
            .map(|m| files.iter().map(|f| predict(f, m)).collect())
            .collect();
        // The thesis' own model is the original, one of MODELS: its predictions are reused.
        let original = MODELS.iter().position(|&m| m == "original").unwrap();
        let thesis: Vec<&serde_json::Value> = by_model[original]
            .iter()
            .map(|p| p.as_ref().unwrap())
            .collect();
        for (q, (quantity, key)) in quantities.into_iter().enumerate() {
            let ratios = by_model
                .iter()
                .map(|preds| {
                    let each: Option<Vec<f64>> = preds
                        .iter()
                        .zip(&thesis)
                        .map(|(p, t)| {
                            let p = p.as_ref()?;
                            let (model, base) = if key == "mass_mg" {
                                (number(p, key), thesis_model_mass(t))
                            } else {
                                (number(p, key), number(t, key))
                            };
                            Some(model / base)
                        })
                        .collect();
                    each.map(|v| {
                        let r = k[q] * v.iter().sum::<f64>() / v.len() as f64;
                        (r, r)
                    })
                })
                .collect();
            rows.push(Row {
                item: format!("thesis designs {}-{}", designs.start(), designs.end()),
                quantity,
                published: format!("k = {} (s {})", k[q], sd[q]),
                scatter: Some(sd[q]),
                source: match table {
                    "Table 4.2" => "thesis Table 4.2 (method 1)",
                    "Table 4.3" => "thesis Table 4.3",
                    "Table 4.4" => "thesis Table 4.4",
                    _ => "thesis Table 4.5",
                },
                assumption: format!(
                    "the designs of Tables 3.4-3.6 as built ({process}), parallel drive at 50 V"
                ),
                ratios,
            });
        }
    }
    rows
}

/// One design file against single published values: `(quantity, json key, scale to the published
/// unit, published value, its text)`.
fn single(
    file: &Path,
    item: &str,
    source: &'static str,
    assumption: &str,
    values: &[(&'static str, &str, f64, f64, &str)],
) -> Vec<Row> {
    let preds: Vec<_> = MODELS.iter().map(|m| predict(file, m)).collect();
    values
        .iter()
        .map(|&(quantity, key, scale, published, text)| Row {
            item: item.to_string(),
            quantity,
            published: text.to_string(),
            scatter: None,
            source,
            assumption: assumption.to_string(),
            ratios: preds
                .iter()
                .map(|p| {
                    p.as_ref().map(|p| {
                        let r = number(p, key) * scale / published;
                        (r, r)
                    })
                })
                .collect(),
        })
        .collect()
}

/// The MFI 02γ actuators over the carbon stacks the outline allows (3, 4 and 5 plies of the thesis'
/// carbon; the lab does not publish its stack): the lowest and highest ratio over the band.
fn mfi_band(dir: &Path) -> Vec<Row> {
    let base = std::fs::read_to_string(example_path("published/mfi-02gamma.toml")).unwrap();
    let stacks = ["[0, 90, 0]", "[0, 90, 90, 0]", "[0, 0, 90, 0, 0]"];
    let files: Vec<_> = stacks
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let path = dir.join(format!("mfi-{i}.toml"));
            std::fs::write(&path, base.replace("[0, 90, 0]", s)).unwrap();
            path
        })
        .collect();
    // (quantity, key, scale, published: the mean of the two actuators, their half range over it, text)
    let values: [(&str, &str, f64, f64, f64, &str); 4] = [
        (
            "free deflection",
            "free_deflection_mm",
            1e3,
            326.0,
            11.0 / 326.0,
            "315, 337 µm",
        ),
        (
            "blocked force",
            "blocked_force_N",
            1e3,
            43.0,
            0.0,
            "43, 43 mN",
        ),
        (
            "stiffness",
            "stiffness_N_per_m",
            1.0,
            122.0,
            0.0,
            "122, 122 N/m",
        ),
        (
            "first resonance",
            "resonance_Hz",
            1.0,
            575.0,
            46.0 / 575.0,
            "621, 529 Hz",
        ),
    ];
    let preds: Vec<Vec<Option<serde_json::Value>>> = MODELS
        .iter()
        .map(|m| files.iter().map(|f| predict(f, m)).collect())
        .collect();
    values
        .iter()
        .map(|&(quantity, key, scale, published, half_range, text)| Row {
            item: "MFI 02γ actuator".to_string(),
            quantity,
            published: text.to_string(),
            scatter: Some(half_range),
            source: "Fearing lab, MFI 02γ page",
            assumption: "(10 + 6) × 3 mm, 127 µm PZT-5H, 3 to 5 carbon plies (unpublished), \
                         rectangular, 150 V parallel"
                .to_string(),
            ratios: preds
                .iter()
                .map(|ps| {
                    let r: Option<Vec<f64>> = ps
                        .iter()
                        .map(|p| p.as_ref().map(|p| number(p, key) * scale / published))
                        .collect();
                    r.map(|r| {
                        let lo = r.iter().cloned().fold(f64::INFINITY, f64::min);
                        let hi = r.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
                        (lo, hi)
                    })
                })
                .collect(),
        })
        .collect()
}

/// The actuator of Jafferis, Smith & Wood (2015): its blocked force as transcribed, 150-170 mN after
/// the fixture's correction, at the script's 300 V on one plate. Whether that is the one-sided force or
/// the peak-to-peak one is not transcribed, so the row is the band between the two (twice the one-sided
/// force, every model's half-cycles being the same amplitude either way), against the range's middle;
/// the range is the measurement's own spread, not a scatter of repeated actuators, so no ✓ is given.
fn jafferis2015() -> Row {
    let file = example_path("published/jafferis2015-actuator.toml");
    Row {
        item: "actuator of Jafferis et al. 2015".to_string(),
        quantity: "blocked force",
        published: "150–170 mN".to_string(),
        scatter: None,
        source: "Jafferis, Smith & Wood, Smart Mater. Struct. 2015 (as transcribed, §1)",
        assumption: "135 µm PZT-5H, one 50 µm 340 GPa carbon ply (M60J's transverse values), 9 mm + 0.25 \
                     extension, w_nom 1.125 mm, w_r 1.556, one plate at 300 V; one-sided to peak-to-peak"
            .to_string(),
        ratios: MODELS
            .iter()
            .map(|m| {
                predict(&file, m).map(|p| {
                    let one_sided = number(&p, "blocked_force_N") * 1e3 / 160.0;
                    (one_sided, 2.0 * one_sided)
                })
            })
            .collect(),
    }
}

fn all_rows() -> Vec<Row> {
    let dir = tempfile::tempdir().unwrap();
    let mut rows = thesis_series(dir.path());
    for (design, measured) in [("B", [960.1, 0.0654]), ("C", [293.2, 0.0379])] {
        rows.extend(single(
            &example_path(&format!("thesis-{design}.toml")),
            &format!("thesis design {design}"),
            "thesis Table 4.15",
            "as designed (Table 4.14), method 2, 800 V/mm parallel",
            &[
                (
                    "mass",
                    "mass_mg",
                    1.0,
                    measured[0],
                    &format!("{} mg", measured[0]),
                ),
                (
                    "energy",
                    "energy_mJ",
                    1.0,
                    measured[1],
                    &format!("{} mJ", measured[1]),
                ),
            ],
        ));
    }
    rows.extend(single(
        &example_path("published/omega-strip.toml"),
        "60 × 20 × 0.6 mm strip",
        "thesis Table 4.6",
        "0.2 / 0.2 / 0.2 mm PZT-5H / steel / PZT-5H (unpublished), 60 mm free, 150 V parallel",
        &[
            ("mass", "mass_mg", 1.0, 4450.0, "4.45 g"),
            (
                "free deflection",
                "free_deflection_mm",
                1.0,
                2.47,
                "2.47 mm",
            ),
            ("blocked force", "blocked_force_N", 1.0, 0.39, "0.39 N"),
        ],
    ));
    rows.extend(mfi_band(dir.path()));
    rows.push(jafferis2015());
    rows.push(crate::validation_vehicle::operating_point(dir.path()));
    rows
}

fn ratio_cell(r: Option<(f64, f64)>) -> String {
    match r {
        None => "—".to_string(),
        Some((lo, hi)) if (hi - lo).abs() < 5e-4 => format!("{lo:.3}"),
        Some((lo, hi)) => format!("{lo:.3}–{hi:.3}"),
    }
}

/// How far a ratio is from 1, either way: |ln r|.
fn miss(r: f64) -> f64 {
    r.ln().abs()
}

/// The table and, below it, the median and the worst ratio of each model (a band counts at both
/// ends; the worst is the farthest from 1 either way).
fn render(rows: &[Row]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| item | quantity | published | source | stack or assumption | {} |",
        MODELS.join(" | ")
    );
    let _ = writeln!(s, "|---|---|---|---|---|{}", "---|".repeat(MODELS.len()));
    let within = |r: &Row, x: Option<(f64, f64)>| match (r.scatter, x) {
        // A band is within where some stack of it is.
        (Some(sd), Some((lo, hi))) => lo <= 1.0 + sd && hi >= 1.0 - sd,
        _ => false,
    };
    for r in rows {
        let cells: Vec<String> = r
            .ratios
            .iter()
            .map(|&x| {
                let mark = if within(r, x) { " ✓" } else { "" };
                format!("{}{mark}", ratio_cell(x))
            })
            .collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            r.item,
            r.quantity,
            r.published,
            r.source,
            r.assumption,
            cells.join(" | ")
        );
    }
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "| model | rows | median ratio | worst ratio | within the published scatter |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|");
    let with_scatter = rows.iter().filter(|r| r.scatter.is_some()).count();
    for (m, model) in MODELS.iter().enumerate() {
        let mut all: Vec<f64> = rows
            .iter()
            .filter_map(|r| r.ratios[m])
            .flat_map(|(lo, hi)| [lo, hi])
            .collect();
        let n = rows.iter().filter(|r| r.ratios[m].is_some()).count();
        all.sort_by(f64::total_cmp);
        let median = if all.len() % 2 == 1 {
            all[all.len() / 2]
        } else {
            (all[all.len() / 2 - 1] + all[all.len() / 2]) / 2.0
        };
        let worst = all
            .iter()
            .cloned()
            .max_by(|a, b| miss(*a).total_cmp(&miss(*b)))
            .unwrap();
        let inside = rows.iter().filter(|r| within(r, r.ratios[m])).count();
        let _ = writeln!(
            s,
            "| {model} | {n} | {median:.3} | {worst:.3} | {inside} of {with_scatter} |"
        );
    }
    s
}

/// The example files of the table, as `predict --model …` prints them: the numbers each ratio above is
/// taken from (the MFI at its file's 3-ply stack), so a reader can run the command and find them.
const PREDICTED: &[(&str, &str)] = &[
    ("thesis-C.toml", "800 V/mm parallel"),
    ("published/omega-strip.toml", "150 V parallel"),
    ("published/mfi-02gamma.toml", "3 plies, 150 V parallel"),
    ("published/jafferis2015-actuator.toml", "300 V on one plate"),
    (
        "published/robobee-jafferis2016.toml",
        "200 V bias, 100 V signal",
    ),
];

fn render_predictions() -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| file | drive | model | free deflection mm | blocked force mN | stiffness N/m | resonance Hz | energy mJ |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for (file, drive) in PREDICTED {
        for model in MODELS {
            let p = predict(&example_path(file), model)
                .unwrap_or_else(|| panic!("{file} under {model} is refused"));
            let _ = writeln!(
                s,
                "| `examples/{file}` | {drive} | {model} | {:.4} | {:.2} | {:.1} | {:.1} | {:.4} |",
                number(&p, "free_deflection_mm"),
                number(&p, "blocked_force_N") * 1e3,
                number(&p, "stiffness_N_per_m"),
                number(&p, "resonance_Hz"),
                number(&p, "energy_mJ"),
            );
        }
    }
    s
}

#[test]
fn the_validation_table_is_what_the_tool_predicts() {
    let rows = all_rows();
    assert!(rows.len() >= 20, "{} rows", rows.len());
    let table = format!(
        "{}\nThe numbers each ratio is taken from, as `actuator-cam predict --model MODEL FILE` prints them:\n\n{}",
        render(&rows),
        render_predictions()
    );
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/validation.md");
    let doc = std::fs::read_to_string(&path).unwrap();
    let (head, rest) = doc
        .split_once(BEGIN)
        .expect("docs/validation.md: begin marker");
    let (_, tail) = rest
        .split_once(END)
        .expect("docs/validation.md: end marker");
    let want = format!("{head}{BEGIN}\n{table}{END}{tail}");
    if std::env::var_os("VALIDATION_UPDATE").is_some() {
        std::fs::write(&path, &want).unwrap();
        return;
    }
    assert!(
        doc == want,
        "docs/validation.md's table differs from the tool's predictions (VALIDATION_UPDATE=1 rewrites it):\n{table}"
    );
}
