//! The settle: a compressed sheet's parts pushed down and left, one at a time, onto the parts
//! under them, with jagua-rs's exact collision test.
//!
//! Compression leaves every contact a little open. Its overlap measure calls two parts clear
//! only once they are [`crate::overlap`]'s clearance apart, and its moves stop at a share of
//! the part's size, so a separated part rests up to a few thousandths of its size off the part
//! beneath. Up a column of parts those gaps add up: on a strip of parts a few units long, such as
//! ESICUP's jakobs1, about a thousandth of the strip's length, where sparrow, whose parts rest on
//! one another, is within a few ten-thousandths of the optimum. The settle closes those gaps. It
//! moves no part up or right, so the sheet's top never rises.

use jagua_rs::probs::bpp::entities::{BPLayoutType, BPProblem};

use super::model::{slide, Model};
use crate::placement::Placement;

/// First and last step of a part's settling slide. The first is above the gaps compression
/// leaves, and the last far under them, yet far above f32 rounding at a few hundred millimetres
/// (a few micrometres), where jagua-rs's collision test could no longer tell a step from noise.
const SETTLE_STEPS_MM: (f32, f32) = (0.01, 1e-4);

/// Passes over the parts: a part held up by one that settles after it gets down in the next.
const SETTLE_PASSES: usize = 3;

impl Model<'_> {
    /// `sheet` with each part, lowest first, slid down and left as far as it stays clear
    /// ([`slide`] with [`SETTLE_STEPS_MM`]), over [`SETTLE_PASSES`] passes or until one moves
    /// nothing. The parts keep their order in the list.
    pub(super) fn settled(&self, sheet: &[Placement]) -> Vec<Placement> {
        let mut sheet = sheet.to_vec();
        if sheet.len() < 2 {
            return sheet;
        }
        let mut problem = BPProblem::new(self.instance.clone());
        let mut keys = Vec::with_capacity(sheet.len());
        let mut layout = None;
        for &spot in &sheet {
            let layout_id = layout.map_or(BPLayoutType::Closed { bin_id: 0 }, BPLayoutType::Open);
            let (l, key) = problem.place_item(self.bp_placement(layout_id, spot));
            layout = Some(l);
            keys.push(key);
        }
        let layout = layout.expect("a sheet of two parts or more");
        let bottom = |s: &Placement| s.t.1 - self.shapes[s.part][s.rot].y.0;
        for _ in 0..SETTLE_PASSES {
            let mut order: Vec<usize> = (0..sheet.len()).collect();
            order.sort_by(|&a, &b| bottom(&sheet[a]).total_cmp(&bottom(&sheet[b])));
            let mut moved = false;
            for i in order {
                let spot = sheet[i];
                let shape = &self.shapes[spot.part][spot.rot];
                problem.remove_item(layout, keys[i]);
                let cde = problem.layouts()[layout].cde();
                let t = slide(
                    cde,
                    shape,
                    &mut shape.plain.clone(),
                    spot.t,
                    SETTLE_STEPS_MM,
                );
                moved |= t != spot.t;
                sheet[i].t = t;
                let placed = self.bp_placement(BPLayoutType::Open(layout), sheet[i]);
                keys[i] = problem.place_item(placed).1;
            }
            if !moved {
                break;
            }
        }
        sheet
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::job::Job;
    use crate::problem::NestSettings;
    use crate::test_support::squares_job;

    #[test]
    fn a_floating_part_comes_to_rest_on_the_part_under_it_and_nothing_rises() {
        // 10 mm squares, 0.3 mm apart: jagua-rs's collision squares are 10 mm plus the model's
        // separation, so resting squares sit one collision side apart, to the slide's last step.
        let (items, bin) = squares_job(3, 1);
        let job = Job::new(&items, &bin, &NestSettings::default()).unwrap();
        let model = Model::new(&job).unwrap();
        let shape = &model.shapes[0][0];
        let b = shape.plain.bbox();
        let (w, h) = (b.x_max - b.x_min, b.y_max - b.y_min);
        let corner = (shape.x.0, shape.y.0);
        let at = |x: f32, y: f32| Placement {
            part: 0,
            rot: 0,
            t: (corner.0 + x, corner.1 + y),
        };
        // One square in the corner, one 0.5 mm above it, one floating up and to the right.
        let start = vec![at(0.0, 0.0), at(0.0, h + 0.5), at(30.0, 3.0)];
        assert!(model.clear(&start));
        let settled = model.settled(&start);
        assert!(model.clear(&settled), "{settled:?}");
        assert!(model.sheet_top(&settled) <= model.sheet_top(&start));
        assert_eq!(settled[0], start[0], "the corner square cannot move");
        // The second rests on the first: down by the 0.5 mm gap, to within the last step.
        let rise = settled[1].t.1 - (corner.1 + h);
        assert!((0.0..2.0 * SETTLE_STEPS_MM.1).contains(&rise), "{rise}");
        assert_eq!(settled[1].t.0, corner.0);
        // The third goes down to the sheet's bottom, then left against the first.
        assert_eq!(settled[2].t.1, corner.1);
        let off = settled[2].t.0 - (corner.0 + w);
        assert!((0.0..2.0 * SETTLE_STEPS_MM.1).contains(&off), "{off}");
        // The list keeps its order, and a sheet of one part is left alone.
        assert!(settled
            .iter()
            .zip(&start)
            .all(|(s, t)| s.part == t.part && s.rot == t.rot));
        let alone = vec![at(20.0, 20.0)];
        assert_eq!(model.settled(&alone), alone);
    }
}
