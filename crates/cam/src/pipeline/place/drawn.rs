//! A cut layer's drawn sheets (remnants, sheets with flaws: [`crate::process::DrawnSheet`]) filled
//! before its whole sheets, each checked by the verifier against its outline and keep-outs.

use crate::pipeline::cut::CutLayer;
use cam_nest::{
    nest_shaped_until, verify_shape, NestBin, NestError, NestItem, NestProgress, NestSettings,
    NestViolation, NestedBin, SearchLimit, SheetShape,
};

/// What the drawn sheets took: the sheets used (in the packers' frame, copies numbered from 0 per
/// item), the drawn sheet each is, and the copies of each item still to place.
pub(super) struct OnDrawn {
    pub sheets: Vec<NestedBin>,
    pub drawn: Vec<usize>,
    pub left: Vec<usize>,
}

/// The items nested on the layer's drawn sheets one after the other, each taking the fullest
/// sheet of a nest of the copies still to place on sheets of its shape (the shape moved into the
/// packers' room by `shift_mm`, [`super::room_of`]); an item that fits no such sheet waits for the
/// next. The irregular nester keeps `settings.separation_mm` from the outline and keep-outs as
/// between parts.
pub(super) fn fill_drawn(
    layer: &CutLayer,
    items: &[NestItem],
    room: &NestBin,
    shift_mm: f64,
    settings: &NestSettings,
    limit: &SearchLimit<'_>,
    observe: &dyn Fn(&NestProgress),
) -> Result<OnDrawn, NestError> {
    let mut left: Vec<usize> = items.iter().map(|i| i.demand).collect();
    let (mut sheets, mut drawn) = (Vec::new(), Vec::new());
    for (k, sheet) in layer.spec.drawn.iter().enumerate() {
        let shape = moved(&sheet.shape, -shift_mm);
        let mut these: Vec<NestItem> = items
            .iter()
            .zip(&left)
            .map(|(i, &n)| NestItem {
                demand: n,
                ..i.clone()
            })
            .collect();
        let best = loop {
            let copies: usize = these.iter().map(|i| i.demand).sum();
            if copies == 0 {
                break None;
            }
            let bin = NestBin {
                stock: copies,
                ..*room
            };
            match nest_shaped_until(&these, &bin, &shape, settings, limit, observe) {
                Ok((layout, _)) => break layout.bins.into_iter().next(),
                // A part this sheet cannot take waits for the next sheet.
                Err(NestError::PartLargerThanBin { item, .. }) => these[item].demand = 0,
                Err(e) => return Err(e),
            }
        };
        let Some(mut best) = best else { continue };
        for p in &mut best.parts {
            p.copy = items[p.item].demand - left[p.item];
            left[p.item] -= 1;
        }
        best.index = sheets.len();
        sheets.push(best);
        drawn.push(k);
    }
    Ok(OnDrawn {
        sheets,
        drawn,
        left,
    })
}

/// `shape` moved by `by_mm` along both axes.
fn moved(shape: &SheetShape, by_mm: f64) -> SheetShape {
    let ring = |r: &Vec<[f64; 2]>| r.iter().map(|q| [q[0] + by_mm, q[1] + by_mm]).collect();
    SheetShape {
        outline: shape
            .outline
            .iter()
            .map(|q| [q[0] + by_mm, q[1] + by_mm])
            .collect(),
        keep_outs: shape.keep_outs.iter().map(ring).collect(),
    }
}

/// The verifier's check of the drawn sheets among `sheets` (the first `drawn.len()`, on the sheet
/// in its own frame): no packed ring within `separation_mm` of its drawn sheet's outline or
/// keep-outs.
pub(super) fn verify_drawn(
    layer: &CutLayer,
    sheets: &[NestedBin],
    drawn: &[usize],
    separation_mm: f64,
) -> Result<(), NestViolation> {
    for (sheet, &k) in sheets.iter().zip(drawn) {
        verify_shape(
            &layer.spec.drawn[k].shape,
            super::promised(separation_mm),
            sheet.index,
            &sheet.parts,
            super::ROUNDING_MM,
        )?;
    }
    Ok(())
}
