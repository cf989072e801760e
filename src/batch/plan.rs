//! Planning a batch: every design's parts on shared sheets through the layout pipeline, with the
//! irregular nester for the cut-through layers (each nest compared with the bounding-box baseline).
//! Nothing is written here.

use super::file::Batch;
use super::report::NestReport;
use crate::pipeline::{
    build, BuildError, Names, NestObserver, NestOptions, Packing, SheetDrawing, Unobserved,
};

/// Everything a batch run produces, in memory, before anything is written.
#[derive(Debug, Clone)]
pub struct Planned {
    /// Drawings in file order.
    pub drawings: Vec<SheetDrawing>,
    /// The report (files filled in when rendered).
    pub report: NestReport,
}

/// Plan every layer of a batch.
pub fn plan(batch: &Batch, opts: &NestOptions) -> Result<Planned, BuildError> {
    plan_observed(batch, opts, &Unobserved)
}

/// Plan every layer of a batch, telling `observer` how the nesting goes (the same layout as
/// [`plan`]).
pub fn plan_observed(
    batch: &Batch,
    opts: &NestOptions,
    observer: &dyn NestObserver,
) -> Result<Planned, BuildError> {
    let names = Names {
        title: batch.name.clone(),
        file: batch.source.display().to_string(),
        name_designs: true,
    };
    let designs: Vec<_> = batch
        .items
        .iter()
        .map(|i| (&i.design, i.quantity))
        .collect();
    let built = build(
        &designs,
        &batch.parts,
        &batch.template,
        &names,
        &Packing::Irregular(*opts, observer),
    )?;
    let report = NestReport::new(batch, opts, &built);
    Ok(Planned {
        drawings: built.drawings,
        report,
    })
}
