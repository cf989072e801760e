//! Discovery (issue 17 item 5): on data whose effect is outside the library, the report says which
//! variable the residual follows and which primitive would produce it.
//!
//! Each case hides one effect outside the library in random designs (30 actuators x 4 voltages, 5 %
//! noise on deflection and force, 1 % on mass). Two kinds:
//! - primitives of the model crate outside the library (the passive plies' E1 off its datasheet value,
//!   a clamp compliance per unit clamped width): discovery must point at the right variable and rank the
//!   true primitive first or second;
//! - effects no primitive expresses yet (a rigid root length held in the clamp, an inactive surface layer
//!   of the PZT, unelectroded edge margins; their physics in `tests/synthetic`): discovery must point at
//!   the variable they act through.
//!
//! The right variables come from the physics of each effect, not from the runs: a softer passive ply
//! matters in proportion to the passive share of the bending stiffness (ply count, thickness ratio); a
//! clamp whose compliance falls with width leaves the constant-clamp fit a residual in the width; a rigid
//! root matters most for short actuators; an inactive surface layer is a larger share of a thin plate;
//! an edge margin is a larger share of a narrow one.
//!
//! Seeds: expectations were set on seeds 0-9 of the stream `seed * 7919 + 17` (`CALIBRATE_SEED_BASE=tuning`);
//! the measured rates use seeds 6000-6009 of the stream `seed * 104_723 + 31`. CI asserts on the
//! measuring seeds: the variable right in at least 8 of 10 discoveries, the primitive in the top two in at
//! least 8 of 10, and discovery run (verdict `not-explained`) in at least 8 of 10.
//! `cargo test --release --test calibrate_discovery -- --nocapture` prints the table in the README.

mod synthetic;

use actuator_cam::calibrate::{self, csv::parse, Settings};
use actuator_model::primitives::{Primitive, Property, Target};
use rayon::prelude::*;
use synthetic::*;

struct Hidden {
    name: &'static str,
    truth: Truth,
    /// Variables (as the report names them) that count as pointing at the effect.
    variables: &'static [&'static str],
    /// The primitive's report name, when it is one of the model crate's.
    primitive: Option<&'static str>,
}

fn hidden() -> Vec<Hidden> {
    vec![
        Hidden {
            name: "passive E1 x 0.6",
            truth: Truth::Primitive(
                Primitive::Scale {
                    target: Target::Passive,
                    property: Property::E1,
                },
                0.6,
            ),
            variables: &["plies", "t_p/t_passive"],
            primitive: Some("passive-E1-scale"),
        },
        Hidden {
            name: "clamp per width",
            truth: Truth::Primitive(Primitive::ClampCompliancePerWidth, 4e-3),
            variables: &["w0_mm", "w0*t_p_mm2", "w0/l_p"],
            primitive: Some("clamp-compliance-per-width"),
        },
        Hidden {
            name: "rigid root 2 mm",
            truth: Truth::RigidRoot(2e-3),
            variables: &["l_tot_mm", "l_p_mm"],
            primitive: None,
        },
        Hidden {
            name: "inactive surface 15 um",
            truth: Truth::InactiveSurface(15e-6),
            variables: &["t_p_mm", "t_p/t_passive"],
            primitive: None,
        },
        Hidden {
            name: "edge margin 0.4 mm",
            truth: Truth::EdgeMargin(0.4e-3),
            variables: &["w0_mm", "w0/l_p", "w0*t_p_mm2"],
            primitive: None,
        },
    ]
}

struct Outcome {
    verdict: String,
    variable: Option<String>,
    rank: Option<usize>,
    top: Vec<String>,
}

/// How often, over the seeds: discovery ran, it named one of the right variables, the truth ranked first,
/// and in the top two.
struct Tally {
    discovered: usize,
    right: usize,
    first: usize,
    top2: usize,
}

fn tally(outcomes: &[Outcome], variables: &[&str]) -> Tally {
    let count = |keep: &dyn Fn(&Outcome) -> bool| outcomes.iter().filter(|o| keep(o)).count();
    Tally {
        discovered: count(&|o| o.verdict == "not-explained"),
        right: count(&|o| {
            o.variable
                .as_deref()
                .is_some_and(|v| variables.contains(&v))
        }),
        first: count(&|o| o.rank == Some(0)),
        top2: count(&|o| o.rank.is_some_and(|r| r < 2)),
    }
}

fn run(h: &Hidden, seed: u64) -> Outcome {
    run_on(h, seed, as_measured)
}

/// The synthetic data as they are, every column measured.
fn as_measured(csv: String) -> String {
    csv
}

/// [`run`] on the data as `measured` leaves them (e.g. with the masses not measured).
fn run_on(h: &Hidden, seed: u64, measured: Measured) -> Outcome {
    let data = parse(&measured(random_csv(h.truth, seed))).unwrap();
    let cal = calibrate::calibrate(&data, &Settings::default()).unwrap();
    let d = cal.selection.discovery.as_ref();
    Outcome {
        verdict: cal.model.verdict.clone(),
        variable: d.and_then(|d| d.trends.first().map(|t| t.exponent.variable.to_string())),
        rank: d.and_then(|d| {
            h.primitive
                .and_then(|p| d.candidates.iter().position(|c| c.name == p))
        }),
        top: d.map_or(Vec::new(), |d| {
            d.candidates
                .iter()
                .take(3)
                .map(|c| c.name.clone())
                .collect()
        }),
    }
}

/// Run each case on each seed and print the table (`CALIBRATE_VERBOSE` adds each run); the failures,
/// where discovery ran, named a right variable or (for a primitive) ranked it in the top two in fewer than
/// `share` = (k, of) of the seeds.
fn study(cases: Vec<(Hidden, Measured)>, seeds: &[u64], share: (usize, usize)) -> Vec<String> {
    let n = seeds.len();
    let short = |k: usize| k * share.1 < share.0 * n;
    let mut failures = Vec::new();
    println!(
        "{:<28} {:>13} {:>14} {:>10} {:>10}",
        "hidden effect", "not-explained", "right variable", "rank 1", "rank <= 2"
    );
    for (h, measured) in cases {
        let outcomes: Vec<Outcome> = seeds.par_iter().map(|&s| run_on(&h, s, measured)).collect();
        let Tally {
            discovered,
            right,
            first,
            top2,
        } = tally(&outcomes, h.variables);
        let rank_cells = if h.primitive.is_some() {
            (format!("{first}/{n}"), format!("{top2}/{n}"))
        } else {
            ("-".into(), "-".into())
        };
        println!(
            "{:<28} {:>10}/{:<2} {:>11}/{:<2} {:>10} {:>10}",
            h.name, discovered, n, right, n, rank_cells.0, rank_cells.1
        );
        if std::env::var("CALIBRATE_VERBOSE").is_ok() {
            for o in &outcomes {
                println!(
                    "    {} {:?} rank {:?} top {:?}",
                    o.verdict, o.variable, o.rank, o.top
                );
            }
        }
        if short(discovered) {
            failures.push(format!("{}: discovery ran {discovered}/{n}", h.name));
        }
        if short(right) {
            failures.push(format!("{}: right variable {right}/{n}", h.name));
        }
        if let Some(p) = h.primitive.filter(|_| short(top2)) {
            failures.push(format!("{}: {p} in the top two {top2}/{n}", h.name));
        }
    }
    failures
}

#[test]
fn discovery_points_at_the_variable_and_the_primitive() {
    let tuning = std::env::var("CALIBRATE_SEED_BASE").is_ok_and(|v| v == "tuning");
    let seeds: Vec<u64> = if tuning {
        (0..10).map(|s| s * 7919 + 17).collect()
    } else {
        (6000..6010).map(|s| s * 104_723 + 31).collect()
    };
    let cases = hidden()
        .into_iter()
        .map(|h| (h, as_measured as Measured))
        .collect();
    let failures = study(cases, &seeds, (8, 10));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// report.json and report.md carry the discovery when not explained, and only then.
#[test]
fn the_report_carries_the_discovery_only_when_not_explained() {
    let render = |truth: Truth| {
        let data = parse(&random_csv(truth, 7001)).unwrap();
        let cal = calibrate::calibrate(&data, &Settings::default()).unwrap();
        let files = calibrate::report::render(&cal, &data, "measured.csv").unwrap();
        let get = |name: &str| files.iter().find(|(n, _)| n == name).unwrap().1.clone();
        let json: serde_json::Value = serde_json::from_str(&get("report.json")).unwrap();
        (json, get("report.md"))
    };
    let (json, md) = render(hidden()[1].truth);
    assert_eq!(json["verdict"], "not-explained");
    let d = &json["discovery"];
    assert_eq!(d["candidates"][0]["name"], "clamp-compliance-per-width");
    assert_eq!(d["candidates"][0]["library"], false);
    assert_eq!(d["designs"].as_array().unwrap().len(), 3);
    assert_eq!(
        d["designs"][0]["predictions"].as_array().unwrap().len(),
        3,
        "the three leading candidates' predictions"
    );
    let law = &d["power_laws"][1];
    assert_eq!(law["residual"], "stiffness");
    assert!(
        law["exponents"][0]["interval"][0].as_f64().unwrap()
            <= law["exponents"][0]["estimate"].as_f64().unwrap()
    );
    assert!(md.contains("## Discovery: what the residual looks like"));
    assert!(md.contains("| 1 | clamp-compliance-per-width | no |"));
    let (json, md) = render(Truth::Library(actuator_model::Effects {
        dead_length: 3e-3,
        ..actuator_model::Effects::default()
    }));
    assert_eq!(json["verdict"], "explained");
    assert!(json.get("discovery").is_none());
    assert!(!md.contains("## Discovery"));
}

/// Discovery fits the best library effect together with each primitive outside the library. On data with
/// a library effect and an out-of-library primitive both present, the combination of the two is ranked
/// first and the residual's leading variable is the primitive's.
///
/// Seeds: set up on seeds 6500-6509 of the stream `seed * 104_723 + 31` (`CALIBRATE_SEED_BASE=tuning`);
/// measured (CI) on 6000-6009 of the same stream, which the tuning never saw. CI asserts the combination
/// first in at least 8 of 10 and the right variable in at least 8 of 10.
#[test]
fn discovery_ranks_a_library_effect_with_a_primitive_first() {
    let tuning = std::env::var("CALIBRATE_SEED_BASE").is_ok_and(|v| v == "tuning");
    let range = if tuning { 6500..6510 } else { 6000..6010 };
    let seeds: Vec<u64> = range.map(|s: u64| s * 104_723 + 31).collect();
    let n = seeds.len();
    let cases = [
        (
            "dead-length 2 mm + clamp per width",
            Truth::Composed(
                actuator_model::Effects {
                    dead_length: 2e-3,
                    ..actuator_model::Effects::default()
                },
                actuator_model::primitives::Applied {
                    primitive: Primitive::ClampCompliancePerWidth,
                    value: 4e-3,
                },
            ),
            "dead-length + clamp-compliance-per-width",
            &["w0_mm", "w0*t_p_mm2", "w0/l_p"][..],
        ),
        (
            "field d31 + passive E1 x 0.6",
            Truth::Composed(
                actuator_model::Effects {
                    d31_field_coefficient: 0.8e-6,
                    ..actuator_model::Effects::default()
                },
                actuator_model::primitives::Applied {
                    primitive: Primitive::Scale {
                        target: Target::Passive,
                        property: Property::E1,
                    },
                    value: 0.6,
                },
            ),
            "field-dependent-d31 + passive-E1-scale",
            &["plies", "t_p/t_passive"][..],
        ),
    ];
    let mut failures = Vec::new();
    println!(
        "{:<36} {:>13} {:>14} {:>10}",
        "hidden effects", "not-explained", "right variable", "rank 1"
    );
    for (label, truth, combination, variables) in cases {
        let h = Hidden {
            name: label,
            truth,
            variables,
            primitive: Some(combination),
        };
        let outcomes: Vec<Outcome> = seeds.par_iter().map(|&s| run(&h, s)).collect();
        let Tally {
            discovered,
            right,
            first,
            ..
        } = tally(&outcomes, variables);
        println!("{label:<36} {discovered:>10}/{n:<2} {right:>11}/{n:<2} {first:>7}/{n:<2}");
        if std::env::var("CALIBRATE_VERBOSE").is_ok() {
            for o in &outcomes {
                println!(
                    "    {} {:?} rank {:?} top {:?}",
                    o.verdict, o.variable, o.rank, o.top
                );
            }
        }
        if right * 10 < 8 * n {
            failures.push(format!("{label}: right variable {right}/{n}"));
        }
        if first * 10 < 8 * n {
            failures.push(format!("{label}: {combination} first {first}/{n}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A bond layer the library cannot fit, pointed at by discovery's bond primitives:
/// - a 60 µm bond of an adhesive at half its datasheet density: the masses show a 30 µm bond (the
///   library's `bond-layer`, fitted on them), the stack holds twice that; `bond-thickness-scale` must
///   rank first or second;
/// - a 30 µm bond on data without measured masses: the library fits `bond-layer` on the masses only, so
///   nothing in it adds the bond; `inserted-layer` must rank first or second.
///
/// The right variables follow from the physics before any run: the bond is a larger share of a thin
/// stack, so its residual follows the ply count (and the share of 0° plies, which the test's layups tie
/// to it one to one), the PZT thickness and their ratio.
///
/// A bond's modulus is not a case: in the model's perfectly bonded stack, E × 0.2 to × 3 moves δ and F_b
/// by under 1 % (docs/calibration.md §3, "Discovery"), far below the 5 % noise, and discovery does not
/// try it.
///
/// Seeds of the stream `seed * 104_723 + 31`: set up on 7500-7509 (`CALIBRATE_SEED_BASE=tuning`),
/// measured on 7000-7019, which the tuning never saw ([`bond_study`], ignored: about 60 CPU-seconds).
/// The CI check below runs the first three measuring seeds, to keep the discovery tests' time.
/// The variables that count for a bond (see above).
const BOND_VARIABLES: &[&str] = &["plies", "zero_ply_share", "t_p_mm", "t_p/t_passive"];

/// What is measured of synthetic data (e.g. [`without_masses`]).
type Measured = fn(String) -> String;

/// Each hidden bond, with what is measured of its data.
fn bond_cases() -> [(Hidden, Measured); 2] {
    let light_bond = actuator_model::Effects {
        bond_thickness: 60e-6,
        bond_scale: actuator_model::effects::BondScale {
            density: 0.5,
            ..Default::default()
        },
        ..actuator_model::Effects::default()
    };
    let bond = actuator_model::Effects {
        bond_thickness: 30e-6,
        ..actuator_model::Effects::default()
    };
    [
        (
            Hidden {
                name: "bond 60 um at half density",
                truth: Truth::Library(light_bond),
                variables: BOND_VARIABLES,
                primitive: Some("bond-thickness-scale"),
            },
            as_measured,
        ),
        (
            Hidden {
                name: "bond 30 um, no masses",
                truth: Truth::Library(bond),
                variables: BOND_VARIABLES,
                primitive: Some("inserted-layer"),
            },
            without_masses,
        ),
    ]
}

/// The bond study's seeds: tuning 7500-7509, measuring 7000-7019 (the first `take` of them).
fn bond_seeds(take: usize) -> Vec<u64> {
    let tuning = std::env::var("CALIBRATE_SEED_BASE").is_ok_and(|v| v == "tuning");
    let range = if tuning { 7500..7510 } else { 7000..7020 };
    range.take(take).map(|s: u64| s * 104_723 + 31).collect()
}

/// CI: discovery run, a right variable and the bond primitive in the top two on each of the first three
/// measuring seeds.
#[test]
fn discovery_points_at_a_bond_the_library_cannot_fit() {
    let failures = study(bond_cases().into(), &bond_seeds(3), (1, 1));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The measured study: on the 20 measuring seeds, discovery run, a right variable and the bond primitive
/// in the top two in at least 16 of 20 each (figures in docs/calibration.md §3).
#[test]
#[ignore = "bond discovery study: about 60 CPU-seconds"]
fn bond_study() {
    let failures = study(bond_cases().into(), &bond_seeds(20), (4, 5));
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
