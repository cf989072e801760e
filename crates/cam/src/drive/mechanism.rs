//! What the drive flaps and through what, built before the operating field is searched: the wing, and
//! the transmission's kinematics, its drawn laminate (when the file gives flexures), its flexures
//! checked, and the stiffness, inertia and mass it adds. A solved linkage is sized from the
//! actuator's free deflection at the design's own field, so a field-dependent model's search moves the
//! actuator, not the linkage.

use super::spec::{DriveSpec, LinkageSpec};
use super::stages::{self, kinematics, linkage};
use super::DriveError;
use crate::design::transmission::TransmissionSpec;
use crate::design::Design;
use crate::input::fixed;
use crate::input::InputError;
use crate::linkage::flexures::FlexureRow;
use crate::linkage::LinkageLaminate;
use crate::prediction::performance;
use crate::process::template::Template;
use actuator_model::kinematics::Kinematics;
use actuator_model::model::ModelChoice;
use actuator_model::wing::Wing;
use actuator_model::Performance;

/// The wing and the transmission, SI.
#[derive(Debug, Clone)]
pub struct Mechanism {
    /// The wing the drive sees.
    pub wing: Wing,
    /// The transmission's kinematics.
    pub kinematics: Kinematics,
    /// The drawn linkage, when the file gives its flexures.
    pub laminate: Option<LinkageLaminate>,
    /// A two-stage linkage's flexures, or why one cannot be made ([`stages::two_stage_flexures`]).
    pub two_stage: Option<Result<Vec<FlexureRow>, String>>,
    /// Why the linkage cannot be built, if it cannot.
    pub unbuildable: Option<String>,
    /// Flexure stiffness about the wing hinge, N·m/rad.
    pub flexure_stiffness: f64,
    /// The links' inertia about the wing hinge, kg·m².
    pub link_inertia: f64,
    /// The transmission's mass, kg.
    pub mass: f64,
}

impl Mechanism {
    /// The mechanism of a drive file for its design (at the design's own field) under `model`. With
    /// flexures in the file, the transmission's stiffness, inertia and mass are the drawn linkage's.
    pub fn of(spec: &DriveSpec, design: &Design, model: &ModelChoice) -> Result<Self, DriveError> {
        let perf = performance(design, model)?;
        let kinematics = kinematics(&spec.transmission, &perf)?;
        // The template read once: the drawn linkage, the two-stage's flexures and the check of a
        // linkage given by its stiffness all take their rules from it.
        let template = Template::resolve(&design.process, &design.source);
        let laminate = match spec.transmission.flexures {
            Some(_) => Some(drawn(spec, &perf, &template.clone()?)?),
            None => None,
        };
        let template = template.ok();
        let two_stage =
            stages::two_stage_flexures(&kinematics, &spec.transmission, template.as_ref());
        let unbuildable = match (&laminate, &two_stage) {
            (_, Some(checked)) => checked.clone().err(),
            (Some(_), None) => None,
            // A linkage given by its stiffness alone is still drawn, as cut-sheet would draw it, to
            // check that its flexures can be built at all.
            (None, None) => template
                .as_ref()
                .and_then(|t| unbuildable_linkage(spec, &perf, t)),
        };
        let (flexure_stiffness, link_inertia, mass) = match &laminate {
            Some(l) => (l.flexure_stiffness(), l.link_inertia(), l.mass()),
            None => (
                spec.transmission.flexure_stiffness,
                spec.transmission.link_inertia,
                spec.transmission.transmission_mass,
            ),
        };
        Ok(Mechanism {
            wing: spec.wing.wing(),
            kinematics,
            laminate,
            two_stage,
            unbuildable,
            flexure_stiffness,
            link_inertia,
            mass,
        })
    }
}

/// The linkage laminate of the transmission `spec` (given in the file `source`, which refusals name)
/// with the materials and rules of `template`'s `[linkage]` (a batch's template, whose kerf is the
/// larger of the linkage's and the prepreg sheet's when the carbon shares the prepreg sheets).
pub fn linkage_laminate_in(
    spec: &TransmissionSpec,
    source: &std::path::Path,
    design: &Design,
    model: &ModelChoice,
    template: &Template,
) -> Result<LinkageLaminate, DriveError> {
    laminate_for(spec, source, &performance(design, model)?, template)
}

/// The drawn linkage of a drive file's transmission for an actuator predicted as `perf`.
fn drawn(
    spec: &DriveSpec,
    perf: &Performance,
    template: &Template,
) -> Result<LinkageLaminate, DriveError> {
    laminate_for(&spec.transmission, &spec.source, perf, template)
}

/// [`linkage_laminate_in`] for an actuator predicted as `perf`: refused where the transmission cannot
/// be drawn ([`no_drawing`]) or the template has no `[linkage]`.
fn laminate_for(
    spec: &TransmissionSpec,
    source: &std::path::Path,
    perf: &Performance,
    template: &Template,
) -> Result<LinkageLaminate, DriveError> {
    if let Some(refusal) = no_drawing(spec, source) {
        return Err(refusal.into());
    }
    let Some(process) = template.linkage.as_ref() else {
        return Err(InputError::invalid(
            &template.source,
            "linkage",
            "(missing)",
            "a [linkage] table (materials of the flexure linkage laminate, docs/cam.md §7)",
        )
        .into());
    };
    Ok(LinkageLaminate::design(
        linkage(&spec.linkage, perf)?,
        spec.end_angles(),
        &spec.flexures.clone().unwrap_or_default(),
        process,
        source,
        &template.source,
    )?)
}

/// Why no linkage drawing is made of a transmission: a ratio alone has no lengths, and the two-stage
/// linkage's flexures are checked by `drive` but its layer files are not drawn.
fn no_drawing(spec: &TransmissionSpec, source: &std::path::Path) -> Option<InputError> {
    let (field, value, why) = match (spec.linkage, spec.four_bar) {
        (LinkageSpec::Ratio(law), _) => (
            "transmission.ratio_rad_per_m",
            fixed(law.ratio, 0),
            "link lengths to draw: no linkage drawing can be made from a ratio alone (give coupler_ratio for the slider-crank of that ratio)",
        ),
        (_, Some(_)) => (
            "transmission.four_bar",
            "(given)".to_string(),
            "a one-stage slider-crank to draw: drive checks the two-stage linkage's flexures, but no layer files are drawn of it",
        ),
        _ => return None,
    };
    Some(InputError::invalid(source, field, value, why))
}

/// Why the linkage of a drive file that gives no flexures cannot be built with its design's process
/// (the flexure rules cut-sheet applies: the film's fatigue strain, the gap against the links beside it,
/// the carbon left bonded), or `None` when it can, or when the process has no `[linkage]` to build it with.
fn unbuildable_linkage(
    spec: &DriveSpec,
    perf: &Performance,
    template: &Template,
) -> Option<String> {
    // A ratio alone or a two-stage linkage is not drawn; the two-stage's flexures are checked apart.
    no_drawing(&spec.transmission, &spec.source)
        .is_none()
        .then_some(())?;
    template.linkage.as_ref()?;
    let refusal = drawn(spec, perf, template).err()?;
    // The refusal's field is the flexure request the file leaves out; what is wrong is its text.
    let why = match refusal {
        DriveError::Input(e) => e.expected,
        e => e.to_string(),
    };
    Some(format!(
        "{why}; to build it: a longer crank (a larger travel_mm), a thinner film (film_thickness_um), or a second stage"
    ))
}
