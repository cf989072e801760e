//! The drive report in lab units: the table `drive` prints, report.md, report.json and the
//! frequency-response plot.

pub use super::linkage_row::LinkageRow;
use crate::drawing::svg::xml_escape;
pub use crate::field_limits::{ModeRow, PolingRow};
use crate::input::fixed;
use crate::plot::{nice_ceiling, Anchor, Area, Canvas, Label, Marker, DASHED};
use actuator_model::ModelError;
use serde::Serialize;
use std::fmt::Write;

/// The bare actuator as the drive sees it.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct ActuatorRow {
    pub resonance_Hz: f64,
    pub stiffness_N_per_m: f64,
    pub modal_mass_mg: f64,
    pub blocked_force_per_field_mN_per_V_per_mm: f64,
    pub free_deflection_mm: f64,
    pub loss_factor: f64,
}

/// The wing.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct WingRow {
    /// The wing's own inertia and its added mass's.
    pub inertia_mg_mm2: f64,
    /// The added mass's part of the inertia (docs/physics.md §13).
    pub added_inertia_mg_mm2: f64,
    pub damping_nN_m_s2: f64,
    pub mass_mg: f64,
}

/// A steady state at the flapping frequency.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct OperatingRow {
    pub stroke_deg: f64,
    pub mean_angle_deg: f64,
    pub phase_deg: f64,
    pub tip_amplitude_mm: f64,
    pub force_amplitude_N: f64,
    pub field_V_per_mm: f64,
    pub voltage_V: f64,
    pub survival: f64,
    /// Peak over a period along the active length, and where it is (`x / l_p`).
    pub peak_pzt_stress_MPa: f64,
    pub peak_pzt_stress_x_over_l_p: f64,
    pub peak_pzt_strain: f64,
    pub peak_pzt_strain_x_over_l_p: f64,
    /// Survival of the peak strain by the thesis' strain fit (Table 4.12).
    pub strain_survival: f64,
    pub peak_tip_load_N: f64,
    pub mechanical_power_mW: f64,
    pub reactive_power_mW: f64,
    /// The plates' field against the limits of the mode (docs/physics.md §2.1).
    #[serde(flatten)]
    pub poling: PolingRow,
}

/// Actuator + transmission against the budget.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MassRow {
    pub actuator_mg: f64,
    pub transmission_mg: f64,
    pub total_mg: f64,
    pub budget_mg: f64,
    pub within_budget: bool,
}

/// Why the required stroke is out of reach.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Unreachable {
    pub best_stroke_deg: f64,
    pub binding: String,
    pub change: String,
}

/// One point of the frequency response.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct SweepPoint {
    pub frequency_Hz: f64,
    pub stroke_deg: f64,
    pub phase_deg: f64,
}

/// Everything `drive` reports (the report.json object).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct DriveReport {
    pub drive_file: String,
    pub design: String,
    pub model: String,
    pub drive_mode: String,
    pub frequency_Hz: f64,
    pub required_stroke_deg: f64,
    /// The stroke reached within the field limit, and the linkage buildable.
    pub reached: bool,
    /// Why the linkage cannot be built, for a drive file that gives its flexures' stiffness, not their
    /// sizes (the drawn check of docs/cam.md §7).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unbuildable_linkage: Option<String>,
    /// Why the tip amplitude is past the small-deflection range of the model (docs/physics.md §3.1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub past_small_deflection: Option<String>,
    /// Why no operating point is reported: a field-dependent model's operating field that does not
    /// settle (docs/physics.md §18.5).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unsettled_field: Option<String>,
    /// Small-stroke resonance of actuator + transmission + wing.
    pub resonance_Hz: f64,
    /// Resonance at the required stroke: the frequency where the steady stroke of that amplitude is
    /// 90° behind the drive (none where no steady state of that amplitude is found).
    pub resonance_at_stroke_Hz: Option<f64>,
    pub actuator: ActuatorRow,
    pub linkage: LinkageRow,
    pub wing: WingRow,
    /// The highest signal field within every limit of the design's mode, and the limit that sets it.
    pub field_limit_V_per_mm: f64,
    pub field_limit_binds: String,
    /// The failure fit's field at `survival_limit`, along the poling.
    pub failure_limit_V_per_mm: f64,
    /// The PZT's depolarization field, against the poling.
    pub depolarization_limit_V_per_mm: f64,
    pub survival_limit: f64,
    /// At the required stroke when reached, else at the best stroke within the field limit.
    pub operating: Option<OperatingRow>,
    pub modes: Vec<ModeRow>,
    pub mass: MassRow,
    pub unreachable: Option<Unreachable>,
    pub sweep: Vec<SweepPoint>,
    /// The drawn linkage, when the drive file gives its flexures (docs/cam.md §7).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub linkage_laminate: Option<crate::linkage::LinkageReport>,
}

impl DriveReport {
    /// Every number by its JSON name, for the finite check.
    pub fn numbers(&self) -> Vec<(&'static str, f64)> {
        let a = &self.actuator;
        let l = &self.linkage;
        let mut n = vec![
            ("resonance_Hz", self.resonance_Hz),
            (
                "resonance_at_stroke_Hz",
                self.resonance_at_stroke_Hz.unwrap_or(0.0),
            ),
            ("actuator.resonance_Hz", a.resonance_Hz),
            ("actuator.stiffness_N_per_m", a.stiffness_N_per_m),
            ("actuator.modal_mass_mg", a.modal_mass_mg),
            (
                "actuator.blocked_force_per_field_mN_per_V_per_mm",
                a.blocked_force_per_field_mN_per_V_per_mm,
            ),
            ("actuator.free_deflection_mm", a.free_deflection_mm),
            ("linkage.coupler_mm", l.coupler_mm),
            ("linkage.crank_mm", l.crank_mm),
            ("linkage.offset_mm", l.offset_mm),
            (
                "linkage.ratio_at_rest_deg_per_mm",
                l.ratio_at_rest_deg_per_mm,
            ),
            ("wing.inertia_mg_mm2", self.wing.inertia_mg_mm2),
            ("wing.added_inertia_mg_mm2", self.wing.added_inertia_mg_mm2),
            ("wing.damping_nN_m_s2", self.wing.damping_nN_m_s2),
            ("field_limit_V_per_mm", self.field_limit_V_per_mm),
            ("mass.total_mg", self.mass.total_mg),
        ];
        if let Some(o) = &self.operating {
            n.extend([
                ("operating.stroke_deg", o.stroke_deg),
                ("operating.phase_deg", o.phase_deg),
                ("operating.force_amplitude_N", o.force_amplitude_N),
                ("operating.field_V_per_mm", o.field_V_per_mm),
                ("operating.voltage_V", o.voltage_V),
                ("operating.peak_pzt_stress_MPa", o.peak_pzt_stress_MPa),
                ("operating.peak_pzt_strain", o.peak_pzt_strain),
                ("operating.strain_survival", o.strain_survival),
                ("operating.mechanical_power_mW", o.mechanical_power_mW),
                ("operating.reactive_power_mW", o.reactive_power_mW),
            ]);
        }
        if let Some(o) = &self.operating {
            n.extend(o.poling.numbers());
        }
        for m in &self.modes {
            n.push(("modes.field_V_per_mm", m.field_V_per_mm));
            n.push(("modes.voltage_V", m.voltage_V));
            n.extend(m.poling.numbers());
        }
        for p in &self.sweep {
            n.push(("sweep.stroke_deg", p.stroke_deg));
            n.push(("sweep.phase_deg", p.phase_deg));
        }
        if let Some(l) = &self.linkage_laminate {
            n.push(("linkage_laminate.mass_mg", l.mass_mg));
            n.push((
                "linkage_laminate.flexure_stiffness_uNm_per_rad",
                l.flexure_stiffness_uNm_per_rad,
            ));
            n.push((
                "linkage_laminate.link_inertia_mg_mm2",
                l.link_inertia_mg_mm2,
            ));
        }
        n
    }

    /// Refuse a report with a number that is not finite (never `NaN` on screen or `null` in JSON).
    pub fn ensure_finite(&self) -> Result<(), ModelError> {
        match self.numbers().into_iter().find(|(_, v)| !v.is_finite()) {
            Some((name, value)) => Err(ModelError::OutOfRange {
                name,
                value,
                range: "finite (the drive file's numbers give no steady state)",
            }),
            None => Ok(()),
        }
    }

    /// The summary `drive` prints: one quantity a line.
    pub fn table(&self) -> String {
        let mut rows = SummaryRows::default();
        self.system_rows(&mut rows);
        if let Some(o) = &self.operating {
            self.operating_rows(o, &mut rows);
        }
        self.limit_rows(&mut rows);
        let mut out = rows.aligned();
        crate::field_limits::modes_table(&self.modes, "stroke", &mut out);
        if let Some(l) = &self.linkage_laminate {
            let _ = write!(out, "\nthe drawn linkage (docs/cam.md §7):\n{}", l.table());
        }
        if let Some(table) = self.linkage.flexure_table() {
            out.push_str(&table);
        }
        if let Some(why) = &self.unbuildable_linkage {
            let _ = writeln!(out, "\nNOT BUILDABLE: {why}");
        }
        if let Some(why) = &self.past_small_deflection {
            let _ = writeln!(out, "\nPAST THE MODEL: {why}");
        }
        if let Some(why) = &self.unsettled_field {
            let _ = writeln!(out, "\nNOT SETTLED: {why}");
        }
        if let Some(u) = &self.unreachable {
            let _ = writeln!(
                out,
                "\nNOT REACHED: ±{} deg is out of reach; the best stroke within the limit is ±{} deg.\n  binding: {}\n  to reach it: {}",
                fixed(self.required_stroke_deg, 1),
                fixed(u.best_stroke_deg, 2),
                u.binding,
                u.change
            );
        }
        out
    }

    /// The system: design, model, frequency, stroke, resonances, linkage, wing, and whether the
    /// stroke is reached.
    fn system_rows(&self, rows: &mut SummaryRows) {
        rows.row("design", self.design.clone(), "");
        rows.row("model", self.model.clone(), "");
        rows.row("flapping frequency", fixed(self.frequency_Hz, 1), "Hz");
        rows.row(
            "required stroke",
            format!("±{}", fixed(self.required_stroke_deg, 1)),
            "deg",
        );
        let at_stroke = (self.resonance_at_stroke_Hz).map_or("none found".into(), |f| fixed(f, 1));
        let stroke = fixed(self.required_stroke_deg, 1);
        rows.row(&format!("resonance at ±{stroke}"), at_stroke, "Hz");
        let (small, bare) = (self.resonance_Hz, self.actuator.resonance_Hz);
        rows.row("resonance at small stroke", fixed(small, 1), "Hz");
        rows.row("  bare actuator", fixed(bare, 1), "Hz");
        rows.row(
            "  actuator stiffness",
            fixed(self.actuator.stiffness_N_per_m, 1),
            "N/m",
        );
        rows.row(
            "  actuator modal mass",
            fixed(self.actuator.modal_mass_mg, 2),
            "mg",
        );
        rows.row(
            "  actuator loss factor",
            format!(
                "{} (Q {})",
                fixed(self.actuator.loss_factor, 4),
                fixed(1.0 / self.actuator.loss_factor, 1)
            ),
            "",
        );
        for (name, value, unit) in self.linkage.summary() {
            rows.row(name, value, unit);
        }
        rows.row(
            "wing inertia",
            fixed(self.wing.inertia_mg_mm2, 1),
            "mg mm^2",
        );
        rows.row(
            "  of which added mass",
            fixed(self.wing.added_inertia_mg_mm2, 1),
            "mg mm^2",
        );
        rows.row(
            "wing drag coefficient K",
            fixed(self.wing.damping_nN_m_s2, 4),
            "nN m s^2",
        );
        rows.row(
            "reached",
            if self.reached { "yes" } else { "NO" }.to_string(),
            "",
        );
    }

    /// The operating point: the stroke reached (the required one, else the best within the limit)
    /// and what it takes.
    fn operating_rows(&self, o: &OperatingRow, rows: &mut SummaryRows) {
        let at = if self.unreachable.is_none() {
            "at the required stroke"
        } else {
            "at the best stroke"
        };
        rows.row(
            &format!("stroke ({at})"),
            format!("±{}", fixed(o.stroke_deg, 2)),
            "deg",
        );
        rows.row("  phase behind the drive", fixed(o.phase_deg, 1), "deg");
        rows.row(
            "  actuator tip amplitude",
            fixed(o.tip_amplitude_mm, 4),
            "mm",
        );
        rows.row(
            &format!("  voltage ({})", self.drive_mode),
            fixed(o.voltage_V, 1),
            "V",
        );
        rows.row("  field", fixed(o.field_V_per_mm, 1), "V/mm");
        if o.poling.bias_V > 0.0 {
            rows.row("  bias", fixed(o.poling.bias_V, 1), "V");
        }
        rows.row(
            "  plate field along / against poling",
            format!(
                "{} / {}",
                fixed(o.poling.along_V_per_mm, 1),
                fixed(o.poling.against_V_per_mm, 1)
            ),
            "V/mm",
        );
        rows.row("  field survival", fixed(o.survival, 4), "");
        rows.row(
            "  margin to the failure fit",
            fixed(o.poling.failure_margin_V_per_mm, 1),
            "V/mm (along the poling)",
        );
        rows.row(
            "  margin to depolarization",
            fixed(o.poling.depolarization_margin_V_per_mm, 1),
            "V/mm (against the poling)",
        );
        rows.row(
            "  peak PZT stress along the plate",
            format!(
                "{} MPa at x/l_p {}",
                fixed(o.peak_pzt_stress_MPa, 1),
                fixed(o.peak_pzt_stress_x_over_l_p, 2)
            ),
            "",
        );
        rows.row(
            "  peak PZT strain along the plate",
            format!(
                "{} µstrain at x/l_p {}",
                fixed(o.peak_pzt_strain * 1e6, 0),
                fixed(o.peak_pzt_strain_x_over_l_p, 2)
            ),
            "",
        );
        rows.row(
            "  strain survival",
            fixed(o.strain_survival, 4),
            "(thesis Table 4.12)",
        );
        rows.row("  peak tip load", fixed(o.peak_tip_load_N * 1e3, 2), "mN");
        rows.row(
            "  mechanical power into the wing",
            fixed(o.mechanical_power_mW, 3),
            "mW",
        );
        rows.row(
            "  reactive electrical power",
            fixed(o.reactive_power_mW, 3),
            "mvar",
        );
    }

    /// The field limit and the mass budget.
    fn limit_rows(&self, rows: &mut SummaryRows) {
        rows.row(
            "field limit",
            format!(
                "{} (binds: {}; failure fit {} at survival {}, depolarization {} against the poling)",
                fixed(self.field_limit_V_per_mm, 1),
                self.field_limit_binds,
                fixed(self.failure_limit_V_per_mm, 1),
                self.survival_limit,
                fixed(self.depolarization_limit_V_per_mm, 1)
            ),
            "V/mm",
        );
        rows.row(
            "mass: actuator + transmission",
            format!(
                "{} + {} = {}",
                fixed(self.mass.actuator_mg, 1),
                fixed(self.mass.transmission_mg, 1),
                fixed(self.mass.total_mg, 1)
            ),
            "mg",
        );
        rows.row(
            "  budget",
            format!(
                "{} ({})",
                fixed(self.mass.budget_mg, 1),
                if self.mass.within_budget {
                    "within"
                } else {
                    "OVER"
                }
            ),
            "mg",
        );
    }

    /// report.md: the table with a title.
    pub fn markdown(&self) -> String {
        format!(
            "# Drive: {} at {} Hz\n\nDrive file {}, model {}. The frequency response is in \
             frequency-response.svg.\n\n```text\n{}```\n",
            crate::markdown::text(&self.design),
            fixed(self.frequency_Hz, 1),
            crate::markdown::code(&self.drive_file),
            self.model,
            self.table()
        )
    }

    /// The frequency response: stroke amplitude and phase against frequency at the operating force, the
    /// operating point marked, the resonance dashed.
    pub fn svg(&self) -> String {
        let (w, h) = (640.0, 520.0);
        let mut c = Canvas::new(w, h, 12.0, true);
        c.background(w, h, "white");
        let f_hi = self
            .sweep
            .iter()
            .map(|p| p.frequency_Hz)
            .fold(self.frequency_Hz, f64::max);
        let x_hi = nice_ceiling(f_hi);
        let amp_hi = nice_ceiling(
            self.sweep
                .iter()
                .map(|p| p.stroke_deg)
                .fold(self.required_stroke_deg, f64::max),
        );
        let panels = [
            (
                Area {
                    left: 70.0,
                    right: 610.0,
                    top: 40.0,
                    bottom: 230.0,
                },
                "stroke amplitude (deg)",
                0.0,
                amp_hi,
            ),
            (
                Area {
                    left: 70.0,
                    right: 610.0,
                    top: 290.0,
                    bottom: 480.0,
                },
                "phase behind the drive (deg)",
                -90.0,
                270.0,
            ),
        ];
        let title = format!(
            "{}: frequency response at {} N blocked-force amplitude",
            xml_escape(&self.design),
            fixed(
                self.operating.as_ref().map_or(0.0, |o| o.force_amplitude_N),
                4
            )
        );
        c.label(&Label {
            bold: true,
            ..Label::new(w / 2.0, 20.0, Anchor::Middle, &title)
        });
        for (k, (area, name, lo, hi)) in panels.iter().enumerate() {
            let xs = area.x_scale(0.0, x_hi);
            let ys = area.y_scale(*lo, *hi);
            c.frame(area, "#333");
            for i in 0..=4 {
                let fx = x_hi * i as f64 / 4.0;
                let text = fixed(fx, 0);
                c.label(&Label::new(
                    xs.at(fx),
                    area.bottom + 16.0,
                    Anchor::Middle,
                    &text,
                ));
                let fy = lo + (hi - lo) * i as f64 / 4.0;
                let text = fixed(fy, 0);
                c.label(&Label::new(
                    area.left - 6.0,
                    ys.at(fy) + 4.0,
                    Anchor::End,
                    &text,
                ));
            }
            c.label(&Label::new(
                area.centre_x(),
                area.bottom + 32.0,
                Anchor::Middle,
                "frequency (Hz)",
            ));
            c.vertical_label(18.0, area.centre_y(), name);
            if self.resonance_Hz <= x_hi {
                c.vertical_rule(area, xs.at(self.resonance_Hz), "#999", Some(DASHED));
            }
            let points: Vec<(f64, f64)> = self
                .sweep
                .iter()
                .map(|p| {
                    let v = if k == 0 { p.stroke_deg } else { p.phase_deg };
                    (xs.at(p.frequency_Hz), ys.at(v.clamp(*lo, *hi)))
                })
                .collect();
            if points.len() >= 2 {
                c.polyline(&points, "#1f77b4");
            }
            if let Some(o) = &self.operating {
                let v = if k == 0 { o.stroke_deg } else { o.phase_deg };
                c.marker(
                    (xs.at(self.frequency_Hz), ys.at(v.clamp(*lo, *hi))),
                    &Marker::dot(4.0, "#d62728"),
                );
            }
        }
        c.finish()
    }
}

/// The summary's quantities: name, value and unit, one a line, the values in one column.
#[derive(Default)]
struct SummaryRows(Vec<(String, String, &'static str)>);

impl SummaryRows {
    fn row(&mut self, name: &str, value: String, unit: &'static str) {
        self.0.push((name.to_string(), value, unit));
    }

    /// The rows with the names padded to the longest.
    fn aligned(self) -> String {
        let width = self
            .0
            .iter()
            .map(|r| r.0.chars().count())
            .max()
            .unwrap_or(0);
        let mut out = String::new();
        for (name, value, unit) in self.0 {
            let pad = width - name.chars().count();
            let _ = writeln!(out, "{name}{}  {value} {unit}", " ".repeat(pad));
        }
        out
    }
}
