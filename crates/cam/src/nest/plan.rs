//! Planning a batch: every design's parts on shared sheets through the layout pipeline, with the
//! irregular nester for the cut-through layers (each nest compared with the bounding-box baseline).
//! Nothing is written here.

use super::file::Batch;
use super::file::RollPrice;
use super::linkage::coupon_drawings;
use super::remnant::remnant_drawings;
use super::report::NestReport;
use crate::linkage::jig::jig_drawing;
use crate::pipeline::{
    build, sheets_instead_of_roll, BuildError, Names, NestObserver, NestOptions, Packing,
    SheetDrawing, StockCount, Unobserved,
};

/// Everything a batch run produces, in memory, before anything is written.
#[derive(Debug, Clone)]
pub struct Planned {
    /// Drawings in file order.
    pub drawings: Vec<SheetDrawing>,
    /// The report (files filled in when rendered).
    pub report: NestReport,
    /// The snapping-order picture of each PZT sheet, (file name, SVG).
    pub snap_guides: Vec<(String, String)>,
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
    // A priced roll is compared with the cut sheets a lab would buy instead: its parts are nested
    // on those too (one more job per roll layer, numbered after the build's jobs: the bar counts
    // on rather than starting again at 1; its total grows by these jobs when they start, as the
    // build cannot tell which of its layers are priced rolls before it has made them).
    let priced: Vec<(usize, RollPrice)> = built
        .cut_layers
        .iter()
        .enumerate()
        .filter(|(_, l)| l.layer.spec.roll)
        .filter_map(|(i, l)| batch.roll_price(&l.layer.layer).map(|p| (i, p)))
        .collect();
    let mut on_sheets = vec![None; built.cut_layers.len()];
    for (k, (i, price)) in priced.iter().enumerate() {
        let layer = &built.cut_layers[*i].layer;
        let label = format!(
            "{} on {} x {} mm sheets instead of the roll",
            layer.layer, price.sheet_width_mm, price.sheet_height_mm
        );
        let copies = layer.items.iter().map(|i| i.count).sum();
        let jobs = built.cut_layers.len();
        observer.layer(jobs + k, jobs + priced.len(), &label, copies);
        let sheets = sheets_instead_of_roll(
            layer,
            price.sheet_width_mm,
            price.sheet_height_mm,
            opts,
            observer,
            &names,
        )
        .map_err(|e| match e {
            BuildError::Geometry { file, what } => BuildError::Geometry {
                file,
                what: format!(
                    "the sheets a roll is compared with (compare_with, default the process template's sheet): {what}"
                ),
            },
            other => other,
        })?;
        on_sheets[*i] = Some(sheets);
    }
    let coupons = coupon_drawings(&batch.linkages, &designs, &batch.template)?;
    let prefixes: Vec<String> = coupons.iter().map(|(p, _)| p.clone()).collect();
    let jig = jig_of(batch, &designs);
    let mut report = NestReport::new(
        batch,
        opts,
        &built,
        &on_sheets,
        &prefixes,
        jig.as_ref().map(|j| j.stem.as_str()),
    );
    if let Some(j) = &jig {
        StockCount::count(&mut report.stock_list, &j.drawing, 1);
    }
    let remnants = remnant_drawings(&batch.name, &built.sheets, &built.drawings);
    let mut drawings = built.drawings;
    drawings.extend(remnants);
    drawings.extend(coupons.into_iter().flat_map(|(_, d)| d));
    drawings.extend(jig);
    Ok(Planned {
        drawings,
        report,
        snap_guides: built.snap_guides,
    })
}

/// The jig of the batch's linkage coupons, each named by its item's design; `None` without linkages.
fn jig_of(batch: &Batch, designs: &[(&crate::design::Design, usize)]) -> Option<SheetDrawing> {
    let first = batch.linkages.first()?;
    let coupons: Vec<_> = batch
        .linkages
        .iter()
        .map(|l| {
            let name = designs[l.item].0.name.clone();
            (name, l.coupon.clamp.clone(), l.quantity)
        })
        .collect();
    jig_drawing(
        &coupons,
        &first.laminate.process,
        &batch.template.features,
        &batch.name,
    )
}
