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

/// Designs evaluated together (in parallel) before they are handed on in order: enough to keep both
/// cores busy, few enough that memory does not grow with the sweep (about 25 MB of designs).
const BATCH: usize = 1 << 16;

/// Designs of one laminate evaluated by one task: the laminate is solved once per task.
const TASK: usize = 1024;

/// Level indices of design `index` over factors with these level counts, the first factor outermost
/// (mixed-radix digits of the index).
fn digits<const N: usize>(mut index: usize, counts: &[usize]) -> [usize; N] {
    let mut out = [0; N];
    for k in (0..N).rev() {
        out[k] = index % counts[k];
        index /= counts[k];
    }
    out
}

/// Evaluate every design in factor order (the first factor outermost) and hand each to `visit` with
/// its index, in that order. Designs are evaluated a batch at a time, so memory stays the same
/// whatever the number of designs; the first error (a design the model refuses, or `visit`'s own)
/// ends the sweep.
pub fn for_each_design<E: From<ModelError> + Send>(
    spec: &SweepSpec,
    kind: ModelKind,
    compare: Option<ModelKind>,
    mut visit: impl FnMut(usize, &SweepDesign) -> Result<(), E>,
) -> Result<(), E> {
    let counts: Vec<usize> = Factor::ALL.iter().map(|f| spec.level_count(*f)).collect();
    let per_laminate: usize = counts[4..].iter().product();
    let total = spec.count();
    let mut start = 0;
    while start < total {
        let end = (start + BATCH).min(total);
        // Tasks of at most TASK designs that share one laminate.
        let mut tasks = Vec::new();
        let mut i = start;
        while i < end {
            let laminate_end = (i / per_laminate + 1) * per_laminate;
            let task_end = end.min(laminate_end).min(i + TASK);
            tasks.push(i..task_end);
            i = task_end;
        }
        let batch: Vec<Vec<SweepDesign>> = tasks
            .into_par_iter()
            .map(|range| {
                let laminate: [usize; 4] = digits(range.start / per_laminate, &counts[..4]);
                evaluate_laminate(spec, kind, compare, laminate, &counts[4..], range)
            })
            .collect::<Result<_, ModelError>>()?;
        for (k, design) in batch.iter().flatten().enumerate() {
            visit(start + k, design)?;
        }
        start = end;
    }
    Ok(())
}

/// The designs `range` (global indices), all on the laminate with level indices `laminate`.
fn evaluate_laminate(
    spec: &SweepSpec,
    kind: ModelKind,
    compare: Option<ModelKind>,
    [i_e, i_d, i_t, i_l]: [usize; 4],
    planform_counts: &[usize],
    range: std::ops::Range<usize>,
) -> Result<Vec<SweepDesign>, ModelError> {
    let per_laminate: usize = planform_counts.iter().product();
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
            bias: spec.bias,
        },
    )?;
    range
        .map(|index| {
            let p: [usize; 4] = digits(index % per_laminate, planform_counts);
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
