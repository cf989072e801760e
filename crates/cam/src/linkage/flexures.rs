//! The flexures checked against the film and the links, and re-sized where that is all it takes
//! (docs/physics.md §16.2, docs/cam.md §7):
//!
//! | bound | rule | when broken |
//! |---|---|---|
//! | fatigue | `ε = t β / (2 L)` at the film's largest bend `β` over the stroke ≤ the film's fatigue strain | lengthened to `L = t β / (2 ε)` |
//! | bending | `L ≥ n t` (the template's `min_length_thicknesses`): a shorter gap shears more than it bends | lengthened to `n t` |
//! | pivot | `L ≤ f ×` the shorter link beside it (`max_length_fraction`): a longer gap is no pivot | refused |
//! | cutting | `L`, `w` at least two kerfs | refused |
//!
//! A lengthened flexure is rounded up to 0.1 µm, so the strain it reports is within the bound.
//!
//! The film's bend is measured from the flat laminate. O and A are flat at rest (their tabs are fixed at the
//! links' rest angles), so their bend is the turn over the stroke; B is folded about 90° at assembly and
//! turns on top of that fold, so its bend is the fold and the turn together (docs/physics.md §16.7).
//!
//! The film bends wherever it is unbonded: over the carbon gap `L` and the adhesive's cut-back `c` either
//! side of it, where the film lies loose under the carbon at the strip's width `W`. The model's flexure is
//! that drawn unbonded length, `L + 2 c`, its two widths in series (docs/physics.md §16.6): the strain and
//! fatigue bounds hold on it, the bending and pivot bounds on the gap.

use super::pattern::{FlexureSize, JOINTS};
use crate::process::linkage::LinkageProcess;
use actuator_model::flexure::Flexure;
use actuator_model::fourbar::{TwoStage, TWO_STAGE_JOINTS};
use actuator_model::transmission::Linkage;
use serde::Serialize;

/// Samples of the stroke for each joint's largest turn.
const STROKE_SAMPLES: usize = 64;

/// One flexure as checked (JSON `linkage.flexures[]`).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct FlexureRow {
    /// Which joint.
    pub joint: String,
    /// Gap length as drawn, µm.
    pub length_um: f64,
    /// Film left unbonded, the gap and the adhesive's cut-back either side, as drawn: the length the
    /// stiffness and strain are of, µm.
    pub unbonded_um: f64,
    /// Width, mm.
    pub width_mm: f64,
    /// Film thickness, µm.
    pub film_um: f64,
    /// `k = E w t³ / (12 L)`, µN·m/rad.
    pub stiffness_uNm_per_rad: f64,
    /// Largest turn over the stroke from rest, deg.
    pub peak_rotation_deg: f64,
    /// Bend of the film at rest from the flat laminate, set at assembly (joint B's fold), deg.
    pub assembly_fold_deg: f64,
    /// Largest bend of the film from the flat laminate over the stroke, the fold and the turn together, deg.
    pub peak_bend_deg: f64,
    /// `ε = t β / (2 L)` at that bend.
    pub peak_strain: f64,
    /// The film's fatigue strain.
    pub strain_limit: f64,
    /// Why the length differs from the one asked for, if it does.
    pub resized: Option<String>,
}

/// A flexure that cannot be made: the joint, the value and what is allowed, for the caller to name
/// the field it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Refusal {
    /// Joint index (O, B, A).
    pub joint: usize,
    /// `length` or `width`.
    pub what: &'static str,
    /// The value asked for, in the file's unit (µm for lengths, mm for widths).
    pub value: f64,
    /// What is allowed, and why.
    pub allowed: String,
}

/// The unbonded film of one joint as a flexure of the gap's width `w` (mm): the gap `gap` and the
/// cut-backs' `loose` length (mm, at the gap's width) in series, `1/k = 12 (L/w + 2c/W) / (E t³)`, so
/// `k = E w t³ / (12 (L + 2c w/W))`; the strain `t φ / (2 (L + 2c w/W))` is the narrower gap's, which carries
/// the larger curvature (docs/physics.md §16.6).
fn unbonded(gap: f64, loose: f64, w: f64, t: f64, modulus: f64) -> Flexure {
    Flexure {
        length: (gap + loose) * 1e-3,
        width: w * 1e-3,
        thickness: t * 1e-3,
        modulus,
    }
}

/// One joint's film over the stroke, rad: its largest turn from rest, the fold set at assembly (its bend at
/// rest) and its largest bend from the flat laminate, the fold and the turn together.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointBend {
    /// Largest `|turn|` from rest.
    pub turn: f64,
    /// `|bend|` at rest.
    pub fold: f64,
    /// Largest `|bend|`, at least the fold.
    pub bend: f64,
}

/// Each joint's [`JointBend`] over the stroke between the end angles, from `at(θ)`: the joints' turns
/// from rest and their bends from the flat laminate with the wing at `θ` (`None` past the linkage's
/// reach, skipped), sampled at [`STROKE_SAMPLES`] + 1 angles; `fold` is the bend at the `rest` angle.
pub fn joint_bends<const N: usize>(
    at: impl Fn(f64) -> Option<([f64; N], [f64; N])>,
    rest: f64,
    end_angles: (f64, f64),
) -> [JointBend; N] {
    // A film laid flat at rest reads a bend of rounding there (the two-stage's rest is found through the
    // four-bar and back): under a nanoradian it is no fold.
    let folds = at(rest).map_or([0.0; N], |(_, bends)| {
        bends.map(|b| if b.abs() < 1e-9 { 0.0 } else { b.abs() })
    });
    let mut out = folds.map(|fold| JointBend {
        turn: 0.0,
        fold,
        bend: fold,
    });
    for i in 0..=STROKE_SAMPLES {
        let angle = end_angles.0 + (end_angles.1 - end_angles.0) * i as f64 / STROKE_SAMPLES as f64;
        if let Some((turns, bends)) = at(angle) {
            for (j, o) in out.iter_mut().enumerate() {
                o.turn = o.turn.max(turns[j].abs());
                o.bend = o.bend.max(bends[j].abs());
            }
        }
    }
    out
}

/// The slider-crank's joints over the stroke: O and A are laid flat at rest, so their bend is their
/// turn; B's is `β(θ) = π/2 + θ - ψ(θ)` (docs/physics.md §16.7).
pub fn film_bends(linkage: &Linkage, end_angles: (f64, f64)) -> [JointBend; 3] {
    let rest = linkage.stroke_angle(0.0).unwrap_or(0.0);
    let at = |angle: f64| {
        let turns = linkage.joint_rotations(angle)?;
        Some((turns, [turns[0], linkage.bend_at_b(angle)?, turns[2]]))
    };
    joint_bends(at, rest, end_angles)
}

/// The two-stage linkage's six joints over the stroke (docs/physics.md §16.8): each turn is the bend less
/// its bend at rest.
pub fn two_stage_bends(stage: &TwoStage, end_angles: (f64, f64)) -> [JointBend; 6] {
    let rest = stage
        .first
        .stroke_angle(0.0)
        .and_then(|t| stage.second.output_angle(t))
        .unwrap_or(0.0);
    let folds = stage.bends(rest);
    let at = |angle: f64| {
        let (bends, folds) = (stage.bends(angle)?, folds?);
        Some((std::array::from_fn(|i| bends[i] - folds[i]), bends))
    };
    joint_bends(at, rest, end_angles)
}

/// Why a flexure was lengthened from `asked` (mm) to the shortest allowed: the bound that set it.
fn resize_reason(
    asked: f64,
    bound: (f64, f64, f64),
    bend: (f64, f64),
    strain: f64,
    process: &LinkageProcess,
) -> String {
    let (by_strain, by_bending, kerfs) = bound;
    let (fold, bend) = bend;
    let folded = if fold != 0.0 {
        format!("{:.1}° of it folded at assembly", fold.to_degrees())
    } else {
        String::new()
    };
    let at = match folded.is_empty() {
        true => format!("{:.1}°", bend.to_degrees()),
        false => format!("{:.1}° ({folded})", bend.to_degrees()),
    };
    if asked == 0.0 {
        let folded = match folded.is_empty() {
            true => folded,
            false => format!("{folded}; "),
        };
        format!(
            "none given, the shortest the film allows bent {:.1}° ({folded}{:.2} % fatigue strain, {} film thicknesses)",
            bend.to_degrees(),
            process.film_fatigue_strain * 100.0,
            process.min_length_thicknesses
        )
    } else if by_strain >= by_bending && by_strain >= kerfs {
        format!(
            "{:.1} µm strains the film {:.2} % bent {at}, over its fatigue strain {:.2} %",
            asked * 1e3,
            strain * 100.0,
            process.film_fatigue_strain * 100.0
        )
    } else if by_bending >= kerfs {
        format!(
            "{:.1} µm is under {} film thicknesses (a shorter gap shears more than it bends)",
            asked * 1e3,
            process.min_length_thicknesses
        )
    } else {
        format!("{:.1} µm is under two kerfs ({kerfs} mm)", asked * 1e3)
    }
}

/// Check each flexure asked for (lengths 0 mean "the shortest allowed") against the film and the
/// links; lengthen those the film strains too much or that are too short to bend.
pub fn check_flexures(
    linkage: &Linkage,
    end_angles: (f64, f64),
    asked: [FlexureSize; 3],
    film_thickness_mm: f64,
    process: &LinkageProcess,
) -> Result<([FlexureSize; 3], [FlexureRow; 3]), Refusal> {
    let bends = film_bends(linkage, end_angles);
    let (crank, coupler) = (linkage.crank * 1e3, linkage.coupler * 1e3);
    let neighbour = [crank, crank.min(coupler), coupler];
    let strip = asked.iter().map(|f| f.width_mm).fold(0.0, f64::max);
    let mut sizes = asked;
    let mut rows = Vec::with_capacity(3);
    for i in 0..3 {
        let film = Film {
            thickness_mm: film_thickness_mm,
            strip_mm: strip,
            process,
        };
        let (size, row) = check_joint(i, JOINTS[i], asked[i], &bends[i], neighbour[i], &film)?;
        sizes[i] = size;
        rows.push(row);
    }
    let rows: [FlexureRow; 3] = rows.try_into().expect("three joints");
    Ok((sizes, rows))
}

/// The two-stage linkage's six flexures, each the shortest the film allows at `width_mm`, checked as the
/// slider-crank's are ([`check_joint`]); the link beside each is the shorter of the two it joins, the
/// crank and the four-bar's input for O (one link).
pub fn check_two_stage(
    stage: &TwoStage,
    end_angles: (f64, f64),
    width_mm: f64,
    film_thickness_mm: f64,
    process: &LinkageProcess,
) -> Result<Vec<FlexureRow>, Refusal> {
    let bends = two_stage_bends(stage, end_angles);
    let (l3, l1) = (stage.first.crank * 1e3, stage.first.coupler * 1e3);
    let f = stage.second;
    let (a, b, c) = (f.input * 1e3, f.coupler * 1e3, f.output * 1e3);
    let neighbour = [l3.min(a), l3.min(l1), l1, a.min(b), b.min(c), c];
    let film = Film {
        thickness_mm: film_thickness_mm,
        strip_mm: width_mm,
        process,
    };
    let asked = FlexureSize {
        length_mm: 0.0,
        width_mm,
    };
    (0..6)
        .map(|i| {
            check_joint(
                i,
                TWO_STAGE_JOINTS[i],
                asked,
                &bends[i],
                neighbour[i],
                &film,
            )
            .map(|r| r.1)
        })
        .collect()
}

/// The film the flexures are of: its thickness and the strip's width (mm), and the process's rules.
struct Film<'a> {
    thickness_mm: f64,
    strip_mm: f64,
    process: &'a LinkageProcess,
}

/// One flexure: joint `i`, named `name`, asked at `f`, bent as `bend` beside a link of `neighbour` mm;
/// lengthened to the shortest the film's fatigue strain, its bending and the kerf allow, or refused
/// past the pivot bound.
fn check_joint(
    i: usize,
    name: &str,
    f: FlexureSize,
    bend: &JointBend,
    neighbour: f64,
    film_of: &Film<'_>,
) -> Result<(FlexureSize, FlexureRow), Refusal> {
    let process = film_of.process;
    let kerf = process.kerf_mm;
    let t = film_of.thickness_mm;
    let cutback = process.adhesive_cutback_mm;
    let strip = film_of.strip_mm;
    if f.width_mm < 2.0 * kerf {
        return Err(Refusal {
            joint: i,
            what: "width",
            value: f.width_mm,
            allowed: format!("at least two kerfs, {} mm", 2.0 * kerf),
        });
    }
    // The cut-backs' film at the strip's width, as gap length of the flexure's width.
    let loose = 2.0 * cutback * f.width_mm / strip;
    let film = unbonded(f.length_mm, loose, f.width_mm, t, process.film_modulus);
    // A small bend is taken by the cut-backs' loose film alone: the strain then asks for no gap, not
    // for a negative one.
    let by_strain =
        (film.shortest_length_for(bend.bend, process.film_fatigue_strain) * 1e3 - loose).max(0.0);
    let by_bending = process.min_length_thicknesses * t;
    let shortest = by_strain.max(by_bending).max(2.0 * kerf);
    let longest = process.max_length_fraction * neighbour;
    let mut length = f.length_mm;
    let mut resized = None;
    if length < shortest {
        // Up to the next 0.1 µm, so the drawn length keeps the strain within the bound.
        let up = (shortest * 1e4).ceil() / 1e4;
        let reason = resize_reason(
            f.length_mm,
            (by_strain, by_bending, 2.0 * kerf),
            (bend.fold, bend.bend),
            film.strain(bend.bend),
            process,
        );
        resized = Some(format!("{:.1} µm: {reason}", up * 1e3));
        length = up;
    }
    if length > longest {
        let fold = if bend.fold != 0.0 {
            format!(", folded {:.1}° at assembly", bend.fold.to_degrees())
        } else {
            String::new()
        };
        return Err(Refusal {
            joint: i,
            what: "length",
            value: f.length_mm * 1e3,
            allowed: format!(
                "{:.1} to {:.1} µm: at least {:.1} µm for the strain bent {:.1}°{fold} (the film unbonded over the gap and {} mm of adhesive cut-back either side; {:.2} % fatigue strain of {} µm film), {} film thicknesses and two kerfs, at most {} of the {:.3} mm link beside it (a longer gap is no pivot)",
                shortest * 1e3,
                longest * 1e3,
                by_strain * 1e3,
                bend.bend.to_degrees(),
                cutback,
                process.film_fatigue_strain * 100.0,
                t * 1e3,
                process.min_length_thicknesses,
                process.max_length_fraction,
                neighbour
            ),
        });
    }
    let drawn = unbonded(length, loose, f.width_mm, t, process.film_modulus);
    let row = FlexureRow {
        joint: name.to_string(),
        // To a nanometre, as the drawing's decimals go: a length given as 50 µm is not reported
        // as 49.99999999999999 after its trip through metres.
        length_um: (length * 1e6).round() / 1e3,
        unbonded_um: ((length + 2.0 * cutback) * 1e6).round() / 1e3,
        width_mm: f.width_mm,
        film_um: t * 1e3,
        stiffness_uNm_per_rad: drawn.stiffness() * 1e6,
        peak_rotation_deg: bend.turn.to_degrees(),
        assembly_fold_deg: bend.fold.to_degrees(),
        peak_bend_deg: bend.bend.to_degrees(),
        peak_strain: drawn.strain(bend.bend),
        strain_limit: process.film_fatigue_strain,
        resized,
    };
    Ok((
        FlexureSize {
            length_mm: length,
            width_mm: f.width_mm,
        },
        row,
    ))
}
