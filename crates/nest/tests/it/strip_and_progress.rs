//! Strip mode (`nest_strip`), the progress reports (`nest_observed`) and the stop rule, checked
//! on layouts whose best is known in closed form; every layout is checked with `cam_nest::verify`.

use std::cell::RefCell;

use cam_nest::{
    nest, nest_observed, nest_strip, verify, NestBin, NestItem, NestProgress, NestSettings,
};

fn rectangle(width: f64, height: f64, demand: usize) -> NestItem {
    NestItem {
        outline: vec![[0.0, 0.0], [width, 0.0], [width, height], [0.0, height]],
        demand,
        rotations_deg: vec![0.0],
    }
}

fn settings(separation_mm: f64, iterations: usize) -> NestSettings {
    NestSettings {
        separation_mm,
        seed: 5,
        iterations,
        workers: 2,
    }
}

#[test]
fn twelve_squares_on_a_40_mm_strip_take_four_rows() {
    // Closed form: with 0.3 mm separation a row of k 10 mm squares needs 10k + 0.3(k + 1) mm of
    // width, so three fit across 40 mm (31.2) and four do not (41.5); twelve need four rows, and
    // the used length (top of the highest part plus the separation) is at least
    // 4 x 10 + 5 x 0.3 = 41.5 mm. The nester keeps 1 % more separation (its f32 margin).
    let items = vec![rectangle(10.0, 10.0, 12)];
    let s = settings(0.3, 200);
    let strip = nest_strip(&items, 40.0, &s, &|_| {}).expect("nest");
    verify(&items, &strip.bin, &s, &strip.solution, 1e-9).expect("layout verifies");
    assert_eq!(strip.solution.parts_placed(), 12);
    assert!(strip.length_mm >= 41.5 - 1e-9, "{}", strip.length_mm);
    assert!(
        strip.length_mm < 41.6,
        "four rows reach 41.5, got {}",
        strip.length_mm
    );
    let density = 1200.0 / (40.0 * strip.length_mm);
    assert!((strip.density - density).abs() < 1e-12);
}

#[test]
fn a_strip_takes_parts_that_overrun_its_first_reserve() {
    // 60 bars 21 x 1 mm on a 40 mm strip: one per row (two need 42.9 mm), so the used length
    // is at least 60 x 1 + 61 x 0.3 = 78.3 mm, more than the first reserve (twice the part
    // area over the width plus the longest part and 10 mm: 63 + 1 + 10.6 = 74.6 mm); the
    // second pass, on one row per copy, must take them.
    let items = vec![rectangle(21.0, 1.0, 60)];
    let s = settings(0.3, 50);
    let strip = nest_strip(&items, 40.0, &s, &|_| {}).expect("nest");
    verify(&items, &strip.bin, &s, &strip.solution, 1e-9).expect("layout verifies");
    assert!(strip.bin.height_mm > 78.3);
    assert!(strip.length_mm >= 78.3 - 1e-9);
    // ... and a part wider than the strip is refused by name.
    let wide = vec![rectangle(41.0, 1.0, 1)];
    let err = nest_strip(&wide, 40.0, &s, &|_| {}).unwrap_err();
    assert!(err.to_string().contains("item 0"), "{err}");
}

#[test]
fn progress_reports_climb_to_a_finished_report_and_do_not_change_the_layout() {
    // 40 squares of 10 mm (4000 mm²) on 60 mm sheets (3600 mm²): the area lower bound is 2.
    let items = vec![rectangle(10.0, 10.0, 40)];
    let bin = NestBin {
        width_mm: 60.0,
        height_mm: 60.0,
        stock: 5,
    };
    let s = settings(0.3, 300);
    let reports: RefCell<Vec<NestProgress>> = RefCell::new(Vec::new());
    let observed = nest_observed(&items, &bin, &s, &|p| reports.borrow_mut().push(*p)).unwrap();
    assert_eq!(observed, nest(&items, &bin, &s).unwrap());
    let reports = reports.into_inner();
    assert!(reports.len() >= 2, "{reports:?}");
    let last = reports.last().unwrap();
    assert!(last.finished);
    assert_eq!(reports.iter().filter(|p| p.finished).count(), 1);
    assert!(reports
        .windows(2)
        .all(|w| w[0].iterations_done <= w[1].iterations_done));
    assert!(reports
        .iter()
        .all(|p| p.iterations_done <= p.iterations_budget));
    assert!(reports.iter().all(|p| p.sheets_lower_bound == 2));
    assert_eq!(last.sheets, observed.bins_used());
    // The reported density is the final layout's used-length utilisation (the model's 1 %
    // separation margin aside).
    let used = observed.used_length_utilization(&bin, 0.3);
    assert!(
        (last.best_density - used).abs() < 0.01,
        "{} vs {used}",
        last.best_density
    );
}

#[test]
fn a_layout_at_its_bounds_stops_the_search_at_once() {
    // Ten 20 x 5 mm bars on a 20.02 mm wide sheet without separation: one per row, 50 mm of
    // used length against 1000 / 20.02 = 49.95 mm at full density, within the stop rule's 5 %
    // on one sheet (the lower bound). The greedy fill finds it, so no iteration is spent.
    let items = vec![rectangle(20.0, 5.0, 10)];
    let bin = NestBin {
        width_mm: 20.02,
        height_mm: 100.0,
        stock: 1,
    };
    let s = settings(0.0, 1000);
    let last = RefCell::new(None);
    let solution = nest_observed(&items, &bin, &s, &|p| *last.borrow_mut() = Some(*p)).unwrap();
    verify(&items, &bin, &s, &solution, 1e-9).unwrap();
    let last = last.into_inner().unwrap();
    // 10 of the 60 copies that get the whole budget: 1000 x 10 / 60.
    assert_eq!(last.iterations_budget, 166);
    assert_eq!(last.iterations_done, 0);
}
