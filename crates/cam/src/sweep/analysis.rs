//! What a sweep reports: main effects per output, the comparison of two models, the CSV of every design.

use super::spec::{Factor, SweepSpec};
use super::SweepDesign;
use actuator_model::{ModelKind, Performance};
use std::fmt::Write;

/// One output of a design, in the units of reports and the CSV.
#[derive(Debug, Clone, Copy)]
pub struct Output {
    /// Name with unit, as a CSV column.
    pub column: &'static str,
    /// Short name for tables.
    pub label: &'static str,
    /// The value in the column's unit.
    pub value: fn(&Performance) -> f64,
}

/// The outputs a sweep reports.
pub const OUTPUTS: [Output; 5] = [
    Output {
        column: "mass_mg",
        label: "mass",
        value: |p| p.mass * 1e6,
    },
    Output {
        column: "free_deflection_mm",
        label: "free deflection",
        value: |p| p.free_deflection * 1e3,
    },
    Output {
        column: "blocked_force_mN",
        label: "blocked force",
        value: |p| p.blocked_force * 1e3,
    },
    Output {
        column: "energy_mJ",
        label: "energy",
        value: |p| p.energy * 1e3,
    },
    Output {
        column: "energy_density_J_per_kg",
        label: "energy density",
        value: |p| p.energy_density,
    },
];

/// Below this |effect| (% of the grand mean) a factor has no effect (`=`).
pub const NO_EFFECT_PERCENT: f64 = 1.0;
/// From this |effect| on, an effect is strong (double arrow, as thesis Table 4.11).
pub const STRONG_EFFECT_PERCENT: f64 = 10.0;

/// Mean outputs per level of every factor that varies.
#[derive(Debug, Clone)]
pub struct MainEffects {
    /// Grand mean per output.
    pub grand_mean: [f64; 5],
    /// Per varying factor: its levels ordered by value, with the mean outputs at each.
    pub factors: Vec<FactorEffect>,
}

/// One factor's main effect.
#[derive(Debug, Clone)]
pub struct FactorEffect {
    /// The factor.
    pub factor: Factor,
    /// Level indices, ascending by value, with the mean of each output over the designs at that level.
    pub means: Vec<(usize, [f64; 5])>,
    /// `(mean at the highest level - mean at the lowest) / grand mean`, % per output.
    pub effect_percent: [f64; 5],
}

impl MainEffects {
    /// Main effects of a full factorial: the mean at a level is over every design at that level, so each
    /// factor's effect is averaged over all combinations of the others.
    pub fn new(spec: &SweepSpec, designs: &[SweepDesign]) -> Self {
        let mut sums = EffectSums::new(spec);
        designs.iter().for_each(|d| sums.add(d));
        sums.finish(spec)
    }
}

/// The running sums behind `MainEffects`, fed one design at a time in sweep order, so a sweep need
/// not keep its designs.
#[derive(Debug, Clone)]
pub struct EffectSums {
    /// Designs of the whole sweep (the grand mean adds each value divided by it).
    count: f64,
    grand_mean: [f64; 5],
    /// Per varying factor: its slot in [`Factor::ALL`], the sum of each output and the designs at
    /// each level.
    factors: Vec<(usize, Vec<[f64; 5]>, Vec<usize>)>,
}

impl EffectSums {
    /// Nothing added yet, for a sweep of `spec.count()` designs.
    pub fn new(spec: &SweepSpec) -> Self {
        EffectSums {
            count: spec.count().max(1) as f64,
            grand_mean: [0.0; 5],
            factors: Factor::ALL
                .iter()
                .enumerate()
                .filter(|(_, f)| spec.level_count(**f) > 1)
                .map(|(slot, f)| {
                    let n = spec.level_count(*f);
                    (slot, vec![[0.0; 5]; n], vec![0; n])
                })
                .collect(),
        }
    }

    /// Add one design.
    pub fn add(&mut self, d: &SweepDesign) {
        let values = OUTPUTS.map(|o| (o.value)(&d.primary));
        for (mean, v) in self.grand_mean.iter_mut().zip(values) {
            *mean += v / self.count;
        }
        for (slot, sums, hits) in &mut self.factors {
            let level = d.levels[*slot];
            hits[level] += 1;
            for (sum, v) in sums[level].iter_mut().zip(values) {
                *sum += v;
            }
        }
    }

    /// The main effects of the designs added.
    pub fn finish(self, spec: &SweepSpec) -> MainEffects {
        let grand_mean = self.grand_mean;
        let factors = self
            .factors
            .into_iter()
            .map(|(slot, sums, hits)| {
                let factor = Factor::ALL[slot];
                let mut order: Vec<usize> = (0..sums.len()).collect();
                order.sort_by(|a, b| {
                    spec.level_value(factor, *a)
                        .total_cmp(&spec.level_value(factor, *b))
                        .then(a.cmp(b))
                });
                let means: Vec<(usize, [f64; 5])> = order
                    .iter()
                    .map(|&l| (l, sums[l].map(|s| s / hits[l].max(1) as f64)))
                    .collect();
                let (low, high) = (means[0].1, means[means.len() - 1].1);
                let mut effect_percent = [0.0; 5];
                for k in 0..5 {
                    effect_percent[k] = (high[k] - low[k]) / grand_mean[k] * 100.0;
                }
                FactorEffect {
                    factor,
                    means,
                    effect_percent,
                }
            })
            .collect();
        MainEffects {
            grand_mean,
            factors,
        }
    }
}

/// Thesis Table 4.11's notation for an effect in percent.
pub fn arrow(effect_percent: f64) -> &'static str {
    let size = effect_percent.abs();
    if size < NO_EFFECT_PERCENT {
        "="
    } else if effect_percent > 0.0 {
        if size >= STRONG_EFFECT_PERCENT {
            "↑↑"
        } else {
            "↑"
        }
    } else if size >= STRONG_EFFECT_PERCENT {
        "↓↓"
    } else {
        "↓"
    }
}

/// Percent differences `(X_a - X_b) / X_a` between two models per design (thesis eq. 3.1).
#[derive(Debug, Clone, Copy)]
pub struct Comparison {
    /// Mean and sample standard deviation (n - 1) of the percent difference: free deflection, blocked
    /// force, energy.
    pub mean_std: [(f64, f64); 3],
    /// Designs compared.
    pub count: usize,
}

/// The running mean and spread behind `Comparison`, one design at a time (Welford's update, so a
/// sweep need not keep its percent differences: B. P. Welford, Technometrics 4(3), 1962).
#[derive(Debug, Clone, Copy, Default)]
pub struct ComparisonSums {
    count: usize,
    mean: [f64; 3],
    /// Sum of squared deviations from the running mean.
    m2: [f64; 3],
}

impl ComparisonSums {
    /// Add one design (no change if it has no compared prediction).
    pub fn add(&mut self, d: &SweepDesign, thesis_eq_2_36: bool) {
        let Some(diff) = percent_differences(d, thesis_eq_2_36) else {
            return;
        };
        self.count += 1;
        let n = self.count as f64;
        for ((mean, m2), x) in self.mean.iter_mut().zip(&mut self.m2).zip(diff) {
            let delta = x - *mean;
            *mean += delta / n;
            *m2 += delta * (x - *mean);
        }
    }

    /// Mean and sample standard deviation (n - 1) of the designs added.
    pub fn finish(self) -> Comparison {
        let n = self.count as f64;
        let mean_std = [0, 1, 2].map(|k| {
            let mean = if self.count == 0 {
                f64::NAN
            } else {
                self.mean[k]
            };
            (mean, (self.m2[k] / (n - 1.0).max(1.0)).sqrt())
        });
        Comparison {
            mean_std,
            count: self.count,
        }
    }
}

/// The factor the thesis' eq. 2.36 puts on the rectangular blocked force (4/3 in place of 3/2).
pub const EQ_2_36_FACTOR: f64 = 8.0 / 9.0;

/// Percent differences of δ, F_b and U between a design's main and compared model, with eq. 2.36's
/// factor on the main model's F_b (and so U) if asked.
fn percent_differences(d: &SweepDesign, thesis_eq_2_36: bool) -> Option<[f64; 3]> {
    let (a, b) = (d.primary, d.compared?);
    let k = if thesis_eq_2_36 { EQ_2_36_FACTOR } else { 1.0 };
    let a = [a.free_deflection, a.blocked_force * k, a.energy * k];
    let b = [b.free_deflection, b.blocked_force, b.energy];
    Some([0, 1, 2].map(|i| (a[i] - b[i]) / a[i] * 100.0))
}

impl Comparison {
    /// Summarise the designs that carry a compared prediction.
    pub fn new(designs: &[SweepDesign], thesis_eq_2_36: bool) -> Self {
        let mut sums = ComparisonSums::default();
        designs.iter().for_each(|d| sums.add(d, thesis_eq_2_36));
        sums.finish()
    }

    /// The thesis Table 4.1 layout.
    pub fn report(&self, a: ModelKind, b: ModelKind, thesis_eq_2_36: bool) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "model comparison over {} designs: % difference (X_{} - X_{}) / X_{} (thesis eq. 3.1){}",
            self.count,
            a.name(),
            b.name(),
            a.name(),
            if thesis_eq_2_36 {
                "; blocked force and energy of the first model scaled by 8/9 as printed in eq. 2.36"
            } else {
                ""
            }
        );
        let _ = writeln!(
            s,
            "  {:<18} {:>12} {:>20}",
            "", "mean %", "std dev % (n - 1)"
        );
        for (name, (mean, std)) in ["free deflection", "blocked force", "energy"]
            .iter()
            .zip(self.mean_std)
        {
            let _ = writeln!(s, "  {name:<18} {mean:>12.3} {std:>20.3}");
        }
        s
    }
}

/// The text summary: designs, main effects, means per level.
pub fn report(spec: &SweepSpec, file: &str, kind: ModelKind, effects: &MainEffects) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "actuator-cam sweep {file}: {} designs, model {}, {} drive at {:.1} V/mm, PZT {} / {} plies",
        spec.count(),
        kind.name(),
        spec.mode.name(),
        spec.field * 1e-3,
        spec.pzt.name,
        spec.ply.name
    );
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "main effects: change of the mean output from the lowest to the highest level, % of the grand mean"
    );
    let _ = writeln!(
        s,
        "(thesis Table 4.11 in numbers: ↑↑/↓↓ at {STRONG_EFFECT_PERCENT}% or more, ↑/↓ at {NO_EFFECT_PERCENT}% or more, = below; layups ordered by ply count)"
    );
    let _ = write!(s, "  {:<18}", "factor");
    for o in OUTPUTS {
        let _ = write!(s, " {:>17}", o.label);
    }
    let _ = writeln!(s);
    for fe in &effects.factors {
        let _ = write!(s, "  {:<18}", fe.factor.name());
        for e in fe.effect_percent {
            let _ = write!(s, " {:>14} {:<2}", format!("{e:+.2}"), arrow(e));
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(s);
    let _ = writeln!(s, "mean output per level");
    let _ = write!(s, "  {:<18} {:<18}", "factor", "level");
    for o in OUTPUTS {
        let _ = write!(s, " {:>23}", o.column);
    }
    let _ = writeln!(s);
    for fe in &effects.factors {
        for (level, means) in &fe.means {
            let _ = write!(
                s,
                "  {:<18} {:<18}",
                fe.factor.name(),
                spec.level_label(fe.factor, *level)
            );
            for m in means {
                let _ = write!(s, " {:>23}", format!("{m:.6}"));
            }
            let _ = writeln!(s);
        }
    }
    let _ = write!(s, "  {:<18} {:<18}", "all designs", "");
    for m in effects.grand_mean {
        let _ = write!(s, " {:>23}", format!("{m:.6}"));
    }
    let _ = writeln!(s);
    s
}

/// Every design as CSV, one row at a time: levels, outputs, and with a comparison the other model's δ,
/// F_b, U and the percent differences. Numbers in Rust's shortest form that reads back to the same
/// `f64`.
pub struct CsvRows<'s, W: std::io::Write> {
    spec: &'s SweepSpec,
    thesis_eq_2_36: bool,
    writer: csv::Writer<W>,
}

impl<'s, W: std::io::Write> CsvRows<'s, W> {
    /// Write the header into `out`.
    pub fn new(
        out: W,
        spec: &'s SweepSpec,
        compare: Option<ModelKind>,
        thesis_eq_2_36: bool,
    ) -> Result<Self, csv::Error> {
        let mut writer = csv::Writer::from_writer(out);
        let mut header: Vec<String> = vec!["design".into()];
        header.extend(Factor::ALL.iter().map(|f| f.name().to_string()));
        header.extend(OUTPUTS.iter().map(|o| o.column.to_string()));
        if let Some(b) = compare {
            let b = b.name();
            header.extend([
                format!("{b}_free_deflection_mm"),
                format!("{b}_blocked_force_mN"),
                format!("{b}_energy_mJ"),
                "diff_free_deflection_percent".into(),
                "diff_blocked_force_percent".into(),
                "diff_energy_percent".into(),
            ]);
        }
        writer.write_record(&header)?;
        Ok(CsvRows {
            spec,
            thesis_eq_2_36,
            writer,
        })
    }

    /// Write design `index` (0-based; the CSV numbers designs from 1).
    pub fn row(&mut self, index: usize, d: &SweepDesign) -> Result<(), csv::Error> {
        let mut row: Vec<String> = vec![(index + 1).to_string()];
        row.extend(
            Factor::ALL
                .iter()
                .zip(d.levels)
                .map(|(f, l)| self.spec.level_label(*f, l)),
        );
        row.extend(OUTPUTS.iter().map(|o| (o.value)(&d.primary).to_string()));
        if let (Some(b), Some(diff)) = (d.compared, percent_differences(d, self.thesis_eq_2_36)) {
            row.extend(
                [
                    b.free_deflection * 1e3,
                    b.blocked_force * 1e3,
                    b.energy * 1e3,
                ]
                .iter()
                .chain(&diff)
                .map(|x| x.to_string()),
            );
        }
        self.writer.write_record(&row)
    }

    /// Flush and hand back the writer.
    pub fn finish(self) -> Result<W, csv::Error> {
        self.writer
            .into_inner()
            .map_err(|e| csv::Error::from(e.into_error()))
    }
}
