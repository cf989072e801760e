//! Designs that would tell contending models apart: corners of the data's span where their predictions
//! differ most. [`probes`] lists the corners; [`separate`] scores them for two fitted models, and
//! discovery scores them for its leading candidates with the same probes.

use crate::calibrate::csv::{Dataset, Measurement};
use crate::calibrate::rounded::six_digits;
use actuator_model::effects::Actuator;
use actuator_model::EffectModel;
use actuator_model::{Drive, Planform};
use serde::Serialize;

/// A design and drive to build and measure, report units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DesignPoint {
    /// l_tot, mm.
    #[serde(serialize_with = "six_digits")]
    pub l_tot_mm: f64,
    /// l_r.
    #[serde(serialize_with = "six_digits")]
    pub l_r: f64,
    /// w_0, mm.
    #[serde(serialize_with = "six_digits")]
    pub w0_mm: f64,
    /// w_r.
    #[serde(serialize_with = "six_digits")]
    pub w_r: f64,
    /// t_p, mm.
    #[serde(serialize_with = "six_digits")]
    pub t_p_mm: f64,
    /// Layup.
    pub layup: String,
    /// Voltage, V.
    #[serde(rename = "voltage_V", serialize_with = "six_digits")]
    pub voltage_v: f64,
}

impl DesignPoint {
    /// The design as the report's table cells show it (`l_tot | l_r | w0 | w_r | t_p | layup | V`, at
    /// the report's precision): two probes with the same cells are the same design to the reader.
    pub fn cells(&self) -> String {
        format!(
            "{:.1} | {:.2} | {:.1} | {:.2} | {:.3} | {} | {:.0}",
            self.l_tot_mm, self.l_r, self.w0_mm, self.w_r, self.t_p_mm, self.layup, self.voltage_v
        )
    }
}

/// A design that would tell two contenders apart.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SeparatingDesign {
    /// The design.
    #[serde(flatten)]
    pub design: DesignPoint,
    /// Predicted ratio of deflections (contender 1 / contender 2).
    #[serde(serialize_with = "six_digits")]
    pub deflection_ratio: f64,
    /// Predicted ratio of blocked forces.
    #[serde(serialize_with = "six_digits")]
    pub force_ratio: f64,
}

/// A corner of the data's span: a planform, the materials and layup of one row, a PZT thickness and a
/// field that occur in the data.
#[derive(Debug, Clone, Copy)]
pub struct Probe<'a> {
    /// The row whose materials, layup and drive mode the probe uses.
    pub row: &'a Measurement,
    /// PZT thickness, m.
    pub pzt_thickness: f64,
    /// Planform.
    pub planform: Planform,
    /// Drive field, V/m.
    pub field: f64,
}

impl Probe<'_> {
    /// The model's view of the probe.
    pub fn actuator(&self) -> Actuator<'_> {
        Actuator {
            pzt: &self.row.pzt,
            pzt_thickness: self.pzt_thickness,
            ply: &self.row.ply,
            ply_thickness: self.row.ply_thickness,
            layup_deg: &self.row.layup_deg,
            planform: self.planform,
            drive: Drive::new(self.row.drive_mode, self.field),
        }
    }

    /// The probe in report units.
    pub fn design(&self) -> DesignPoint {
        let pl = &self.planform;
        DesignPoint {
            l_tot_mm: pl.length * 1e3,
            l_r: pl.extension_ratio,
            w0_mm: pl.base_width * 1e3,
            w_r: pl.width_ratio,
            t_p_mm: self.pzt_thickness * 1e3,
            layup: self.row.layup.clone(),
            voltage_v: self
                .row
                .drive_mode
                .voltage_from_field(self.field, self.pzt_thickness),
        }
    }
}

/// Every corner of the data's span: shortest and longest length, lowest and highest `l_r` and `w_0`,
/// lowest, 1 (if within) and highest `w_r`, each layup and PZT thickness in the data, lowest and highest
/// field. Within the span only: a design outside what was built would be an extrapolation of both models.
/// Each design once (corners coincide where a range is a single value or `w_r = 1` is one of its ends),
/// as the report shows it ([`DesignPoint::cells`]).
pub fn probes(data: &Dataset) -> Vec<Probe<'_>> {
    let range = |f: &dyn Fn(&Measurement) -> f64| {
        let v: Vec<f64> = data.rows.iter().map(f).collect();
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let (l_lo, l_hi) = range(&|m| m.planform.length);
    let (lr_lo, lr_hi) = range(&|m| m.planform.extension_ratio);
    let (w_lo, w_hi) = range(&|m| m.planform.base_width);
    let (wr_lo, wr_hi) = range(&|m| m.planform.width_ratio);
    let (e_lo, e_hi) = range(&|m| m.field);
    let mut layups: Vec<usize> = Vec::new();
    let mut thick: Vec<usize> = Vec::new();
    for (i, m) in data.rows.iter().enumerate() {
        if !layups.iter().any(|&j| data.rows[j].layup == m.layup) {
            layups.push(i);
        }
        if !thick
            .iter()
            .any(|&j| (data.rows[j].pzt_thickness - m.pzt_thickness).abs() < 1e-9)
        {
            thick.push(i);
        }
    }
    let mut out = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for l in [l_lo, l_hi] {
        for lr in [lr_lo, lr_hi] {
            for w in [w_lo, w_hi] {
                for wr in [wr_lo, 1.0f64.clamp(wr_lo, wr_hi), wr_hi] {
                    for &li in &layups {
                        for &ti in &thick {
                            for e in [e_lo.max(1.0), e_hi] {
                                let Ok(planform) = Planform::new(l, lr, w, wr, 0.0) else {
                                    continue;
                                };
                                let probe = Probe {
                                    row: &data.rows[li],
                                    pzt_thickness: data.rows[ti].pzt_thickness,
                                    planform,
                                    field: e,
                                };
                                if seen.insert(probe.design().cells()) {
                                    out.push(probe);
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    out
}

/// Designs in the span of the data where two fitted models disagree most.
pub(super) fn separate(data: &Dataset, a: &EffectModel, b: &EffectModel) -> Vec<SeparatingDesign> {
    let mut scored = Vec::new();
    for probe in probes(data) {
        let act = probe.actuator();
        let (Ok(pa), Ok(pb)) = (a.predict(&act), b.predict(&act)) else {
            continue;
        };
        let rd = pa.free_deflection / pb.free_deflection;
        let rf = pa.blocked_force / pb.blocked_force;
        let score = rd.ln().abs().max(rf.ln().abs());
        scored.push((
            score,
            SeparatingDesign {
                design: probe.design(),
                deflection_ratio: rd,
                force_ratio: rf,
            },
        ));
    }
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    scored.into_iter().take(3).map(|(_, d)| d).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibrate::csv::parse;

    /// Rectangles only (`w_r` = 1 is both ends of its range) and one length: the corners that coincide
    /// are listed once, so no table shows a design twice.
    #[test]
    fn each_corner_is_probed_once() {
        let text = "id,l_tot_mm,l_r,w0_mm,w_r,t_p_mm,layup,voltage_V,mass_mg,free_deflection_mm,blocked_force_N\n\
            A,30,0,5,1,0.191,0/90/0,50,,0.1,0.05\n\
            A,30,0,5,1,0.191,0/90/0,100,,0.2,0.1\n\
            B,30,0.5,9,1,0.191,0/90/0,100,,0.3,0.1\n";
        let data = parse(text).unwrap();
        let cells: Vec<String> = probes(&data).iter().map(|p| p.design().cells()).collect();
        let unique: std::collections::HashSet<&String> = cells.iter().collect();
        assert_eq!(unique.len(), cells.len(), "{cells:?}");
        // One length, l_r 0 and 0.5, w0 5 and 9, w_r 1, one layup and thickness, two fields.
        assert_eq!(cells.len(), 8);
    }
}
