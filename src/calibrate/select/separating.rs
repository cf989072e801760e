//! Designs that would tell two contending models apart: corners of the data's span where their
//! predictions differ most.

use crate::calibrate::csv::{Dataset, Measurement};
use crate::calibrate::rounded::six_digits;
use actuator_model::effects::Actuator;
use actuator_model::EffectModel;
use actuator_model::{Drive, Planform};
use serde::Serialize;

/// A design that would tell two contenders apart.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SeparatingDesign {
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
    /// Predicted ratio of deflections (contender 1 / contender 2).
    #[serde(serialize_with = "six_digits")]
    pub deflection_ratio: f64,
    /// Predicted ratio of blocked forces.
    #[serde(serialize_with = "six_digits")]
    pub force_ratio: f64,
}

/// Designs in the span of the data where two fitted models disagree most.
pub(super) fn separate(data: &Dataset, a: &EffectModel, b: &EffectModel) -> Vec<SeparatingDesign> {
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
    let mut scored = Vec::new();
    for l in [l_lo, l_hi] {
        for lr in [lr_lo, lr_hi] {
            for w in [w_lo, w_hi] {
                for wr in [wr_lo, 1.0f64.clamp(wr_lo, wr_hi), wr_hi] {
                    for &li in &layups {
                        for &ti in &thick {
                            for e in [e_lo.max(1.0), e_hi] {
                                let lay = &data.rows[li];
                                let t_p = data.rows[ti].pzt_thickness;
                                let Ok(pl) = Planform::new(l, lr, w, wr, 0.0) else {
                                    continue;
                                };
                                let act = Actuator {
                                    pzt: &lay.pzt,
                                    pzt_thickness: t_p,
                                    ply: &lay.ply,
                                    ply_thickness: lay.ply_thickness,
                                    layup_deg: &lay.layup_deg,
                                    planform: pl,
                                    drive: Drive {
                                        mode: lay.drive_mode,
                                        field: e,
                                    },
                                };
                                let (Ok(pa), Ok(pb)) = (a.predict(&act), b.predict(&act)) else {
                                    continue;
                                };
                                let rd = pa.free_deflection / pb.free_deflection;
                                let rf = pa.blocked_force / pb.blocked_force;
                                let score = rd.ln().abs().max(rf.ln().abs());
                                scored.push((
                                    score,
                                    SeparatingDesign {
                                        l_tot_mm: l * 1e3,
                                        l_r: lr,
                                        w0_mm: w * 1e3,
                                        w_r: wr,
                                        t_p_mm: t_p * 1e3,
                                        layup: lay.layup.clone(),
                                        voltage_v: lay.drive_mode.voltage_from_field(e, t_p),
                                        deflection_ratio: rd,
                                        force_ratio: rf,
                                    },
                                ));
                            }
                        }
                    }
                }
            }
        }
    }
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    scored.into_iter().take(3).map(|(_, d)| d).collect()
}
