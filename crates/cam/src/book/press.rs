//! The clamp and the press as numbers in the build book: the measuring step with the tolerance the
//! press fit leaves, the registration dowels against the stack height, and the clamp force from the
//! template's pressure over the parts of a panel (docs/cam.md §6, "The clamp as data").

use crate::markdown;
use crate::pipeline::{Build, ClampBuild};
use crate::process::template::{ClampSpec, Template};
use cam_geometry::signed_area;

/// Thickness of each level of `clamp`'s stack, bottom to top, mm: mold films from the mold choice,
/// the other layers from the template.
fn level_thicknesses_mm(template: &Template, clamp: &ClampBuild) -> Vec<f64> {
    let mut molds = clamp.mold.films_mm.iter();
    clamp
        .stack
        .iter()
        .map(|name| {
            if name.starts_with("mold-") {
                molds.next().copied().unwrap_or(0.0)
            } else {
                let base = name.rsplit_once('-').map_or(name.as_str(), |(b, _)| b);
                template.covers.get(base).map_or(0.0, |c| c.thickness_mm)
            }
        })
        .collect()
}

/// The dowel window of a clamp stack, mm: `(reach, below, stack)`: a dowel must reach the top of the
/// highest mold sheet, end below the top layer, and the stack stands `stack` high before it is
/// pressed.
fn dowel_window_mm(template: &Template, clamp: &ClampBuild) -> (f64, f64, f64) {
    let t = level_thicknesses_mm(template, clamp);
    let stack: f64 = t.iter().sum();
    let last_mold = clamp.stack.iter().rposition(|n| n.starts_with("mold-"));
    let reach: f64 = last_mold.map_or(0.0, |k| t[..=k].iter().sum());
    let below = stack - t.last().copied().unwrap_or(0.0);
    (reach, below, stack)
}

/// `0.123` for a length in mm, to the micrometre.
fn mm(x: f64) -> String {
    let s = format!("{:.3}", x);
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The dowels in the pin holes of `clamp`: the template's dowel diameter, the holes' and the clearance
/// between them (half of it each way is how far a sheet may sit off its place); without a dowel
/// diameter, the largest dowel the holes take.
pub fn pin_fit_text(clamp: &ClampSpec) -> String {
    let hole = 2.0 * clamp.pin_radius_mm;
    match clamp.dowel_diameter_mm {
        Some(d) => format!(
            "dowels of Ø{} mm (the template's {}) in the Ø{} mm pin holes, {:.0} µm of clearance: \
             each sheet sits within {:.0} µm of its place",
            mm(d),
            markdown::code("clamp.dowel_diameter_mm"),
            mm(hole),
            (hole - d) * 1e3,
            (hole - d) * 1e3 / 2.0
        ),
        None => format!(
            "dowels no larger than the Ø{} mm pin holes (the template gives no {})",
            mm(hole),
            markdown::code("clamp.dowel_diameter_mm")
        ),
    }
}

/// The first stacking step's dowel sentence for `clamp`.
pub(super) fn dowel_text(template: &Template, clamp: &ClampBuild) -> String {
    let dowel = pin_fit_text(&template.clamp);
    let (reach, below, stack) = dowel_window_mm(template, clamp);
    let top = clamp.stack.last().map_or("", String::as_str);
    let length = if reach < below {
        format!(
            "standing {} to {} mm above the plate: through the top mold sheet ({} mm up, the stack \
             not yet pressed) and below the top layer, {} (the stack is {} mm, bottom to top, before \
             it is pressed), so that the press bears on the stack, never on a dowel",
            mm(reach),
            mm(below),
            mm(reach),
            markdown::text(top),
            mm(stack)
        )
    } else {
        format!(
            "but no dowel length both reaches the top mold sheet ({} mm up) and ends below the top \
             layer ({} mm up): put a thicker layer at the top of the stack",
            mm(reach),
            mm(below)
        )
    };
    format!("Stand the registration {dowel}, {length}.")
}

/// The measuring step: the PZT and the mold films against the press fit's tolerance.
pub(super) fn measure_step(template: &Template, built: &Build) -> String {
    let tolerance_um = template.mold_stock.tolerance_mm * 1e3;
    let fits: Vec<String> = built
        .clamps
        .iter()
        .enumerate()
        .filter_map(|(k, clamp)| {
            let proud = clamp.mold.fits.iter().find(|f| f.region == "laminate")?.proud_mm * 1e3;
            let of = if built.clamps.len() > 1 {
                format!(" (clamp stack {})", k + 1)
            } else {
                String::new()
            };
            Some(format!(
                "the laminate{of} stands {proud:.1} µm proud of its mold: each plate may measure up to \
                 {:.1} µm under or {:.1} µm over its nominal thickness when the films measure theirs",
                proud / 2.0,
                (tolerance_um - proud).max(0.0) / 2.0
            ))
        })
        .collect();
    format!(
        "Before cutting, measure with a micrometer at three places each: every PZT sheet (its nominal \
         thickness is in its file name) and each mold film in stock. The press fit allows {:.0} µm \
         (the template's {}): the laminate (two plates and the core) must stand 0 to {:.0} µm above \
         the mold films around it. As drawn, {}. Outside it, put the measured thicknesses into the \
         design ({}) and the template ({}) and run again.",
        tolerance_um,
        markdown::code("layers.mold.height_tolerance_mm"),
        tolerance_um,
        fits.join("; "),
        markdown::code("pzt_thickness_mm"),
        markdown::code("stock_thicknesses_mm")
    )
}

/// The clamp force on the fullest panel of each clamp stack at the template's pressure, if the
/// template gives the pressure as a number.
pub(super) fn force_text(template: &Template, built: &Build) -> Option<String> {
    let kpa = template.cure.clamp.pressure_kpa?;
    let forces: Vec<String> = built
        .clamps
        .iter()
        .enumerate()
        .map(|(k, clamp)| {
            let area = clamp
                .panels
                .iter()
                .map(|p| {
                    p.iter()
                        .map(|(job, _)| signed_area(&built.geometry[*job].passive_outline()).abs())
                        .sum::<f64>()
                })
                .fold(0.0, f64::max);
            // kPa × mm² = 1e3 N/m² × 1e-6 m² = 1e-3 N.
            let stack = if built.clamps.len() > 1 {
                format!("clamp stack {}: ", k + 1)
            } else {
                String::new()
            };
            format!(
                "{stack}{:.1} N over {:.1} mm² of parts",
                kpa * area * 1e-3,
                area
            )
        })
        .collect();
    Some(format!(
        "{} kPa on the parts (the template's {}), for the fullest panel {}: set a press to it, or \
         tighten the clamp on a force gauge",
        kpa,
        markdown::code("cure.pressure_kPa"),
        forces.join("; ")
    ))
}
