//! Parts in holes: small parts nested inside the cut-outs of larger extra parts (frames, spars with
//! lightening holes) before the sheets are filled, carried with the copy whose hole holds them, and
//! checked against that hole by the verifier.

use crate::pipeline::cut::CutLayer;
use cam_geometry::{normalize_deg, place_point, place_ring, Bounds};
use cam_nest::{
    nest_shaped_until, verify_shape, verify_sheet, Clearance, NestBin, NestError, NestItem,
    NestProgress, NestSettings, NestViolation, NestedBin, PlacedPart, SearchLimit, SheetShape,
};

/// What the holes took: per host item, per copy, the parts in its cut-outs (in the host's own
/// frame, with the cut-out each lies in); and the copies of each item still to place on sheets.
pub(super) struct Kits {
    pub kits: Vec<Vec<Vec<(usize, PlacedPart)>>>,
    pub left: Vec<usize>,
}

/// A part placed in a hole on a sheet: the host's index among the sheet's parts, the cut-out, and
/// the guest's index among the sheet's parts.
#[derive(Debug, Clone, Copy)]
pub(super) struct Hosted {
    pub host: usize,
    pub hole: usize,
    pub guest: usize,
}

/// The rotations of `guest` that stay allowed whichever allowed rotation its host takes: a part in
/// a hole turns with the part around it.
fn turning_with(guest: &NestItem, host: &NestItem) -> Vec<f64> {
    let allowed = |deg: f64| {
        guest
            .rotations_deg
            .iter()
            .any(|&a| (normalize_deg(deg) - normalize_deg(a)).abs() < 1e-9)
    };
    guest
        .rotations_deg
        .iter()
        .copied()
        .filter(|&r| host.rotations_deg.iter().all(|&h| allowed(h + r)))
        .collect()
}

/// Every copy of each layer item with cut-outs gets its cut-outs filled, one after the other, each
/// with the fullest sheet of a nest, on sheets of the cut-out's shape, of the copies still to place
/// of the parts without cut-outs or holes of their own (one per actuator) at the rotations that
/// turn with the host. Parts keep `settings.separation_mm` from the cut-out's edge, as between parts.
pub(super) fn fill_holes(
    layer: &CutLayer,
    items: &[NestItem],
    settings: &NestSettings,
    limit: &SearchLimit<'_>,
    observe: &dyn Fn(&NestProgress),
) -> Result<Kits, NestError> {
    let mut left: Vec<usize> = items.iter().map(|i| i.demand).collect();
    let mut kits = vec![Vec::new(); items.len()];
    let guest = |g: usize| {
        let i = &layer.items[g];
        i.cutouts.is_empty() && i.holes.is_empty() && i.per_actuator == 1
    };
    for (h, host) in layer.items.iter().enumerate() {
        for _ in 0..items[h].demand {
            let mut kit = Vec::new();
            for (c, hole) in host.cutouts.iter().enumerate() {
                let b = Bounds::of(hole);
                let guests: Vec<NestItem> = items
                    .iter()
                    .enumerate()
                    .map(|(g, i)| NestItem {
                        demand: if g != h && guest(g) { left[g] } else { 0 },
                        rotations_deg: turning_with(i, &items[h]),
                        ..i.clone()
                    })
                    .map(|i| NestItem {
                        demand: if i.rotations_deg.is_empty() {
                            0
                        } else {
                            i.demand
                        },
                        ..i
                    })
                    .collect();
                let shape = SheetShape {
                    outline: hole
                        .iter()
                        .map(|q| [q[0] - b.min[0], q[1] - b.min[1]])
                        .collect(),
                    keep_outs: Vec::new(),
                };
                let bin = NestBin {
                    width_mm: b.width(),
                    height_mm: b.height(),
                    stock: 1,
                };
                for mut p in fullest(guests, &bin, &shape, settings, limit, observe)? {
                    p.translation = [p.translation[0] + b.min[0], p.translation[1] + b.min[1]];
                    for q in &mut p.outline {
                        *q = [q[0] + b.min[0], q[1] + b.min[1]];
                    }
                    left[p.item] -= 1;
                    kit.push((c, p));
                }
            }
            if kit.is_empty() {
                // The next copies' cut-outs are the same, and fewer parts are left for them.
                break;
            }
            kits[h].push(kit);
        }
    }
    Ok(Kits { kits, left })
}

/// The parts of the fullest sheet of a nest of `items` on sheets `bin` of `shape`; an item no such
/// sheet takes is left out.
fn fullest(
    mut items: Vec<NestItem>,
    bin: &NestBin,
    shape: &SheetShape,
    settings: &NestSettings,
    limit: &SearchLimit<'_>,
    observe: &dyn Fn(&NestProgress),
) -> Result<Vec<PlacedPart>, NestError> {
    loop {
        let copies: usize = items.iter().map(|i| i.demand).sum();
        if copies == 0 {
            return Ok(Vec::new());
        }
        let bin = NestBin {
            stock: copies,
            ..*bin
        };
        match nest_shaped_until(&items, &bin, shape, settings, limit, observe) {
            Ok((layout, _)) => {
                return Ok(layout
                    .bins
                    .into_iter()
                    .next()
                    .map(|b| b.parts)
                    .unwrap_or_default())
            }
            Err(NestError::PartLargerThanBin { item, .. }) => items[item].demand = 0,
            Err(e) => return Err(e),
        }
    }
}

/// Each placed copy of a host on `sheets` with its kit's parts placed on the sheet as the copy is
/// (turned by its rotation and moved by its translation), numbered after the `numbered` copies of
/// their item placed on sheets; the parts in holes of each sheet. A sheet's fill stays that of its
/// outlines: a host's outline counts the area of its cut-outs.
pub(super) fn carry(kits: &Kits, items: &[NestItem], sheets: &mut [NestedBin]) -> Vec<Vec<Hosted>> {
    let mut next: Vec<usize> = kits.left.clone();
    sheets
        .iter_mut()
        .map(|sheet| {
            let mut hosted = Vec::new();
            for host in 0..sheet.parts.len() {
                let p = sheet.parts[host].clone();
                let Some(kit) = kits.kits[p.item].get(p.copy) else {
                    continue;
                };
                for (hole, g) in kit {
                    let rotation_deg = normalize_deg(p.rotation_deg + g.rotation_deg);
                    let translation = place_point(g.translation, p.rotation_deg, p.translation);
                    hosted.push(Hosted {
                        host,
                        hole: *hole,
                        guest: sheet.parts.len(),
                    });
                    sheet.parts.push(PlacedPart {
                        item: g.item,
                        copy: next[g.item],
                        rotation_deg,
                        translation,
                        outline: place_ring(&items[g.item].outline, rotation_deg, translation),
                    });
                    next[g.item] += 1;
                }
            }
            hosted
        })
        .collect()
}

/// The verifier's check of the parts in holes (nominal outlines on `sheets`, in the sheet's frame):
/// each its item moved as stated, the parts in one cut-out `separation_mm` apart, and every one
/// inside its cut-out and `separation_mm` from its edge.
pub(super) fn verify_hosted(
    layer: &CutLayer,
    items: &[NestItem],
    bin: &NestBin,
    sheets: &[NestedBin],
    hosted: &[Vec<Hosted>],
    separation_mm: f64,
) -> Result<(), NestViolation> {
    let gap = super::promised(separation_mm);
    for (sheet, hosted) in sheets.iter().zip(hosted) {
        let mut holes: Vec<(usize, usize)> = hosted.iter().map(|h| (h.host, h.hole)).collect();
        holes.dedup();
        for (host, hole) in holes {
            let guests: Vec<PlacedPart> = hosted
                .iter()
                .filter(|h| (h.host, h.hole) == (host, hole))
                .map(|h| sheet.parts[h.guest].clone())
                .collect();
            let clearance = Clearance {
                between_parts_mm: gap,
                to_edge_mm: 0.0,
            };
            verify_sheet(
                items,
                bin,
                clearance,
                sheet.index,
                &guests,
                super::ROUNDING_MM,
            )?;
            let h = &sheet.parts[host];
            let outline = place_ring(
                &layer.items[h.item].cutouts[hole],
                h.rotation_deg,
                h.translation,
            );
            let shape = SheetShape {
                outline,
                keep_outs: Vec::new(),
            };
            verify_shape(&shape, gap, sheet.index, &guests, super::ROUNDING_MM)?;
        }
    }
    Ok(())
}
