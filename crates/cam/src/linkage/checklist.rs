//! The build steps of the linkage laminate (docs/cam.md §7), a section of their own that the cut sheet's
//! build checklist calls after the actuator's, and the nest's build book after the batch's.

use super::LinkageReport;

/// The steps, in order, for `panels` linkage panels whose files are `linkage-*`; `pin_fit` says the
/// dowels in the pin holes ([`crate::book::pin_fit_text`]).
pub fn linkage_steps(l: &LinkageReport, panels: usize, pin_fit: &str) -> Vec<String> {
    let stack: Vec<String> = l
        .layers
        .iter()
        .map(|x| format!("{} ({})", x.layer, x.material))
        .collect();
    vec![
        format!(
            "Cut each linkage layer on its own sheet ({panels} panel(s)): the carbon layers with their flexure gap slots, from the layup laid with its 0° fibres along the sheet's x axis, the links' direction, as each file says; the adhesive with its windows over the gaps (kept on its release liner), the {:.1} µm film with its windows; every sheet is cut to the panel outline with the panel's pin holes.",
            l.layers[2].thickness_mm * 1e3
        ),
        format!(
            "Stack on the clamp's pins, {pin_fit}; bottom to top: {}; peel each adhesive liner as its layer goes on. Check that every carbon slot lies under film and that no adhesive shows in a slot.",
            stack.join(" → ")
        ),
        cure_step(l, "the stack", "on the same pins"),
        "Put the laminated stack back on the laser's pins and run the release cut (linkage-6-release-*): it cuts the outlines and the mounting holes through the stack, and the film alone across each gap; the pin holes are drawn grey, a guide the laser never runs, since the stack sits on the steel dowels through them.".to_string(),
    ]
    .into_iter()
    .chain(assembly(l))
    .collect()
}

/// The steps for `quantity` linkages nested as coupons (docs/cam.md §7, "Nested with the actuators"):
/// `sheets` says where each layer's coupons are (stack positions, sheet), `prefix` names the coupon's
/// files; `pin_fit` says the dowels in the pin holes; `jig` is the jig's step and file stem
/// ([`super::jig::jig_step`]).
pub fn coupon_steps(
    l: &LinkageReport,
    quantity: usize,
    sheets: &[(Vec<usize>, String)],
    prefix: &str,
    pin_fit: &str,
    jig: (&str, &str),
) -> Vec<String> {
    let (jig_step, jig) = jig;
    let whereabouts: Vec<String> = sheets
        .iter()
        .map(|(layers, sheet)| {
            let numbers: Vec<String> = layers.iter().map(|n| n.to_string()).collect();
            format!("layer {} on {sheet}", numbers.join(" and "))
        })
        .collect();
    let stack: Vec<String> = l
        .layers
        .iter()
        .map(|x| format!("{} ({})", x.layer, x.material))
        .collect();
    let release = l.layers.len() + 1;
    vec![
        format!(
            "The {quantity} linkage(s) are nested as coupons, one per layer and linkage, each with four pin holes of the clamp panel's pin radius: {}. Keep each adhesive coupon on its release liner. `{prefix}1-…` to `{prefix}{}-…` are reference only, never to be cut (each file's title says so): one coupon of each layer as nested, before its turn on the sheet.",
            whereabouts.join("; "),
            l.layers.len()
        ),
        jig_step.to_string(),
        format!(
            "For each linkage stack its coupons on the jig's four dowels (`{jig}`) through their pin holes, {pin_fit}, the chamfered corner on the jig's outline; bottom to top: {}; peel each adhesive liner as its coupon goes on. Check that every carbon slot lies under film and that no adhesive shows in a slot.",
            stack.join(" → ")
        ),
        cure_step(l, "the coupons", "on the jig's dowels"),
        format!(
            "Lay the jig on the laser bed with each laminated coupon on its dowels and run the release cut `{prefix}{release}-release-1` over each coupon, the file's origin on the lower-left corner of the coupon's outline engraved on the jig: it cuts the outline and the mounting hole through the stack, and the film alone across each gap; the pin holes are drawn grey, a guide the laser never runs, since the coupon sits on the steel dowels through them."
        ),
    ]
    .into_iter()
    .chain(assembly(l))
    .collect()
}

/// The laminate's cure: the template's `[linkage.cure]`, or, where it has none, the adhesive's
/// datasheet, named as missing.
fn cure_step(l: &LinkageReport, what: &str, pins: &str) -> String {
    match &l.cure {
        Some(cure) => format!(
            "Cure {what} under the clamp, {pins}, between non-porous Teflon release films: {cure} (the template's `[linkage.cure]`); let it cool in the clamp."
        ),
        None => format!(
            "Cure {what} under the clamp, {pins}, between non-porous Teflon release films, as the adhesive's and the carbon's datasheets ask: the template gives no `[linkage.cure]`."
        ),
    }
}

/// Assembling a released linkage to its actuator and checking it. Joint B's fold and the strain of
/// the fold with the flight's turn on top, `ε = t β / (2 L_e)` (docs/physics.md §16.7), are the report's:
/// the flexure check chose B's length for them, so they are within the film's limit.
fn assembly(l: &LinkageReport) -> Vec<String> {
    let fold = l.flexures.get(1).map_or(String::new(), |b| {
        format!(
            " Joint B folds {:.1}° here and turns on that fold in flight: its film bends up to {:.1}° from flat, {:.2} % strain over its {:.1} µm of unbonded film (t β / (2 L)), within the film's {:.2} %.",
            b.assembly_fold_deg,
            b.peak_bend_deg,
            b.peak_strain * 100.0,
            b.unbonded_um,
            b.strain_limit * 100.0
        )
    });
    vec![
        format!(
            "Fold the crank up against the coupler at joint B and fix the airframe tab through its {:.2} mm hole; bond the tip tab (beyond joint A) onto the actuator's extension end with the coupler along the actuator's travel.{fold}",
            l.hole_diameter_mm
        ),
        "Move the actuator tip by hand: the wing crank must turn about joint O with no adhesive stiffening a hinge and no film torn at a gap edge.".to_string(),
    ]
}
