//! The laser set-up of a build book: each stock's setting per operation from the template's
//! `[laser]` table, starting points where it has none, and the PZT test coupon scored before any
//! production sheet (docs/cam.md §6, "Laser settings and the test coupon").

use crate::drawing::model::Operation;
use crate::markdown;
use crate::pipeline::Build;
use crate::process::laser::{operation_name, starting_point};
use crate::process::template::Template;
use crate::process::Feature;

/// The features each kind of layer file draws: what decides the operations it runs.
fn features_of(layer: &str) -> &'static [Feature] {
    match layer {
        "pzt" => &[
            Feature::PztScoreLine,
            Feature::PztSheetOutline,
            Feature::SheetLabel,
        ],
        "passive" | "pyralux" => &[
            Feature::PartOutline,
            Feature::Via,
            Feature::RegistrationHole,
            Feature::PartLabel,
            Feature::SheetLabel,
        ],
        _ => &[
            Feature::PanelOutline,
            Feature::PinHole,
            Feature::MoldCavity,
            Feature::StackingWindow,
            Feature::WindowNumber,
            Feature::PanelLabel,
            Feature::Fiducial,
        ],
    }
}

/// The `[layers]` name of a sheet layer or a clamp stack level: `passive-2` → `passive`, `felt-1` →
/// `felt`, `mold-3` → `mold`.
fn template_layer(name: &str) -> &str {
    if name.starts_with("passive") {
        return "passive";
    }
    match name.rsplit_once('-') {
        Some((base, n)) if n.chars().all(|c| c.is_ascii_digit()) => base,
        _ => name,
    }
}

/// The layers the build cuts, in file order, each once, with the operations its files run (the
/// reference layer is never run).
fn layers_and_operations(template: &Template, built: &Build) -> Vec<(String, Vec<Operation>)> {
    let mut names: Vec<&str> = Vec::new();
    let sheets = built.sheets.iter().map(|s| s.layer.as_str());
    let clamps = built
        .clamps
        .iter()
        .flat_map(|c| c.stack.iter().map(String::as_str));
    for name in sheets.chain(clamps).map(template_layer) {
        if !names.contains(&name) {
            names.push(name);
        }
    }
    names
        .into_iter()
        .map(|name| {
            let mut ops: Vec<Operation> = features_of(name)
                .iter()
                .map(|f| template.features.op(*f))
                .filter(|op| *op != Operation::Reference)
                .collect();
            ops.sort();
            ops.dedup();
            (name.to_string(), ops)
        })
        .collect()
}

/// The step that sets the laser up: the template's settings, then each operation it leaves out with
/// its starting point.
pub(super) fn settings_step(template: &Template, built: &Build) -> String {
    let mut given = Vec::new();
    let mut missing: Vec<(Operation, Vec<String>)> = Vec::new();
    for (layer, ops) in layers_and_operations(template, built) {
        for op in ops {
            match template.laser.get(&layer, op) {
                Some(s) => given.push(format!("{layer} {}: {}", operation_name(op), s.text())),
                None => match missing.iter_mut().find(|(o, _)| *o == op) {
                    Some((_, layers)) => layers.push(layer.clone()),
                    None => missing.push((op, vec![layer.clone()])),
                },
            }
        }
    }
    missing.sort_by_key(|(op, _)| *op);
    let mut text = String::from(
        "Set the laser up for each stock and operation (power, speed, passes, focus below the top \
         surface). ",
    );
    if !given.is_empty() {
        text.push_str(&format!(
            "From the template's {} table: {}. ",
            markdown::code("[laser]"),
            markdown::text(&given.join("; "))
        ));
    }
    if !missing.is_empty() {
        let rows: Vec<String> = missing
            .iter()
            .map(|(op, layers)| {
                format!(
                    "{} on {} (starting point: {})",
                    operation_name(*op),
                    layers.join(", "),
                    starting_point(*op)
                )
            })
            .collect();
        text.push_str(&format!(
            "Not in the template, so only starting points, to be confirmed on a test piece before \
             the production files: {}. Write the settings that pass into the template's {} \
             table for the next build.",
            markdown::text(&rows.join("; ")),
            markdown::code("[laser.LAYER]")
        ));
    }
    text.trim_end().to_string()
}

/// The test-score step: every PZT stock's coupon, scored and snapped before its production sheets.
pub(super) fn coupon_step(built: &Build) -> Option<String> {
    built.coupons.first()?;
    let size = |[w, h]: [f64; 2]| format!("{w} x {h} mm");
    let files: Vec<String> = built
        .coupons
        .iter()
        .map(|(stem, wh)| format!("{} (at least {})", markdown::code(stem), size(*wh)))
        .collect();
    Some(format!(
        "Before the first production PZT sheet, score the test coupon of each PZT stock on an \
         offcut of that stock, + face up, with the score setting above: {}. Snap it as the sheets \
         snap, the lines across first, then the slanted line: every strip must break along its \
         line, the narrow top strip (the narrowest a sheet leaves) whole and the slanted line \
         straight, the score's smooth band 1/3-1/2 of the thickness on the broken edge under a \
         loupe. A strip that breaks off its line, chips or will not snap: change the passes or \
         the power, note the setting and score a fresh coupon. Score the production sheets only \
         with a setting that passed.",
        files.join(", ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sheet_and_stack_names_map_to_the_template_layers() {
        assert_eq!(template_layer("passive-2"), "passive");
        assert_eq!(template_layer("passive"), "passive");
        assert_eq!(template_layer("teflon-cover-2"), "teflon-cover");
        assert_eq!(template_layer("mold-12"), "mold");
        assert_eq!(template_layer("pzt"), "pzt");
        assert_eq!(template_layer("porous-teflon-1"), "porous-teflon");
    }
}
