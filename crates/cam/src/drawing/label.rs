//! A tiny single-stroke font for part labels (design name, index) engraved or scored on
//! laser-cut pieces. Single strokes because a laser follows a path: an outline font would be
//! engraved twice around every letter.
//!
//! Glyphs are drawn on a grid 4 units wide and 6 units tall (the cap height), with the origin
//! at the lower left of the baseline and the y axis up, like the drawing model. Characters
//! advance by 6 units (4 of glyph, 2 of gap). Supported: `0-9`, `A-Z` (lower case is drawn as
//! upper case), `-`, `.`, `#` and space. Any other character is drawn as a box outline of the
//! glyph cell, so a missing glyph is visible on the part rather than silently dropped.

use cam_geometry::Point;

/// Glyph cell width in grid units.
const GLYPH_WIDTH: f64 = 4.0;
/// Cap height in grid units.
const GLYPH_HEIGHT: f64 = 6.0;
/// Advance from one character to the next in grid units.
const ADVANCE: f64 = 6.0;

type Glyph = &'static [&'static [Point]];

const OCTAGON: &[Point] = &[
    [1.0, 0.0],
    [3.0, 0.0],
    [4.0, 1.0],
    [4.0, 5.0],
    [3.0, 6.0],
    [1.0, 6.0],
    [0.0, 5.0],
    [0.0, 1.0],
    [1.0, 0.0],
];
const P_BOWL: &[Point] = &[
    [0.0, 0.0],
    [0.0, 6.0],
    [3.0, 6.0],
    [4.0, 5.0],
    [4.0, 4.0],
    [3.0, 3.0],
    [0.0, 3.0],
];
const BOX: &[Point] = &[[0.0, 0.0], [4.0, 0.0], [4.0, 6.0], [0.0, 6.0], [0.0, 0.0]];

/// Strokes of each character the font has, in grid units: upper case, digits and marks.
const GLYPHS: &[(char, Glyph)] = &[
    (' ', &[]),
    ('0', &[OCTAGON, &[[0.5, 1.5], [3.5, 4.5]]]),
    (
        '1',
        &[
            &[[1.0, 5.0], [2.0, 6.0], [2.0, 0.0]],
            &[[1.0, 0.0], [3.0, 0.0]],
        ],
    ),
    (
        '2',
        &[&[
            [0.0, 5.0],
            [1.0, 6.0],
            [3.0, 6.0],
            [4.0, 5.0],
            [4.0, 4.0],
            [0.0, 0.0],
            [4.0, 0.0],
        ]],
    ),
    (
        '3',
        &[&[
            [0.0, 6.0],
            [4.0, 6.0],
            [2.0, 4.0],
            [3.0, 4.0],
            [4.0, 3.0],
            [4.0, 1.0],
            [3.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
        ]],
    ),
    ('4', &[&[[3.0, 0.0], [3.0, 6.0], [0.0, 2.0], [4.0, 2.0]]]),
    (
        '5',
        &[&[
            [4.0, 6.0],
            [0.0, 6.0],
            [0.0, 3.0],
            [3.0, 3.0],
            [4.0, 2.0],
            [4.0, 1.0],
            [3.0, 0.0],
            [0.0, 0.0],
        ]],
    ),
    (
        '6',
        &[&[
            [3.0, 6.0],
            [1.0, 6.0],
            [0.0, 5.0],
            [0.0, 1.0],
            [1.0, 0.0],
            [3.0, 0.0],
            [4.0, 1.0],
            [4.0, 2.0],
            [3.0, 3.0],
            [0.0, 3.0],
        ]],
    ),
    ('7', &[&[[0.0, 6.0], [4.0, 6.0], [1.0, 0.0]]]),
    (
        '8',
        &[&[
            [1.0, 3.0],
            [0.0, 4.0],
            [0.0, 5.0],
            [1.0, 6.0],
            [3.0, 6.0],
            [4.0, 5.0],
            [4.0, 4.0],
            [3.0, 3.0],
            [1.0, 3.0],
            [0.0, 2.0],
            [0.0, 1.0],
            [1.0, 0.0],
            [3.0, 0.0],
            [4.0, 1.0],
            [4.0, 2.0],
            [3.0, 3.0],
        ]],
    ),
    (
        '9',
        &[&[
            [4.0, 3.0],
            [1.0, 3.0],
            [0.0, 4.0],
            [0.0, 5.0],
            [1.0, 6.0],
            [3.0, 6.0],
            [4.0, 5.0],
            [4.0, 1.0],
            [3.0, 0.0],
            [1.0, 0.0],
        ]],
    ),
    (
        'A',
        &[
            &[[0.0, 0.0], [0.0, 4.0], [2.0, 6.0], [4.0, 4.0], [4.0, 0.0]],
            &[[0.0, 3.0], [4.0, 3.0]],
        ],
    ),
    (
        'B',
        &[
            P_BOWL,
            &[[3.0, 3.0], [4.0, 2.0], [4.0, 1.0], [3.0, 0.0], [0.0, 0.0]],
        ],
    ),
    (
        'C',
        &[&[
            [4.0, 5.0],
            [3.0, 6.0],
            [1.0, 6.0],
            [0.0, 5.0],
            [0.0, 1.0],
            [1.0, 0.0],
            [3.0, 0.0],
            [4.0, 1.0],
        ]],
    ),
    (
        'D',
        &[&[
            [0.0, 0.0],
            [0.0, 6.0],
            [2.0, 6.0],
            [4.0, 4.0],
            [4.0, 2.0],
            [2.0, 0.0],
            [0.0, 0.0],
        ]],
    ),
    (
        'E',
        &[
            &[[4.0, 6.0], [0.0, 6.0], [0.0, 0.0], [4.0, 0.0]],
            &[[0.0, 3.0], [3.0, 3.0]],
        ],
    ),
    (
        'F',
        &[
            &[[4.0, 6.0], [0.0, 6.0], [0.0, 0.0]],
            &[[0.0, 3.0], [3.0, 3.0]],
        ],
    ),
    (
        'G',
        &[&[
            [4.0, 5.0],
            [3.0, 6.0],
            [1.0, 6.0],
            [0.0, 5.0],
            [0.0, 1.0],
            [1.0, 0.0],
            [3.0, 0.0],
            [4.0, 1.0],
            [4.0, 3.0],
            [2.0, 3.0],
        ]],
    ),
    (
        'H',
        &[
            &[[0.0, 0.0], [0.0, 6.0]],
            &[[4.0, 0.0], [4.0, 6.0]],
            &[[0.0, 3.0], [4.0, 3.0]],
        ],
    ),
    (
        'I',
        &[
            &[[1.0, 6.0], [3.0, 6.0]],
            &[[2.0, 6.0], [2.0, 0.0]],
            &[[1.0, 0.0], [3.0, 0.0]],
        ],
    ),
    (
        'J',
        &[&[[4.0, 6.0], [4.0, 1.0], [3.0, 0.0], [1.0, 0.0], [0.0, 1.0]]],
    ),
    (
        'K',
        &[
            &[[0.0, 0.0], [0.0, 6.0]],
            &[[4.0, 6.0], [0.0, 2.0]],
            &[[1.0, 3.0], [4.0, 0.0]],
        ],
    ),
    ('L', &[&[[0.0, 6.0], [0.0, 0.0], [4.0, 0.0]]]),
    (
        'M',
        &[&[[0.0, 0.0], [0.0, 6.0], [2.0, 3.0], [4.0, 6.0], [4.0, 0.0]]],
    ),
    ('N', &[&[[0.0, 0.0], [0.0, 6.0], [4.0, 0.0], [4.0, 6.0]]]),
    ('O', &[OCTAGON]),
    ('P', &[P_BOWL]),
    ('Q', &[OCTAGON, &[[2.0, 2.0], [4.0, 0.0]]]),
    ('R', &[P_BOWL, &[[2.0, 3.0], [4.0, 0.0]]]),
    (
        'S',
        &[&[
            [4.0, 5.0],
            [3.0, 6.0],
            [1.0, 6.0],
            [0.0, 5.0],
            [0.0, 4.0],
            [1.0, 3.0],
            [3.0, 3.0],
            [4.0, 2.0],
            [4.0, 1.0],
            [3.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
        ]],
    ),
    ('T', &[&[[0.0, 6.0], [4.0, 6.0]], &[[2.0, 6.0], [2.0, 0.0]]]),
    (
        'U',
        &[&[
            [0.0, 6.0],
            [0.0, 1.0],
            [1.0, 0.0],
            [3.0, 0.0],
            [4.0, 1.0],
            [4.0, 6.0],
        ]],
    ),
    ('V', &[&[[0.0, 6.0], [2.0, 0.0], [4.0, 6.0]]]),
    (
        'W',
        &[&[[0.0, 6.0], [1.0, 0.0], [2.0, 3.0], [3.0, 0.0], [4.0, 6.0]]],
    ),
    ('X', &[&[[0.0, 0.0], [4.0, 6.0]], &[[0.0, 6.0], [4.0, 0.0]]]),
    (
        'Y',
        &[
            &[[0.0, 6.0], [2.0, 3.0], [4.0, 6.0]],
            &[[2.0, 3.0], [2.0, 0.0]],
        ],
    ),
    ('Z', &[&[[0.0, 6.0], [4.0, 6.0], [0.0, 0.0], [4.0, 0.0]]]),
    ('-', &[&[[1.0, 3.0], [3.0, 3.0]]]),
    (
        '.',
        &[&[
            [1.75, 0.0],
            [2.25, 0.0],
            [2.25, 0.5],
            [1.75, 0.5],
            [1.75, 0.0],
        ]],
    ),
    (
        '#',
        &[
            &[[1.0, 0.5], [1.0, 5.5]],
            &[[3.0, 0.5], [3.0, 5.5]],
            &[[0.0, 2.0], [4.0, 2.0]],
            &[[0.0, 4.0], [4.0, 4.0]],
        ],
    ),
];

/// Strokes of one character in grid units; `None` for characters the font lacks.
fn glyph(c: char) -> Option<Glyph> {
    let c = c.to_ascii_uppercase();
    GLYPHS
        .iter()
        .find(|(g, _)| *g == c)
        .map(|(_, strokes)| *strokes)
}

/// Open polylines (mm) drawing `text` with its baseline's left end at `origin` and capitals
/// `height_mm` tall. Unsupported characters come out as a box the size of the glyph cell.
/// Everything lies within `[x0, x0 + label_width] x [y0, y0 + height_mm]`.
pub fn label_strokes(text: &str, origin: Point, height_mm: f64) -> Vec<Vec<Point>> {
    let scale = height_mm / GLYPH_HEIGHT;
    let mut strokes = Vec::new();
    for (i, c) in text.chars().enumerate() {
        let x0 = origin[0] + i as f64 * ADVANCE * scale;
        for stroke in glyph(c).unwrap_or(&[BOX]) {
            strokes.push(
                stroke
                    .iter()
                    .map(|p| [x0 + p[0] * scale, origin[1] + p[1] * scale])
                    .collect(),
            );
        }
    }
    strokes
}

/// Width (mm) of `text` set at cap height `height_mm`: from the left of the first glyph to the
/// right of the last, without trailing gap; 0 for empty text.
pub fn label_width(text: &str, height_mm: f64) -> f64 {
    let n = text.chars().count();
    if n == 0 {
        return 0.0;
    }
    let scale = height_mm / GLYPH_HEIGHT;
    ((n - 1) as f64 * ADVANCE + GLYPH_WIDTH) * scale
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strokes_stay_inside_the_label_box() {
        let text = "A1-07 #3.Z9";
        let (origin, h) = ([12.5, -3.0], 2.5);
        let w = label_width(text, h);
        // 11 characters: 10 advances of 6 units plus one 4-unit glyph, at 2.5/6 mm per unit.
        assert!((w - 64.0 * 2.5 / 6.0).abs() < 1e-12);
        let strokes = label_strokes(text, origin, h);
        assert!(!strokes.is_empty());
        let pts: Vec<Point> = strokes.iter().flatten().copied().collect();
        assert!(pts.iter().all(|p| p[0] >= origin[0] - 1e-12
            && p[0] <= origin[0] + w + 1e-12
            && p[1] >= origin[1] - 1e-12
            && p[1] <= origin[1] + h + 1e-12));
        // The box is tight: something touches each side.
        let b = cam_geometry::Bounds::of(&pts);
        assert!((b.min[0] - origin[0]).abs() < 1e-12);
        assert!((b.max[0] - (origin[0] + w)).abs() < 1e-12);
        assert!((b.max[1] - (origin[1] + h)).abs() < 1e-12);
    }

    #[test]
    fn every_documented_character_has_a_glyph_of_open_paths() {
        let supported = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ-.# ";
        for c in supported.chars() {
            let g = glyph(c).unwrap_or_else(|| panic!("{c:?} missing"));
            assert_eq!(g.is_empty(), c == ' ', "{c:?}");
            for stroke in g {
                assert!(stroke.len() >= 2, "{c:?}");
                assert!(stroke
                    .iter()
                    .all(|p| (0.0..=GLYPH_WIDTH).contains(&p[0])
                        && (0.0..=GLYPH_HEIGHT).contains(&p[1])));
            }
        }
    }

    #[test]
    fn the_glyph_table_holds_each_character_once() {
        // A second row for a character would never be found: the first one wins.
        for (i, (c, _)) in GLYPHS.iter().enumerate() {
            assert!(GLYPHS[i + 1..].iter().all(|(d, _)| d != c), "{c:?} twice");
        }
    }

    #[test]
    fn distinct_characters_look_different() {
        let chars: Vec<char> = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ-.#".chars().collect();
        for (i, a) in chars.iter().enumerate() {
            for b in &chars[i + 1..] {
                assert_ne!(glyph(*a), glyph(*b), "{a:?} and {b:?}");
            }
        }
    }

    #[test]
    fn lower_case_is_upper_and_unknown_is_a_box() {
        assert_eq!(
            label_strokes("abc", [0.0, 0.0], 3.0),
            label_strokes("ABC", [0.0, 0.0], 3.0)
        );
        let unknown = label_strokes("µ", [1.0, 2.0], 6.0);
        assert_eq!(
            unknown,
            vec![vec![
                [1.0, 2.0],
                [5.0, 2.0],
                [5.0, 8.0],
                [1.0, 8.0],
                [1.0, 2.0]
            ]]
        );
        assert!(label_strokes("   ", [0.0, 0.0], 3.0).is_empty());
        assert_eq!(label_width("", 3.0), 0.0);
    }
}
