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
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
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
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let designs: Vec<Design> = (0..30).map(|_| random_design(&mut rng)).collect();
    let data = parse(&synthetic_csv(h.truth, &designs, &mut rng)).unwrap();
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

#[test]
fn discovery_points_at_the_variable_and_the_primitive() {
    let tuning = std::env::var("CALIBRATE_SEED_BASE").is_ok_and(|v| v == "tuning");
    let seeds: Vec<u64> = if tuning {
        (0..10).map(|s| s * 7919 + 17).collect()
    } else {
        (6000..6010).map(|s| s * 104_723 + 31).collect()
    };
    let n = seeds.len();
    let mut failures = Vec::new();
    println!(
        "{:<26} {:>13} {:>14} {:>10} {:>10}",
        "hidden effect", "not-explained", "right variable", "rank 1", "rank <= 2"
    );
    for h in hidden() {
        let outcomes: Vec<Outcome> = seeds.par_iter().map(|&s| run(&h, s)).collect();
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
            "{:<26} {:>10}/{:<2} {:>11}/{:<2} {:>10} {:>10}",
            h.name, discovered, n, right, n, rank_cells.0, rank_cells.1
        );
        for o in &outcomes {
            if std::env::var("CALIBRATE_VERBOSE").is_ok() {
                println!(
                    "    {} {:?} rank {:?} top {:?}",
                    o.verdict, o.variable, o.rank, o.top
                );
            }
        }
        if discovered * 10 < 8 * n {
            failures.push(format!("{}: discovery ran {discovered}/{n}", h.name));
        }
        if right * 10 < 8 * n {
            failures.push(format!("{}: right variable {right}/{n}", h.name));
        }
        if h.primitive.is_some() && top2 * 10 < 8 * n {
            failures.push(format!("{}: primitive in the top two {top2}/{n}", h.name));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// report.json and report.md carry the discovery when not explained, and only then.
#[test]
fn the_report_carries_the_discovery_only_when_not_explained() {
    let render = |truth: Truth| {
        let mut rng = ChaCha8Rng::seed_from_u64(7001);
        let designs: Vec<Design> = (0..30).map(|_| random_design(&mut rng)).collect();
        let data = parse(&synthetic_csv(truth, &designs, &mut rng)).unwrap();
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
