//! The anytime search (`nest_until`, `nest_strip_until`): more iterations never give a worse
//! layout with the same seed, a limit that strikes in the rounds leaves a layout that its
//! iterations replay exactly, and a limit that strikes at once still gives a whole layout. Every
//! layout is checked with `cam_nest::verify`.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::fixtures;
use cam_nest::{
    nest_strip_until, nest_until, verify, NestBin, NestItem, NestSettings, NestSolution, Reached,
    SearchEnd, SearchLimit, StripLayout,
};

/// The base search's budget: iterations above it are anytime rounds of 100.
const BASE: usize = 1000;
const ROUND: usize = 100;

fn settings(iterations: usize) -> NestSettings {
    NestSettings {
        separation_mm: 0.3,
        seed: 11,
        iterations,
        workers: 2,
    }
}

/// Nine actuator outlines of three designs: small enough that a round is quick, large enough
/// that the rounds have something to improve.
fn items() -> Vec<NestItem> {
    fixtures::random_designs(3011, 3, 3)
}

fn strip(iterations: usize, limit: &SearchLimit) -> (StripLayout, Reached) {
    let items = items();
    let s = settings(iterations);
    let (strip, reached) = nest_strip_until(&items, 60.0, &s, limit, &|_| {}).expect("nest");
    verify(&items, &strip.bin, &s, &strip.solution, 1e-9).expect("layout verifies");
    (strip, reached)
}

#[test]
#[ignore = "study: about 30 s in release (four strips of up to 5,000 iterations); run with -- --ignored"]
fn a_longer_budget_never_gives_a_longer_strip_with_the_same_seed() {
    // 40 rounds take in compression passes, which begin once the rounds stall.
    let mut previous: Option<f64> = None;
    for rounds in [0, 2, 5, 40] {
        let (strip, reached) = strip(BASE + rounds * ROUND, &SearchLimit::default());
        assert!(reached.replayable);
        assert_eq!(reached.ended, SearchEnd::Budget);
        assert!(reached.iterations <= BASE + rounds * ROUND);
        if let Some(shorter_budget) = previous {
            assert!(
                strip.length_mm <= shorter_budget + 1e-9,
                "{rounds} rounds: {} mm, fewer rounds {shorter_budget} mm",
                strip.length_mm
            );
        }
        previous = Some(strip.length_mm);
    }
}

#[test]
fn a_search_stopped_in_its_rounds_is_replayed_by_the_iterations_it_reached() {
    // The interrupt is set by the observer after the second round's report, so where the search
    // stops is decided by counted work, not by the clock: the rounds after it are not done.
    let items = items();
    let s = settings(BASE + 20 * ROUND);
    let flag = AtomicBool::new(false);
    let limit = SearchLimit {
        deadline: None,
        interrupt: Some(&flag),
    };
    // A round's report carries the rounds still to go in its budget: 18 of the 20 after the
    // second (the base search's own reports carry at most its 1000).
    let observe = |p: &cam_nest::NestProgress| {
        if !p.finished && p.iterations_budget - p.iterations_done == 18 * ROUND {
            flag.store(true, Ordering::Relaxed);
        }
    };
    let bin = NestBin {
        width_mm: 60.0,
        height_mm: 200.0,
        stock: 1,
    };
    let (stopped, reached) = nest_until(&items, &bin, &s, &limit, &observe).expect("nest");
    verify(&items, &bin, &s, &stopped, 1e-9).expect("layout verifies");
    assert_eq!(reached.ended, SearchEnd::Interrupt);
    assert!(reached.replayable);
    assert_eq!(reached.iterations, BASE + 2 * ROUND);
    let replay: NestSolution = cam_nest::nest(&items, &bin, &settings(reached.iterations)).unwrap();
    assert_eq!(replay, stopped);
}

#[test]
fn a_deadline_already_past_still_gives_every_part_and_says_it_cannot_be_replayed() {
    let past = SearchLimit {
        deadline: Some(Instant::now() - Duration::from_millis(1)),
        interrupt: None,
    };
    let (strip, reached) = strip(BASE + 10 * ROUND, &past);
    assert_eq!(strip.solution.parts_placed(), 9);
    assert_eq!(reached.ended, SearchEnd::Time);
    assert!(!reached.replayable);
    // Every part had to be placed after the deadline: the result says it ran over.
    assert!(reached.over_budget.is_some());
}

#[test]
fn on_fixed_sheets_more_rounds_never_give_more_sheets_or_a_longer_last_sheet() {
    // Sheets too small for all parts at once: the rounds' search may empty a sheet, their
    // compression shortens the last one; the used length (all sheets but the last whole, plus
    // the last one's used height) orders layouts as the search does.
    let items = items();
    let bin = NestBin {
        width_mm: 40.0,
        height_mm: 40.0,
        stock: 9,
    };
    let mut previous: Option<(usize, f64)> = None;
    for rounds in [0, 2, 5] {
        let s = settings(BASE + rounds * ROUND);
        let (layout, reached) =
            nest_until(&items, &bin, &s, &SearchLimit::default(), &|_| {}).expect("nest");
        verify(&items, &bin, &s, &layout, 1e-9).expect("layout verifies");
        assert!(reached.replayable);
        let now = (
            layout.bins_used(),
            layout.used_length_mm(&bin, s.separation_mm),
        );
        if let Some((sheets, length)) = previous {
            assert!(
                // Lengths within the score's 1 µm tolerance are equal to the search (plus f32
                // rounding of a 40 mm figure); below it, fuller sheets win.
                now.0 < sheets || (now.0 == sheets && now.1 <= length + 1.01e-3),
                "{rounds} rounds: {now:?}, fewer rounds {sheets} sheets {length} mm"
            );
        }
        previous = Some(now);
    }
}

#[test]
fn a_layout_that_cannot_get_shorter_still_gets_every_round_it_is_given() {
    // One part: no chain can lower the strip, and no search can shorten it. The rounds still
    // run to their number (thousands of them without a shorter layout), as a time budget runs to
    // its deadline: no stall rule ends them.
    let items = vec![fixtures::fibre(
        fixtures::actuator(20.0, 6.0, 3.0, 4.0, 2.0),
        1,
    )];
    let rounds = 5000;
    let s = settings(BASE + rounds * ROUND);
    let (strip, reached) =
        nest_strip_until(&items, 60.0, &s, &SearchLimit::default(), &|_| {}).expect("nest");
    verify(&items, &strip.bin, &s, &strip.solution, 1e-9).expect("layout verifies");
    assert_eq!(reached.ended, SearchEnd::Budget);
    assert_eq!(reached.iterations, BASE + rounds * ROUND);
}
