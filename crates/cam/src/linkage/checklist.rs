//! The build steps of the linkage laminate (docs/cam.md §7), a section of their own that the cut sheet's
//! build checklist calls after the actuator's.

use super::LinkageReport;

/// The steps, in order, for `panels` linkage panels whose files are `linkage-*`.
pub fn linkage_steps(l: &LinkageReport, panels: usize) -> Vec<String> {
    let stack: Vec<String> = l
        .layers
        .iter()
        .map(|x| format!("{} ({})", x.layer, x.material))
        .collect();
    vec![
        format!(
            "Cut each linkage layer on its own sheet ({panels} panel(s)): the carbon layers with their flexure gap slots, the adhesive with its windows over the gaps (kept on its release liner), the {:.1} µm film with its windows; every sheet is cut to the panel outline with the panel's pin holes.",
            l.layers[2].thickness_mm * 1e3
        ),
        format!(
            "Stack on the clamp's pins, bottom to top: {}; peel each adhesive liner as its layer goes on. Check that every carbon slot lies under film and that no adhesive shows in a slot.",
            stack.join(" → ")
        ),
        "Cure under the clamp as the adhesive's datasheet asks, on the same pins.".to_string(),
        "Put the laminated stack back on the laser's pins and run the release cut (linkage-6-release-*): it cuts the outlines and the mounting holes through the stack, and the film alone across each gap.".to_string(),
        format!(
            "Fold the crank up against the coupler at joint B and fix the airframe tab through its {:.2} mm hole; bond the tip tab (beyond joint A) onto the actuator's extension end with the coupler along the actuator's travel.",
            l.hole_diameter_mm
        ),
        "Move the actuator tip by hand: the wing crank must turn about joint O with no adhesive stiffening a hinge and no film torn at a gap edge.".to_string(),
    ]
}
