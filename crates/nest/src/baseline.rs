//! Bounding-box baseline: each part's axis-aligned bounding box, at its allowed rotation with the
//! smallest box, packed by MaxRects (best short side fit, Jylänki 2010, "A Thousand Ways to Pack
//! the Bin", §3.2) onto as many sheets as needed. This is what a rectangle packer achieves; the
//! irregular nester is measured against it.

use cam_geometry::{place_ring, Bounds};

use crate::job::{Job, Placed};
use crate::problem::{NestBin, NestError, NestItem, NestSettings, NestSolution};

/// Rotations (index) of one copy that give its smallest box, with the box size.
type BoxChoices = Vec<(usize, [f64; 2])>;

/// Nests every part by its bounding box (see the module docs).
pub fn nest_bounding_boxes(
    items: &[NestItem],
    bin: &NestBin,
    settings: &NestSettings,
) -> Result<NestSolution, NestError> {
    let job = Job::new(items, bin, settings)?;
    let sep = settings.separation_mm;

    // One entry per copy: (part, candidate rotations with the smallest box, box size).
    let mut copies: Vec<(usize, BoxChoices)> = Vec::with_capacity(job.copies());
    for (p, part) in job.parts.iter().enumerate() {
        let sizes: Vec<(usize, [f64; 2])> = part
            .rotations_deg
            .iter()
            .enumerate()
            .map(|(r, &deg)| (r, part.bbox_size(deg)))
            .collect();
        let smallest = sizes
            .iter()
            .map(|(_, s)| s[0] * s[1])
            .fold(f64::INFINITY, f64::min);
        let best: BoxChoices = sizes
            .into_iter()
            .filter(|(_, s)| s[0] * s[1] <= smallest * (1.0 + 1e-9))
            .collect();
        copies.extend((0..part.demand).map(|_| (p, best.clone())));
    }
    // Largest boxes first (longest side, then area); stable, so ties keep input order.
    copies.sort_by(|a, b| {
        let key = |c: &(usize, BoxChoices)| {
            let s = c.1[0].1;
            (s[0].max(s[1]), s[0] * s[1])
        };
        let (ka, kb) = (key(a), key(b));
        kb.0.total_cmp(&ka.0).then(kb.1.total_cmp(&ka.1))
    });

    // Each box grows by the separation on its right and top; the free region starts one
    // separation in from the bottom-left sheet edges, so boxes keep the gap to each other and to
    // all four edges.
    let region = Rect {
        x: sep,
        y: sep,
        w: bin.width_mm - sep,
        h: bin.height_mm - sep,
    };
    let mut sheets: Vec<(MaxRects, Vec<Placed>)> = Vec::new();
    for (p, candidates) in copies {
        let part = &job.parts[p];
        let sized: Vec<(usize, f64, f64)> = candidates
            .iter()
            .map(|&(r, s)| (r, s[0] + sep, s[1] + sep))
            .collect();
        let mut placed = None;
        for (s, (packer, _)) in sheets.iter_mut().enumerate() {
            if let Some((r, x, y)) = packer.insert(&sized) {
                placed = Some((s, r, x, y));
                break;
            }
        }
        let (s, r, x, y) = match placed {
            Some(found) => found,
            None => {
                let mut packer = MaxRects::new(region);
                // Job::new checked that some rotation fits an empty sheet; the smallest box
                // fits too unless the sheet is narrower than it is tall in the wrong way.
                let (r, x, y) = packer.insert(&sized).ok_or_else(|| job.too_large(p))?;
                sheets.push((packer, Vec::new()));
                (sheets.len() - 1, r, x, y)
            }
        };
        let deg = part.rotations_deg[r];
        let b = Bounds::of(&place_ring(&part.outline, deg, [0.0, 0.0]));
        sheets[s].1.push(Placed {
            part: p,
            rot: r,
            translation: [x - b.min[0], y - b.min[1]],
        });
    }
    job.solution(sheets.into_iter().map(|(_, placed)| placed).collect())
}

/// The parts of the interval `[start, start + len)` before and after `[cut, cut + cut_len)`, as
/// `(start, len)`.
fn outside(start: f64, len: f64, cut: f64, cut_len: f64) -> [Option<(f64, f64)>; 2] {
    let (end, cut_end) = (start + len, cut + cut_len);
    [
        (cut > start).then_some((start, cut - start)),
        (cut_end < end).then_some((cut_end, end - cut_end)),
    ]
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Rect {
    x: f64,
    y: f64,
    w: f64,
    h: f64,
}

impl Rect {
    fn contains(&self, o: &Rect) -> bool {
        o.x >= self.x
            && o.y >= self.y
            && o.x + o.w <= self.x + self.w
            && o.y + o.h <= self.y + self.h
    }

    fn overlaps(&self, o: &Rect) -> bool {
        o.x < self.x + self.w && self.x < o.x + o.w && o.y < self.y + self.h && self.y < o.y + o.h
    }
}

/// Maximal free rectangles of one sheet.
struct MaxRects {
    free: Vec<Rect>,
}

impl MaxRects {
    fn new(region: Rect) -> Self {
        Self { free: vec![region] }
    }

    /// Places the first fitting of `sizes` `(rotation, w, h)` by best short side fit; returns
    /// the rotation and the bottom-left corner.
    fn insert(&mut self, sizes: &[(usize, f64, f64)]) -> Option<(usize, f64, f64)> {
        let mut best: Option<((f64, f64), usize, Rect)> = None;
        for free in &self.free {
            for &(r, w, h) in sizes {
                if w <= free.w && h <= free.h {
                    let (dw, dh) = (free.w - w, free.h - h);
                    let score = (dw.min(dh), dw.max(dh));
                    if best.as_ref().is_none_or(|(s, _, _)| score < *s) {
                        let placed = Rect {
                            x: free.x,
                            y: free.y,
                            w,
                            h,
                        };
                        best = Some((score, r, placed));
                    }
                }
            }
        }
        let (_, r, placed) = best?;
        self.split(&placed);
        Some((r, placed.x, placed.y))
    }

    /// Cuts `used` out of every free rectangle and drops rectangles inside others.
    fn split(&mut self, used: &Rect) {
        let mut next = Vec::with_capacity(self.free.len() + 4);
        for f in &self.free {
            if !f.overlaps(used) {
                next.push(*f);
                continue;
            }
            let beside =
                outside(f.x, f.w, used.x, used.w).map(|r| r.map(|(x, w)| Rect { x, w, ..*f }));
            let over =
                outside(f.y, f.h, used.y, used.h).map(|r| r.map(|(y, h)| Rect { y, h, ..*f }));
            next.extend(beside.into_iter().chain(over).flatten());
        }
        let mut kept: Vec<Rect> = Vec::with_capacity(next.len());
        for (i, r) in next.iter().enumerate() {
            let covered = next
                .iter()
                .enumerate()
                .any(|(j, o)| j != i && o.contains(r) && (o != r || j < i));
            if !covered {
                kept.push(*r);
            }
        }
        self.free = kept;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::verify::verify;

    #[test]
    fn four_squares_fill_a_sheet_exactly() {
        // Four 49 mm squares with 1 mm gaps need 2 * 49 + 3 * 1 = 101 mm per side.
        let square = vec![[0.0, 0.0], [49.0, 0.0], [49.0, 49.0], [0.0, 49.0]];
        let items = [NestItem {
            outline: square,
            demand: 4,
            rotations_deg: vec![0.0],
        }];
        let (bin, settings) = (
            NestBin {
                width_mm: 101.5,
                height_mm: 101.5,
                stock: 1,
            },
            NestSettings {
                separation_mm: 1.0,
                ..NestSettings::default()
            },
        );
        let solution = nest_bounding_boxes(&items, &bin, &settings).unwrap();
        assert_eq!(solution.bins_used(), 1);
        verify(&items, &bin, &settings, &solution, 1e-9).unwrap();
    }
}
