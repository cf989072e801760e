//! Where a passive part's engraved label goes: never on the bonded face. The PZT plates (and, by
//! method 1, the Pyralux film) are bonded over the part's PZT zone, `0 <= y <= l_p` from the root;
//! an engraved groove there is a void in the bond line (docs/cam.md §1 "Labels"). The
//! label goes where nothing is bonded: the base tab behind the root, else the extension beyond the
//! PZT zone. A part with no room there carries no label, and the report says so ([`Label::note`]).

use super::parts::PartGeometry;
use crate::drawing::label::{label_strokes, label_width};
use crate::process::template::{PassiveCut, Template};
use cam_geometry::{place_ring, Point};

/// The engraved label of a part, if it has room for one off the bonded zone.
#[derive(Debug, Clone)]
pub enum Label {
    /// No label.
    None,
    /// `"{name} {n}"` (or just `n`) on the base tab or the extension.
    OffBonded {
        /// Plan dimensions.
        geometry: PartGeometry,
        /// Design name.
        name: String,
        /// Text height, mm.
        height_mm: f64,
        /// Room to keep to the part edge and to the bonded zone, mm.
        margin_mm: f64,
    },
    /// Each copy's strokes, placed by the part's maker (a linkage coupon's border).
    PerCopy(Vec<Vec<Vec<Point>>>),
}

/// A rectangle of the part where nothing is bonded, in part coordinates: `[x0, y0, x1, y1]`.
type Site = [f64; 4];

impl Label {
    /// Each copy's strokes as given, or no label when none are.
    pub fn per_copy(strokes: &[Vec<Vec<Point>>]) -> Label {
        match strokes.is_empty() {
            true => Label::None,
            false => Label::PerCopy(strokes.to_vec()),
        }
    }

    /// The label of a design's passive part: the template's text height, and the passive kerf (at
    /// least 0.2 mm, the engraved line's own width and the frayed edge) to every edge. Plies cut one
    /// by one carry none.
    pub fn passive(geometry: PartGeometry, name: &str, template: &Template) -> Label {
        match template.passive_cut {
            PassiveCut::Stack => Label::OffBonded {
                geometry,
                name: name.to_string(),
                height_mm: template.label_height_mm,
                margin_mm: template.passive.kerf_mm.max(0.2),
            },
            PassiveCut::PlyByPly => Label::None,
        }
    }

    /// Strokes of the label of copy `copy` (0-based), in part coordinates: the full label where it
    /// fits, else the copy number alone, else none.
    pub fn strokes(&self, copy: usize) -> Option<Vec<Vec<Point>>> {
        match self {
            Label::None => None,
            Label::PerCopy(each) => each.get(copy).cloned(),
            Label::OffBonded {
                geometry,
                name,
                height_mm,
                margin_mm,
            } => [format!("{name} {}", copy + 1), format!("{}", copy + 1)]
                .iter()
                .find_map(|text| place(&sites(geometry), text, *height_mm, *margin_mm)),
        }
    }

    /// What the report says when some of `quantity` copies carry no label: how many, why, and what
    /// would make room. `None` when every copy is labelled or the part has no label by design.
    pub fn note(&self, quantity: usize) -> Option<String> {
        let Label::OffBonded {
            geometry: g,
            height_mm,
            margin_mm,
            ..
        } = self
        else {
            return None;
        };
        let missing = (0..quantity).filter(|&c| self.strokes(c).is_none()).count();
        (missing > 0).then(|| {
            format!(
                "{missing} of {quantity} passive parts carry no engraved label: labels stay off the bonded PZT zone \
                 (the first {:.3} mm from the root), and neither the base tab ({:.3} x {:.3} mm) nor the extension \
                 ({:.3} x {:.3} mm) holds a {height_mm} mm label {margin_mm} mm from every edge; a base tab of at \
                 least {:.3} mm would hold the number",
                g.piezo_length_mm,
                g.base_tab_mm,
                g.base_width_mm,
                g.extension_length_mm,
                g.tip_width_mm,
                height_mm + 2.0 * margin_mm
            )
        })
    }
}

/// Where nothing is bonded, in order of preference: the base tab (clamped, it does not bend), then
/// the extension.
fn sites(g: &PartGeometry) -> Vec<Site> {
    let (b, t, l) = (
        g.base_width_mm / 2.0,
        g.tip_width_mm / 2.0,
        g.piezo_length_mm,
    );
    let mut out = Vec::new();
    if g.base_tab_mm > 0.0 {
        out.push([-b, -g.base_tab_mm, b, 0.0]);
    }
    if g.extension_length_mm > 0.0 {
        out.push([-t, l, t, l + g.extension_length_mm]);
    }
    out
}

/// `text` `height` mm tall centred in the first site that holds it `margin` mm inside every side,
/// reading along the part's axis or, failing that, across it.
fn place(sites: &[Site], text: &str, height: f64, margin: f64) -> Option<Vec<Vec<Point>>> {
    if height <= 0.0 {
        return None;
    }
    let width = label_width(text, height);
    sites.iter().find_map(|&[x0, y0, x1, y1]| {
        let (room_x, room_y) = (x1 - x0 - 2.0 * margin, y1 - y0 - 2.0 * margin);
        let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let strokes = label_strokes(text, [0.0, 0.0], height);
        if room_y >= width && room_x >= height {
            // Turned 90°: the text runs along +y, its glyphs' height across the axis.
            Some(
                strokes
                    .iter()
                    .map(|s| place_ring(s, 90.0, [cx + height / 2.0, cy - width / 2.0]))
                    .collect(),
            )
        } else if room_x >= width && room_y >= height {
            Some(
                strokes
                    .iter()
                    .map(|s| place_ring(s, 0.0, [cx - width / 2.0, cy - height / 2.0]))
                    .collect(),
            )
        } else {
            None
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use cam_geometry::Bounds;

    fn part(tab: f64, ext: f64, tip: f64) -> PartGeometry {
        PartGeometry {
            piezo_length_mm: 23.0,
            extension_length_mm: ext,
            base_width_mm: 5.0,
            tip_width_mm: tip,
            base_tab_mm: tab,
            pzt_margin_mm: 0.0,
        }
    }

    fn label(g: PartGeometry) -> Label {
        Label::OffBonded {
            geometry: g,
            name: "C".into(),
            height_mm: 1.0,
            margin_mm: 0.2,
        }
    }

    fn bounds(strokes: &[Vec<Point>]) -> Bounds {
        Bounds::of(&strokes.iter().flatten().copied().collect::<Vec<_>>())
    }

    #[test]
    fn labels_go_on_the_tab_or_the_extension_never_on_the_pzt_zone() {
        // A 2 mm tab holds "C 1" (1 x 2.33 mm) across the 5 mm base, 0.2 mm inside every side.
        let b = bounds(&label(part(2.0, 19.0, 1.0)).strokes(0).unwrap());
        assert!(
            b.max[1] <= -0.2 + 1e-12 && b.min[1] >= -2.0 + 0.2 - 1e-12,
            "{b:?}"
        );
        assert!(b.min[0] >= -2.5 + 0.2 - 1e-12 && b.max[0] <= 2.5 - 0.2 + 1e-12);
        // No tab, a 2 mm wide extension: along the axis, beyond the PZT zone.
        let b = bounds(&label(part(0.0, 19.0, 2.0)).strokes(0).unwrap());
        assert!(
            b.min[1] >= 23.0 + 0.2 - 1e-12 && b.max[1] <= 42.0 - 0.2 + 1e-12,
            "{b:?}"
        );
        assert!(b.min[0] >= -1.0 + 0.2 - 1e-12 && b.max[0] <= 1.0 - 0.2 + 1e-12);
    }

    #[test]
    fn no_room_means_no_label_and_the_report_says_so() {
        // Design C: no tab, a 1 mm extension (needs 1 + 2 x 0.2 = 1.4 mm): nothing fits.
        let c = label(part(0.0, 19.178, 0.999));
        assert!(c.strokes(0).is_none());
        let note = c.note(6).unwrap();
        assert!(
            note.starts_with("6 of 6 passive parts carry no engraved label"),
            "{note}"
        );
        assert!(note.contains("a base tab of at least 1.400 mm"), "{note}");
        // A 1.5 mm tab is 1.1 mm tall and 4.6 mm wide inside: "C 10" (3.67 mm) fits across it.
        let tab = label(part(1.5, 0.0, 5.0));
        assert!(tab.strokes(9).is_some());
        assert!(tab.note(12).is_none());
        assert!(Label::None.note(3).is_none());
    }
}
