//! Offsetting a closed ring with sharp (mitre) corners: how kerf compensation grows a part's
//! outer contour by half the kerf and shrinks a hole's (docs/cam.md §4). The caller chooses the
//! sign; this module knows nothing of lasers or materials.
//!
//! Offsets use geo 0.33's `Buffer` (i_overlay underneath) with `LineJoin::Miter(a)`, where `a`
//! is the sharpest interior corner angle (radians) that is still mitred; sharper spikes get a
//! bevel. A mitred convex corner with interior angle θ ends up `d / sin(θ/2)` from the
//! original vertex, so every offset edge stays parallel to its source edge at distance `d`.

use geo::algorithm::buffer::{Buffer, BufferStyle, LineJoin};
use geo::{Coord, LineString, Polygon};
use thiserror::Error;

use crate::{signed_area, Point};

/// Interior corners sharper than this (radians, about 5.7°) get a bevel instead of a mitre
/// whose tip would run out 20 times the offset distance.
pub const MITER_MIN_ANGLE_RAD: f64 = 0.1;

/// Why a ring could not be offset. Every variant names the offset distance so the message
/// tells the user which kerf setting to look at.
#[derive(Debug, Error, PartialEq)]
pub enum OffsetError {
    #[error("ring is not a polygon: {0}")]
    InvalidRing(&'static str),
    #[error(
        "offset of {delta_mm} mm makes the feature vanish: it is narrower than {width_mm} mm \
         (twice the offset); enlarge the feature or reduce the kerf"
    )]
    Vanished { delta_mm: f64, width_mm: f64 },
    #[error(
        "offset of {delta_mm} mm splits the feature into {pieces} pieces at a neck narrower \
         than {width_mm} mm"
    )]
    Split {
        delta_mm: f64,
        pieces: usize,
        width_mm: f64,
    },
    #[error(
        "offset of {delta_mm} mm closes a slot or notch narrower than {width_mm} mm into a \
         pocket or fills it; widen the slot or reduce the kerf"
    )]
    ClosedUp { delta_mm: f64, width_mm: f64 },
    #[error(
        "offset of {delta_mm} mm loses a detail (notch, slot, tab or short edge) smaller than \
         {width_mm} mm: the offset contour is {deviation_mm} mm from where it should be"
    )]
    FeatureLost {
        delta_mm: f64,
        width_mm: f64,
        deviation_mm: f64,
    },
}

/// How far a round trip (offset by `d`, then by `-d`) may stray from the original before we
/// call a detail lost: the larger of 1 µm (the offset engine works on an integer grid) and
/// 10 % of the offset.
fn round_trip_tolerance(delta_mm: f64) -> f64 {
    (0.1 * delta_mm.abs()).max(1e-3)
}

fn validate(ring: &[Point], delta_mm: f64) -> Result<(), OffsetError> {
    if ring.len() < 3 {
        return Err(OffsetError::InvalidRing("fewer than 3 vertices"));
    }
    if !ring.iter().flatten().all(|v| v.is_finite()) || !delta_mm.is_finite() {
        return Err(OffsetError::InvalidRing("non-finite coordinate or offset"));
    }
    if signed_area(ring) == 0.0 {
        return Err(OffsetError::InvalidRing("zero area"));
    }
    Ok(())
}

/// Raw offset through geo: the outer rings of the pieces, each without its closing point.
/// A piece with holes means a growth closed a slot or notch into a pocket.
fn buffer_pieces(ring: &[Point], delta_mm: f64) -> Vec<(Vec<Point>, usize)> {
    let exterior: LineString<f64> = ring.iter().map(|&[x, y]| Coord { x, y }).collect();
    let style = BufferStyle::new(delta_mm).line_join(LineJoin::Miter(MITER_MIN_ANGLE_RAD));
    let grown = Polygon::new(exterior, vec![]).buffer_with_style(style);
    grown
        .0
        .iter()
        .map(|piece| {
            let mut pts: Vec<Point> = piece.exterior().coords().map(|c| [c.x, c.y]).collect();
            pts.dedup();
            if pts.len() > 1 && pts.first() == pts.last() {
                pts.pop();
            }
            (drop_collinear(pts), piece.interiors().len())
        })
        .filter(|(pts, _)| signed_area(pts) != 0.0)
        .collect()
}

/// Vertices closer than this to the line through their neighbours are dropped (mm). The
/// offset engine snaps to a grid of about 1e-9 mm here and leaves the start of each mitre as
/// an extra vertex on a straight edge; 1 nm is far below any laser's resolution.
const COLLINEAR_TOLERANCE_MM: f64 = 1e-6;

/// Removes vertices that lie on the straight segment between their neighbours.
fn drop_collinear(mut ring: Vec<Point>) -> Vec<Point> {
    let mut i = 0;
    while ring.len() > 3 && i < ring.len() {
        let n = ring.len();
        let (a, b, c) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
        let between = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]) >= 0.0;
        if between && point_segment_distance(b, a, c) < COLLINEAR_TOLERANCE_MM {
            ring.remove(i);
            i = i.saturating_sub(1);
        } else {
            i += 1;
        }
    }
    ring
}

/// Offset of one ring, checked for a single piece without holes.
fn offset_once(ring: &[Point], delta_mm: f64) -> Result<Vec<Point>, OffsetError> {
    let width_mm = 2.0 * delta_mm.abs();
    let mut pieces = buffer_pieces(ring, delta_mm);
    match pieces.len() {
        0 => Err(OffsetError::Vanished { delta_mm, width_mm }),
        1 => {
            let (piece, holes) = pieces.pop().expect("one piece");
            if holes > 0 {
                // A notch or slot narrower than the offset closed up and left a pocket.
                return Err(OffsetError::ClosedUp { delta_mm, width_mm });
            }
            Ok(piece)
        }
        n => Err(OffsetError::Split {
            delta_mm,
            pieces: n,
            width_mm,
        }),
    }
}

/// Distance from `p` to the segment `a`-`b`.
fn point_segment_distance(p: Point, a: Point, b: Point) -> f64 {
    let (abx, aby) = (b[0] - a[0], b[1] - a[1]);
    let len2 = abx * abx + aby * aby;
    let t = if len2 == 0.0 {
        0.0
    } else {
        (((p[0] - a[0]) * abx + (p[1] - a[1]) * aby) / len2).clamp(0.0, 1.0)
    };
    (p[0] - a[0] - t * abx).hypot(p[1] - a[1] - t * aby)
}

/// Largest distance from a vertex of `from` to the boundary of ring `to`.
fn max_vertex_distance(from: &[Point], to: &[Point]) -> f64 {
    from.iter()
        .map(|&p| {
            (0..to.len())
                .map(|i| point_segment_distance(p, to[i], to[(i + 1) % to.len()]))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// Offsets a closed ring by `delta_mm` with mitre joins: `delta_mm > 0` grows the region
/// (outer contour of a part), `delta_mm < 0` shrinks it (a hole's contour shrinks the hole:
/// pass the negative sign). The result keeps the input's orientation; its first vertex may
/// differ from the input's. A zero offset returns the ring unchanged.
///
/// Errors: [`OffsetError::Vanished`] when an inset leaves nothing, [`OffsetError::Split`] when it
/// cuts the region at a narrow neck, [`OffsetError::ClosedUp`] when a growth closes a slot into
/// a pocket, [`OffsetError::FeatureLost`] when a notch, slot, tab or
/// edge smaller than the offset disappears (detected by offsetting back by `-delta_mm` and
/// requiring the original contour back within max(1 µm, 10 % of the offset)).
pub fn offset_ring(ring: &[Point], delta_mm: f64) -> Result<Vec<Point>, OffsetError> {
    validate(ring, delta_mm)?;
    if delta_mm == 0.0 {
        return Ok(ring.to_vec());
    }
    let mut offset = offset_once(ring, delta_mm)?;

    // Mitre offsets are invertible while every edge survives: going back must give the
    // original contour. Anything that does not come back was smaller than the kerf.
    let width_mm = 2.0 * delta_mm.abs();
    let back = offset_once(&offset, -delta_mm)
        .map_err(|_| OffsetError::ClosedUp { delta_mm, width_mm })?;
    let deviation_mm = max_vertex_distance(ring, &back).max(max_vertex_distance(&back, ring));
    if deviation_mm > round_trip_tolerance(delta_mm) {
        return Err(OffsetError::FeatureLost {
            delta_mm,
            width_mm,
            deviation_mm,
        });
    }

    if (signed_area(&offset) > 0.0) != (signed_area(ring) > 0.0) {
        offset.reverse();
    }
    Ok(offset)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Area of a convex polygon offset outwards by `k` with mitre joins:
    /// A + P k + k² Σ tan(φᵢ/2), φᵢ the exterior (turning) angle at vertex i
    /// (each mitred corner adds two right triangles with legs k and k tan(φ/2)).
    fn mitre_grown_area(ring: &[Point], k: f64) -> f64 {
        let n = ring.len();
        let mut perimeter = 0.0;
        let mut corner = 0.0;
        for i in 0..n {
            let (a, b, c) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
            let (u, v) = ([b[0] - a[0], b[1] - a[1]], [c[0] - b[0], c[1] - b[1]]);
            perimeter += v[0].hypot(v[1]);
            let turn = (u[0] * v[1] - u[1] * v[0]).atan2(u[0] * v[0] + u[1] * v[1]);
            corner += (turn / 2.0).tan();
        }
        signed_area(ring) + perimeter * k + k * k * corner
    }

    fn inside(p: Point, ring: &[Point]) -> bool {
        let mut crossings = false;
        for i in 0..ring.len() {
            let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
            if (a[1] > p[1]) != (b[1] > p[1])
                && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0])
            {
                crossings = !crossings;
            }
        }
        crossings
    }

    /// Distance from `p` to the infinite line through `a` and `b`.
    fn line_distance(p: Point, a: Point, b: Point) -> f64 {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        ((p[0] - a[0]) * dy - (p[1] - a[1]) * dx).abs() / dx.hypot(dy)
    }

    /// Every edge of `grown` lies on a line parallel to some edge of `ring` at distance `k`.
    fn edges_at_distance(grown: &[Point], ring: &[Point], k: f64, tol: f64) -> bool {
        (0..grown.len()).all(|i| {
            let (p, q) = (grown[i], grown[(i + 1) % grown.len()]);
            (0..ring.len()).any(|j| {
                let (a, b) = (ring[j], ring[(j + 1) % ring.len()]);
                (line_distance(p, a, b) - k).abs() < tol && (line_distance(q, a, b) - k).abs() < tol
            })
        })
    }

    const RECT: [Point; 4] = [[0.0, 0.0], [20.0, 0.0], [20.0, 10.0], [0.0, 10.0]];
    const TRAPEZOID: [Point; 4] = [[0.0, 0.0], [30.0, 7.0], [30.0, 13.0], [0.0, 20.0]];

    #[test]
    fn grown_rectangle_has_mitred_area_and_sharp_corners() {
        let k = 0.015;
        let grown = offset_ring(&RECT, k).unwrap();
        assert_eq!(
            grown.len(),
            4,
            "sharp corners, no bevel vertices: {grown:?}"
        );
        // (20 + 2k)(10 + 2k) = A + P k + 4 k².
        let expected = (20.0 + 2.0 * k) * (10.0 + 2.0 * k);
        assert!((signed_area(&grown) - expected).abs() < 1e-6);
        assert!((mitre_grown_area(&RECT, k) - expected).abs() < 1e-12);
    }

    #[test]
    fn grown_trapezoid_encloses_original_at_offset_distance() {
        let k = 0.03;
        let grown = offset_ring(&TRAPEZOID, k).unwrap();
        assert_eq!(grown.len(), 4, "{grown:?}");
        assert!(signed_area(&grown) > 0.0, "orientation kept");
        assert!((signed_area(&grown) - mitre_grown_area(&TRAPEZOID, k)).abs() < 1e-5);
        assert!(TRAPEZOID.iter().all(|&p| inside(p, &grown)));
        assert!(edges_at_distance(&grown, &TRAPEZOID, k, 1e-6));
        // Each mitred vertex sits k / sin(θ/2) from its source vertex, θ the interior angle.
        for &v in &TRAPEZOID {
            let nearest = grown
                .iter()
                .map(|g| (g[0] - v[0]).hypot(g[1] - v[1]))
                .fold(f64::INFINITY, f64::min);
            let acute = (7.0f64 / 30.0).atan(); // angle of the slanted edge to the x axis
            let theta = if v[0] == 0.0 {
                std::f64::consts::FRAC_PI_2 - acute
            } else {
                std::f64::consts::FRAC_PI_2 + acute
            };
            assert!((nearest - k / (theta / 2.0).sin()).abs() < 1e-6, "{v:?}");
        }
    }

    #[test]
    fn inset_shrinks_and_keeps_clockwise_orientation() {
        let k = 0.015;
        let mut cw = TRAPEZOID.to_vec();
        cw.reverse();
        let inset = offset_ring(&cw, -k).unwrap();
        assert!(signed_area(&inset) < 0.0, "clockwise in, clockwise out");
        assert!(inset.iter().all(|&p| inside(p, &TRAPEZOID)));
        assert!(edges_at_distance(&inset, &TRAPEZOID, k, 1e-6));
        // The same formula holds for an inset with -k: A - P k + k² Σ tan(φ/2).
        let expected = mitre_grown_area(&TRAPEZOID, -k);
        assert!((-signed_area(&inset) - expected).abs() < 1e-5);
    }

    #[test]
    fn concave_part_with_tab_grows_without_loss() {
        // Trapezoid plus a tab: two reflex corners.
        let part = [
            [10.0, 5.0],
            [40.0, 12.0],
            [48.0, 12.0],
            [48.0, 18.0],
            [40.0, 18.0],
            [10.0, 25.0],
        ];
        let grown = offset_ring(&part, 0.02).unwrap();
        assert_eq!(grown.len(), part.len(), "{grown:?}");
        assert!(edges_at_distance(&grown, &part, 0.02, 1e-6));
    }

    #[test]
    fn inset_of_sliver_narrower_than_kerf_vanishes() {
        let sliver = [[0.0, 0.0], [5.0, 0.0], [5.0, 0.02], [0.0, 0.02]];
        let err = offset_ring(&sliver, -0.03).unwrap_err();
        assert!(matches!(err, OffsetError::Vanished { .. }), "{err:?}");
        assert!(err.to_string().contains("vanish"));
    }

    #[test]
    fn inset_through_a_narrow_neck_splits() {
        // Two 2 mm squares joined by a 0.02 mm neck.
        let dumbbell = [
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 0.99],
            [3.0, 0.99],
            [3.0, 0.0],
            [5.0, 0.0],
            [5.0, 2.0],
            [3.0, 2.0],
            [3.0, 1.01],
            [2.0, 1.01],
            [2.0, 2.0],
            [0.0, 2.0],
        ];
        let err = offset_ring(&dumbbell, -0.03).unwrap_err();
        assert!(
            matches!(err, OffsetError::Split { pieces: 2, .. }),
            "{err:?}"
        );
    }

    #[test]
    fn growth_that_fills_a_narrow_notch_is_reported() {
        // Keyhole: a 0.02 mm slit from the top edge into a 4 x 4 mm cavity. Growing by
        // 0.03 mm closes the slit and would leave the cavity as an enclosed pocket.
        let keyhole = [
            [0.0, 0.0],
            [10.0, 0.0],
            [10.0, 10.0],
            [5.01, 10.0],
            [5.01, 6.0],
            [7.0, 6.0],
            [7.0, 2.0],
            [3.0, 2.0],
            [3.0, 6.0],
            [4.99, 6.0],
            [4.99, 10.0],
            [0.0, 10.0],
        ];
        let err = offset_ring(&keyhole, 0.03).unwrap_err();
        assert!(matches!(err, OffsetError::ClosedUp { .. }), "{err:?}");
        // The same slit survives a kerf offset that fits inside it.
        assert!(offset_ring(&keyhole, 0.005).is_ok());
        // A notch 0.02 mm wide and 1 mm deep filled by the growth.
        let shallow = [
            [0.0, 0.0],
            [10.0, 0.0],
            [10.0, 5.0],
            [5.01, 5.0],
            [5.01, 4.0],
            [4.99, 4.0],
            [4.99, 5.0],
            [0.0, 5.0],
        ];
        let err = offset_ring(&shallow, 0.03).unwrap_err();
        assert!(matches!(err, OffsetError::FeatureLost { .. }), "{err:?}");
    }

    #[test]
    fn invalid_input_is_rejected() {
        assert_eq!(
            offset_ring(&[[0.0, 0.0], [1.0, 0.0]], 0.1),
            Err(OffsetError::InvalidRing("fewer than 3 vertices"))
        );
        assert!(offset_ring(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]], 0.1).is_err());
        assert!(offset_ring(&RECT, f64::NAN).is_err());
        assert_eq!(offset_ring(&RECT, 0.0).unwrap(), RECT.to_vec());
    }
}
