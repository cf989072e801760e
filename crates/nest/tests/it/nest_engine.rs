//! Nesting engine: every layout is checked with `cam_nest::verify` (plain `geo` distances, not
//! jagua-rs), plus determinism, the bounding-box baseline comparison and error messages.
//! `report_*` tests are `#[ignore]`d measurements: run them in release with
//! `cargo test --release -p cam-nest --test it -- --ignored report_ --nocapture`.

use crate::fixtures::{actuator, fibre, random_designs, sixty_mixed, write_svg};
use cam_nest::{
    nest, nest_bounding_boxes, verify, NestBin, NestError, NestItem, NestSettings, NestSolution,
    NestedBin, PlacedPart,
};
use proptest::prelude::*;
use std::time::Instant;

fn sheet(stock: usize) -> NestBin {
    NestBin {
        width_mm: 150.0,
        height_mm: 150.0,
        stock,
    }
}

fn settings(separation_mm: f64, seed: u64, iterations: usize) -> NestSettings {
    NestSettings {
        separation_mm,
        seed,
        iterations,
        workers: 2,
    }
}

fn nest_verified(items: &[NestItem], bin: &NestBin, settings: &NestSettings) -> NestSolution {
    let solution = nest(items, bin, settings).expect("nest");
    if let Err(violation) = verify(items, bin, settings, &solution, 1e-9) {
        panic!("invalid nest: {violation}");
    }
    solution
}

/// Item, copy, rotation bits and translation bits of one placed part.
type ExactPlacement = (usize, usize, u64, [u64; 2]);

/// Placements only, exactly (bit for bit).
fn placements(solution: &NestSolution) -> Vec<Vec<ExactPlacement>> {
    solution
        .bins
        .iter()
        .map(|b| {
            b.parts
                .iter()
                .map(|p| {
                    (
                        p.item,
                        p.copy,
                        p.rotation_deg.to_bits(),
                        p.translation.map(f64::to_bits),
                    )
                })
                .collect()
        })
        .collect()
}

fn fixed_batches() -> Vec<(&'static str, Vec<NestItem>, f64)> {
    let mut quarter_turns = random_designs(3, 3, 4);
    for item in &mut quarter_turns {
        item.rotations_deg = vec![0.0, 90.0, 180.0, 270.0];
    }
    quarter_turns.push(NestItem {
        outline: vec![[0.0, 0.0], [30.0, 0.0], [30.0, 8.0], [0.0, 8.0]],
        demand: 6,
        rotations_deg: vec![90.0],
    });
    vec![
        ("60 mixed actuators, 0.3 mm", sixty_mixed(), 0.3),
        (
            "random designs 4 x 10, 0.5 mm",
            random_designs(11, 4, 10),
            0.5,
        ),
        ("quarter turns + fixed 90°", quarter_turns, 0.4),
    ]
}

#[test]
fn fixed_batches_verify_and_never_lose_to_the_baseline() {
    for (name, items, sep) in fixed_batches() {
        let s = settings(sep, 1, 40);
        let solution = nest_verified(&items, &sheet(20), &s);
        let baseline = nest_bounding_boxes(&items, &sheet(20), &s).expect("baseline");
        verify(&items, &sheet(20), &s, &baseline, 1e-9).expect("baseline verifies");
        println!(
            "{name}: nester {} sheets at {:.1} %, baseline {} sheets at {:.1} %",
            solution.bins_used(),
            solution.utilization() * 100.0,
            baseline.bins_used(),
            baseline.utilization() * 100.0
        );
        assert!(
            solution.bins_used() <= baseline.bins_used(),
            "{name}: nester used {} sheets, baseline {}",
            solution.bins_used(),
            baseline.bins_used()
        );
    }
}

/// Used-length utilisation of both nesters on `bin` (verified), `(nester, baseline)`.
fn used_length_pair(items: &[NestItem], bin: &NestBin, s: &NestSettings) -> (f64, f64) {
    let solution = nest_verified(items, bin, s);
    let baseline = nest_bounding_boxes(items, bin, s).expect("baseline");
    verify(items, bin, s, &baseline, 1e-9).expect("baseline verifies");
    (
        solution.used_length_utilization(bin, s.separation_mm),
        baseline.used_length_utilization(bin, s.separation_mm),
    )
}

/// The engine's target, on the measure that does not jump at sheet boundaries: at least 10
/// points above the bounding-box baseline on 60 passive parts of mixed designs on 150 mm sheets
/// (measured margins 21-34 points in the bench), and for the fixed mix on a 150 mm wide strip too (about 25).
/// Not asserted on the strip for every random mix: where the designs are near-rectangles the
/// baseline packs a strip well (random mix 1: 76 % vs 70 %, see the bench).
#[test]
#[ignore = "study: about 30 s in release (four batches of sixty parts on sheets and a strip); run with -- --ignored"]
fn sixty_mixed_parts_beat_the_baseline_by_ten_points_of_used_length() {
    let s = settings(0.3, 1, 100);
    let strip = NestBin {
        width_mm: 150.0,
        height_mm: 500.0,
        stock: 1,
    };
    let batches = [
        ("fixed mix", sixty_mixed()),
        ("random mix 1", random_designs(1, 4, 15)),
        ("random mix 2", random_designs(2, 4, 15)),
        ("random mix 3", random_designs(3, 4, 15)),
    ];
    for (i, (name, items)) in batches.into_iter().enumerate() {
        let shapes = [("sheets", sheet(10)), ("strip", strip)];
        for (shape, bin) in shapes.into_iter().take(if i == 0 { 2 } else { 1 }) {
            let (nester, baseline) = used_length_pair(&items, &bin, &s);
            println!(
                "{name}, {shape}: nester {:.1} %, baseline {:.1} %",
                nester * 100.0,
                baseline * 100.0
            );
            assert!(
                nester >= baseline + 0.10,
                "{name}, {shape}: used-length utilisation {:.1} % vs baseline {:.1} %",
                nester * 100.0,
                baseline * 100.0
            );
        }
    }
}

#[test]
fn used_length_counts_full_sheets_and_the_lowest_top() {
    // Sheet 0: a 10 x 100 bar (top at 101); sheet 1: a 10 x 20 bar (top at 21).
    let bar = |height: f64, copy: usize| {
        let outline = vec![[0.0, 0.0], [10.0, 0.0], [10.0, height], [0.0, height]];
        PlacedPart {
            item: 0,
            copy,
            rotation_deg: 0.0,
            translation: [1.0, 1.0],
            outline: cam_geometry::place_ring(&outline, 0.0, [1.0, 1.0]),
        }
    };
    let solution = NestSolution {
        bins: vec![
            NestedBin {
                index: 0,
                parts: vec![bar(100.0, 0)],
                utilization: 1000.0 / 15000.0,
                score_lines: Vec::new(),
            },
            NestedBin {
                index: 1,
                parts: vec![bar(20.0, 1)],
                utilization: 200.0 / 15000.0,
                score_lines: Vec::new(),
            },
        ],
    };
    let bin = NestBin {
        width_mm: 100.0,
        height_mm: 150.0,
        stock: 2,
    };
    // 150 for the first sheet + 21 + 0.5 separation for the second.
    assert!((solution.used_length_mm(&bin, 0.5) - 171.5).abs() < 1e-12);
    let want = 1200.0 / (100.0 * 171.5);
    assert!((solution.used_length_utilization(&bin, 0.5) - want).abs() < 1e-12);
    assert!((solution.utilization() - 1200.0 / 30000.0).abs() < 1e-12);
    assert_eq!(
        NestSolution::default().used_length_utilization(&bin, 0.5),
        0.0
    );
}

#[test]
fn same_seed_same_layout_other_seed_still_valid() {
    let items = random_designs(5, 3, 8);
    let a = nest_verified(&items, &sheet(10), &settings(0.3, 42, 30));
    let b = nest_verified(&items, &sheet(10), &settings(0.3, 42, 30));
    assert_eq!(placements(&a), placements(&b));
    assert_eq!(a, b);
    nest_verified(&items, &sheet(10), &settings(0.3, 43, 30));
}

#[test]
fn one_worker_and_three_workers_both_verify() {
    let items = random_designs(8, 2, 6);
    for workers in [1, 3] {
        let s = NestSettings {
            workers,
            ..settings(0.4, 9, 12)
        };
        nest_verified(&items, &sheet(10), &s);
    }
}

#[test]
fn oversize_part_names_both_sizes() {
    let items = vec![fibre(vec![[0.0, 0.0], [160.0, 0.0], [0.0, 10.0]], 1)];
    let err = nest(&items, &sheet(1), &settings(0.3, 0, 0)).unwrap_err();
    assert!(matches!(err, NestError::PartLargerThanBin { item: 0, .. }));
    let msg = err.to_string();
    assert!(
        msg.contains("160.000 x 10.000") && msg.contains("150 x 150"),
        "{msg}"
    );
    let err = nest_bounding_boxes(&items, &sheet(1), &settings(0.3, 0, 0)).unwrap_err();
    assert!(matches!(err, NestError::PartLargerThanBin { .. }));
}

#[test]
fn a_part_that_fits_only_turned_is_turned() {
    let items = vec![NestItem {
        outline: vec![[0.0, 0.0], [10.0, 0.0], [10.0, 140.0], [0.0, 140.0]],
        demand: 1,
        rotations_deg: vec![90.0, 0.0],
    }];
    let bin = NestBin {
        width_mm: 150.0,
        height_mm: 20.0,
        stock: 1,
    };
    let solution = nest_verified(&items, &bin, &settings(0.3, 0, 0));
    assert_eq!(solution.bins[0].parts[0].rotation_deg, 90.0);
}

#[test]
fn stock_too_small_says_how_many_sheets_are_needed() {
    // 40 x 40 mm squares: at most 9 a sheet, so 20 need 3 sheets.
    let items = vec![fibre(
        vec![[0.0, 0.0], [40.0, 0.0], [40.0, 40.0], [0.0, 40.0]],
        20,
    )];
    let err = nest(&items, &sheet(2), &settings(0.3, 0, 10)).unwrap_err();
    assert_eq!(
        err,
        NestError::StockTooSmall {
            needed: 3,
            stock: 2
        }
    );
    assert!(err.to_string().contains("need 3 sheets"), "{err}");
}

#[test]
fn empty_and_degenerate_outlines_are_rejected() {
    for outline in [
        vec![],
        vec![[0.0, 0.0], [1.0, 1.0]],
        vec![[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]],
    ] {
        let err = nest(&[fibre(outline, 1)], &sheet(1), &settings(0.3, 0, 0)).unwrap_err();
        assert!(
            matches!(err, NestError::DegenerateOutline { item: 0, .. }),
            "{err}"
        );
    }
}

#[test]
fn closed_repeated_and_clockwise_rings_are_accepted() {
    let mut clockwise = actuator(25.0, 8.0, 2.0, 10.0, 2.0);
    clockwise.reverse();
    let mut closed = actuator(30.0, 10.0, 1.0, 0.0, 0.0);
    closed.push(closed[0]);
    closed.insert(2, closed[1]);
    let items = vec![fibre(clockwise, 5), fibre(closed, 5)];
    let solution = nest_verified(&items, &sheet(5), &settings(0.3, 4, 10));
    assert_eq!(solution.parts_placed(), 10);
}

#[test]
fn bad_settings_are_rejected() {
    let items = sixty_mixed();
    let mut s = settings(0.3, 0, 0);
    s.workers = 0;
    assert!(matches!(
        nest(&items, &sheet(5), &s),
        Err(NestError::BadSettings(_))
    ));
    s = settings(-0.1, 0, 0);
    assert!(matches!(
        nest(&items, &sheet(5), &s),
        Err(NestError::BadSettings(_))
    ));
    let mut no_rotation = sixty_mixed();
    no_rotation[1].rotations_deg.clear();
    assert!(matches!(
        nest(&no_rotation, &sheet(5), &settings(0.3, 0, 0)),
        Err(NestError::BadRotations { item: 1, .. })
    ));
}

#[test]
fn nothing_demanded_gives_an_empty_solution() {
    let solution = nest(
        &[fibre(actuator(20.0, 5.0, 1.0, 0.0, 0.0), 0)],
        &sheet(0),
        &settings(0.3, 0, 5),
    )
    .expect("nest");
    assert_eq!(solution.bins_used(), 0);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]
    #[test]
    fn random_batches_verify(
        seed in any::<u64>(),
        designs in 1usize..4,
        copies in 1usize..8,
        separation in 0.0f64..0.6,
        quarter in any::<bool>(),
    ) {
        let mut items = random_designs(seed, designs, copies);
        if quarter {
            items[0].rotations_deg = vec![0.0, 90.0, 180.0, 270.0];
        }
        let s = settings(separation, seed, 8);
        let solution = nest(&items, &sheet(50), &s).expect("nest");
        prop_assert_eq!(verify(&items, &sheet(50), &s, &solution, 1e-9), Ok(()));
    }
}

/// Nests `items` with both nesters, prints sheets, utilisation and wall time, and returns
/// `(nester, baseline)` used-length utilisation.
fn report(name: &str, items: &[NestItem], s: &NestSettings) -> (f64, f64) {
    let bin = sheet(100);
    let started = Instant::now();
    let solution = nest(items, &bin, s).expect("nest");
    let elapsed = started.elapsed();
    verify(items, &bin, s, &solution, 1e-9).expect("verifies");
    if let Some(dir) = std::env::var_os("NEST_SVG_DIR") {
        let file = format!("{}-{}.svg", name.replace([' ', ','], "_"), s.iterations);
        write_svg(&std::path::Path::new(&dir).join(file), &solution, &bin);
    }
    let baseline = nest_bounding_boxes(items, &bin, s).expect("baseline");
    let parts: usize = items.iter().map(|i| i.demand).sum();
    let fills = |sol: &NestSolution| {
        sol.bins
            .iter()
            .map(|b| format!("{:.1}", b.utilization * 100.0))
            .collect::<Vec<_>>()
            .join("/")
    };
    println!(
        "{name}: {parts} parts, {} iterations, {} workers: {:.2} s\n  nester   {} sheets, utilisation {:.1} %, used-length {:.1} % (per sheet {})\n  baseline {} sheets, utilisation {:.1} %, used-length {:.1} % (per sheet {})",
        s.iterations,
        s.workers,
        elapsed.as_secs_f64(),
        solution.bins_used(),
        solution.utilization() * 100.0,
        solution.used_length_utilization(&bin, s.separation_mm) * 100.0,
        fills(&solution),
        baseline.bins_used(),
        baseline.utilization() * 100.0,
        baseline.used_length_utilization(&bin, s.separation_mm) * 100.0,
        fills(&baseline),
    );
    (
        solution.used_length_utilization(&bin, s.separation_mm),
        baseline.used_length_utilization(&bin, s.separation_mm),
    )
}

#[test]
#[ignore = "measurement; run in release with --nocapture"]
fn report_sixty_mixed_actuators() {
    for iterations in [0, 500, 2000] {
        report(
            "60 mixed (4 x 15)",
            &sixty_mixed(),
            &settings(0.3, 1, iterations),
        );
    }
}

#[test]
#[ignore = "measurement; run in release with --nocapture"]
fn report_sixty_random_designs() {
    let seeds = 1..=12u64;
    let n = seeds.clone().count() as f64;
    let (mut nester, mut baseline) = (0.0, 0.0);
    for seed in seeds {
        let (a, b) = report(
            &format!("60 random (4 designs x 15, seed {seed})"),
            &random_designs(seed, 4, 15),
            &settings(0.3, 1, 1000),
        );
        nester += a / n;
        baseline += b / n;
    }
    println!(
        "mean used-length utilisation over the batches: nester {:.1} %, baseline {:.1} %",
        nester * 100.0,
        baseline * 100.0
    );
}

#[test]
#[ignore = "measurement; run in release with --nocapture"]
fn report_three_hundred_parts() {
    for iterations in [0, 1000, 3000] {
        report(
            "300 parts (10 random designs x 30)",
            &random_designs(2024, 10, 30),
            &settings(0.3, 1, iterations),
        );
    }
}
