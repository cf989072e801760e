//! `actuator-cam sweep`: a full factorial over listed levels (thesis Tables 3.1 and 3.2), every design's
//! outputs as CSV, a main-effects summary per output (thesis Table 4.11 in numbers), and the percent
//! differences between two models (thesis eq. 3.1, Table 4.1).

pub mod analysis;
pub mod spec;

use crate::optimize::model::SearchModel;
use actuator_model::{model, Laminate, ModelError, ModelKind, Performance, Planform, Section};
use rayon::prelude::*;
use spec::{Factor, SweepSpec};

/// One design of the sweep: its level per factor ([`Factor::ALL`] order) and predictions.
#[derive(Debug, Clone, Copy)]
pub struct SweepDesign {
    /// Level index per factor.
    pub levels: [usize; 8],
    /// The main model's prediction.
    pub primary: Performance,
    /// The compared model's prediction.
    pub compared: Option<Performance>,
}

/// Predict with a model from a section solved once per laminate (the Euler-Bernoulli beam goes through the
/// model crate, which solves its own).
fn predict(
    kind: ModelKind,
    laminate: &Laminate,
    section: &Section,
    planform: &Planform,
) -> Result<Performance, ModelError> {
    match SearchModel::from_kind(kind).and_then(|m| m.section_performance(section, planform)) {
        Some(p) => Ok(p),
        None => model::predict(kind, laminate, planform, section.drive),
    }
}

/// Evaluate every design, in factor order (the first factor outermost).
pub fn evaluate(
    spec: &SweepSpec,
    kind: ModelKind,
    compare: Option<ModelKind>,
) -> Result<Vec<SweepDesign>, ModelError> {
    let laminates: Vec<[usize; 4]> = cartesian(
        &Factor::ALL[..4]
            .iter()
            .map(|f| spec.level_count(*f))
            .collect::<Vec<_>>(),
    )
    .into_iter()
    .map(|v| [v[0], v[1], v[2], v[3]])
    .collect();
    let planforms = cartesian(
        &Factor::ALL[4..]
            .iter()
            .map(|f| spec.level_count(*f))
            .collect::<Vec<_>>(),
    );
    let per_laminate: Vec<Vec<SweepDesign>> = laminates
        .par_iter()
        .map(|&[i_e, i_d, i_t, i_l]| {
            let mut pzt = spec.pzt.clone();
            pzt.e1 = spec.pzt_modulus[i_e];
            pzt.e2 = pzt.e1;
            pzt.g12 = pzt.e1 / (2.0 * (1.0 + pzt.nu12));
            pzt.d31 = spec.pzt_d31[i_d];
            let laminate = Laminate::bimorph(
                &pzt,
                spec.pzt_thickness[i_t],
                &spec.ply,
                spec.ply_thickness,
                &spec.layups[i_l],
                None,
            )?;
            let section = Section::new(
                &laminate,
                actuator_model::Drive {
                    mode: spec.mode,
                    field: spec.field,
                },
            )?;
            planforms
                .iter()
                .map(|p| {
                    let planform = Planform::new(
                        spec.length[p[0]],
                        spec.extension_ratio[p[1]],
                        spec.base_width[p[2]],
                        spec.width_ratio[p[3]],
                        0.0,
                    )?;
                    Ok(SweepDesign {
                        levels: [i_e, i_d, i_t, i_l, p[0], p[1], p[2], p[3]],
                        primary: predict(kind, &laminate, &section, &planform)?,
                        compared: compare
                            .map(|k| predict(k, &laminate, &section, &planform))
                            .transpose()?,
                    })
                })
                .collect()
        })
        .collect::<Result<_, ModelError>>()?;
    Ok(per_laminate.into_iter().flatten().collect())
}

/// Every combination of level indices, the first factor outermost.
fn cartesian(counts: &[usize]) -> Vec<Vec<usize>> {
    counts.iter().fold(vec![Vec::new()], |acc, &n| {
        acc.into_iter()
            .flat_map(|prefix| {
                (0..n).map(move |i| {
                    let mut v = prefix.clone();
                    v.push(i);
                    v
                })
            })
            .collect()
    })
}

/// Why a sweep cannot run with these models.
#[derive(Debug, Clone, thiserror::Error)]
pub enum SweepError {
    /// The Euler-Bernoulli beam has no taper or extension.
    #[error("factors.extension_ratio / factors.width_ratio: the Euler-Bernoulli model covers rectangles only; use extension_ratio = [0] and width_ratio = [1] (or leave them out)")]
    BeamNeedsRectangles,
}

/// Check that every model of the sweep covers its factors.
pub fn check_models(
    spec: &SweepSpec,
    kind: ModelKind,
    compare: Option<ModelKind>,
) -> Result<(), SweepError> {
    let uses_beam = kind == ModelKind::EulerBernoulli || compare == Some(ModelKind::EulerBernoulli);
    if uses_beam && (spec.extension_ratio != [0.0] || spec.width_ratio != [1.0]) {
        return Err(SweepError::BeamNeedsRectangles);
    }
    Ok(())
}
