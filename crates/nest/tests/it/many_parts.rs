//! Many small parts: a deadline holds however many parts there are (the greedy fill that makes
//! the first layout checks it and shares its effort out over the copies), a layout that must
//! take longer says so, and an iteration budget of 1 ends promptly. Every layout is checked
//! with `cam_nest::verify`.

use std::time::{Duration, Instant};

use cam_nest::{nest_until, verify, NestBin, NestItem, NestSettings, SearchEnd, SearchLimit};

/// `demand` circles of 1 mm radius as 32-gons.
fn circles(demand: usize) -> Vec<NestItem> {
    let outline = (0..32)
        .map(|k| {
            let a = std::f64::consts::TAU * f64::from(k) / 32.0;
            [a.cos(), a.sin()]
        })
        .collect();
    vec![NestItem {
        outline,
        demand,
        rotations_deg: vec![0.0],
    }]
}

/// A sheet that holds several thousand of the circles.
fn sheet(stock: usize) -> NestBin {
    NestBin {
        width_mm: 200.0,
        height_mm: 200.0,
        stock,
    }
}

fn settings(iterations: usize) -> NestSettings {
    NestSettings {
        separation_mm: 0.3,
        seed: 1,
        iterations,
        workers: 2,
    }
}

#[test]
fn thousands_of_small_parts_end_near_a_short_deadline_and_say_whether_they_ran_over() {
    let (items, bin, settings) = (circles(3000), sheet(3000), settings(usize::MAX));
    let budget = Duration::from_secs(1);
    let started = Instant::now();
    let limit = SearchLimit {
        deadline: Some(started + budget),
        interrupt: None,
    };
    let (layout, reached) = nest_until(&items, &bin, &settings, &limit, &|_| {}).unwrap();
    let took = started.elapsed();
    verify(&items, &bin, &settings, &layout, 1e-9).unwrap();
    assert_eq!(layout.parts_placed(), 3000);
    assert_eq!(reached.ended, SearchEnd::Time);
    assert!(!reached.replayable);
    // The fill shares its effort out over the copies: about 1.4 s here on 2 cores at a load
    // average of 8, where a fill at a fixed effort per part takes tens of seconds. The bound
    // leaves room for a machine shared with other builds and tests (8 s at a load average of 17).
    assert!(took < 30 * budget, "{took:?} for a budget of {budget:?}");
    if let Some(over) = reached.over_budget {
        // The first layout came after the deadline: the search took longer than the budget,
        // and no longer than the call.
        assert!(over > budget && over <= took, "{over:?} of {took:?}");
    }
}

#[test]
fn a_deadline_shorter_than_the_first_layout_is_reported_exceeded() {
    // A deadline already past: every part is still placed, and the result says the budget
    // was exceeded, by the whole time the search took.
    let (items, bin, settings) = (circles(1500), sheet(1500), settings(usize::MAX));
    let started = Instant::now();
    let limit = SearchLimit {
        deadline: Some(started),
        interrupt: None,
    };
    let (layout, reached) = nest_until(&items, &bin, &settings, &limit, &|_| {}).unwrap();
    let took = started.elapsed();
    verify(&items, &bin, &settings, &layout, 1e-9).unwrap();
    assert_eq!(layout.parts_placed(), 1500);
    let over = reached
        .over_budget
        .expect("the first layout came after the deadline");
    assert!(
        over > Duration::ZERO && over <= took,
        "{over:?} of {took:?}"
    );
    assert_eq!(reached.ended, SearchEnd::Time);
}

#[test]
fn an_iteration_budget_of_one_with_thousands_of_parts_ends_promptly() {
    let (items, bin, settings) = (circles(2000), sheet(2000), settings(1));
    let started = Instant::now();
    let (layout, reached) =
        nest_until(&items, &bin, &settings, &SearchLimit::default(), &|_| {}).unwrap();
    let took = started.elapsed();
    verify(&items, &bin, &settings, &layout, 1e-9).unwrap();
    assert_eq!(layout.parts_placed(), 2000);
    assert_eq!(
        layout.bins_used(),
        1,
        "2,000 circles cover a quarter of a 200 mm sheet"
    );
    assert_eq!(
        (reached.ended, reached.over_budget),
        (SearchEnd::Budget, None)
    );
    // About 5 s on 2 cores at a load average of 8; a fill at the whole effort per part, on a
    // quadtree of fixed depth, takes 90 s for as many circles at that load.
    assert!(took < Duration::from_secs(45), "{took:?}");
}
