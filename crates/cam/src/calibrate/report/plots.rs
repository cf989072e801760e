//! The parity and residual plots of a calibration, drawn with the crate's plotting module.

use crate::calibrate::baseline::group_residuals;
use crate::calibrate::csv::Dataset;
use crate::calibrate::variables::design_variables;
use crate::plot::{grid_cell, Anchor, Area, Canvas, Label, Marker, DASHED};
use actuator_model::Performance;

/// One scatter panel: log axes for parity, a symmetric y range around zero for residuals.
struct Panel<'a> {
    title: &'a str,
    xlabel: &'a str,
    points: Vec<(f64, f64)>,
    log: bool,
    /// Draw y = x with a ±20% band (parity) or y = 0 (residuals).
    parity: bool,
}

/// Panels in a grid of `cols` columns, 320 × 280 px each.
fn svg(panels: &[Panel], cols: usize) -> String {
    let (pw, ph) = (320.0, 280.0);
    let rows = panels.len().div_ceil(cols);
    let mut canvas = Canvas::new(pw * cols as f64, ph * rows as f64, 11.0, false);
    for (i, p) in panels.iter().enumerate() {
        let (ox, oy) = grid_cell(i, cols, pw, ph);
        let area = Area {
            left: ox + 50.0,
            right: ox + pw - 15.0,
            top: oy + 25.0,
            bottom: oy + ph - 40.0,
        };
        let (l, r, t, b) = (area.left, area.right, area.top, area.bottom);
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
        let (sx, sy) = (area.x_scale(x0, x1), area.y_scale(y0, y1));
        canvas.frame(&area, "#444");
        canvas.label(&Label {
            bold: true,
            ..Label::new(area.centre_x(), oy + 15.0, Anchor::Middle, p.title)
        });
        canvas.label(&Label::new(
            area.centre_x(),
            b + 30.0,
            Anchor::Middle,
            p.xlabel,
        ));
        // Axis ends in data units (undo the log).
        let shown = |v: f64| format!("{:.3}", if p.log { 10f64.powf(v) } else { v });
        let (xa, xb, ya, yb) = (shown(x0), shown(x1), shown(y0), shown(y1));
        canvas.labels(&[
            Label::new(l, b + 14.0, Anchor::Start, &xa),
            Label::new(r, b + 14.0, Anchor::End, &xb),
        ]);
        canvas.labels(&[
            Label::new(l - 3.0, b, Anchor::End, &ya),
            Label::new(l - 3.0, t + 10.0, Anchor::End, &yb),
        ]);
        if p.parity {
            for (f, dash) in [
                (1.0f64, None),
                (1.2, Some(DASHED)),
                (1.0 / 1.2, Some(DASHED)),
            ] {
                let d = if p.log { f.log10() } else { 0.0 };
                canvas.line(
                    (sx.at(x0), sy.at(x0 + d)),
                    (sx.at(x1), sy.at(x1 + d)),
                    "#999",
                    dash,
                );
            }
        } else {
            canvas.line((l, sy.at(0.0)), (r, sy.at(0.0)), "#999", None);
        }
        let dot = Marker {
            fill_opacity: Some(0.7),
            ..Marker::dot(2.5, "#1f77b4")
        };
        for &(x, y) in &pts {
            canvas.marker((sx.at(x), sy.at(y)), &dot);
        }
    }
    canvas.finish()
}

/// Model against measured free deflection and blocked force, log axes, with y = x and a ±20% band;
/// `when` names the model in the titles.
pub fn parity_svg(data: &Dataset, preds: &[Performance], when: &str) -> String {
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

/// Per-actuator log residuals of deflection and stiffness against five design variables, one panel
/// each; a trend left in a panel is an effect the model misses.
pub fn residual_svg(data: &Dataset, preds: &[Performance], when: &str) -> String {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn panel(points: Vec<(f64, f64)>, log: bool, parity: bool) -> Panel<'static> {
        Panel {
            title: "title",
            xlabel: "x label",
            points,
            log,
            parity,
        }
    }

    #[test]
    fn parity_panels_draw_the_diagonal_and_the_20_percent_band_on_log_axes() {
        let s = svg(
            &[
                panel(vec![(1.0, 1.1), (10.0, 8.0)], true, true),
                panel(vec![], true, true),
            ],
            2,
        );
        assert!(s.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"640\" height=\"280\" font-family=\"sans-serif\" font-size=\"11\">\n"));
        assert!(s.ends_with("</svg>\n"));
        assert_eq!(s.matches("<rect ").count(), 2);
        assert_eq!(s.matches("<circle ").count(), 2);
        // Diagonal plus two dashed band lines per panel.
        assert_eq!(s.matches("<line ").count(), 6);
        assert_eq!(s.matches("stroke-dasharray=\"4 3\"").count(), 4);
        // The axis ends are in data units: the log is undone.
        assert!(s.contains(">0.891</text>"), "{s}");
        assert!(s.contains("font-weight=\"bold\">title</text>"));
    }

    #[test]
    fn residual_panels_are_symmetric_about_a_zero_line() {
        let s = svg(&[panel(vec![(1.0, 0.2), (2.0, -0.1)], false, false)], 1);
        assert!(
            s.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"320\" height=\"280\"")
        );
        assert_eq!(s.matches("<line ").count(), 1);
        // y from -0.2 to 0.2, padded by 5% of the span.
        assert!(
            s.contains(">-0.220</text>") && s.contains(">0.220</text>"),
            "{s}"
        );
        // The zero line runs at mid-height of the frame (25 .. 240).
        assert!(s.contains("<line x1=\"50.0\" y1=\"132.5\" x2=\"305.0\" y2=\"132.5\""));
    }
}
